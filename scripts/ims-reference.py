#!/usr/bin/env python3
"""Write tests/data/fema_ims_eqsig.json: every FEMA P695 component's intensity measures as
eqsig computes them (an implementation independent of rocklab), for tests/ims.rs.

    /tmp/eqsig-venv/bin/python scripts/ims-reference.py

Records in g are converted with g = 9.80665; eqsig's Arias (g = 9.81) is rescaled to it.
PGV and PGD are eqsig's sample maxima, durations its sample-based readings; Sa at 5 %.
eqsig's displacement integrates its velocity by the trapezoid rule, which is not the issue's
definition (the exact integral of the piecewise-linear record), so `pgv_exact_m_s` and
`pgd_exact_m` are that definition written here again with numpy (closed-form velocity and
displacement at the samples, and the peaks between them where a or v changes sign), for
rocklab's continuous peaks to be checked to rounding.
"""
import csv
import json
import os

import numpy as np
import eqsig

G0 = 9.80665
PERIODS = [0.2, 0.5, 1.0, 2.0]
FOLDERS = {"far_field": "farfield", "near_field_pulse": "nearfield_pulse",
           "near_field_no_pulse": "nearfield_no_pulse"}



def components():
    """(name, dt, acceleration in m/s²) of every FEMA P695 component, in index order."""
    for suite, folder in FOLDERS.items():
        base = os.path.join("records/fema-p695", folder)
        with open(os.path.join(base, "index.csv")) as f:
            rows = list(csv.DictReader(f))
        for row in rows:
            values, dt = [], None
            with open(os.path.join(base, row["file"])) as f:
                for line in f:
                    if line.startswith("#"):
                        if line.lower().startswith("# dt:"):
                            dt = float(line.split(":")[1])
                        continue
                    values.append(float(line))
            yield f"{suite}/{row['record_id']}{row['component']}", dt, np.array(values) * G0


def eqsig_ims(dt, acc, periods):
    """eqsig's PGA, PGV, PGD, Arias (rescaled to g = 9.80665), CAV, D5-75, D5-95, Sa (5 %)."""
    sig = eqsig.AccSignal(acc, dt)
    _, _, sa = eqsig.sdof.pseudo_response_spectra(acc, dt, np.array(periods), 0.05)
    return {
        "dt": dt,
        "pga_g": float(np.max(np.abs(acc)) / G0),
        "pgv_m_s": float(np.max(np.abs(sig.velocity))),
        "pgd_m": float(np.max(np.abs(sig.displacement))),
        "arias_m_s": float(eqsig.im.calc_arias_intensity(sig)[-1] * 9.81 / G0),
        "cav_m_s": float(eqsig.im.calc_cav(sig)[-1]),
        "d5_75_s": float(eqsig.im.calc_sig_dur(sig, 0.05, 0.75)),
        "d5_95_s": float(eqsig.im.calc_sig_dur(sig, 0.05, 0.95)),
        "sa_g": [float(s / G0) for s in sa],
    }


def exact_peaks(dt, acc):
    """PGV and PGD of the piecewise-linear record from rest, peaks between samples included."""
    a0, a1 = acc[:-1], acc[1:]
    b = (a1 - a0) / dt
    v = np.concatenate([[0.0], np.cumsum(0.5 * (a0 + a1) * dt)])
    d = np.concatenate([[0.0], np.cumsum(v[:-1] * dt + a0 * dt**2 / 3 + a1 * dt**2 / 6)])
    v0, d0 = v[:-1], d[:-1]
    pgv, pgd = np.max(np.abs(v)), np.max(np.abs(d))
    with np.errstate(divide="ignore", invalid="ignore"):
        # v is extreme where a(t) = a0 + b t = 0 inside the step.
        t = -a0 / b
        inside = (b != 0) & (t > 0) & (t < dt)
        vt = v0 + a0 * t + 0.5 * b * t**2
        if inside.any():
            pgv = max(pgv, np.max(np.abs(vt[inside])))
        # d is extreme where v(t) = v0 + a0 t + b t²/2 = 0 inside the step.
        roots = []
        disc = a0**2 - 2 * b * v0
        ok = disc >= 0
        sq = np.sqrt(np.where(ok, disc, 0.0))
        quad = b != 0
        roots.append(np.where(quad, (-a0 + sq) / b, np.nan))
        roots.append(np.where(quad, (-a0 - sq) / b, np.nan))
        roots.append(np.where(~quad & (a0 != 0), -v0 / a0, np.nan))
        for t in roots:
            inside = ok & np.isfinite(t) & (t > 0) & (t < dt)
            dt_ = d0 + v0 * t + 0.5 * a0 * t**2 + b * t**3 / 6
            if inside.any():
                pgd = max(pgd, np.max(np.abs(dt_[inside])))
    return float(pgv), float(pgd)


def main():
    out = {"eqsig": eqsig.__version__, "periods_s": PERIODS, "components": {}}
    for name, dt, acc in components():
        out["components"][name] = eqsig_ims(dt, acc, PERIODS)
        pgv, pgd = exact_peaks(dt, acc)
        out["components"][name]["pgv_exact_m_s"] = pgv
        out["components"][name]["pgd_exact_m"] = pgd
    with open("tests/data/fema_ims_eqsig.json", "w") as f:
        json.dump(out, f, indent=1, sort_keys=True)
        f.write("\n")
    print(len(out["components"]), "components")


if __name__ == "__main__":
    main()
