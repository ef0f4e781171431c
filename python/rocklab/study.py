"""``rocklab.Study``: a study built or edited in Python, saved as RON."""

import copy
import json
import os
from pathlib import Path
from typing import Any, Dict, Optional, Union

from . import _native


class Study:
    """A study as plain Python data (``study.data``: dicts, lists, numbers, the study
    file's field names), read from and written to RON.

    >>> s = rocklab.Study.load("studies/fig12_rigid_spectra.ron")
    >>> s["name"] = "fig12_coarse"
    >>> s.save("fig12_coarse.ron")

    Saving keeps the comments, spelling and left-out defaults of the file the study was
    read from wherever the study still agrees with it, and an unedited study is written
    back byte for byte. Every study written is checked by the same parser as
    ``rocklab run``: an invalid one raises :class:`rocklab.StudyError`.
    """

    def __init__(self, data: Dict[str, Any], original: Optional[str] = None) -> None:
        #: The study's fields (serde's form of the study: enums as ``{"variant": {...}}``).
        self.data = data
        self._original = original

    @classmethod
    def load(cls, path: Union[str, "os.PathLike[str]"]) -> "Study":
        """Read a study file (``"default"``: the built-in study)."""
        data, text = _native.study_parse(os.fspath(path), False)
        return cls(json.loads(data), text)

    @classmethod
    def from_ron(cls, text: str) -> "Study":
        """Parse a study from RON text."""
        data, text = _native.study_parse(text, True)
        return cls(json.loads(data), text)

    def to_ron(self) -> str:
        """The study as RON text, validated."""
        return _native.study_ron(json.dumps(self.data), self._original)

    def save(self, path: Union[str, "os.PathLike[str]"]) -> Path:
        """Write the study as RON to ``path``."""
        path = Path(path)
        path.write_text(self.to_ron(), encoding="utf-8")
        return path

    def copy(self) -> "Study":
        return Study(copy.deepcopy(self.data), self._original)

    @property
    def name(self) -> str:
        return self.data["name"]

    def __getitem__(self, field: str) -> Any:
        return self.data[field]

    def __setitem__(self, field: str, value: Any) -> None:
        self.data[field] = value

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Study) and self.data == other.data

    def __repr__(self) -> str:
        return f"rocklab.Study(name={self.name!r})"
