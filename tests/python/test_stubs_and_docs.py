"""The stubs match the module (mypy.stubtest), and every code block of
docs/python.md runs, in order, in one namespace."""

import re
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parents[2]


def test_stubtest():
    r = subprocess.run([sys.executable, "-m", "mypy.stubtest", "lens"], capture_output=True, text=True, cwd=ROOT / "tests")
    assert r.returncode == 0, r.stdout + r.stderr


def test_docs_python_md_runs(tmp_path, monkeypatch):
    text = (ROOT / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 6
    monkeypatch.setenv("LENS_DOCS_OUT", str(tmp_path))
    namespace: dict = {}
    for i, code in enumerate(blocks):
        exec(compile(code, f"docs/python.md block {i + 1}", "exec"), namespace)
