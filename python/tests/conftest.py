"""Shared fixtures: the repository's paths and one run of the paper's drive
that several tests read (it takes several seconds)."""

from __future__ import annotations

import pathlib
import warnings

import pytest

import chaindrive as cd

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    return ROOT


@pytest.fixture(scope="session")
def data() -> pathlib.Path:
    return DATA


@pytest.fixture(scope="session")
def paper_run() -> cd.RunResult:
    """The paper's drive for 4 s (1 s ramp to 120 rpm), sampled at 1 kHz."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cd.RunWarning)
        return cd.run(cd.Scene.l60mc(), duration=4.0)
