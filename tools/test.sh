#!/usr/bin/env bash
# The project's tests, Rust and Python together (README's test command;
# .ci/run calls it): the workspace's cargo tests, then the Python package
# built into a virtual environment under target/ (made on first use, with
# maturin, numpy, pytest, mypy, matplotlib and Dask distributed from PyPI)
# and its pytest suite, which also runs mypy.stubtest on the stubs and every
# code block of docs/python.md.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --workspace --release
venv=target/python-venv
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
# maturin, as the build backend without isolation, runs from the venv
export PATH="$PWD/$venv/bin:$PATH"
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet "maturin>=1.9.4,<2" "numpy>=1.21" pytest mypy matplotlib distributed
"$venv/bin/python" -m pip install --quiet --no-build-isolation .
"$venv/bin/python" -m pytest -q tests/python
