"""Shared fixtures: the ramtk command (the C++ result to compare with), the data sets and a scratch
folder. ctest sets RAMTK_BINARY, RAMTK_DATASETS_DIR, RAMTK_TEST_TMP and PYTHONPATH."""
import json
import os
import pathlib
import subprocess

import pytest


@pytest.fixture(scope="session")
def ramtk_binary():
    return os.environ["RAMTK_BINARY"]


@pytest.fixture(scope="session")
def datasets():
    return pathlib.Path(os.environ["RAMTK_DATASETS_DIR"])


@pytest.fixture(scope="session")
def scratch():
    p = pathlib.Path(os.environ.get("RAMTK_TEST_TMP", "/tmp/ramtk_pytest"))
    p.mkdir(parents=True, exist_ok=True)
    return p


@pytest.fixture(scope="session")
def cli(ramtk_binary):
    """Runs `ramtk ARGS...`, returns stdout; fails the test on a non-zero exit."""

    def run(*args):
        r = subprocess.run([ramtk_binary, *map(str, args)], capture_output=True, text=True)
        assert r.returncode == 0, f"ramtk {' '.join(map(str, args))}: {r.stderr}"
        return r.stdout

    return run


def read_json(path):
    with open(path) as f:
        return json.load(f)
