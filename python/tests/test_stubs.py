"""The type stubs of the native module match it (mypy's stubtest)."""

from __future__ import annotations

import subprocess
import sys

import pytest


def test_the_stubs_match_the_native_module():
    pytest.importorskip("mypy")
    done = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "chaindrive._chaindrive"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stdout + done.stderr
