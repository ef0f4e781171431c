"""``rocklab.simulate``: one scene, as ``rocklab simulate --json``."""

import io
import json
from typing import Any, Dict

from . import _native
from ._flags import to_argv


def simulate(history: bool = False, **flags: Any) -> Dict[str, Any]:
    """Run one scene and return its peaks, counters and solver statistics.

    Keyword arguments are ``rocklab simulate``'s flags with dashes as underscores, e.g.
    ``simulate(alpha=0.2, p=2.0, device="mechanistic", sigma=0.5, pulse="sine",
    amplitude_g=0.3, frequency=8.0, rtol=1e-8)`` or ``simulate(record="landers",
    scale_pga=0.4)``; see ``rocklab simulate --help`` for all of them. Switches take
    ``True``. The result has exactly the keys and numbers ``rocklab simulate --json``
    prints (``wall_seconds`` is this run's own time).

    With ``history=True`` the dict also holds ``"history"``: a pandas DataFrame of the
    time history (the columns of ``--history``'s CSV; ``dt="steps"`` gives one row per
    solver step).

    Raises :class:`rocklab.StudyError` (a ValueError) for an unknown flag or a refused
    value, with the CLI's message.
    """
    flags.pop("json", None)  # always JSON: that is what is parsed here
    text, csv = _native.simulate(to_argv(flags), history)
    out: Dict[str, Any] = json.loads(text)
    if csv is not None:
        import pandas as pd

        out["history"] = pd.read_csv(io.StringIO(csv))
    return out
