"""Shared fixtures: the repository's root, the CLI binary the cargo tests
built (target/release/lens), and a helper that runs it for its JSON."""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LENS = ROOT / "target" / "release" / "lens"

SHIPPED = sorted(
    [p for p in (ROOT / "lens-data").glob("*.json")]
    + [p for p in (ROOT / "lens-data" / "library").glob("*.json")]
    + [p for p in (ROOT / "lens-data" / "pbrt").glob("*.dat")]
)


def cli(*args: str) -> subprocess.CompletedProcess:
    """Runs the CLI; its output as text."""
    if not LENS.exists():
        pytest.skip("target/release/lens not built (cargo build --release)")
    return subprocess.run([str(LENS), *args], capture_output=True, text=True, cwd=ROOT)


def cli_json(*args: str):
    """The CLI's --json output, or (None, stderr) where it failed."""
    r = cli(*args, "--json")
    if r.returncode != 0:
        return None, r.stderr
    return json.loads(r.stdout), r.stderr


@pytest.fixture(autouse=True)
def at_root(monkeypatch):
    """Every test runs at the repository's root (docs use its paths)."""
    monkeypatch.chdir(ROOT)
    os.environ.setdefault("RAYON_NUM_THREADS", "2")
