"""``rocklab.run`` and ``rocklab.open``: a study's results directory as pandas and xarray."""

import io
import json
import os
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Union

from . import _native
from ._flags import to_argv

PathLike = Union[str, "os.PathLike[str]"]

#: The tables a run writes beside its results, by name (the library's one list).
TABLE_FILES: Dict[str, str] = dict(_native.table_files())


class Results:
    """The results of a study in an output directory (``out/<study name>`` by default).

    Everything here reads what ``rocklab run`` wrote, through the same library code as the
    CLI commands named in each method, so a table here equals the CLI's.
    """

    def __init__(self, out: PathLike, scenes: int = 0, reused: int = 0,
                 notes: Optional[List[str]] = None) -> None:
        self.dir = Path(out)
        if not (self.dir / "results.json").is_file():
            raise FileNotFoundError(
                f"{self.dir}: no results.json there (hint: rocklab.run(study, out=...) "
                "writes one)"
            )
        #: Scenes in the results and how many of them this run reused from the journal.
        self.scenes = scenes
        self.reused = reused
        #: What opening the directory decided (resumed, set aside), as `rocklab run` notes.
        self.notes = notes or []

    def __repr__(self) -> str:
        return f"rocklab.Results({str(self.dir)!r})"

    @property
    def results_path(self) -> Path:
        return self.dir / "results.json"

    def study(self):
        """The study these results came from (the ``study.ron`` beside them)."""
        from .study import Study

        return Study.load(self.dir / "study.ron")

    def table(self, wide: bool = False):
        """The results as ``rocklab table`` prints them: long (one row per scene and
        quantity, the default) or ``wide`` (one row per scene, a column per quantity)."""
        import pandas as pd

        return pd.read_csv(io.StringIO(_native.table(str(self.results_path), wide)))

    def to_xarray(self):
        """An xarray Dataset: a dimension per study axis (device variant, then each swept
        coordinate), a variable per response quantity. A cell no scene ran is NaN."""
        wide = self.table(wide=True)
        quantities = [q for q in _native.quantities() if q in wide.columns]
        coords = _native.axis_columns(str(self.results_path))
        # The variant, then the excitation where the coordinates leave it open (a suite's
        # records), then the swept coordinates.
        for dims in (["group"] + coords, ["group", "excitation"] + coords):
            data = wide.set_index(dims)[quantities]
            if not data.index.has_duplicates:
                return data.to_xarray()
        raise ValueError(
            f"{self.dir}: no set of study axes identifies each scene; use table(wide=True)"
        )

    def _csv(self, name: str):
        import pandas as pd

        path = self.dir / TABLE_FILES[name]
        if not path.is_file():
            raise FileNotFoundError(
                f"{path}: this study wrote no {name} table (hint: only a study with a "
                f"{name} section has one)"
            )
        return pd.read_csv(path)

    def fragility(self):
        """The fitted fragility curves (``fragility.csv``)."""
        return self._csv("fragility")

    def stripes(self):
        """The stripes of a fragility study (``stripes.csv``)."""
        return self._csv("stripes")

    def ida(self):
        """The capacities of an incremental dynamic analysis (``ida.csv``)."""
        return self._csv("ida")

    def design(self):
        """The answers of a design study (``design.csv``)."""
        return self._csv("design")

    def risk(self, hazard: Optional[PathLike] = None, years: Optional[float] = None,
             mce: Optional[float] = None, beta_total: Optional[float] = None,
             ratings: Optional[str] = None, mu_t: Optional[float] = None):
        """Seismic risk at a site (``risk.csv``): per variant and damage state the mean annual
        frequency ``maf`` with its bootstrap interval, ``p_years``, the ratio to bare and the
        deaggregation, as ``rocklab risk``. With ``hazard`` (a CSV ``pga,annual_rate``,
        ``pgv,annual_rate`` or ``sa(T),annual_rate``) it is computed now, as ``rocklab risk
        RESULTS --hazard FILE`` with the other arguments as its flags (``mce`` with
        ``beta_total`` or ``ratings``, e.g. ``"B,B,B"``, gives FEMA P695 margins, in
        ``risk.json``), and written beside the results; without, the study's own ``risk``
        section's table is read."""
        if hazard is not None:
            args = [str(self.dir)] + to_argv({
                "hazard": os.fspath(hazard), "years": years, "mce": mce,
                "beta_total": beta_total, "ratings": ratings, "mu_t": mu_t})
            _native.risk(args)
        return self._csv("risk")

    def boundary(self):
        """The overturning boundary of a study with a map (``boundary.csv``)."""
        return self._csv("boundary")

    def compare(self, a: Optional[str] = None, b: Optional[str] = None,
                quantity: Optional[str] = None):
        """The paired statistics of ``rocklab compare --json``: one row per pair of spectra
        of variant ``b`` against ``a`` (e.g. ``"sequential"``, ``"mechanistic(sigma: 0.5)"``;
        the CLI's defaults when left out)."""
        import pandas as pd

        args = [str(self.results_path)] + to_argv({"a": a, "b": b, "quantity": quantity})
        found = json.loads(_native.compare(args))
        rows = []
        for pair in found["pairs"]:
            row = {k: v for k, v in pair.items() if not isinstance(v, (dict, list))}
            row.update(pair.get("stats", {}))
            rows.append(row)
        return pd.DataFrame(rows)


def run(study: Union[PathLike, "Study"], out: Optional[PathLike] = None,  # noqa: F821
        jobs: Optional[int] = None, progress: bool = True, fresh: bool = False) -> Results:
    """Run a study as ``rocklab run`` does and return its :class:`Results`.

    ``study`` is a study file's path, ``"default"`` (the built-in study), RON text, or a
    :class:`rocklab.Study`. The scenes run in parallel (``jobs`` threads, default all cores)
    into ``out`` (default ``out/<study name>``), each finished scene journalled at once: a
    rerun reuses every finished scene, and Ctrl-C stops the sweep cleanly (the journal
    keeps what finished; run again to continue) and raises KeyboardInterrupt. The GIL is
    released while the sweep runs. ``progress`` shows a bar (tqdm when installed).

    Raises :class:`rocklab.StudyError` for a study rocklab refuses, with the CLI's message.
    """
    from .study import Study

    if isinstance(study, Study):
        source, is_text = study.to_ron(), True
    else:
        source = os.fspath(study)
        is_text = _looks_like_ron(source)
    bar = _ProgressBar() if progress else None
    try:
        out_dir, _, scenes, reused, notes = _native.run(
            source, is_text, None if out is None else os.fspath(out), jobs, fresh,
            bar.update if bar else None,
        )
    finally:
        if bar:
            bar.close()
    return Results(out_dir, scenes=scenes, reused=reused, notes=notes)


def open(out: PathLike) -> Results:  # noqa: A001 (the module's verb, as in the CLI)
    """The finished results in ``out`` (a results directory, or its results.json)."""
    path = Path(out)
    return Results(path.parent if path.name == "results.json" else path)


def _looks_like_ron(source: str) -> bool:
    # A study's text always holds a parenthesis, a path almost never (nor a newline).
    if "(" not in source:
        return False
    try:
        return "\n" in source or not Path(source).exists()
    except OSError:  # too long for a file name
        return True


class _ProgressBar:
    """tqdm when it is installed, otherwise a line on stderr now and then."""

    def __init__(self) -> None:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            tqdm = None
        self._tqdm: Optional[Any] = None
        self._make: Optional[Callable[..., Any]] = tqdm
        self._last = -1

    def update(self, done: int, total: int) -> None:
        if self._make is not None:
            if self._tqdm is None:
                self._tqdm = self._make(total=total, unit="scene")
            self._tqdm.total = total
            self._tqdm.n = done
            self._tqdm.refresh()
        elif done * 10 // max(total, 1) != self._last:
            import sys

            self._last = done * 10 // max(total, 1)
            print(f"rocklab: {done}/{total} scenes", file=sys.stderr)

    def close(self) -> None:
        if self._tqdm is not None:
            self._tqdm.close()
