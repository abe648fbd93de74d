"""Shared fixtures of the softpbr pytest suite (run by ctest as python_pytest, with
PYTHONPATH=build/python and the interpreter the module was built for)."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

SOURCE_DIR = Path(os.environ.get("SOFTPBR_SOURCE_DIR", Path(__file__).resolve().parents[2]))
SCENES = SOURCE_DIR / "examples" / "scenes"


@pytest.fixture
def source_dir() -> Path:
    return SOURCE_DIR


@pytest.fixture
def scenes() -> Path:
    return SCENES


@pytest.fixture
def cli() -> str:
    """The softpbr command of this build (SOFTPBR_CLI, set by ctest); skips without it."""
    path = os.environ.get("SOFTPBR_CLI") or shutil.which("softpbr")
    if not path:
        pytest.skip("the softpbr command is not built (SOFTPBR_CLI unset)")
    return path
