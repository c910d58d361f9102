# SPDX-License-Identifier: MIT
"""sfit.session_model / calibrate / apply_session (a lab session,
docs/session.md): the same C code as `sfit calibrate` / `sfit apply`, on
files and on arrays; against the CLI, and on a synthetic ball joint whose
centre is known."""
import glob
import json
import os
import subprocess

import numpy as np
import pytest

import sfit
from conftest import DATA_DIR, SOURCE_DIR
from test_hostile import _SESSION_MODEL, _session_data

SES = os.path.join(DATA_DIR, "c3d", "lower_limb_session")
MODEL = os.path.join(SOURCE_DIR, "docs", "lower_limb_session.txt")
FILES = sorted(glob.glob(os.path.join(SES, "*.c3d")))


def test_model_of_the_shared_session():
    m = sfit.session_model(MODEL)
    assert m["root"] == "pelvis"
    assert [j["name"] for j in m["joints"]] == ["r_hip", "r_knee", "r_ankle", "trunk"]
    assert m["joints"][2]["points"] == ["RAJC", "RAJC_AX1", "RAJC_AX2"]
    with pytest.raises(ValueError, match="line 2: joint 'j': segment 'b' is not declared"):
        sfit.session_model("segment a A,B,C\njoint j a b ball P\n")


def test_synthetic_ball_joint():
    data = _session_data()
    s = sfit.calibrate(_SESSION_MODEL, {"trial1": data})
    j = s["joints"][0]
    pel = np.array([data[n][0] for n in ("P1", "P2", "P3", "P4")])
    want = np.array([0.0, 0.0, -100.0]) - pel.mean(axis=0)  # template frame: lab axes, centroid origin
    assert np.allclose(j["center"], want, atol=1e-3), (j["center"], want)
    assert j["type"] == "ball" and j["verdict"].startswith("hip (ball)")
    # placed back: the centre in every frame; a frame with 2 pelvis markers is invalid
    trial = {k: v.copy() for k, v in data.items()}
    trial["P1"][5] = np.nan
    trial["P2"][5] = np.nan
    r = sfit.apply_session(s, trial)
    assert r["invalid"] == {"hip": 1}
    ok = np.arange(len(r["HJC"])) != 5
    assert np.isnan(r["HJC"][5]).all()
    assert np.allclose(r["HJC"][ok], [0.0, 0.0, -100.0], atol=1e-3)


def test_files_and_arrays_equal_the_cli(tmp_path):
    cli = os.environ.get("SFIT_CLI")
    if not cli:
        if os.environ.get("CI") == "true":
            pytest.fail("SFIT_CLI not set")
        pytest.skip("SFIT_CLI not set")
    out = tmp_path / "cli.json"
    subprocess.run([cli, "calibrate", MODEL] + FILES + ["-o", str(out)], check=True,
                   capture_output=True)
    want = json.load(open(out))
    got = sfit.calibrate(MODEL, FILES)
    assert json.dumps(got, sort_keys=True) == json.dumps(want, sort_keys=True)
    # on arrays: the same markers from read_c3d give the same session
    arrays = {}
    for p in FILES:
        c = sfit.read_c3d(p)
        d = {lab: c.points[:, i] for i, lab in enumerate(c.labels)}
        d["units"] = c.units
        arrays[os.path.basename(p)] = d
    arr = sfit.calibrate(MODEL, arrays)
    for a, b in zip(arr["joints"], want["joints"]):
        for k in ("center", "template", "center_cov", "semi_axes_95", "verdict", "flag_bits"):
            assert a[k] == b[k], (a["name"], k)
    # apply: the C3D written by Python is the CLI's byte for byte
    anat = os.path.join(SES, "anatomical_posture.c3d")
    subprocess.run([cli, "apply", str(out), anat, "-o", str(tmp_path / "cli.c3d")], check=True,
                   capture_output=True)
    r = sfit.apply_session(str(out), anat, out=str(tmp_path / "py.c3d"))
    assert (tmp_path / "py.c3d").read_bytes() == (tmp_path / "cli.c3d").read_bytes()
    assert r["invalid"] == {"r_hip": 0, "r_knee": 0, "r_ankle": 0, "trunk": 0}
    c = sfit.read_c3d(str(tmp_path / "py.c3d"))
    assert np.array_equal(c.points[:, c.labels.index("RKJC_AX2")], r["RKJC_AX2"].astype(np.float32))
