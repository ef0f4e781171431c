import math
import subprocess
import sys

import pytest

import rocklab
from conftest import REPO


def test_pelicun_loads_the_demand_sample(tmp_path):
    pelicun = pytest.importorskip("pelicun")
    from pelicun.assessment import Assessment

    results = rocklab.run(REPO / "studies" / "default.ron", out=tmp_path / "r",
                          progress=False)
    first = results.table(wide=True)["group"].iloc[0]
    path = rocklab.to_pelicun(results, tmp_path / "demands.csv", group=first)
    asmnt = Assessment({"PrintLog": False})
    asmnt.demand.load_sample(str(path))
    sample = asmnt.demand.sample
    wide = results.table(wide=True)
    mine = wide[wide["group"] == first]
    assert len(sample) == len(mine) == 12
    got = sample.xs("RROT", level="type", axis=1).iloc[:, 0].to_numpy()
    assert list(got) == pytest.approx(list(mine["peak_rotation_ratio"]), rel=1e-12, nan_ok=True)
    assert pelicun.__version__


def test_pelicun_needs_a_group_when_there_are_several(tmp_path):
    results = rocklab.run(REPO / "studies" / "default.ron", out=tmp_path / "r",
                          progress=False)
    with pytest.raises(ValueError, match="group="):
        rocklab.to_pelicun(results, tmp_path / "d.csv")


PARAMS_STANDARD = """                    2 variables
                      2.000000000000000e-01 alpha
                      5.000000000000000e-01 sigma
                    2 functions
                    1 ASV_1:peak_rotation_ratio
                    1 ASV_2:impacts
                    2 derivative_variables
                    1 DVV_1:alpha
                    2 DVV_2:sigma
                    0 analysis_components
                    1 eval_id
"""

PARAMS_APREPRO = """{ DAKOTA_VARS     =                      2 }
{ alpha           =  2.000000000000000e-01 }
{ sigma           =  5.000000000000000e-01 }
{ DAKOTA_FNS      =                      2 }
{ ASV_1:peak_rotation_ratio =          1 }
{ ASV_2:impacts   =                      1 }
"""


@pytest.mark.parametrize("params", [PARAMS_STANDARD, PARAMS_APREPRO])
def test_quofem_driver_writes_one_line_of_qois(tmp_path, params):
    (tmp_path / "params.in").write_text(params)
    fixed = ["--set", "p=2.0", "--set", "device=sequential", "--set", "pulse=sine",
             "--set", "amplitude_alpha=2.0", "--set", "frequency_ratio=3.0"]
    done = subprocess.run([sys.executable, "-m", "rocklab.quofem", "params.in", *fixed],
                          cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    line = (tmp_path / "results.out").read_text()
    assert line.count("\n") == 1
    values = [float(v) for v in line.split()]
    direct = rocklab.simulate(alpha=0.2, sigma=0.5, p=2.0, device="sequential", pulse="sine",
                              amplitude_alpha=2.0, frequency_ratio=3.0)
    assert values == [direct["peak_rotation_ratio"], direct["impacts"]]
    assert all(math.isfinite(v) for v in values)


def test_quofem_refuses_a_bad_params_file(tmp_path):
    (tmp_path / "params.in").write_text("hello\n")
    done = subprocess.run([sys.executable, "-m", "rocklab.quofem", "params.in"],
                          cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 2
    assert "variables" in done.stderr
