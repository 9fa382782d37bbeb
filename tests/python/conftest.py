# pytest setup for the asimov module tests: the repository root, and the module from the build
# tree (CTest sets PYTHONPATH=BUILD/python; README.md says how to run them by hand).
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def root():
    return ROOT


def built(variable, what):
    """A path CTest passes in the environment; the test is skipped without it."""
    path = os.environ.get(variable)
    if not path:
        pytest.skip(f"{variable} not set (CTest sets it to {what})")
    return path


@pytest.fixture
def engine_batch():
    return built("ASIMOV_ENGINE_BATCH", "tests/python/engine_batch.cpp, the C++ peer")


@pytest.fixture
def cli():
    return built("ASIMOV_BINARY", "the asimov executable")
