"""``rocklab.records``: the ground-motion records, as ``rocklab records --json``."""

import json
from typing import Optional

from . import _native
from ._flags import to_argv


def records(suite: Optional[str] = None, baseline: bool = False,
            records_dir: Optional[str] = None):
    """The records this build can run as a pandas DataFrame, one row per record: name,
    Table 1 number, event, station, npts, dt, duration, PGA (g) and PGV (m/s) computed from
    the data, the paper's Table 1 PGV, and where the record came from.

    ``suite`` lists a record suite instead (``far_field``, ``near_field_pulse``,
    ``near_field_no_pulse``, ``near_field`` or ``table1``) with its metadata; ``baseline``
    baseline-corrects before PGA/PGV; ``records_dir`` reads another records directory.
    """
    import pandas as pd

    argv = to_argv({"suite": suite, "baseline": baseline, "records_dir": records_dir})
    return pd.DataFrame(json.loads(_native.records(argv)))
