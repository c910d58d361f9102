# SPDX-License-Identifier: MIT
"""Double-precision numpy references for the sfit Python tests.

Written from the formulas of the chapter and the library's header
documentation, not from lib/src: every function here works in float64 on the
float32 samples the library saw (the arrays are converted with
``as_f32(x).astype(np.float64)`` by the callers).
"""
import numpy as np


def as_f32(x):
    """The samples exactly as the library sees them."""
    return np.ascontiguousarray(np.asarray(x, dtype=np.float64).astype(np.float32))


def valid_rows(x):
    """Rows the library accepts: finite, every |coordinate| < 2**27 (in float32)."""
    x = as_f32(x)
    ok = np.all(np.isfinite(x), axis=1) & np.all(np.abs(x) < 2.0 ** 27, axis=1)
    return x[ok].astype(np.float64), int((~ok).sum())


def moments(x):
    """mean m, C = sum y y^T/(N-1), S = sum |y|^2 y/(N-1), y = x - m."""
    x = np.asarray(x, dtype=np.float64)
    n = len(x)
    m = x.mean(axis=0)
    y = x - m
    c = y.T @ y / (n - 1)
    s = ((y * y).sum(axis=1)[:, None] * y).sum(axis=0) / (n - 1)
    return m, c, s


def _sigma(noise_var=None, noise_cov=None):
    if noise_cov is not None:
        return np.asarray(noise_cov, dtype=np.float64)
    if noise_var is not None:
        return float(noise_var) * np.eye(3)
    return np.zeros((3, 3))


def sphere(x, noise_var=None, noise_cov=None):
    """GDKE (Kasa) / UGDK sphere: c = m + C'^-1 S/2, r^2 = (N-1)/N tr C' + |m - c|^2,
    C' = C - Sigma. Returns centre, radius, eigenvalues of C, trust, leontief."""
    x = np.asarray(x, dtype=np.float64)
    n = len(x)
    m, c, s = moments(x)
    sig = _sigma(noise_var, noise_cov)
    cp = c - sig
    centre = m + 0.5 * np.linalg.solve(cp, s)
    r = np.sqrt((n - 1) / n * np.trace(cp) + np.sum((m - centre) ** 2))
    trust = float(np.max(np.abs(np.linalg.eigvals(np.linalg.solve(c, sig)))))
    leon = float(np.max(np.abs(np.linalg.eigvals(np.linalg.solve(cp, sig)))))
    return centre, r, np.linalg.eigvalsh(c), trust, leon


def circle(x, noise_var=None):
    """Planar solution (eq. 214-218): pseudo-inverse of C' over its two largest
    eigen-directions; the dropped eigenvector is the axis."""
    x = np.asarray(x, dtype=np.float64)
    n = len(x)
    m, c, s = moments(x)
    cp = c - _sigma(noise_var)
    lam, vec = np.linalg.eigh(cp)
    w = sum(vec[:, k] * (vec[:, k] @ s) / lam[k] for k in (1, 2)) * 0.5
    centre = m + w
    r = np.sqrt((n - 1) / n * (lam[1] + lam[2]) + w @ w)
    axis = vec[:, 0]
    axis = axis if axis[np.argmax(np.abs(axis))] > 0 else -axis
    return centre, r, axis


def smallest_axis(c):
    lam, vec = np.linalg.eigh(c)
    a = vec[:, 0]
    return a if a[np.argmax(np.abs(a))] > 0 else -a


def multi(markers, noise_var=None, weight="equal"):
    """Common centre (eq. 220/222): (sum w C'_p) c = sum w (C'_p m_p + S_p/2),
    r_p^2 = (N_p-1)/N_p tr C'_p + |m_p - c|^2 (sphere case)."""
    sig = _sigma(noise_var)
    stats = [moments(np.asarray(x, dtype=np.float64)) + (len(x),) for x in markers]
    if weight == "equal":
        w = np.ones(len(stats))
    else:
        w = np.array([n - 1.0 for *_, n in stats])
        w = w * len(stats) / w.sum()
    a = sum(wi * (c - sig) for wi, (m, c, s, n) in zip(w, stats))
    b = sum(wi * ((c - sig) @ m + s / 2) for wi, (m, c, s, n) in zip(w, stats))
    centre = np.linalg.solve(a, b)
    radii = [np.sqrt((n - 1) / n * np.trace(c - sig) + np.sum((m - centre) ** 2))
             for (m, c, s, n) in stats]
    return centre, np.array(radii)


def noise_calibrate(x, c0, r0):
    """eq. 177 and eq. 190: T = mean |x - c0|^2 - r0^2, sigma^2 = T/3,
    sd = sqrt(2 s2 (3 s2 + 2 r0^2)/(9 N)) at |s2|."""
    x = np.asarray(x, dtype=np.float64)
    t = np.mean(np.sum((x - np.asarray(c0, dtype=np.float64)) ** 2, axis=1)) - r0 * r0
    s2 = t / 3.0
    return t, s2, calib_std(abs(s2), r0, len(x))


def calib_std(s2, r0, n):
    return np.sqrt(2.0 * s2 * (3.0 * s2 + 2.0 * r0 * r0) / (9.0 * n))


def cap_eigs(theta, r):
    """eq. 210/211."""
    s = np.sin(theta / 2)
    return r * r * s ** 4 / 3, r * r * (2 + np.cos(theta)) * s ** 2 / 3


def arc_eigs(theta, r):
    """eq. 203/204."""
    lmin = r * r * (theta * (2 * theta + np.sin(2 * theta)) - 4 * np.sin(theta) ** 2) / (4 * theta ** 2)
    lmax = r * r * (theta - np.sin(theta) * np.cos(theta)) / (2 * theta)
    return lmin, lmax


def eigs(kind, theta, r):
    return cap_eigs(theta, r) if kind == "cap" else arc_eigs(theta, r)


def _bisect(f, target, lo=1e-9, hi=np.pi):
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(mid) < target:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def min_theta(kind, q):
    """theta with sqrt(lmin(theta))/r = q (lmin increasing)."""
    return _bisect(lambda t: np.sqrt(eigs(kind, t, 1.0)[0]), q)


def estimate_theta(kind, lam):
    """theta whose model ratio equals the measured one: cap lam0 / mean(lam1,
    lam2), arc lam1 / lam2."""
    lam = np.asarray(lam, dtype=np.float64)
    if kind == "cap":
        q = lam[0] / (0.5 * (lam[1] + lam[2]))
        f = lambda t: np.sin(t / 2) ** 2 / (2 + np.cos(t))  # noqa: E731
    else:
        q = lam[1] / lam[2]
        f = lambda t: arc_eigs(t, 1.0)[0] / arc_eigs(t, 1.0)[1]  # noqa: E731
    return _bisect(f, q, 1e-4)


def residual_noise_var(x, c, r):
    """Radial residual variance (divisor N - 4), curvature-corrected:
    sigma^2 = 2 s^2 / (1 + sqrt(1 - 4 s^2/r^2))."""
    x = np.asarray(x, dtype=np.float64)
    d = np.linalg.norm(x - c, axis=1) - r
    s2 = np.sum((d - d.mean()) ** 2) / (len(x) - 4)
    disc = max(0.0, 1 - 4 * s2 / (r * r))
    return 2 * s2 / (1 + np.sqrt(disc))


def selfcal(x, max_iters=12, rel_tol=1e-4, max_trust=0.5):
    """Self-calibrated UGDK (sfit_selfcal.h steps 1-5) in double."""
    x = np.asarray(x, dtype=np.float64)
    _, c, _ = moments(x)
    cap = max_trust * np.linalg.eigvalsh(c)[0]
    s2 = 0.0
    centre, r = sphere(x)[:2]
    for _ in range(max_iters):
        new = min(residual_noise_var(x, centre, r), cap)
        centre, r = sphere(x, noise_var=new)[:2]
        done = abs(new - s2) <= rel_tol * new
        s2 = new
        if done:
            break
    return centre, r, s2


def geometric(x, c0, iters=100):
    """Orthogonal-distance sphere fit: Gauss-Newton on the centre with the
    radius profiled out (r = mean distance)."""
    x = np.asarray(x, dtype=np.float64)
    c = np.asarray(c0, dtype=np.float64).copy()
    for _ in range(iters):
        d = np.linalg.norm(x - c, axis=1)
        u = (x - c) / d[:, None]
        j = -(u - u.mean(axis=0))
        f = d - d.mean()
        step = np.linalg.lstsq(j, -f, rcond=None)[0]
        c = c + step
        if np.linalg.norm(step) < 1e-13 * d.mean():
            break
    d = np.linalg.norm(x - c, axis=1)
    r = d.mean()
    return c, r, np.sqrt(np.mean((d - r) ** 2))


def uncert_points(x, c, noise_var):
    """First order sigma^2 (J^T J)^-1, rows [-u^T, -1]."""
    x = np.asarray(x, dtype=np.float64)
    u = (x - c) / np.linalg.norm(x - c, axis=1)[:, None]
    j = np.hstack([-u, -np.ones((len(x), 1))])
    cov = noise_var * np.linalg.inv(j.T @ j)
    return cov[:3, :3], cov[3, 3], cov[:3, 3]


def uncert_moments(x, c, r, s2, estimated=False):
    """sfit_uncert.h: first + second order centre covariance, first-order radius."""
    x = np.asarray(x, dtype=np.float64)
    n = len(x)
    m, cc, _ = moments(x)
    mm = (n - 1) * (cc - s2 * np.eye(3))
    mi = np.linalg.inv(mm)
    a = m - c
    s = -1.0 if estimated else 1.0
    cov = s2 * r * r * mi + 7.5 * s2 * s2 * mi + n * s2 * s2 * mi @ (r * r * np.eye(3) + s * np.outer(a, a)) @ mi
    rv = s2 * (1.0 / n + a @ mi @ a)
    crc = -s2 * r * (mi @ a)
    return cov, rv, crc


def uncert_geometric(x, c):
    """Sandwich A^-1 B A^-1 of the geometric fit (sfit_uncert.h)."""
    x = np.asarray(x, dtype=np.float64)
    n = len(x)
    d = np.linalg.norm(x - c, axis=1)
    u = (x - c) / d[:, None]
    f = d - d.mean()
    ub = u.mean(axis=0)
    mu = (u - ub).T @ (u - ub)
    a = mu + sum(fi * (np.eye(3) - np.outer(ui, ui)) / di for fi, ui, di in zip(f, u, d))
    s2 = np.sum(f * f) / (n - 4)
    ai = np.linalg.inv(a)
    core = ai @ mu @ ai
    return s2 * core, s2 * (1.0 / n + ub @ core @ ub), -s2 * core @ ub, s2


# K of the widening of docs/coverage.md rule 7 (issue 28); the library's
# SFIT_I_COV_WIDEN_K, written here independently (tests/ref REF_COV_WIDEN_K)
COV_WIDEN_K = 3.5


def uncert_selfcal(x, c, r, v):
    """Sandwich of the self-calibrated UGDK (sfit_uncert_selfcal):
    the 5 x 5 stacked estimating equations in (c, rho = r^2, v), analytic
    Jacobian, B = sum psi psi^T, n/(n-13) [A^-1 B A^-T]_cc, times
    1 + K (v / r^2) sqrt(96 / (n - 4)), K = COV_WIDEN_K (docs/coverage.md rule 7)."""
    x = np.asarray(x, dtype=np.float64)
    c = np.asarray(c, dtype=np.float64)
    n = len(x)
    k = (n - 1) / n
    rho = float(r) ** 2
    z = x - c
    z2 = np.sum(z * z, axis=1)
    d = np.sqrt(z2)
    u = z / d[:, None]
    f = d - d.mean()
    psi = np.column_stack([(z2 - rho - 5 * k * v)[:, None] * z, z2 - rho - 3 * k * v,
                           f * f - (n - 4) / n * (v - v * v / rho)])
    a = np.zeros((5, 5))
    a[:3, :3] = -2 * z.T @ z - np.sum(z2 - rho - 5 * k * v) * np.eye(3)
    a[:3, 3] = -z.sum(axis=0)
    a[:3, 4] = -5 * k * z.sum(axis=0)
    a[3, :3] = -2 * z.sum(axis=0)
    a[3, 3] = -n
    a[3, 4] = -3 * k * n
    a[4, :3] = -2 * (f[:, None] * u).sum(axis=0)
    a[4, 3] = -(n - 4) * v * v / rho ** 2
    a[4, 4] = -(n - 4) * (1 - 2 * v / rho)
    ai = np.linalg.inv(a)
    # times the widening of docs/coverage.md rule 7 (K = COV_WIDEN_K)
    widen = 1 + COV_WIDEN_K * (v / (r * r)) * np.sqrt(96 / max(n - 4, 10))
    return (ai @ (psi.T @ psi) @ ai.T)[:3, :3] * n / (n - 13) * widen


def sphere_samples(rng, n, centre, r, sigma, half_angle=np.pi, axis=(0.0, 0.0, 1.0)):
    """n samples uniform on a cap of half-angle half_angle about axis, plus
    isotropic Gaussian noise."""
    z = rng.uniform(np.cos(half_angle), 1.0, n)
    phi = rng.uniform(0, 2 * np.pi, n)
    s = np.sqrt(1 - z * z)
    p = np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1)
    ax = np.asarray(axis, dtype=np.float64)
    ax = ax / np.linalg.norm(ax)
    # rotate +z onto ax
    v = np.cross([0.0, 0.0, 1.0], ax)
    cth = ax[2]
    if np.linalg.norm(v) > 1e-12:
        vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
        rot = np.eye(3) + vx + vx @ vx / (1 + cth)
        p = p @ rot.T
    elif cth < 0:
        p = -p
    return np.asarray(centre, dtype=np.float64) + r * p + rng.normal(0, sigma, (n, 3))
