# SPDX-License-Identifier: MIT
"""sfit: the fits over samples (fit, fit_multi, Moments, Incremental, noise, coverage, refine, uncertainty).

Private: the public names are re-exported by sfit/__init__.py (the one
place that lists them) and documented in sfit/__init__.pyi."""
from __future__ import annotations

from collections.abc import Mapping as _Mapping

from . import _sfit
from ._base import _Record, _arg_error, _float, _int

class FitResult(_Record):
    """A sphere or circle fit.

    Attributes:
        center: (3,) centre of the sphere, or of the circle (planar mode).
        radius: sphere or circle radius.
        n: samples used; rejected: rows skipped (NaN, Inf, out of range).
        eigenvalues: (3,) eigenvalues of the sample covariance C, ascending.
        axis: (3,) unit eigenvector of the smallest eigenvalue: the hinge axis
            (planar) or the cap axis (sphere); largest component positive.
        trust_ratio: rho(C^-1 Sigma_hat) (0 for GDKE), eq. 193.
        leontief_ratio: trust/(1 - trust); >= 1 sets the "untrusted" flag.
        flags: list of names: "untrusted" (do not believe centre_cov; the
            reason is "noise_capped", "cov_limit" or leontief_ratio >= 1,
            docs/coverage.md), "few_samples", "near_planar", "rounding".
        flags_mask: the same as the library's bit mask.
        method: "gdke", "ugdk" or "geometric" (refine=True).
        mode: "sphere" or "planar" (the solution used).
        noise_var: the sigma^2 used (given or estimated), None without a noise model.
        noise_estimated: True when noise_var was estimated from the samples.
        noise_capped: self-calibration hit its cap (do not trust the fit).
        iterations: self-calibration or refinement iterations (0 otherwise).
        rms: RMS radial residual (refine=True only, else None).
        outliers: samples rejected by the outlier gate (gate=K only).
        center_cov: (3, 3) covariance of the centre, radius_var: variance of
            the radius, center_radius_cov: (3,) their covariance - where the
            library gives them (a sphere with an isotropic noise variance, or
            the refined fit's sandwich estimate); else None.
    """

    __slots__ = ("center", "radius", "n", "rejected", "eigenvalues", "axis", "trust_ratio",
                 "leontief_ratio", "flags", "flags_mask", "method", "mode", "noise_var",
                 "noise_estimated", "noise_capped", "iterations", "rms", "outliers",
                 "center_cov", "radius_var", "center_radius_cov")
    _repr_fields = ("center", "radius", "method", "mode", "n", "rejected", "flags")


class MultiResult(_Record):
    """A common centre of several markers (fit_multi).

    Attributes: center, radii ((M,) per-marker radii; 0 for a skipped
    marker), marker_n ((M,) samples per marker), marker_rejected ((M,) rows
    skipped per marker), n (samples of the markers used), markers (markers
    used), skipped (markers with fewer than MIN_SAMPLES samples), eigenvalues,
    axis, trust_ratio, leontief_ratio, flags (names; "skipped_markers" when
    a marker was skipped), flags_mask, method, mode, weight, rejected.
    """

    __slots__ = ("center", "radii", "marker_n", "marker_rejected", "n", "markers", "skipped",
                 "eigenvalues", "axis", "trust_ratio", "leontief_ratio", "flags", "flags_mask",
                 "method", "mode", "weight", "rejected")
    _repr_fields = ("center", "radii", "method", "mode", "markers", "flags")


class NoiseEstimate(_Record):
    """A noise calibration against a known sphere (eq. 177, 190).

    Attributes: n, noise_trace (Tr Sigma_hat), noise_var (sigma^2 =
    trace/3, unclamped: may be negative), noise_var_std (predicted standard
    deviation, eq. 190), flags ("negative", "imprecise"), rejected.
    """

    __slots__ = ("n", "noise_trace", "noise_var", "noise_var_std", "flags", "rejected")
    _repr_fields = __slots__


class Uncertainty(_Record):
    """Uncertainty of a sphere fit: center_cov (3, 3), radius_var,
    center_radius_cov (3,), noise_var (the sigma^2 used)."""

    __slots__ = ("center_cov", "radius_var", "center_radius_cov", "noise_var")
    _repr_fields = __slots__

    def __init__(self, d):
        if not isinstance(d, _Mapping):
            raise TypeError("Uncertainty(d): d must be a mapping of the fields, not %s"
                            % type(d).__name__)
        d = dict(d)
        if "uncert_noise_var" in d:
            d["noise_var"] = d.pop("uncert_noise_var")
        super().__init__(d)


class RefineResult(_Record):
    """A geometric (orthogonal-distance) fit: center, radius, rms (RMS
    radial residual), noise_var (sigma^2 from the residuals), n, iterations,
    rejected."""

    __slots__ = ("center", "radius", "rms", "noise_var", "n", "iterations", "rejected")
    _repr_fields = __slots__


class Estimate(_Record):
    """An incremental estimate: center, radius, n."""

    __slots__ = ("center", "radius", "n")
    _repr_fields = __slots__


class Track(_Record):
    """Estimates after every sample (Incremental.track): n (K,), centers
    (K, 3), radii (K,) for the K samples after which an estimate existed."""

    __slots__ = ("n", "centers", "radii")
    _repr_fields = ("n",)


def fit(points, noise_var=None, noise_cov=None, mode="auto", refine=False, *,
        planar_ratio=0.0, gate=None) -> FitResult:
    """Fit a sphere (or a circle) to an (N, 3) array of samples.

    Args:
        points: (N, 3) array-like; float64 is rounded to float32. Rows with
            NaN / Inf / |x| >= 2**27 are skipped and counted (``rejected``).
        noise_var: None (GDKE, the Kasa fit), a number sigma^2 >= 0 (UGDK
            with isotropic noise; adds center_cov and radius_var for a
            sphere), or ``"auto"`` (self-calibrated UGDK: sigma^2 estimated
            from the radial residuals; sphere only).
        noise_cov: a (3, 3) symmetric noise covariance, or its 6 packed
            entries XX, YY, ZZ, XY, XZ, YZ (UGDK). Not with noise_var.
        mode: "auto" (sphere, or circle when the samples are near-planar),
            "sphere" or "planar".
        refine: the library's combined recipe (sfit_refine_fit):
            self-calibrated UGDK start, geometric (orthogonal-distance) fit,
            and the sandwich covariance of the refined centre (sphere only).
            The noise is estimated, so no numeric noise_var / noise_cov
            (noise_var="auto" is allowed and means the same). The result's
            eigenvalues and trust ratios are those of the start.
        planar_ratio: lambda_min/lambda_max threshold of "near-planar"
            (0 = the library default).
        gate: K > 1 runs the samples through the library's outlier gate
            (reject samples more than K sigma off the running fit); not with
            "auto" or refine.

    Returns:
        FitResult. Equal to ``sfit fit --json`` on the same float32 samples.

    Raises:
        ArgError: bad shape, dtype or option; TooFewError: fewer than
        MIN_SAMPLES valid rows (also for an empty array); DegenerateError,
        NotPosDefError, NoConvergenceError, RangeError: the library's status.
    """
    return FitResult(_sfit.fit(points, noise_var, noise_cov, mode, bool(refine),
                               _float(planar_ratio, "planar_ratio"), gate))


def fit_multi(markers, noise_var=None, noise_cov=None, mode="auto", weight="equal", *,
              planar_ratio=0.0) -> MultiResult:
    """Common centre of several markers on one segment (MGDK, eq. 219-223).

    Args:
        markers: a sequence of (N_p, 3) arrays (one per marker, lengths may
            differ) or one (M, N, 3) array. NaN rows (occlusions) are skipped
            per marker; a marker with fewer than MIN_SAMPLES valid rows is
            skipped (radius 0, flag "skipped_markers").
        noise_var, noise_cov: noise model (unbiased MGDK), as in :func:`fit`
            (no "auto").
        mode: "auto", "sphere" or "planar" (hinge: common axis).
        weight: "equal" (eq. 220 as printed) or "samples" (joint least squares).

    Returns:
        MultiResult with the common centre and the per-marker radii.
    """
    return MultiResult(_sfit.fit_multi(markers, noise_var, noise_cov, mode, weight,
                                       _float(planar_ratio, "planar_ratio")))


class Moments(_sfit.Moments):
    """Streaming moments accumulator: the O(1) state a firmware keeps per marker.

    ``Moments(points=None)``; ``add(x)`` takes one sample (3,) or an (N, 3)
    array (NaN rows skipped and counted in ``rejected``) and returns the
    number added; ``merge(other)``; ``count`` (also ``len()``); ``stats()``;
    ``fit()`` (``sfit_fit_moments``; ``solve()`` is the 0.2 name of it);
    ``calibrate_noise()``; ``uncertainty()``;
    ``reset()``; ``copy()``. Adding chunks one after the other gives exactly
    (bit for bit) the state of adding them in one call; ``merge`` of
    separately accumulated chunks agrees up to float rounding.
    """

    __slots__ = ()

    def fit(self, noise_var=None, noise_cov=None, mode="auto", *, planar_ratio=0.0) -> FitResult:
        """Solve from the accumulator (it is not modified; call again after more
        samples). Options as :func:`fit` (no "auto", no refine: those need the
        samples). With a noise_var, a sphere result carries center_cov and
        radius_var."""
        return FitResult(self._fit(noise_var, noise_cov, mode,
                                   _float(planar_ratio, "planar_ratio")))

    solve = fit  # the 0.2 name, kept for existing code

    def calibrate_noise(self, center, radius) -> NoiseEstimate:
        """Noise calibration against a known sphere (centre, radius >= 0; 0 =
        a fixed point): Tr(Sigma_hat) = mean |x - c0|^2 - r0^2 (eq. 177) and
        sigma^2 = Tr/3 with its predicted standard deviation (eq. 190)."""
        return NoiseEstimate(self._calibrate_noise(center, _float(radius, "radius")))

    def uncertainty(self, center, radius, noise_var, estimated=False) -> Uncertainty:
        """Centre covariance and radius variance of a fit of these samples
        from the moments alone (first + second order in the noise).
        estimated=True when noise_var came from the same samples."""
        return Uncertainty(self._uncertainty(center, _float(radius, "radius"), noise_var,
                                             bool(estimated)))


class Incremental(_sfit.Incremental):
    """Incremental estimator (chapter 5.4): a new sphere centre and radius
    after every sample, in constant memory; equal to the batch GDKE / UGDK
    sphere fit of the samples so far.

    ``Incremental(noise_var=None, noise_cov=None)``; ``start(points)``
    (batch start, checks the geometry); ``add(x)``; ``update(x)`` (add then
    fit); ``fit()`` (``sfit_incr_fit``; ``estimate()`` is the 0.2 name of
    it); ``track(points)`` (estimates after every sample); ``count``;
    ``rejected``; ``reset()``.
    """

    __slots__ = ()

    @staticmethod
    def _est(t):
        return Estimate({"center": t[0], "radius": t[1], "n": t[2]})

    def start(self, points) -> Estimate:
        """Replace the samples by an (N, 3) batch and return its estimate."""
        return self._est(self._start(points))

    def fit(self) -> Estimate:
        """The estimate for the samples so far (TooFewError below MIN_SAMPLES):
        sfit_incr_fit."""
        return self._est(self._estimate())

    estimate = fit  # the 0.2 name, kept for existing code

    def update(self, x) -> Estimate:
        """Add one sample (or an (N, 3) array; NaN rows skipped and counted),
        then return the estimate."""
        self.add(x)
        return self.fit()

    def track(self, points) -> Track:
        """Update with every row of an (N, 3) array; the estimates after the
        samples where one exists (n, centers, radii)."""
        n, c, r, k = self._track(points)
        return Track({"n": n[:k].copy(), "centers": c[:k].copy(), "radii": r[:k].copy()})


def calibrate_noise(points, center, radius) -> NoiseEstimate:
    """Noise calibration from samples of a known sphere (centre, radius >= 0):
    see :meth:`Moments.calibrate_noise`. NaN rows are skipped and counted."""
    if points is None:
        raise _arg_error("calibrate_noise: points: not an array of numbers")
    return Moments(points).calibrate_noise(center, radius)


def calibration_std(noise_var, radius, n) -> float:
    """Predicted standard deviation of a noise calibration (eq. 190, D = 3):
    sqrt(2 s2 (3 s2 + 2 r0^2) / (9 N))."""
    return _sfit.calibration_std(_float(noise_var, "noise_var"), _float(radius, "radius"),
                                 _int(n, "n"))


def coverage_eigs(kind, theta, radius):
    """(lmin, lmax): asymptotic covariance eigenvalues of a uniformly covered
    cap (kind="cap", eq. 210/211) or arc ("arc", eq. 203/204) of half-angle
    theta (radians, 0 < theta <= pi) and radius r."""
    return _sfit.coverage_eigs(kind, _float(theta, "theta"), _float(radius, "radius"))


def coverage_max_sigma(kind, theta, radius) -> float:
    """Largest noise sigma a coverage tolerates: sqrt(lmin(theta)) (eq. 212/213)."""
    return _sfit.coverage_max_sigma(kind, _float(theta, "theta"), _float(radius, "radius"))


def coverage_min_theta(kind, sigma_over_r) -> float:
    """Smallest half-angle (radians) at which sqrt(lmin)/r = sigma_over_r."""
    return _sfit.coverage_min_theta(kind, _float(sigma_over_r, "sigma_over_r"))


def coverage_estimate_theta(kind, eigenvalues) -> float:
    """Covered half-angle (radians) from measured covariance eigenvalues
    (ascending, e.g. FitResult.eigenvalues; subtract a known sigma^2 first)."""
    return _sfit.coverage_estimate_theta(kind, eigenvalues)


def residual_noise_var(points, center, radius) -> float:
    """sigma^2 from the radial residuals of a fit that agrees with the
    geometric fit to first order (one pass; curvature-corrected)."""
    return _sfit.residual_noise_var(points, center, _float(radius, "radius"))


def refine(points, center, max_iters=0, tol=0.0) -> RefineResult:
    """Geometric (orthogonal-distance) sphere fit, Levenberg-Marquardt in
    float started at ``center`` (e.g. a UGDK centre). max_iters 0 and tol 0
    are the library defaults."""
    return RefineResult(_sfit.refine(points, center, _int(max_iters, "max_iters"),
                                     _float(tol, "tol")))


def uncertainty(points, center, radius=None, noise_var=None) -> Uncertainty:
    """Uncertainty of a sphere fit from its samples.

    With ``noise_var``: the first-order covariance sigma^2 (J^T J)^-1 at
    (center, radius). Without: the sandwich covariance of the geometric fit
    at its centre (radius unused; s^2 from the residuals, returned as
    noise_var)."""
    if noise_var is None:
        return Uncertainty(_sfit.uncertainty(points, center))
    if radius is None:
        raise _arg_error("uncertainty: radius is needed with noise_var")
    return Uncertainty(_sfit.uncertainty(points, center, _float(radius, "radius"), noise_var))
