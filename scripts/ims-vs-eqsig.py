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
import glob
import json
import os
import subprocess
import time

import numpy as np
import eqsig

G0 = 9.80665
SETS = {"far_field": "farfield", "near_field_pulse": "nearfield_pulse",
        "near_field_no_pulse": "nearfield_no_pulse"}
PERIODS = np.geomspace(0.05, 5.0, 100)


def read(path):
    dt = None
    values = []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                if line.lower().startswith("# dt:"):
                    dt = float(line.split(":")[1])
                continue
            values.append(float(line))
    return dt, np.array(values) * G0


def eqsig_ims(dt, acc):
    sig = eqsig.AccSignal(acc, dt)
    vel = sig.velocity
    disp = sig.displacement
    ia = eqsig.im.calc_arias_intensity(sig)[-1] * 9.81 / G0
    cav = eqsig.im.calc_cav(sig)[-1]
    d575 = eqsig.im.calc_sig_dur(sig, 0.05, 0.75)
    d595 = eqsig.im.calc_sig_dur(sig, 0.05, 0.95)
    _, _, sa = eqsig.sdof.pseudo_response_spectra(acc, dt, PERIODS, 0.05)
    return {
        "pga_g": np.max(np.abs(acc)) / G0,
        "pgv_m_s": np.max(np.abs(vel)),
        "pgd_m": np.max(np.abs(disp)),
        "arias_m_s": ia,
        "cav_m_s": cav,
        "d5_75_s": d575,
        "d5_95_s": d595,
        "sa_g": sa / G0,
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rocklab", default="target/release/rocklab")
    args = ap.parse_args()
    files = {}
    for suite, folder in SETS.items():
        index = os.path.join("records/fema-p695", folder, "index.csv")
        import csv
        with open(index) as f:
            for row in csv.DictReader(f):
                name = f"{suite}/{row['record_id']}{row['component']}"
                files[name] = os.path.join("records/fema-p695", folder, row["file"])
    records = {name: read(path) for name, path in files.items()}

    t0 = time.perf_counter()
    ref = {name: eqsig_ims(dt, acc) for name, (dt, acc) in records.items()}
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
        b = ref[n]["sa_g"][keep]
        worst = max(worst, float(np.max(np.abs(a / b - 1.0))))
    print(f"  sa_g       largest relative difference {worst:.2e} (periods >= 6 dt)")


if __name__ == "__main__":
    main()
