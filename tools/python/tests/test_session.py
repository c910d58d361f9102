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
    # the placement's covariance: the CLI's --json "placement" exactly
    js = subprocess.run([cli, "apply", str(out), anat, "-o", str(tmp_path / "cli2.c3d"), "--json"],
                        check=True, capture_output=True, text=True).stdout
    for j in json.loads(js)["joints"]:
        got = r["placement"][j["name"]]
        assert isinstance(got["gain"], np.ndarray) and got["gain"].shape == (3, 3), got["gain"]
        assert {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in got.items()} \
            == j["placement"], j["name"]


def test_jackknife_of_the_hip():
    """center_cov_jackknife of the hip against a block jackknife computed
    here: the hip solved by sfit.joint_center (the pair module, ball) with
    each of 10 contiguous blocks of the trial's frames left out."""
    s = sfit.calibrate(MODEL, FILES)
    hip = [j for j in s["joints"] if j["name"] == "r_hip"][0]
    c = sfit.read_c3d(os.path.join(SES, "Test_func_rhip.c3d"))
    idx = lambda names: [next(i for i, lab in enumerate(c.labels) if lab.split(":")[-1] == n)
                         for n in names]
    par = c.points[:, idx(hip["parent_markers"])].astype(np.float64)
    chi = c.points[:, idx(["RTHI", "RTHIB", "RTHID", "RKNE", "RKNEM"])].astype(np.float64)
    assert hip["frames_used"] == len(par) == 525
    tpl = np.array(hip["template"])
    ctpl = sfit.Cluster.from_frames(chi)
    full = sfit.joint_center(par, chi, template=tpl, method="default", mode="sphere",
                             child_template=ctpl)
    assert np.allclose(full.center, hip["center"], atol=1e-3)
    n, K = len(par), 10
    reps = []
    for b in range(K):
        keep = np.ones(n, bool)
        keep[n * b // K:n * (b + 1) // K] = False
        r = sfit.joint_center(par[keep], chi[keep], template=tpl, method="default",
                              mode="sphere", child_template=ctpl)
        reps.append(np.asarray(r.center, dtype=np.float64))
    d = np.array(reps) - np.mean(reps, axis=0)
    want = (K - 1) / K * d.T @ d
    got = np.array(hip["center_cov_jackknife"])
    assert np.allclose(got, want, rtol=1e-3, atol=1e-4), (got, want)
    C = np.array(hip["center_cov"])
    ratio = np.trace(np.linalg.solve(C, want)) / 3
    assert abs(hip["jackknife_ratio"] - ratio) < 1e-3 * ratio
    # the thigh's skin motion with the hip angle is in the centre covariance
    # (its model part): not flagged MISFIT, named in the verdict, and the
    # covariance holds what the jackknife sees
    assert "skin motion" in hip["verdict"] and not hip["flag_bits"] & 0x1000
    assert hip["skin_rms"] > 1.0 and hip["jackknife_ratio"] < 1
    assert hip["model_scale"] == 1
    assert np.allclose(hip["center_cov_model"], C, rtol=1e-5)


def _pelvis_trials(rng, trials, frames, sys_sd, rand_sd):
    """Synthetic pelvis trials: a template of 4 markers at random poses,
    each trial's markers displaced by a fixed offset (sd sys_sd, the same in
    every frame) plus frame noise (sd rand_sd)."""
    tpl = np.array([[100.0, 80, 0], [100, -80, 0], [-60, 60, 10], [-60, -60, 10]])
    tpl -= tpl.mean(axis=0)
    for _ in range(trials):
        off = rng.normal(0, sys_sd, tpl.shape)
        xs, rs, ts = [], [], []
        for _f in range(frames):
            q = rng.normal(size=4)
            q /= np.linalg.norm(q)
            w, x, y, z = q
            R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                          [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                          [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
            t = rng.normal(0, 300, 3)
            xs.append((tpl + off + rng.normal(0, rand_sd, tpl.shape)) @ R.T + t)
            rs.append(R)
            ts.append(t)
        yield tpl, np.array(xs), np.array(rs), np.array(ts)


@pytest.mark.parametrize("sys_sd, rand_sd", [(0.0, 1.0), (1.5, 0.3)])
def test_placement_covariance(sys_sd, rand_sd):
    """Monte Carlo (seed 29, 300 trials of 40 frames): the placement's
    covariance against the error of the placed centre, with frame noise
    only and with a fixed deformation of the cluster per trial (the static
    trial: it does not average out over the frames). On average over the
    trials cov_frame and cov_mean equal the error's second moment (the
    error's squared norm in the metric of `gain`, over 3, against the mean
    variance: within 4 standard errors); with frame noise only (the variance
    from 6 x 40 degrees of freedom) the 95 % ellipsoids cover 95 % of the
    frames and of the trial means (4 standard errors of the fraction)."""
    rng = np.random.default_rng(29)
    sess = sfit.calibrate(_SESSION_MODEL, {"trial1": _session_data()})
    center = np.array([30.0, 90.0, -100.0])
    trials, frames = 300, 40
    q95 = 7.814727903251178
    in_frame = in_mean = 0
    e_frame, e_mean, v_frame, v_mean = [], [], [], []
    for tpl, xs, rs, ts in _pelvis_trials(rng, trials, frames, sys_sd, rand_sd):
        j = sess["joints"][0]
        j["template"] = tpl.tolist()
        j["center"] = center.tolist()
        r = sfit.apply_session(sess, {"P%d" % (k + 1): xs[:, k] for k in range(4)})
        pl = r["placement"]["hip"]
        assert pl["frames"] == frames
        # the error in the template frame, R^T (placed - true)
        err = np.einsum("fji,fj->fi", rs, r["HJC"] - (center @ rs.transpose(0, 2, 1) + ts))
        cf, cm, g = (np.array(pl[k]) for k in ("cov_frame", "cov_mean", "gain"))
        gi = np.linalg.inv(g)
        m = err.mean(axis=0)
        e_frame.append(np.einsum("fi,ij,fj->", err, gi, err) / (3 * frames))
        e_mean.append(m @ gi @ m / 3)
        v_frame.append(pl["marker_sigma"] ** 2)
        v_mean.append(pl["var_mean"])
        assert np.allclose(cf, v_frame[-1] * g, rtol=1e-6) and np.allclose(cm, v_mean[-1] * g, rtol=1e-6)
        in_frame += int((np.einsum("fi,ij,fj->f", err, np.linalg.inv(cf), err) < q95).sum())
        in_mean += int(m @ np.linalg.solve(cm, m) < q95)
    se = lambda d: 4 * np.std(d, ddof=1) / np.sqrt(trials)
    d = np.array(e_frame) - np.array(v_frame)
    assert abs(d.mean()) < se(d), (np.mean(e_frame), np.mean(v_frame))
    d = np.array(e_mean) - np.array(v_mean)
    if sys_sd > 0.0:  # the systematic part dominates: unbiased
        assert abs(d.mean()) < se(d), (np.mean(e_mean), np.mean(v_mean))
    else:  # var_sys clipped at 0: conservative, var_mean >= var / frames
        assert d.mean() < 0 and np.mean(v_mean) < 1.5 * np.mean(e_mean), (np.mean(e_mean), np.mean(v_mean))
    print("sys %.1f rand %.1f: error second moment / reported, per frame %.3f, trial mean %.3f; "
          "95 %% coverage per frame %.3f, trial mean %.3f" % (
              sys_sd, rand_sd, np.mean(e_frame) / np.mean(v_frame), np.mean(e_mean) / np.mean(v_mean),
              in_frame / (trials * frames), in_mean / trials))
    if sys_sd == 0.0:
        p_frame, p_mean = in_frame / (trials * frames), in_mean / trials
        # the frames of a trial share its variance estimate: 4 standard
        # errors of the fraction over the trials, not the frames
        assert abs(p_frame - 0.95) < 4 * np.sqrt(0.0475 / trials), p_frame
        assert abs(p_mean - 0.95) < 4 * np.sqrt(0.0475 / trials), p_mean
