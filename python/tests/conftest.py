"""Fixtures of the Python suite: the repository's scenes and the `sph` command line built from
the same tree (`SPH_CLI`, else `$CARGO_TARGET_DIR/release/sph`, else `target/release/sph`)."""

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def dam_break(root) -> Path:
    return root / "scenes" / "dam_break_2d.toml"


@pytest.fixture(scope="session")
def cli(root) -> Path:
    """The `sph` binary of this tree; built with `cargo build --release` when none is given."""
    given = os.environ.get("SPH_CLI")
    if given:
        return Path(given)
    target = Path(os.environ.get("CARGO_TARGET_DIR", root / "target"))
    binary = target / "release" / "sph"
    if not binary.exists():
        subprocess.run(["cargo", "build", "--release", "--bin", "sph"], cwd=root, check=True)
    return binary


@pytest.fixture(autouse=True)
def no_reference_dir(monkeypatch):
    """Runs compare nothing with experiments (as on a bare copy)."""
    monkeypatch.delenv("SPH_REFERENCE_DIR", raising=False)
