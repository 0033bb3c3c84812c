"""Shared fixtures of the Python tests (run by CTest: python_module, dask_batch).

PYTHONPATH points at build/python (the module as built); WARPMESH_EXE at the
CLI, which some tests compare the module with."""
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def root():
    return ROOT


@pytest.fixture
def cli():
    exe = os.environ.get("WARPMESH_EXE")
    if not exe or not os.path.exists(exe):
        pytest.skip("WARPMESH_EXE not set (run through ctest)")
    return exe
