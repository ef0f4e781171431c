"""A quoFEM/Dakota driver: ``python -m rocklab.quofem params.in [results.out]``.

Dakota (and quoFEM, which drives it) writes the sampled variables to a parameters file and
reads the responses back from a results file with one line of numbers. Here each variable
is a ``rocklab simulate`` flag (``alpha``, ``sigma``, ``amplitude_g``, …), each response a
quantity of ``simulate --json`` (``peak_rotation_ratio``, ``energy_residual``, …), so
Dakota's sampling and sensitivity analyses can drive rocklab:

    python -m rocklab.quofem params.in results.out --set device=mechanistic \\
        --set pulse=sine --set frequency=8 --qoi peak_rotation_ratio

Dakota's standard format (``N variables`` / ``value name`` lines, then ``M functions`` /
``ASV_i:name``) and its APREPRO format (``{ name = value }``) are both read. Responses
are the function names the file lists, unless ``--qoi`` gives them. A response the run
did not produce (null) is written as ``nan``.
"""

import argparse
import re
import sys
from pathlib import Path
from typing import Dict, List, Tuple

from . import StudyError, simulate

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def read_params(text: str) -> Tuple[Dict[str, float], List[str]]:
    """The variables (name → value) and response names of a Dakota parameters file."""
    aprepro = re.findall(r"\{\s*(\w+)\s*=\s*(" + _NUMBER + r")\s*\}", text)
    if aprepro:
        variables = {k: float(v) for k, v in aprepro if not k.startswith("DAKOTA_")}
        functions = re.findall(r"\{\s*ASV_\d+:(\w+)\s*=", text)
        return variables, functions
    lines = [line.split() for line in text.splitlines() if line.strip()]
    if not lines or len(lines[0]) < 2 or lines[0][1] != "variables":
        raise StudyError("params file: expected Dakota's `N variables` first line or "
                         "APREPRO `{ name = value }` lines")
    n = int(lines[0][0])
    variables = {}
    for i, fields in enumerate(lines[1:1 + n], start=2):
        try:
            variables[fields[1]] = float(fields[0])
        except (IndexError, ValueError):
            raise StudyError(f"params file, line {i}: expected `value name`, found "
                             f"{' '.join(fields)!r}") from None
    functions = []
    rest = lines[1 + n:]
    if rest and len(rest[0]) >= 2 and rest[0][1] == "functions":
        for fields in rest[1:1 + int(rest[0][0])]:
            label = fields[1] if len(fields) > 1 else fields[0]
            functions.append(label.split(":", 1)[-1])
    return variables, functions


def main(argv: List[str] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m rocklab.quofem", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("params", help="Dakota parameters file (params.in)")
    parser.add_argument("results", nargs="?", default="results.out",
                        help="results file to write (default results.out)")
    parser.add_argument("--qoi", help="responses, comma-separated (default: the file's)")
    parser.add_argument("--set", action="append", default=[], metavar="FLAG=VALUE",
                        help="a fixed simulate flag, e.g. device=mechanistic (repeatable)")
    args = parser.parse_args(argv)
    try:
        variables, functions = read_params(Path(args.params).read_text())
        qois = args.qoi.split(",") if args.qoi else functions
        if not qois:
            raise StudyError(f"{args.params}: no responses listed; give --qoi")
        flags: Dict[str, object] = {}
        for item in args.set:
            name, sep, value = item.partition("=")
            if not sep:
                raise StudyError(f"--set {item!r}: expected FLAG=VALUE")
            flags[name] = True if value == "" else value
        flags.update(variables)
        out = simulate(**flags)
        unknown = [q for q in qois if q not in out]
        if unknown:
            raise StudyError(f"unknown response(s) {unknown}: expected keys of simulate's "
                             f"output, e.g. peak_rotation_ratio")
        values = ["nan" if out[q] is None else repr(float(out[q])) for q in qois]
    except StudyError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    Path(args.results).write_text(" ".join(values) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
