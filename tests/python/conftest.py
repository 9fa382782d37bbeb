# pytest setup for the asimov module tests: the repository root, and the module from the build
# tree (CTest sets PYTHONPATH=BUILD/python; README.md says how to run them by hand).
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def root():
    return ROOT


@pytest.fixture
def engine_batch():
    """The C++ peer (tests/python/engine_batch.cpp), from the build tree."""
    path = os.environ.get("ASIMOV_ENGINE_BATCH")
    if not path:
        pytest.skip("ASIMOV_ENGINE_BATCH not set (CTest sets it)")
    return path
