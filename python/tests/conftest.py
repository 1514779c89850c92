"""Shared fixtures: the cmbrl program and the source tree (CTest sets both)."""
import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("CMBRL_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture
def cmbrl_binary():
    binary = os.environ.get("CMBRL_BINARY", str(SOURCE_DIR / "build" / "bin" / "cmbrl"))
    if not os.path.exists(binary):
        pytest.fail(f"no cmbrl program at {binary}: set CMBRL_BINARY")
    return binary


@pytest.fixture
def source_dir():
    return SOURCE_DIR
