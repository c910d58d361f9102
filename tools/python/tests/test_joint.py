# SPDX-License-Identifier: MIT
"""Joint-centre API (sfit.Cluster, sfit.Joint, sfit.joint_center) against a
numpy double-precision pipeline: Kabsch registration by SVD, child markers
mapped into the parent frame, the multi-marker centre of ref.py."""
import numpy as np
import pytest

import ref
import sfit



def rot(axis, angle):
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def kabsch(template, meas):
    """Least-squares proper rotation and translation meas ~ R template + t,
    over the rows of meas without NaN (double precision, SVD)."""
    ok = np.all(np.isfinite(meas), axis=1)
    p, q = template[ok], meas[ok]
    pc, qc = p.mean(axis=0), q.mean(axis=0)
    h = (q - qc).T @ (p - pc)
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(u @ vt))
    r = u @ np.diag([1, 1, d]) @ vt
    return r, qc - r @ pc


def simulate(rng, frames=600, sigma=0.3, occlude=0.05, hinge=False):
    tpl = np.array([[100.0, 0, 0], [-100.0, 20, 0], [0, 90, 30], [10, -60, 80]])
    centre = np.array([-70.0, -90.0, 80.0])  # joint centre, parent frame
    offs = np.array([[0, -250.0, 40], [30, -400, -20], [-40, -150, 0]])  # child markers
    parent = np.empty((frames, 4, 3))
    child = np.empty((frames, 3, 3))
    for f in range(frames):
        r = rot(rng.normal(size=3), rng.uniform(0, 0.6))
        t = np.array([500.0, 1200.0, 900.0]) + rng.normal(0, 50, 3)
        if hinge:
            q = rot([1, 0, 0], rng.uniform(-1.0, 0.3))
        else:
            q = rot([rng.normal(), 0.0, rng.normal()], rng.uniform(0, 0.7))
        parent[f] = tpl @ r.T + t
        child[f] = (centre + offs @ q.T) @ r.T + t
    parent += rng.normal(0, sigma, parent.shape)
    child += rng.normal(0, sigma, child.shape)
    mask = rng.uniform(size=parent.shape[:2]) < occlude
    parent[mask] = np.nan
    mask = rng.uniform(size=child.shape[:2]) < occlude
    child[mask] = np.nan
    return tpl, centre, ref.as_f32(parent), ref.as_f32(child)


def reference(tpl, parent, child, **kw):
    per_marker = [[] for _ in range(child.shape[1])]
    poses = []
    for f in range(len(parent)):
        if np.sum(np.all(np.isfinite(parent[f]), axis=1)) < 3:
            poses.append(None)
            continue
        r, t = kabsch(tpl, parent[f].astype(np.float64))
        poses.append((r, t))
        for k in range(child.shape[1]):
            x = child[f, k].astype(np.float64)
            if np.all(np.isfinite(x)):
                per_marker[k].append(r.T @ (x - t))
    c, radii = ref.multi([np.array(m) for m in per_marker], **kw)
    return c, radii, poses


def test_cluster_register_matches_kabsch(rng):
    tpl, _, parent, _ = simulate(rng, frames=50)
    cl = sfit.Cluster(tpl)
    assert cl.count == 4 and np.allclose(cl.positions, tpl)
    for f in range(50):
        if np.sum(np.all(np.isfinite(parent[f]), axis=1)) < 3:
            with pytest.raises(sfit.TooFewError):
                cl.register(parent[f])
            continue
        p = cl.register(parent[f])
        r, t = kabsch(tpl, parent[f].astype(np.float64))
        assert np.allclose(p.rotation, r, atol=2e-5)
        assert np.allclose(p.translation, t, atol=2e-3)
        assert abs(np.linalg.det(p.rotation) - 1) < 1e-5
        assert np.allclose(p.to_segment(p.to_global(tpl)), tpl, atol=1e-3)


def test_joint_matches_double_pipeline(rng):
    tpl, centre, parent, child = simulate(rng)
    j = sfit.Joint(sfit.Cluster(tpl), 3)
    assert j.add(parent[:100], child[:100]) + j.rejected_frames == 100
    for f in range(100, 110):  # frame by frame, too
        j.add(parent[f], child[f])
    j.add(parent[110:], child[110:])
    res = j.solve()
    c, radii, poses = reference(tpl, parent, child)
    valid = sum(p is not None for p in poses)
    assert res.frames == valid and res.rejected_frames == len(parent) - valid
    assert np.linalg.norm(res.center - c) < 1e-4 * 400
    assert np.allclose(res.radii, radii, rtol=1e-4)
    assert np.linalg.norm(res.center - centre) < 3.0  # and it finds the joint
    assert res.residual_mean > 0 and res.residual_max >= res.residual_mean
    centers, axes, ok = j.center_at(res, parent)
    assert list(ok) == [p is not None for p in poses]
    for f, p in enumerate(poses):
        if p is None:
            assert np.all(np.isnan(centers[f]))
        else:
            assert np.allclose(centers[f], p[0] @ res.center + p[1], atol=0.02)


def test_joint_center_convenience_and_hinge(rng):
    tpl, centre, parent, child = simulate(rng, hinge=True, sigma=0.1)
    res = sfit.joint_center(parent, child, template=tpl)
    assert res.mode == "planar"
    assert np.allclose(np.abs(res.axis @ [1.0, 0, 0]), 1, atol=1e-3)
    # the centre lies on the hinge axis through the true centre
    off = res.center - centre
    assert np.linalg.norm(off - (off @ res.axis) * res.axis) < 1.0
    assert res.center_global.shape == (len(parent), 3) and res.valid.dtype == bool
    # template from the frames themselves: same joint, in another segment frame
    res2 = sfit.joint_center(parent, child)
    assert res2.cluster.frames_used > 1
    ok = res.valid & res2.valid
    d = np.linalg.norm(res.center_global[ok] - res2.center_global[ok], axis=1)
    assert np.median(d) < 5.0  # along-axis position is set by the data's mean plane


def test_joint_bad_input(rng):
    tpl, _, parent, child = simulate(rng, frames=20)
    cl = sfit.Cluster(tpl)
    with pytest.raises(sfit.ArgError):
        sfit.Joint(cl, 0)
    with pytest.raises(sfit.ArgError):
        sfit.Joint(cl, sfit.JOINT_MAX_CHILD + 1)
    with pytest.raises(sfit.ArgError):
        sfit.Joint("cluster", 3)
    j = sfit.Joint(cl, 3)
    with pytest.raises(sfit.ArgError):
        j.add(parent[:, :3], child)  # wrong parent marker count
    with pytest.raises(sfit.ArgError):
        j.add(parent, child[:10])  # frame counts differ
    with pytest.raises(sfit.ArgError):
        j.add(parent[..., :2], child)
    with pytest.raises(sfit.TooFewError):
        j.solve()
    with pytest.raises(sfit.DegenerateError):
        sfit.Cluster([[0, 0, 0], [1, 1, 1], [2, 2, 2]])
    with pytest.raises(sfit.ArgError):
        sfit.Cluster(np.zeros((2, 3)))
    all_nan = np.full((5, 4, 3), np.nan)
    with pytest.raises(sfit.TooFewError):
        sfit.Cluster.from_frames(all_nan)
    assert j.add(all_nan, child[:5]) == 0 and j.rejected_frames == 5 and j.frames == 0


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def test_marker_noise_model(rng):
    """noise_cov(marker_var) against the first-order expression in double,
    and marker_noise_var = noise_cov given that covariance."""
    tpl, centre, parent, child = simulate(rng, sigma=0.5, occlude=0.0)
    cl = sfit.Cluster(tpl)
    j = sfit.Joint(cl, 3)
    j.add(parent, child)
    var = 0.25
    got = j.noise_cov(var)
    _, _, poses = reference(tpl, parent, child)
    pc = tpl - tpl.mean(axis=0)
    jm = sum(p @ p * np.eye(3) - np.outer(p, p) for p in pc)
    ji = np.linalg.inv(jm)
    terms = []
    for k in range(3):
        ys = np.array([r.T @ (child[f, k].astype(np.float64) - t) for f, (r, t) in enumerate(poses)])
        ys -= tpl.mean(axis=0)
        terms.append(np.mean([skew(y) @ ji @ skew(y).T for y in ys], axis=0))
    want = var * ((1 + 1 / len(tpl)) * np.eye(3) + np.mean(terms, axis=0))
    assert np.allclose(got, want, rtol=2e-3, atol=1e-6)
    a = sfit.Joint(cl, 3, marker_noise_var=var)
    a.add(parent, child)
    b = sfit.Joint(cl, 3, noise_cov=got)
    b.add(parent, child)
    ra, rb = a.solve(), b.solve()
    assert ra.method == "ugdk"
    # marker_noise_var solves with each child marker's own model
    # (sfit_joint_marker_noise, sfit_multi_fit_noise); the averaged covariance
    # leaves an O(sigma^2) bias (docs/joint.md): here about 0.1 mm apart.
    assert np.linalg.norm(ra.center - rb.center) < 0.5
    with pytest.raises(sfit.ArgError):
        sfit.Joint(cl, 3, marker_noise_var=var, noise_var=var)
    with pytest.raises(sfit.ArgError):
        j.noise_cov(-1.0)


def test_joint_center_pair_methods(rng):
    """method="default" / "score" / "sara" (the pair of segments, pair_py.c):
    plain SCoRE equals the 6x6 least squares in double on the same float
    poses' templates; the default carries center_cov (PSD), the noise figure
    from the residuals (close to sigma^2) and the flags; bad options raise."""
    tpl, centre, parent, child = simulate(rng, frames=600, sigma=0.3, occlude=0.0)
    # SCoRE in double: Kabsch of both clusters, the 6x6 normal equations
    cl = sfit.Cluster.from_frames(parent)
    ccl = sfit.Cluster.from_frames(child)
    h = np.zeros((6, 6))
    b = np.zeros(6)
    for f in range(parent.shape[0]):
        rp, tp = kabsch(cl.positions, parent[f].astype(np.float64))
        rc, tc = kabsch(ccl.positions, child[f].astype(np.float64))
        x = np.hstack([rp, -rc])
        h += x.T @ x
        b += x.T @ (tc - tp)
    want = np.linalg.solve(h, b)[:3]
    s = sfit.joint_center(parent, child, method="score")
    assert s.method == "score" and s.mode == "sphere"
    assert np.linalg.norm(s.center - want) < 2e-3, (s.center, want)
    d = sfit.joint_center(parent, child, method="default")
    assert d.method == "default" and d.noise_source == "registration_residuals"
    assert abs(d.marker_noise_var - 0.09) < 0.01, d.marker_noise_var
    cov = d.center_cov
    assert cov.shape == (3, 3) and np.allclose(cov, cov.T) and np.linalg.eigvalsh(cov).min() > 0
    assert d.untrusted == ("untrusted" in d.flags) and isinstance(d.reason, str)
    assert d.valid.all() and d.center_global.shape == (parent.shape[0], 3)
    # the centre is the truth's parent-frame centre (template frames differ by
    # the centroid shift of Cluster.from_frames): compare in the lab frame
    r0, t0 = kabsch(tpl, parent[0].astype(np.float64))
    assert np.linalg.norm(d.center_global[0] - (r0 @ centre + t0)) < 3.0
    g = sfit.joint_center(parent, child, method="default", marker_noise_var=0.09)
    assert g.noise_source == "given" and g.marker_noise_var == pytest.approx(0.09)
    with pytest.raises(sfit.ArgError):
        sfit.joint_center(parent, child, method="nope")
    with pytest.raises(sfit.ArgError):
        sfit.joint_center(parent, child, method="default", noise_var=0.1)
    with pytest.raises(sfit.ArgError):
        sfit.joint_center(parent, child, method="default", marker_noise_var=-1.0)
    with pytest.raises(sfit.ArgError):
        sfit.joint_center(parent, child[:, :2], method="score")
    # the default with fewer than 3 child markers: the multi-marker fit, with
    # a note, as `sfit joint` does
    two = sfit.joint_center(parent, child[:, :2])
    assert two.note is not None and "mgdk" in two.note and two.radii is not None


def test_joint_center_default_is_the_cli_default():
    """joint_center's default method is the CLI's (the pair's "default"),
    and the mgdk result carries a centre covariance, the noise figure and
    its source, untrusted and reason (as `sfit joint --method mgdk`)."""
    import inspect
    assert inspect.signature(sfit.joint_center).parameters["method"].default == "default"
    rng = np.random.default_rng(11)
    tpl, centre, parent, child = simulate(rng, frames=400, sigma=0.3, occlude=0.0)
    d = sfit.joint_center(parent, child)
    assert d.method == "default" and d.center_cov is not None and d.note is None
    m = sfit.joint_center(parent, child, method="mgdk")
    assert m.center_cov.shape == (3, 3) and np.linalg.eigvalsh(m.center_cov).min() > 0
    assert m.noise_source == "registration_residuals" and m.reason in ("none", "leontief_ratio")
    assert abs(m.marker_noise_var - 0.09) < 0.015, m.marker_noise_var
    g = sfit.joint_center(parent, child, method="mgdk", marker_noise_var=0.04)
    assert g.noise_source == "given" and g.marker_noise_var == pytest.approx(0.04)
    # the covariance scales with the variance given (to within the change of
    # the fit itself: a given variance also selects the unbiased MGDK)
    g9 = sfit.joint_center(parent, child, method="mgdk", marker_noise_var=0.09)
    assert np.allclose(g.center_cov * (0.09 / 0.04), g9.center_cov, rtol=2e-2,
                       atol=2e-2 * np.trace(g9.center_cov))


def test_joint_center_zero_is_missing():
    """Samples at exactly (0, 0, 0) are missing (how some systems write it),
    counted in zero_missing: the same centre as with NaN there."""
    rng = np.random.default_rng(12)
    tpl, centre, parent, child = simulate(rng, frames=400, sigma=0.3, occlude=0.0)
    p0, c0 = parent.copy(), child.copy()
    pn, cn = parent.copy(), child.copy()
    p0[5, 1] = 0.0
    c0[[7, 9], 2] = 0.0
    pn[5, 1] = np.nan
    cn[[7, 9], 2] = np.nan
    for method in ("default", "mgdk"):
        a = sfit.joint_center(p0, c0, method=method)
        b = sfit.joint_center(pn, cn, method=method)
        assert a.zero_missing == 3 and b.zero_missing == 0
        assert np.array_equal(a.center, b.center)
        raw = sfit.joint_center(p0, c0, method=method, zero_is_missing=False)
        assert raw.zero_missing == 0 and not np.array_equal(raw.center, b.center)
