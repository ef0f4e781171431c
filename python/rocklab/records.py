"""``rocklab.records``: the ground-motion records, as ``rocklab records --json``."""

import json
from typing import Optional, Sequence

from . import _native
from ._flags import to_argv


def records(suite: Optional[str] = None, baseline: bool = False,
            records_dir: Optional[str] = None, ims: bool = False,
            periods: Optional[Sequence[float]] = None, damping: Optional[float] = None,
            names: Optional[Sequence[str]] = None):
    """The records this build can run as a pandas DataFrame, one row per record: name,
    Table 1 number, event, station, npts, dt, duration, PGA (g) and PGV (m/s) computed from
    the data, the paper's Table 1 PGV, and where the record came from.

    ``suite`` lists a record suite instead (``far_field``, ``near_field_pulse``,
    ``near_field_no_pulse``, ``near_field`` or ``table1``) with its metadata; ``names``
    lists these records only (names, suite components such as ``far_field/7a``, or AT2
    files); ``baseline`` baseline-corrects before PGA/PGV; ``records_dir`` reads another
    records directory.

    ``ims=True`` adds every component's intensity measures as ``records --ims --json``
    gives them (``pgd_m``, ``arias_m_s``, ``cav_m_s``, ``d5_75_s``, ``d5_95_s``, ``tm_s``,
    ``pulse_like``, ``tp_s``, ``rotd50_g``, ...), with Sa at ``periods`` (s; the CLI's
    default list when left out) and ``damping`` (0.05 by default) spread into one column
    per period, ``sa(T)``, in g, beside the ``periods_s``/``sa_g`` lists.
    """
    import pandas as pd

    argv = to_argv({"suite": suite, "baseline": baseline, "records_dir": records_dir,
                    "ims": ims, "periods": list(periods) if periods else None,
                    "damping": damping})
    argv += list(names or [])
    rows = json.loads(_native.records(argv))
    frame = pd.DataFrame(rows)
    if ims and rows:
        for i, period in enumerate(rows[0].get("periods_s") or []):
            frame[f"sa({period:g})"] = [row["sa_g"][i] for row in rows]
    return frame
