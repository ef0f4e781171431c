"""Shared fixtures: the CLI binary to compare against, and small studies."""

import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

#: A small fragility study: 2 far-field records (both components), 3 stripes, 2 variants.
FRAGILITY_STUDY = """(
    version: 1,
    name: "py_fragility",
    structure: rigid(p: 2.0, alpha: 0.2),
    devices: [none, sequential(sigma: 0.5)],
    excitation: record(
        suite: (name: "far_field", records: [1, 2]),
        scale: [1.5, 3.0, 6.0],
        scale_to: pga_star,
        tail: 2.0,
    ),
    quantities: [peak_rotation_ratio],
    spectrum: scale,
    fragility: (damage_states: levels([0.2, 1.0])),
)
"""


@pytest.fixture(scope="session")
def cli():
    """Run the `rocklab` binary built by `cargo build --release` (or $ROCKLAB_BIN)."""
    binary = Path(os.environ.get("ROCKLAB_BIN", REPO / "target" / "release" / "rocklab"))
    if not binary.is_file():
        pytest.fail(f"{binary}: no rocklab binary (run `cargo build --release` first, or set "
                    "ROCKLAB_BIN)")

    def run(*args, cwd=None):
        done = subprocess.run([str(binary), *map(str, args)], capture_output=True,
                              text=True, cwd=cwd)
        if done.returncode != 0:
            raise AssertionError(f"rocklab {' '.join(map(str, args))}: {done.stderr}")
        return done.stdout

    return run


@pytest.fixture(scope="session")
def cli_error():
    """The message (stderr, stripped) of a `rocklab` command that must fail."""
    binary = Path(os.environ.get("ROCKLAB_BIN", REPO / "target" / "release" / "rocklab"))

    def run(*args):
        done = subprocess.run([str(binary), *map(str, args)], capture_output=True, text=True)
        assert done.returncode != 0, f"rocklab {' '.join(map(str, args))} succeeded"
        return done.stderr.strip()

    return run
