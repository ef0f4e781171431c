"""rocklab from Python: seismic studies of rocking structures protected by clutched inerters.

The functions here run the same library code as the ``rocklab`` command line and return
what it prints as Python objects:

- :func:`simulate` -- one scene, as ``rocklab simulate --json`` (a dict; a DataFrame of
  histories with ``history=True``);
- :func:`run` / :func:`open` -- a study through the journalled, resumable sweep of
  ``rocklab run``, as :class:`Results` (pandas tables, an xarray Dataset);
- :func:`records` -- the ground-motion records (``rocklab records``) as a DataFrame;
- :class:`Study` -- build or edit a study and save it as RON;
- :class:`StudyError` -- a study or flag rocklab refuses (a ``ValueError``), with the CLI's
  message (file, line, field, hint).
"""

from ._native import StudyError, __version__
from .simulate import simulate
from .results import Results, open, run
from .records import records
from .study import Study
from .pelicun import to_pelicun

__all__ = [
    "StudyError",
    "Study",
    "Results",
    "simulate",
    "run",
    "open",
    "records",
    "to_pelicun",
    "__version__",
]
