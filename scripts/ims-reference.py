#!/usr/bin/env python3
"""Write tests/data/fema_ims_eqsig.json: every FEMA P695 component's intensity measures as
eqsig computes them (an implementation independent of rocklab), for tests/ims.rs.

    /tmp/eqsig-venv/bin/python scripts/ims-reference.py

Records in g are converted with g = 9.80665; eqsig's Arias (g = 9.81) is rescaled to it.
PGV and PGD are eqsig's sample maxima, durations its sample-based readings; Sa at 5 %.
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


def main():
    out = {"eqsig": eqsig.__version__, "periods_s": PERIODS, "components": {}}
    for name, dt, acc in components():
        out["components"][name] = eqsig_ims(dt, acc, PERIODS)
    with open("tests/data/fema_ims_eqsig.json", "w") as f:
        json.dump(out, f, indent=1, sort_keys=True)
        f.write("\n")
    print(len(out["components"]), "components")


if __name__ == "__main__":
    main()
