"""examples/python/paper_drive.py runs as a user would run it and draws its figure."""

from __future__ import annotations

import subprocess
import sys

import pytest


def test_the_example_script_runs_and_draws(root, tmp_path):
    pytest.importorskip("matplotlib")
    pytest.importorskip("pandas")
    out = tmp_path / "out"
    done = subprocess.run(
        [sys.executable, str(root / "examples" / "python" / "paper_drive.py"), str(out)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    assert "segment 4: mean link force" in done.stdout
    png = (out / "paper_drive.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 20_000
