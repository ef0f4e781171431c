#!/usr/bin/env python3
"""Intensity measures of all 100 FEMA P695 components at 100 periods: rocklab against eqsig.

Usage (eqsig in a virtual environment outside the repository):
    python3 -m venv /tmp/eqsig-venv && /tmp/eqsig-venv/bin/pip install eqsig
    cargo build --release
    /tmp/eqsig-venv/bin/python scripts/ims-vs-eqsig.py [--rocklab target/release/rocklab]

It reads every component of records/fema-p695/*/ (values in g, converted with
g = 9.80665 m/s²), times eqsig computing PGA, PGV, PGD, Arias intensity, CAV, D5-75, D5-95
and Sa at 100 periods (5 % damping) for all of them, times
`rocklab records --suite <set> --ims --periods <the 100> --json` for the three sets, and
prints the two times, their ratio and the largest relative differences per measure.

Conventions that differ (docs/MODEL.md "Intensity measures"): eqsig's Arias uses g = 9.81
(rescaled here), its PGV/PGD are sample maxima of trapezoid-integrated series (rocklab's are
the peaks of the exact continuous functions), its durations are read at samples, and its
Sa at periods below 6 dt is the PGA; the comparison skips those periods.
"""

import argparse
import importlib.util
import json
import os
import subprocess
import time

import numpy as np

# The FEMA components and eqsig's IMs, as the test reference computes them.
_spec = importlib.util.spec_from_file_location(
    "ims_reference", os.path.join(os.path.dirname(__file__), "ims-reference.py"))
ref_mod = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(ref_mod)

SETS = list(ref_mod.FOLDERS)
PERIODS = np.geomspace(0.05, 5.0, 100)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rocklab", default="target/release/rocklab")
    args = ap.parse_args()
    records = {name: (dt, acc) for name, dt, acc in ref_mod.components()}

    t0 = time.perf_counter()
    ref = {name: ref_mod.eqsig_ims(dt, acc, PERIODS) for name, (dt, acc) in records.items()}
    t_eqsig = time.perf_counter() - t0

    periods = ",".join(repr(float(p)) for p in PERIODS)
    ours = {}
    t0 = time.perf_counter()
    for suite in SETS:
        out = subprocess.run(
            [args.rocklab, "records", "--suite", suite, "--ims", "--periods", periods, "--json"],
            check=True, capture_output=True, text=True).stdout
        for row in json.loads(out):
            ours[row["name"]] = row
    t_rocklab = time.perf_counter() - t0

    print(f"{len(records)} components, {len(PERIODS)} periods")
    print(f"eqsig   {t_eqsig:8.2f} s (PGA, PGV, PGD, Arias, CAV, D5-75, D5-95, Sa)")
    print(f"rocklab {t_rocklab:8.2f} s (the same, plus Tm, pulse classification, RotD50)")
    print(f"ratio eqsig / rocklab = {t_eqsig / t_rocklab:.2f}")
    for key in ["pga_g", "pgv_m_s", "pgd_m", "arias_m_s", "cav_m_s", "d5_75_s", "d5_95_s"]:
        worst = max(abs(ours[n][key] / ref[n][key] - 1.0) for n in records)
        print(f"  {key:10s} largest relative difference {worst:.2e}")
    worst = 0.0
    for n, (dt, _) in records.items():
        keep = PERIODS >= 6 * dt
        a = np.array(ours[n]["sa_g"])[keep]
        b = np.array(ref[n]["sa_g"])[keep]
        worst = max(worst, float(np.max(np.abs(a / b - 1.0))))
    print(f"  sa_g       largest relative difference {worst:.2e} (periods >= 6 dt)")


if __name__ == "__main__":
    main()
