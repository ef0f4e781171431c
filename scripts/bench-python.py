#!/usr/bin/env python3
"""The same sweep from Python (rocklab.run) and from the CLI (rocklab run), alternating,
fresh each time (nothing reused): the wall-time ratio Python / CLI for BENCHMARKS.md.

    scripts/bench-python.py [STUDY] [ROUNDS]      # run with the venv that has rocklab
"""
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import rocklab

repo = Path(__file__).resolve().parents[1]
study = sys.argv[1] if len(sys.argv) > 1 else str(repo / "studies" / "fig12_rigid_spectra.ron")
rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
binary = repo / "target" / "release" / "rocklab"
py, cli = [], []
with tempfile.TemporaryDirectory() as tmp:
    for i in range(rounds):
        t = time.perf_counter()
        subprocess.run([str(binary), "run", study, "--out", f"{tmp}/cli", "--fresh", "--quiet"],
                       check=True, capture_output=True)
        cli.append(time.perf_counter() - t)
        t = time.perf_counter()
        r = rocklab.run(study, out=f"{tmp}/py", fresh=True, progress=False)
        py.append(time.perf_counter() - t)
        assert r.reused == 0
print(f"study {Path(study).name}, {r.scenes} scenes, {rounds} rounds alternating")
print("cli s:", " ".join(f"{x:.2f}" for x in cli))
print("py  s:", " ".join(f"{x:.2f}" for x in py))
print(f"median ratio python/cli: {sorted(py)[rounds // 2] / sorted(cli)[rounds // 2]:.3f}")
