# SPDX-License-Identifier: MIT
"""Label swaps in sfit.joint_center (repair_swaps, result.label_swaps): the
same check as `sfit joint` (tools/lab/swaps.c), against references
made here: biobuddy's hip trial with the labels put back by this test,
synthetic swaps with known frames, a near-symmetric cluster."""
import json
import os
import subprocess

import numpy as np
import pytest

import sfit

pytestmark = pytest.mark.skipif(not hasattr(sfit, "Joint"),
                                reason="the C library has no sfit_joint.h yet")

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.environ.get("SFIT_SOURCE_DIR", os.path.normpath(os.path.join(HERE, "..", "..", "..")))
HIP = os.path.join(SOURCE_DIR, "tests", "data", "c3d", "biobuddy_right_hip.c3d")
PELVIS = ["RASIS", "LASIS", "LPSIS", "RPSIS"]
THIGH = ["RTHI1", "RTHI2", "RTHI3", "RLFE", "RMFE"]


def read_markers(path, names):
    """(F, M, 3) trajectories through the independent C3D reader of the CLI tests."""
    import sys
    sys.path.insert(0, os.path.join(SOURCE_DIR, "tests", "scripts"))
    import mocap_ref
    c = mocap_ref.read_c3d(path)
    idx = [c["labels"].index(n) for n in names]
    return np.array([[c["frames"][f][i] for i in idx] for f in range(len(c["frames"]))], float)


def rot(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def simulate(rng, ctpl, frames=500, sigma=0.3):
    ptpl = np.array([[100.0, 0, 0], [-80, 60, 0], [0, -90, 40], [20, 30, 110]])
    P = np.empty((frames, 4, 3))
    C = np.empty((frames, len(ctpl), 3))
    for f in range(frames):
        r = rot(rng.normal(size=3), rng.uniform(0, 0.3))
        t = np.array([500.0, 700, 900]) + rng.normal(0, 30, 3)
        q = rot(rng.normal(size=3), rng.uniform(0, 0.8))
        P[f] = ptpl @ r.T + t
        C[f] = (np.array([40.0, -60, 30]) + ctpl @ q.T) @ r.T + t
    return P + rng.normal(0, sigma, P.shape), C + rng.normal(0, sigma, C.shape)


@pytest.mark.skipif(not os.path.isfile(HIP), reason="tests/data not found")
def test_biobuddy_hip_swap_repaired():
    P, C = read_markers(HIP, PELVIS), read_markers(HIP, THIGH)
    res = sfit.joint_center(P, C)
    ls = res.label_swaps
    assert ls["repair"] is True and ls["parent"]["swaps"] == []
    sw = ls["child"]["swaps"]
    assert len(sw) == 1 and sw[0]["labels"] == [3, 4] and sw[0]["true"] == [4, 3]
    # the test's own put-back: the points labelled RLFE / RMFE whose
    # distances to RTHI1-3 match the other knee marker's at the start
    d = np.linalg.norm(C[:, :3, None, :] - C[:, None, 3:, :], axis=3)  # (F, 3 thigh, 2 knee)
    a = np.median(d[:50], axis=0)
    given = ((d - a) ** 2).sum(axis=(1, 2))
    exch = ((d - a[:, ::-1]) ** 2).sum(axis=(1, 2))
    swapped = np.nonzero(exch < given)[0]
    assert np.array_equal(sw[0]["frames"], swapped) and sw[0]["count"] == len(swapped)
    fixed = C.copy()
    fixed[swapped, 3], fixed[swapped, 4] = C[swapped, 4], C[swapped, 3]
    ref = sfit.joint_center(P, fixed, repair_swaps=False)
    assert np.linalg.norm(res.center - ref.center) <= 0.1
    raw = sfit.joint_center(P, C, repair_swaps=False)
    assert np.linalg.norm(raw.center - ref.center) >= 10.0  # 15 mm
    assert raw.label_swaps["repair"] is False and raw.label_swaps["child"]["swapped_frames"] == 958


@pytest.mark.skipif(not os.path.isfile(HIP) or not os.environ.get("SFIT_CLI"),
                    reason="the sfit CLI (SFIT_CLI) is needed")
@pytest.mark.parametrize("method", ["mgdk", "default", None])
def test_biobuddy_same_as_cli(method):
    """Every front end says the same thing (issue 28, must-show 4): the
    centre, center_cov, the marker noise figure and its source, untrusted,
    reason and flags of `sfit joint --json` and of joint_center, per method;
    None = each one's default (the same method)."""
    args = [os.environ["SFIT_CLI"], "joint", HIP, "--parent", ",".join(PELVIS),
            "--child", ",".join(THIGH), "--json"]
    if method is not None:
        args += ["--method", method]
    cli = json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
    kw = {} if method is None else {"method": method}
    res = sfit.joint_center(read_markers(HIP, PELVIS), read_markers(HIP, THIGH), **kw)
    for seg in ("parent", "child"):
        a, b = res.label_swaps[seg], cli["label_swaps"][seg]
        assert a["swapped_frames"] == b["swapped_frames"]
        assert a["frames_checked"] == b["frames_checked"]
        assert abs(a["noise"] - b["noise"]) <= 1e-5 * b["noise"]
        assert [list(r) for s in a["swaps"] for r in s["runs"]] == \
            [r for s in b["swaps"] for r in s["runs"]]
    assert np.linalg.norm(res.center - np.array(cli["center"])) <= 1e-3
    cov = np.array(cli["center_cov"])
    assert cov.shape == (3, 3) and res.center_cov is not None
    assert np.abs(res.center_cov - cov).max() <= 1e-4 * np.trace(cov)
    assert res.marker_noise_var == pytest.approx(cli["marker_noise"]["var"], rel=1e-5)
    assert res.noise_source == cli["marker_noise"]["source"] == "registration_residuals"
    assert res.untrusted == cli["untrusted"] and res.reason == cli["reason"]
    assert res.zero_missing == cli["zero_missing"] == 0
    if method != "mgdk":
        assert cli["method"] == res.method == "default"
        assert list(res.flags) == cli["flags"]
        assert res.axis_cov is None and "axis_cov" not in cli  # a ball
    else:
        assert cli["center_cov_bias"] == "not_included"


def test_synthetic_swaps_exact():
    rng = np.random.default_rng(7)
    ctpl = np.array([[60.0, -300, 50], [-40, -310, -60], [0, -250, 0], [-70, -380, 20],
                     [30, -450, -10]])
    P, C = simulate(rng, ctpl)
    clean_p, clean_c = P.copy(), C.copy()
    frames = rng.choice(np.arange(60, 500), 40, replace=False)
    want_p, want_c = {}, {}
    for f in frames[:15]:
        i, j = sorted(rng.choice(4, 2, replace=False))
        P[f, [i, j]] = P[f, [j, i]]
        want_p[int(f)] = ([int(i), int(j)], [int(j), int(i)])
    for f in frames[15:]:
        i, j = sorted(rng.choice(5, 2, replace=False))
        C[f, [i, j]] = C[f, [j, i]]
        want_c[int(f)] = ([int(i), int(j)], [int(j), int(i)])
    res = sfit.joint_center(P, C)
    for seg, want in (("parent", want_p), ("child", want_c)):
        rep = res.label_swaps[seg]
        got = {int(f): (s["labels"], s["true"]) for s in rep["swaps"] for f in s["frames"]}
        assert got == want and rep["swapped_frames"] == len(want)
        assert rep["rejected"]["count"] == 0 and rep["undecidable"] == []
        st = rep["status"]
        assert st.shape == (500,) and np.count_nonzero(st > 0) == len(want)
    ref = sfit.joint_center(clean_p, clean_c, repair_swaps=False)
    assert np.linalg.norm(res.center - ref.center) <= 1e-4
    assert np.allclose(res.center_global, ref.center_global, atol=1e-3)
    # reported only: the data as given
    raw = sfit.joint_center(P, C, repair_swaps=False)
    assert raw.label_swaps["child"]["swapped_frames"] == len(want_c)
    assert np.linalg.norm(raw.center - ref.center) > 1e-2


def test_near_symmetric_undecidable():
    rng = np.random.default_rng(28)
    # markers 0 and 1 mirror images across the plane z = 0 of markers 2-4
    ctpl = np.array([[60.0, -300, 50], [60.2, -300, -50], [0, -250, 0], [-70, -380, 0],
                     [30, -450, 0]])
    P, C = simulate(rng, ctpl, frames=300)
    C[100:160, [0, 1]] = C[100:160, [1, 0]]
    res = sfit.joint_center(P, C)
    rep = res.label_swaps["child"]
    assert rep["swaps"] == [] and rep["rejected"]["count"] == 0
    pairs = [(u["labels"], u["true"]) for u in rep["undecidable"]]
    assert ([0, 1], [1, 0]) in pairs
    raw = sfit.joint_center(P, C, repair_swaps=False)
    assert np.array_equal(res.center, raw.center)  # not repaired at random


def test_not_checked_and_garbage():
    rng = np.random.default_rng(3)
    P, C = simulate(rng, np.array([[60.0, -300, 50], [-40, -310, -60]]), frames=50)
    res = sfit.joint_center(P, C)
    assert res.label_swaps["child"]["checked"] is False
    assert res.label_swaps["child"]["why"] == "fewer than 3 markers"
    assert res.label_swaps["parent"]["checked"] is True
    # a single frame is not (F, M, 3): no report, the joint's own error
    with pytest.raises(sfit.ArgError):
        sfit.joint_center(P, C[0])
    # the streaming Joint has no swap check (documented)
    j = sfit.Joint(sfit.Cluster.from_frames(P), 2)
    j.add(P, C)
    assert j.solve().label_swaps is None


def test_swaps_in_the_anchor_and_into_a_gap():
    """Swaps among the first 50 frames (the anchor's median outvotes them),
    and a point given the label of a missing marker."""
    rng = np.random.default_rng(5)
    ctpl = np.array([[60.0, -300, 50], [-40, -310, -60], [0, -250, 0], [-70, -380, 20],
                     [30, -450, -10]])
    P, C = simulate(rng, ctpl)
    for f in (0, 5, 17, 40):
        C[f, [1, 2]] = C[f, [2, 1]]
    C[200, 4], C[200, 3] = C[200, 3], np.nan  # marker 3 labelled 4, label 3 missing
    C[201, 3] = np.nan                         # only missing
    rep = sfit.joint_center(P, C).label_swaps["child"]
    got = sorted((s["labels"], s["true"], list(s["frames"])) for s in rep["swaps"])
    assert got == [([1, 2], [2, 1], [0, 5, 17, 40]), ([3, 4], [4, 3], [200])]
    assert rep["rejected"]["count"] == 0 and rep["status"][201] == 0


@pytest.mark.parametrize("sigma", [0.1, 0.5, 1.0, 2.0])
def test_noise_levels(sigma):
    """The reported noise is the distance noise (sqrt(2) sigma for isotropic
    coordinate noise sigma, within 10 %), and the swaps are found exactly at
    every level where the cluster's exchanges stay decidable (this child's
    smallest relabelling, 128 mm, is 2.2 times 2 z s at sigma = 2 mm; the
    noise reads 0.98-1.02 sqrt(2) sigma)."""
    rng = np.random.default_rng(int(sigma * 10))
    ctpl = 2.0 * np.array([[60.0, -300, 50], [-40, -310, -60], [0, -250, 0], [-70, -380, 20],
                           [30, -450, -10]])
    P, C = simulate(rng, ctpl, frames=400, sigma=sigma)
    frames = rng.choice(np.arange(60, 400), 30, replace=False)
    want = {}
    for f in frames:
        i, j = sorted(rng.choice(5, 2, replace=False))
        C[f, [i, j]] = C[f, [j, i]]
        want[int(f)] = ([int(i), int(j)], [int(j), int(i)])
    rep = sfit.joint_center(P, C).label_swaps["child"]
    assert abs(rep["noise"] / (np.sqrt(2.0) * sigma) - 1.0) <= 0.1, rep["noise"]
    assert rep["decidable_above"] == pytest.approx(20.0 * rep["noise"])
    got = {int(f): (s["labels"], s["true"]) for s in rep["swaps"] for f in s["frames"]}
    assert got == want and rep["rejected"]["count"] == 0 and rep["undecidable"] == []
