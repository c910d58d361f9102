# SPDX-License-Identifier: MIT
"""Every function of the package against the double-precision numpy
references of ref.py, on the float32 samples the library saw. Tolerances:
float32 has 6e-8 relative precision; a fit amplifies it by the conditioning
of C (lambda_max / lambda_min), so the bounds below are a few hundred float
epsilons of the radius scaled by that ratio where it matters."""
import numpy as np
import pytest

import ref
import sfit
from conftest import DATA_DIR, data_files, read_csv_f32

EPS = float(np.finfo(np.float32).eps)


def far_cap(rng, n=2000, sigma=0.5, half_angle=0.9, r=150.0, centre=(2700.0, -300.0, 1200.0)):
    x = ref.sphere_samples(rng, n, centre, r, sigma, half_angle, axis=(0.3, -1.0, 0.5))
    return ref.as_f32(x)


def test_gdke_matches_kasa_reference(rng):
    x = far_cap(rng)
    r = sfit.fit(x)
    c, rad, lam, _, _ = ref.sphere(x.astype(np.float64))
    assert r.method == "gdke" and r.mode == "sphere" and r.n == len(x) and r.rejected == 0
    assert np.linalg.norm(r.center - c) < 2e-4 * rad
    assert abs(r.radius - rad) < 2e-4 * rad
    assert np.allclose(r.eigenvalues, lam, rtol=1e-4, atol=1e-6 * lam[2])
    assert np.allclose(np.abs(r.axis @ ref.smallest_axis(ref.moments(x.astype(np.float64))[1])), 1, atol=1e-5)
    assert r.trust_ratio == 0.0 and r.leontief_ratio == 0.0 and r.flags == []
    assert r.center_cov is None and r.radius_var is None and r.noise_var is None


@pytest.mark.parametrize("noise", [{"noise_var": 0.25}, {"noise_cov": [[0.3, 0.05, 0.0], [0.05, 0.2, 0.01], [0.0, 0.01, 0.25]]}])
def test_ugdk_matches_reference(rng, noise):
    x = far_cap(rng)
    r = sfit.fit(x, **noise)
    c, rad, _, trust, leon = ref.sphere(x.astype(np.float64), **noise)
    assert r.method == "ugdk"
    assert np.linalg.norm(r.center - c) < 5e-4 * rad
    assert abs(r.radius - rad) < 5e-4 * rad
    assert r.trust_ratio == pytest.approx(trust, rel=1e-3)
    assert r.leontief_ratio == pytest.approx(leon, rel=1e-3)
    assert r.leontief_ratio == pytest.approx(r.trust_ratio / (1 - r.trust_ratio), rel=1e-4)
    if "noise_var" in noise:
        cov, rv, crc = ref.uncert_moments(x.astype(np.float64), r.center, r.radius, noise["noise_var"])
        assert np.allclose(r.center_cov, cov, rtol=2e-3, atol=1e-6 * np.abs(cov).max())
        assert r.radius_var == pytest.approx(rv, rel=2e-3)
        assert np.allclose(r.center_radius_cov, crc, rtol=2e-3, atol=1e-6 * np.abs(crc).max())
    else:
        assert r.center_cov is None


def test_planar_matches_reference(rng):
    # a hinge: an arc of a circle in a tilted plane, a little out-of-plane noise
    t = rng.uniform(-1.2, 1.2, 800)
    e1, e2 = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.6, 0.8])
    x = (np.array([100.0, 200.0, -50.0]) + 80.0 * (np.cos(t)[:, None] * e1 + np.sin(t)[:, None] * e2)
         + rng.normal(0, 0.05, (800, 3)))
    x = ref.as_f32(x)
    r = sfit.fit(x)
    c, rad, axis = ref.circle(x.astype(np.float64))
    assert r.mode == "planar" and "near_planar" in r.flags
    assert np.linalg.norm(r.center - c) < 1e-4 * rad
    assert abs(r.radius - rad) < 1e-4 * rad
    assert np.allclose(r.axis, axis, atol=1e-5)
    assert np.allclose(np.abs(r.axis @ np.cross(e1, e2)), 1, atol=1e-3)
    # forced sphere on the same samples: flagged, and the sphere reference
    s = sfit.fit(x, mode="sphere", planar_ratio=1e-9)
    assert s.mode == "sphere" and "near_planar" not in s.flags


def test_selfcal_matches_reference(rng):
    x = far_cap(rng, sigma=1.0)
    r = sfit.fit(x, noise_var="auto")
    c, rad, s2 = ref.selfcal(x.astype(np.float64))
    assert r.method == "ugdk" and r.noise_estimated and 1 <= r.iterations <= 12
    assert r.noise_var == pytest.approx(s2, rel=2e-3)
    assert np.linalg.norm(r.center - c) < 1e-3 * rad
    assert abs(r.radius - rad) < 1e-3 * rad
    # the self-calibration's own sandwich; the radius variance is first order
    cov = ref.uncert_selfcal(x.astype(np.float64), r.center, r.radius, r.noise_var)
    assert np.allclose(r.center_cov, cov, rtol=5e-3, atol=1e-6 * np.abs(cov).max())
    _, rv, _ = ref.uncert_moments(x.astype(np.float64), r.center, r.radius, r.noise_var, estimated=True)
    assert r.radius_var == pytest.approx(rv, rel=5e-3)


def test_refine_matches_geometric_reference(rng):
    x = far_cap(rng, sigma=2.0)
    x64 = x.astype(np.float64)
    c_ref, r_ref, rms_ref = ref.geometric(x64, ref.sphere(x64)[0])
    r = sfit.fit(x, refine=True)
    assert r.method == "geometric" and r.iterations >= 1
    assert np.linalg.norm(r.center - c_ref) < 1e-4 * r_ref
    assert abs(r.radius - r_ref) < 1e-4 * r_ref
    assert r.rms == pytest.approx(rms_ref, rel=1e-3)
    cov, rv, crc, s2 = ref.uncert_geometric(x64, r.center.astype(np.float64))
    assert np.allclose(r.center_cov, cov, rtol=5e-3, atol=1e-5 * np.abs(cov).max())
    assert r.radius_var == pytest.approx(rv, rel=5e-3)
    # the standalone function, from the UGDK start
    g = sfit.refine(x, sfit.fit(x, noise_var=4.0).center)
    assert np.linalg.norm(g.center - c_ref) < 1e-4 * r_ref
    assert g.noise_var == pytest.approx(ref.residual_noise_var(x64, c_ref, r_ref), rel=5e-3)
    assert g.n == len(x) and g.rejected == 0


def test_uncertainty_functions(rng):
    x = far_cap(rng, sigma=0.5)
    x64 = x.astype(np.float64)
    f = sfit.fit(x, noise_var=0.25)
    c = f.center.astype(np.float64)
    u = sfit.uncertainty(x, f.center, f.radius, noise_var=0.25)
    cov, rv, crc = ref.uncert_points(x64, c, 0.25)
    assert np.allclose(u.center_cov, cov, rtol=2e-3, atol=1e-6 * np.abs(cov).max())
    assert u.radius_var == pytest.approx(rv, rel=2e-3)
    assert np.allclose(u.center_radius_cov, crc, rtol=2e-3, atol=1e-6 * np.abs(crc).max())
    assert u.noise_var == pytest.approx(0.25)
    g = sfit.uncertainty(x, f.center)  # sandwich at this centre
    cov, rv, crc, s2 = ref.uncert_geometric(x64, c)
    assert np.allclose(g.center_cov, cov, rtol=5e-3, atol=1e-5 * np.abs(cov).max())
    assert g.noise_var == pytest.approx(s2, rel=2e-3)
    m = sfit.Moments(x)
    for est in (False, True):
        mu = m.uncertainty(f.center, f.radius, 0.25, estimated=est)
        cov, rv, crc = ref.uncert_moments(x64, c, f.radius, 0.25, estimated=est)
        assert np.allclose(mu.center_cov, cov, rtol=2e-3, atol=1e-6 * np.abs(cov).max())
        assert mu.radius_var == pytest.approx(rv, rel=2e-3)


def test_residual_noise_var(rng):
    x = far_cap(rng, sigma=1.5)
    c, r, _ = ref.geometric(x.astype(np.float64), ref.sphere(x.astype(np.float64))[0])
    got = sfit.residual_noise_var(x, c, r)
    assert got == pytest.approx(ref.residual_noise_var(x.astype(np.float64), c, r), rel=2e-3)
    assert got == pytest.approx(1.5 ** 2, rel=0.15)  # and it estimates the noise


@pytest.mark.parametrize("weight", ["equal", "samples"])
def test_fit_multi_matches_reference(rng, weight):
    centre = np.array([-60.0, -90.0, 80.0])
    markers = [ref.as_f32(ref.sphere_samples(rng, n, centre, r, 0.3, 0.7, axis=(0, -1, 0.2)))
               for n, r in ((500, 250.0), (800, 400.0), (650, 120.0))]
    res = sfit.fit_multi(markers, weight=weight)
    c, radii = ref.multi([m.astype(np.float64) for m in markers], weight=weight)
    assert res.markers == 3 and res.skipped == 0 and res.n == 1950
    assert np.linalg.norm(res.center - c) < 2e-4 * 400
    assert np.allclose(res.radii, radii, rtol=2e-4)
    assert list(res.marker_n) == [500, 800, 650]
    u = sfit.fit_multi(markers, noise_var=0.09, weight=weight)
    c, radii = ref.multi([m.astype(np.float64) for m in markers], noise_var=0.09, weight=weight)
    assert u.method == "ugdk"
    assert np.linalg.norm(u.center - c) < 2e-4 * 400
    assert np.allclose(u.radii, radii, rtol=2e-4)
    # one marker: the single-marker fit
    one = sfit.fit_multi(markers[:1])
    assert np.allclose(one.center, sfit.fit(markers[0]).center, atol=1e-4 * 250)


def test_fit_multi_occluded_markers(rng):
    centre = np.array([0.0, 0.0, 0.0])
    a = ref.as_f32(ref.sphere_samples(rng, 300, centre, 100.0, 0.1, 0.8))
    b = ref.as_f32(ref.sphere_samples(rng, 300, centre, 60.0, 0.1, 0.8))
    b[:297] = np.nan  # occluded: 3 valid rows left, too few
    res = sfit.fit_multi(np.stack([a, b]))  # one (M, N, 3) array
    assert res.markers == 1 and res.skipped == 1 and "skipped_markers" in res.flags
    assert res.radii[1] == 0.0 and res.marker_n[1] == 3 and res.marker_rejected[1] == 297
    assert res.rejected == 297
    assert np.allclose(res.center, ref.sphere(a.astype(np.float64))[0], atol=1e-3)


def test_moments_stats(rng):
    x = far_cap(rng)
    mean, c, s = sfit.Moments(x).stats()
    m_ref, c_ref, s_ref = ref.moments(x.astype(np.float64))
    assert np.allclose(mean, m_ref, rtol=1e-6, atol=1e-4)
    assert np.allclose(c, c_ref, rtol=1e-4, atol=1e-5 * np.abs(c_ref).max())
    assert np.allclose(s, s_ref, rtol=1e-3, atol=1e-4 * np.abs(s_ref).max())


def test_incremental_equals_batch(rng):
    x = far_cap(rng, n=3000)
    inc = sfit.Incremental()
    est = inc.start(x[:10])
    assert est.n == 10
    for row in x[10:50]:
        est = inc.update(row)
    assert est.n == 50 and inc.count == 50
    inc.add(x[50:])
    est = inc.estimate()
    c, rad = ref.sphere(x.astype(np.float64))[:2]
    assert est.n == 3000
    assert np.linalg.norm(est.center - c) < 2e-4 * rad
    assert abs(est.radius - rad) < 2e-4 * rad
    # UGDK and track
    inc = sfit.Incremental(noise_var=0.25)
    tr = inc.track(x)
    assert tr.n[0] == sfit.MIN_SAMPLES and tr.n[-1] == 3000 and len(tr.n) == 3000 - 3
    c, rad = ref.sphere(x.astype(np.float64), noise_var=0.25)[:2]
    assert np.linalg.norm(tr.centers[-1] - c) < 5e-4 * rad
    c500 = ref.sphere(x[:500].astype(np.float64), noise_var=0.25)[0]
    assert np.linalg.norm(tr.centers[496] - c500) < 5e-4 * rad
    inc.reset()
    assert inc.count == 0
    with pytest.raises(sfit.TooFewError):
        inc.estimate()


def test_noise_calibration(rng):
    c0, r0 = np.array([500.0, -200.0, 50.0]), 10.0
    x = ref.as_f32(ref.sphere_samples(rng, 5000, c0, r0, 0.7))
    e = sfit.calibrate_noise(x, c0, r0)
    t, s2, sd = ref.noise_calibrate(x.astype(np.float64), c0, r0)
    assert e.n == 5000 and e.rejected == 0
    assert e.noise_trace == pytest.approx(t, rel=1e-3)
    assert e.noise_var == pytest.approx(s2, rel=1e-3)
    assert e.noise_var_std == pytest.approx(sd, rel=1e-3)
    assert e.flags == []
    assert abs(e.noise_var - 0.49) < 4 * sd  # and it measures the noise
    # a fixed point (r0 = 0), and the negative / imprecise flags
    p = ref.as_f32(c0 + rng.normal(0, 0.1, (100, 3)))
    assert sfit.calibrate_noise(p, c0, 0.0).noise_var == pytest.approx(ref.noise_calibrate(p.astype(np.float64), c0, 0.0)[1], rel=1e-3)
    lo = sfit.calibrate_noise(x, c0, r0 + 0.1)  # a radius too large: negative estimate
    assert "negative" in lo.flags and lo.noise_var < 0
    # sigma = 0.05 on r0 = 10 with 100 samples: sd ~ 0.03 >> sigma^2 = 0.0025
    q = ref.as_f32(ref.sphere_samples(rng, 100, c0, r0, 0.05))
    e_q = sfit.calibrate_noise(q, c0, r0)
    t, s2, sd = ref.noise_calibrate(q.astype(np.float64), c0, r0)
    assert abs(s2) < 2 * sd and "imprecise" in e_q.flags
    assert sfit.calibration_std(0.49, 40.0, 5000) == pytest.approx(ref.calib_std(0.49, 40.0, 5000), rel=1e-5)
    # Moments.calibrate_noise is the same computation
    assert sfit.Moments(x).calibrate_noise(c0, r0).noise_var == e.noise_var


@pytest.mark.parametrize("kind", ["cap", "arc"])
@pytest.mark.parametrize("theta", [0.05, 0.3, 1.0, 2.0, 2.9, np.pi])
def test_coverage_functions(kind, theta):
    r = 250.0
    lmin, lmax = sfit.coverage_eigs(kind, theta, r)
    rmin, rmax = ref.eigs(kind, theta, r)
    assert lmin == pytest.approx(rmin, rel=1e-4)
    assert lmax == pytest.approx(rmax, rel=1e-5)
    smax = sfit.coverage_max_sigma(kind, theta, r)
    assert smax == pytest.approx(np.sqrt(rmin), rel=1e-4)
    q = smax / r
    if theta < np.pi:
        assert sfit.coverage_min_theta(kind, q) == pytest.approx(ref.min_theta(kind, q), rel=1e-4)
    lam = [rmin, rmin, rmax] if kind == "arc" else [rmin, rmax, rmax]
    if kind == "arc":
        lam = [0.0, rmin, rmax]
    if theta > 0.1:
        assert sfit.coverage_estimate_theta(kind, lam) == pytest.approx(ref.estimate_theta(kind, lam), rel=1e-3, abs=1e-4)
        assert sfit.coverage_estimate_theta(kind, lam) == pytest.approx(theta, rel=1e-3, abs=1e-4)


def test_coverage_errors():
    with pytest.raises(sfit.ArgError):
        sfit.coverage_eigs("dome", 1.0, 1.0)
    with pytest.raises(sfit.ArgError) as ei:
        sfit.coverage_eigs("cap", 4.0, 1.0)
    assert ei.value.status == "bad_argument"
    with pytest.raises(sfit.RangeError):
        sfit.coverage_min_theta("cap", 0.6)  # >= 1/sqrt(3): no coverage suffices
    with pytest.raises(sfit.NonFiniteError):
        sfit.coverage_max_sigma("arc", float("nan"), 1.0)
    with pytest.raises(sfit.ArgError):
        sfit.coverage_estimate_theta("cap", [3.0, 2.0, 1.0])  # not ascending
    with pytest.raises(sfit.ArgError):
        sfit.calibration_std(-1.0, 1.0, 10)


@pytest.mark.parametrize("path", data_files(), ids=lambda p: p.split("/data/")[-1])
def test_real_data_against_reference(path):
    """Every real recording: GDKE against the double reference (and the
    published Kasa fits of tests/data/README.md through the same reference)."""
    x = read_csv_f32(path)
    r = sfit.fit(x, mode="sphere")
    c, rad, lam = ref.sphere(x.astype(np.float64))[:3]
    cond = lam[2] / lam[0]
    assert np.linalg.norm(r.center - c) < 50 * EPS * cond * rad
    assert abs(r.radius - rad) < 50 * EPS * cond * rad


PUBLISHED_KASA = {  # tests/data/README.md, "Published reference fits"
    "mocap/hip_right/RTHI1.csv": ((-66.129, -93.950, 76.081), 254.519, 1e-3),
    "mocap/hip_right/RLFE.csv": ((-67.523, -85.245, 82.423), 415.261, 1e-3),
    "mocap/hip_right/RGT.csv": ((-94.794, -82.267, 147.767), 44.362, 1e-3),
    "mocap/elbow_right/ForearmR1.csv": ((-0.615184, 0.988093, 0.144978), 0.167362, 1e-6),
    "mag/fusion_example/mag.csv": ((4.692, 0.110, -1.806), 40.351, 1e-3),
}


@pytest.mark.parametrize("name", sorted(PUBLISHED_KASA))
def test_published_kasa_fits(name):
    c, r, tol = PUBLISHED_KASA[name]
    x = np.loadtxt(f"{DATA_DIR}/{name}", delimiter=",", skiprows=1)
    res = sfit.fit(x, mode="sphere")
    assert np.allclose(res.center, c, atol=tol)
    assert res.radius == pytest.approx(r, abs=tol)


def test_gate_removes_outliers(rng):
    """fit(gate=K): with 3 % gross outliers the gated fit is the reference fit
    of the clean samples, and the outliers are counted."""
    x = ref.sphere_samples(rng, 3000, (300.0, -100.0, 50.0), 200.0, 0.5, 1.2, axis=(1, 1, 0))
    bad = rng.choice(np.arange(100, 3000), 90, replace=False)  # after the warm-up
    y = x.copy()
    y[bad] += rng.normal(0, 60.0, (90, 3))
    y = ref.as_f32(y)
    clean = np.delete(y, bad, axis=0).astype(np.float64)
    c, rad = ref.sphere(clean)[:2]
    g = sfit.fit(y, gate=4.0)
    plain = sfit.fit(y)
    assert 80 <= g.outliers <= 110
    assert np.linalg.norm(g.center - c) < 0.05 * np.linalg.norm(plain.center - c)
    assert np.linalg.norm(g.center - c) < 0.5
    gi = sfit.fit(y, gate=4.0, noise_var=0.25)  # fixed gate sigma, UGDK fit
    assert gi.method == "ugdk" and gi.center_cov is not None and gi.outliers >= 80


def test_noise_cov_forms_agree(rng):
    x = far_cap(rng)
    full = [[0.3, 0.05, 0.01], [0.05, 0.2, 0.02], [0.01, 0.02, 0.25]]
    packed = [0.3, 0.2, 0.25, 0.05, 0.01, 0.02]
    a, b = sfit.fit(x, noise_cov=full), sfit.fit(x, noise_cov=packed)
    assert np.array_equal(a.center, b.center) and a.radius == b.radius
    iso = sfit.fit(x, noise_cov=np.eye(3) * 0.25)
    assert np.allclose(iso.center, sfit.fit(x, noise_var=0.25).center, atol=1e-4)
