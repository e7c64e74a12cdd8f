"""Shared fixtures of the Python tests: the module (from PYTHONPATH=build/python, which ctest sets), the
`candela` binary (CANDELA_BINARY) and small scenes."""
import os

import pytest

import candela


@pytest.fixture(scope="session")
def binary():
    path = os.environ.get("CANDELA_BINARY", "")
    if not path:
        pytest.fail("CANDELA_BINARY is not set (ctest sets it)")
    return path


@pytest.fixture(scope="session")
def cornell():
    return candela.load_scene("builtin:cornell")


@pytest.fixture(scope="session")
def manylights():
    return candela.load_scene("builtin:manylights", lights=64)
