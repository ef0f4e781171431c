import runpy
import sys
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "clutch_and_fragility.py"


def test_example_runs_and_draws_both_figures(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(sys, "argv", [str(EXAMPLE), str(tmp_path)])
    env = runpy.run_path(str(EXAMPLE), run_name="__main__")
    for name in ["clutch_grid.png", "fragility.png"]:
        assert (tmp_path / name).stat().st_size > 1000, name
    # The grid: 5 variants (sequential + 4 clutch frequencies), each with 11 frequency ratios.
    assert env["lines"].sizes == {"omega_g_over_p": 11, "line": 5}
    assert len(env["fitted"]) >= 1
