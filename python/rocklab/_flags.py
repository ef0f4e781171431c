"""Keyword arguments to the CLI's flags: ``amplitude_g=0.3`` is ``--amplitude-g 0.3``."""

from typing import Any, Dict, List


def to_argv(flags: Dict[str, Any]) -> List[str]:
    """The command-line arguments for ``flags``: names with dashes, ``True`` a bare switch,
    ``False``/``None`` left out, a list joined by commas."""
    argv: List[str] = []
    for name, value in flags.items():
        flag = "--" + name.replace("_", "-")
        if value is None or value is False:
            continue
        if value is True:
            argv.append(flag)
        elif isinstance(value, (list, tuple)):
            argv += [flag, ",".join(str(v) for v in value)]
        else:
            argv += [flag, _text(value)]
    return argv


def _text(value: Any) -> str:
    # repr keeps every digit of a float (str would too on Python 3, but be explicit).
    if isinstance(value, float):
        return repr(value)
    return str(value)
