# SPDX-License-Identifier: MIT
"""sfit.read_c3d / write_c3d / write_trc (the CLI's C3D reader and writer in
the extension) against the independent reader of the tests
(tests/scripts/c3d_ref.py, numpy + struct), and against the CLI."""
import os
import subprocess
import sys

import numpy as np
import pytest

import sfit
from conftest import DATA_DIR, SOURCE_DIR

sys.path.insert(0, os.path.join(SOURCE_DIR, "tests", "scripts"))
import c3d_ref  # noqa: E402

ORG = os.path.join(DATA_DIR, "c3d", "c3d_org")
CASES = os.path.join(DATA_DIR, "c3d", "cases")
HIP = os.path.join(DATA_DIR, "c3d", "biobuddy_right_hip.c3d")
SHARED = os.environ.get("SFIT_SHARED_DATA", os.path.join(SOURCE_DIR, "..", "shared", "data"))
VARIANTS = ["s02_%s_%s" % (p, s) for p in ("pc", "dec", "sgi") for s in ("int", "real")]


def _ref_points(r):
    return np.where(r["residual"][:, :, None] < 0, np.nan, r["xyz"])


@pytest.mark.parametrize("name", VARIANTS + ["hip"])
def test_read_equals_the_independent_reader(name):
    path = HIP if name == "hip" else os.path.join(ORG, name + ".c3d")
    got, ref = sfit.read_c3d(path), c3d_ref.read(path)
    assert got.labels == ref["labels"]
    assert got.rate == ref["rate"] and got.units == ref["units"]
    assert got.points.dtype == np.float64 and got.points.shape == (ref["nframes"], ref["npoints"], 3)
    assert np.array_equal(got.points, _ref_points(ref), equal_nan=True)
    assert got.processor == {84: "Intel", 85: "DEC", 86: "MIPS"}[ref["proc"]]
    assert got.storage == ("float" if ref["word"] == 4 else "integer")
    assert (len(got.warnings) == 1) == name.startswith("s02_sgi"), got.warnings


def test_six_variants_agree():
    pts = [sfit.read_c3d(os.path.join(ORG, v + ".c3d")).points for v in VARIANTS]
    for p in pts[1:]:
        # the integer files differ from the float ones by at most one scale unit
        assert np.allclose(p, pts[0], rtol=0, atol=0.282, equal_nan=True)


def test_warnings_and_sources():
    r = sfit.read_c3d(os.path.join(CASES, "frames_header_1149.c3d"))
    assert r.points.shape[0] == 5 and r.sources["frames"] == "POINT:FRAMES (file size)"
    assert r.warnings == ["frame count: the header says 1149, POINT:FRAMES 5; the file holds 6: "
                          "read 5 (POINT:FRAMES)"]
    r = sfit.read_c3d(os.path.join(CASES, "dup_labels.c3d"))
    assert r.labels[:3] == ["RFT1", "RFT1#2", "RFT1#3"]
    r = sfit.read_c3d(os.path.join(CASES, "zero_marker.c3d"))
    assert r.zero_samples == 2 and np.all(r.points[[1, 3], 2] == 0.0)
    with pytest.raises(ValueError, match="analog layout conflict"):
        sfit.read_c3d(os.path.join(CASES, "analog_ambiguous.c3d"))
    r = sfit.read_c3d(os.path.join(CASES, "analog_conflict.c3d"))  # the data size decides
    assert r.warnings[0].startswith("analog layout: the header says 16") and r.points.shape == (5, 36, 3)
    with pytest.raises(OSError):
        sfit.read_c3d(os.path.join(CASES, "no_such_file.c3d"))


def _added(n):
    a = np.column_stack([100.0 + 0.5 * np.arange(n), np.full(n, -20.25), np.arange(n, dtype=float)])
    b = a[::-1].copy()
    b[::4] = np.nan
    return {"NEWA": a, "NEWB": b}


@pytest.mark.parametrize("name", VARIANTS + ["sub_labels", "opensim_task_labels2"])
def test_write_round_trip(name, tmp_path):
    if name.startswith("s02"):
        src = os.path.join(ORG, name + ".c3d")
    else:
        src = os.path.join(SHARED, "c3d", "c3d_org", name + ".c3d")
        if not os.path.isfile(src):
            pytest.skip("shared data not found at %s" % SHARED)
    n = sfit.read_c3d(src).points.shape[0]
    pts = _added(n)
    prefix = "Matt:" if name == "sub_labels" else None
    dst = tmp_path / "out.c3d"
    assert sfit.write_c3d(src, dst, pts, prefix=prefix) is False
    xyz = np.stack([pts["NEWA"], pts["NEWB"]], axis=1)
    worst = c3d_ref.check_added(c3d_ref.read(src), c3d_ref.read(str(dst)), ["NEWA", "NEWB"], xyz,
                                prefix or "")
    back = sfit.read_c3d(dst)
    assert back.labels[-2:] == [(prefix or "") + "NEWA", (prefix or "") + "NEWB"]
    assert np.allclose(back.points[:, -2:], xyz, rtol=0, atol=max(worst, 0.0) + 1e-4, equal_nan=True)


def test_integer_storage_that_cannot_hold_a_point_becomes_float(tmp_path):
    src = os.path.join(ORG, "s02_pc_int.c3d")
    pts = _added(89)
    pts["NEWA"][10, 0] = 5.0e4  # > 32767 * 0.28
    dst = tmp_path / "f.c3d"
    assert sfit.write_c3d(src, dst, pts) is True
    r = c3d_ref.read(str(dst))
    assert r["word"] == 4 and r["scale"] < 0
    c3d_ref.check_added(c3d_ref.read(src), r, ["NEWA", "NEWB"], np.stack([pts["NEWA"], pts["NEWB"]], 1))


def test_trc(tmp_path):
    src = os.path.join(ORG, "s02_dec_real.c3d")
    pts = _added(89)
    sfit.write_trc(src, tmp_path / "x.trc", pts)
    t = c3d_ref.read_trc(str(tmp_path / "x.trc"))
    r = sfit.read_c3d(src)
    assert t["names"] == r.labels + ["NEWA", "NEWB"]
    assert float(t["meta"]["DataRate"]) == 50 and t["meta"]["Units"] == "mm"
    assert int(t["meta"]["NumFrames"]) == 89 and int(t["meta"]["NumMarkers"]) == 38
    want = np.concatenate([r.points, np.stack([pts["NEWA"], pts["NEWB"]], 1)], axis=1)
    assert np.allclose(t["xyz"], want, rtol=1e-7, atol=0, equal_nan=True)


def test_same_file_as_the_cli(tmp_path, sfit_cli=os.environ.get("SFIT_CLI")):
    if not sfit_cli:
        if os.environ.get("CI") == "true":
            pytest.fail("SFIT_CLI not set")
        pytest.skip("SFIT_CLI not set")
    src = os.path.join(ORG, "s02_sgi_int.c3d")
    pts = _added(89)
    sfit.write_c3d(src, tmp_path / "py.c3d", pts)
    with open(tmp_path / "add.csv", "w") as f:
        f.write("frame,NEWA_X,NEWA_Y,NEWA_Z,NEWB_X,NEWB_Y,NEWB_Z\n")
        for i in range(89):
            cells = ["" if np.isnan(v) else repr(float(v)) for v in np.concatenate([pts["NEWA"][i], pts["NEWB"][i]])]
            f.write("%d,%s\n" % (i, ",".join(cells)))
    subprocess.run([sfit_cli, "c3d", src, "--add", str(tmp_path / "add.csv"), "--write",
                    str(tmp_path / "cli.c3d")], check=True, capture_output=True)
    assert (tmp_path / "py.c3d").read_bytes() == (tmp_path / "cli.c3d").read_bytes()
