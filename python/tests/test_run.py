import io
import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import rocklab
from conftest import FRAGILITY_STUDY, REPO

DEFAULT = REPO / "studies" / "default.ron"


@pytest.fixture(scope="module")
def default_results(tmp_path_factory):
    out = tmp_path_factory.mktemp("py") / "default"
    return rocklab.run(DEFAULT, out=out, progress=False)


def test_run_writes_what_the_cli_writes(cli, default_results, tmp_path):
    ours = default_results
    theirs = tmp_path / "cli"
    cli("run", DEFAULT, "--out", theirs, "--quiet")
    for name in ["results.csv", "results.columns.csv", "summary.txt", "study.ron"]:
        assert (ours.dir / name).read_text() == (theirs / name).read_text(), name
    long = ours.table()
    assert long.equals(pd.read_csv(io.StringIO(cli("table", theirs))))
    wide = ours.table(wide=True)
    assert wide.equals(pd.read_csv(io.StringIO(cli("table", theirs, "--wide"))))
    assert len(wide) == ours.scenes == 36


def test_rerun_reuses_every_finished_scene(default_results):
    again = rocklab.run(DEFAULT, out=default_results.dir, progress=False)
    assert again.reused == again.scenes == 36
    assert again.table().equals(default_results.table())


def test_open_and_to_xarray(default_results):
    opened = rocklab.open(default_results.dir)
    ds = opened.to_xarray()
    wide = opened.table(wide=True)
    # One dimension per study axis: the 3 variants by the 12 frequency ratios.
    assert dict(ds.sizes) == {"group": 3, **{c: 12 for c in ds.dims if c != "group"}}
    assert len(ds.dims) == 2
    values = ds["peak_rotation_ratio"].values
    assert values.size == len(wide)
    # The same numbers (NaN where the block overturned), each in one cell.
    np.testing.assert_array_equal(np.sort(values.ravel()),
                                  np.sort(wide["peak_rotation_ratio"].to_numpy()))


def test_compare_equals_cli_json(cli, default_results):
    ours = default_results.compare(a="none", b="sequential")
    theirs = json.loads(cli("compare", default_results.dir, "--a", "none", "--b",
                            "sequential", "--json"))
    assert len(ours) == len(theirs["pairs"]) >= 1
    assert ours.iloc[0]["a"] == theirs["pairs"][0]["a"]


def test_study_error_is_the_clis(cli_error, tmp_path):
    bad = DEFAULT.read_text().replace("steps: 12", "steps: 0")
    with pytest.raises(rocklab.StudyError) as e:
        rocklab.run(bad, progress=False)
    assert str(e.value).startswith("<study text>:")  # file:line:column, then the field
    path = tmp_path / "bad.ron"
    path.write_text(bad)
    with pytest.raises(rocklab.StudyError) as from_file:
        rocklab.run(path, progress=False)
    assert cli_error("run", path) == f"error: {from_file.value}"
    with pytest.raises(rocklab.StudyError, match="no_such.ron"):
        rocklab.run("no_such.ron", progress=False)


def test_fragility_tables_equal_the_cli_files(cli, tmp_path):
    ours = rocklab.run(FRAGILITY_STUDY, out=tmp_path / "py", progress=False)
    study = tmp_path / "f.ron"
    study.write_text(FRAGILITY_STUDY)
    cli("run", study, "--out", tmp_path / "cli", "--quiet")
    for name, read in [("fragility.csv", ours.fragility), ("stripes.csv", ours.stripes)]:
        assert read().equals(pd.read_csv(tmp_path / "cli" / name)), name
    fragility = ours.fragility()
    assert len(fragility) > 0
    with pytest.raises(FileNotFoundError, match="design"):
        ours.design()


RISK_STUDY = FRAGILITY_STUDY.replace('records: [1, 2]', 'records: [1, 2, 3, 4, 5, 6]').replace(
    'scale: [1.5, 3.0, 6.0]', 'scale: [1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0]').replace(
    'levels([0.2, 1.0])', 'levels([0.2, 1.0]), bootstrap: 200')


def test_risk_equals_the_cli(cli, tmp_path):
    assert RISK_STUDY != FRAGILITY_STUDY and "bootstrap: 200" in RISK_STUDY
    ours = rocklab.run(RISK_STUDY, out=tmp_path / "py", progress=False)
    study = tmp_path / "r.ron"
    study.write_text(RISK_STUDY)
    cli("run", study, "--out", tmp_path / "cli", "--quiet")
    # Risk at the shipped illustrative site, as `rocklab risk` writes it.
    hazard = REPO / "studies" / "hazards" / "illustrative_pga.csv"
    risk = ours.risk(hazard=hazard, years=50.0)
    cli("risk", tmp_path / "cli", "--hazard", hazard, "--years", "50")
    assert risk.equals(pd.read_csv(tmp_path / "cli" / "risk.csv"))
    fitted = risk[risk["maf"].notna()]
    assert len(fitted) > 0, risk[["device", "damage_state", "status"]]
    # p_years is the Poisson probability of the MAF; the interval holds the MAF.
    assert ((1 - np.exp(-fitted["maf"] * 50.0) - fitted["p_years"]).abs() < 1e-12).all()
    bounded = fitted[fitted["maf_lo"].notna()]
    assert ((bounded["maf_lo"] <= bounded["maf"]) & (bounded["maf"] <= bounded["maf_hi"])).all()
    # Read back without a hazard: the table just written.
    assert ours.risk().equals(risk)
    with pytest.raises(rocklab.StudyError, match="no_such.csv"):
        ours.risk(hazard=tmp_path / "no_such.csv")


def test_progress_reaches_the_total(tmp_path):
    seen = []
    ours = rocklab._native.run(str(DEFAULT), False, str(tmp_path / "p"), 1, False,
                               lambda done, total: seen.append((done, total)))
    assert seen[-1] == (36, 36)
    assert all(a[0] <= b[0] for a, b in zip(seen, seen[1:]))
    assert ours[2] == 36
