import json

import pytest

import rocklab

# Timings differ from run to run; everything else must be equal.
TIMES = {"wall_seconds", "wall_seconds_median"}


def without_times(d):
    return {k: v for k, v in d.items() if k not in TIMES}


@pytest.mark.parametrize("flags", [
    dict(alpha=0.2, p=2.0, device="mechanistic", sigma=0.5, pulse="sine", amplitude_g=0.3,
         frequency=8.0, rtol=1e-8),
    dict(alpha="10deg", p=2.0, device="sequential", sigma=0.5, pulse="ricker",
         amplitude_alpha=2.0, frequency_ratio=3.0),
    dict(structure="flexible", p=2.0, alpha=0.2, omega_ratio=10.0, xi=0.02, device="inerter",
         sigma=0.3, pulse="cosine", amplitude_ratio=1.5, frequency_ratio=4.0),
])
def test_simulate_equals_cli_json(cli, flags):
    ours = rocklab.simulate(**flags)
    argv = rocklab._flags.to_argv(flags)
    theirs = json.loads(cli("simulate", *argv, "--json"))
    assert set(ours) == set(theirs)
    assert without_times(ours) == without_times(theirs)


def test_simulate_record_equals_cli(cli):
    flags = dict(alpha=0.2, p=2.0, record="1", scale_pga=0.3, duration=5.0)
    ours = rocklab.simulate(**flags)
    theirs = json.loads(cli("simulate", *rocklab._flags.to_argv(flags), "--json"))
    assert without_times(ours) == without_times(theirs)
    assert ours["record_source"] == theirs["record_source"]


def test_free_rocking_peak_is_the_release_angle():
    # A rigid block released from rest at θ0 < α under no ground motion only loses energy
    # at impacts: the peak rotation is θ0 and the energy ledger balances.
    out = rocklab.simulate(alpha=0.2, p=2.0, theta0=0.1, amplitude_g=0.0, frequency=1.0,
                           duration=5.0, rtol=1e-10)
    assert out["peak_rotation"] == pytest.approx(0.1, rel=1e-9)
    assert abs(out["energy_residual"]) < 1e-6
    assert out["overturned"] is False


def test_history_is_a_dataframe_matching_the_cli_csv(cli, tmp_path):
    import pandas as pd

    flags = dict(alpha=0.2, p=2.0, pulse="sine", amplitude_alpha=2.0, frequency_ratio=3.0,
                 dt=0.01)
    ours = rocklab.simulate(history=True, **flags)
    path = tmp_path / "h.csv"
    cli("simulate", *rocklab._flags.to_argv(flags), "--history", path)
    theirs = pd.read_csv(path)
    pd.testing.assert_frame_equal(ours["history"], theirs)
    # The history's peak |θ| is the reported peak (to the sampling: never above it).
    theta = ours["history"].iloc[:, 1].abs().max()
    assert theta <= ours["peak_rotation"] * (1 + 1e-12)


def test_bad_flag_raises_study_error_with_the_cli_message(cli_error):
    flags = dict(alpha=0.2, p=2.0, device="sequential", sigma=-1.0, pulse="sine",
                 amplitude_alpha=2.0, frequency_ratio=3.0)
    with pytest.raises(rocklab.StudyError) as e:
        rocklab.simulate(**flags)
    assert isinstance(e.value, ValueError)
    assert "--sigma" in str(e.value)
    assert cli_error("simulate", *rocklab._flags.to_argv(flags)) == f"error: {e.value}"
    with pytest.raises(rocklab.StudyError, match="no-such-flag"):
        rocklab.simulate(no_such_flag=1.0)
