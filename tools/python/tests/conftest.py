# SPDX-License-Identifier: MIT
"""Shared fixtures of the sfit Python tests.

Environment (set by tests/scripts/test_python.sh under ctest):
  SFIT_SOURCE_DIR  the repository root (default: two levels above tools/python)
  SFIT_CLI         the built `sfit` command line (build/bin/sfit); the CLI
                   comparisons are skipped without it, and fail in CI (CI=true).
"""
import ctypes
import ctypes.util
import json
import os
import subprocess
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)  # ref.py

SOURCE_DIR = os.environ.get("SFIT_SOURCE_DIR",
                            os.path.normpath(os.path.join(HERE, "..", "..", "..")))
DATA_DIR = os.path.join(SOURCE_DIR, "tests", "data")

_libc = ctypes.CDLL(ctypes.util.find_library("c"))
_libc.strtof.restype = ctypes.c_float
_libc.strtof.argtypes = [ctypes.c_char_p, ctypes.POINTER(ctypes.c_char_p)]


def read_csv_f32(path):
    """The samples of a CSV exactly as the CLI parses them (C strtof per
    field, header line skipped), as a float32 (N, 3) array."""
    rows = []
    with open(path, "rb") as f:
        for i, line in enumerate(f):
            parts = line.strip().split(b",")
            if i == 0 and parts and parts[0] == b"x":
                continue
            rows.append([_libc.strtof(p.strip(), None) for p in parts])
    return np.array(rows, dtype=np.float32)


def data_files():
    """Every CSV of point samples in tests/data (the two-IMU trials of
    tests/data/imu are signals, not points: test_imu.py reads them)."""
    out = []
    imu = os.path.join(DATA_DIR, "imu")
    for root, _, files in os.walk(DATA_DIR):
        if os.path.commonpath([root, imu]) == imu:
            continue
        out += [os.path.join(root, f) for f in files if f.endswith(".csv")]
    return sorted(out)


@pytest.fixture(scope="session")
def cli():
    exe = os.environ.get("SFIT_CLI", os.path.join(SOURCE_DIR, "build", "bin", "sfit"))
    if not os.access(exe, os.X_OK):
        if os.environ.get("CI") == "true":
            pytest.fail("the sfit CLI is required in CI (SFIT_CLI=%s)" % exe)
        pytest.skip("no sfit CLI at %s (set SFIT_CLI)" % exe)

    def run(*args):
        p = subprocess.run([exe, "fit", "--json", *args], capture_output=True, text=True)
        return json.loads(p.stdout)

    return run


@pytest.fixture
def rng():
    return np.random.default_rng(20261124)
