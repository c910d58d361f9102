# SPDX-License-Identifier: MIT
"""sfit: sphere and circle fitting (GDKE / UGDK) for numpy.

The same C library as the firmware (lib/src of the sfit repository),
compiled into an extension module. Everything works in float32, as the
library does:

* Arrays in: any real-valued array-like of shape (N, 3) (float32, float64,
  integers; C or Fortran order, strided views). float64 values are rounded
  to the nearest float32 before the library sees them; a value beyond
  float32's range becomes inf. Rows with a NaN or Inf coordinate, or with a
  coordinate of magnitude >= 2**27, are skipped and counted (``rejected``),
  as the ``sfit`` command line skips such CSV lines.
* Results out: float64 numpy arrays and Python floats that hold the
  library's float32 values exactly (so they equal the CLI's JSON, which
  prints the same floats with 9 significant digits).
* Errors: a status other than ok raises a subclass of :class:`sfit.Error`
  (``ArgError``, ``TooFewError``, ``NotPosDefError``,
  ``NoConvergenceError``, ``DegenerateError``, ``NonFiniteError``,
  ``RangeError``) with the attributes ``status`` (the library's name, e.g.
  ``"degenerate"``), ``code``, ``message``, ``n`` and ``rejected``. Bad
  shapes, dtypes (complex, bool, object, str) and option values (NaN,
  negative, out of range: integers are never wrapped around) raise
  ``ArgError`` (also a ``ValueError``); something that is not a number at
  all may raise Python's ``TypeError`` / ``ValueError``. A rejected call
  leaves a state object (Moments, Incremental, Cluster, Joint) unchanged.
  Result objects are read-only; they pickle and copy.

Example::

    import numpy as np, sfit
    pts = np.loadtxt("tests/data/mocap/hip_right/RTHI1.csv", delimiter=",", skiprows=1)
    r = sfit.fit(pts)                    # GDKE (Kasa), auto sphere / circle
    r = sfit.fit(pts, noise_var="auto")  # self-calibrated UGDK
    print(r.center, r.radius, r.flags)
"""
from __future__ import annotations

import os as _os
from collections.abc import Mapping as _Mapping

import numpy as _np

from . import _sfit
from ._sfit import (  # noqa: F401  (re-exported)
    ArgError,
    DegenerateError,
    Error,
    NoConvergenceError,
    NonFiniteError,
    NotPosDefError,
    RangeError,
    TooFewError,
)

__all__ = [
    "Error", "ArgError", "TooFewError", "NotPosDefError", "NoConvergenceError",
    "DegenerateError", "NonFiniteError", "RangeError",
    "FitResult", "MultiResult", "NoiseEstimate", "Uncertainty", "RefineResult", "Estimate",
    "Track", "fit", "fit_multi", "Moments", "Incremental", "calibrate_noise",
    "calibration_std", "coverage_eigs", "coverage_max_sigma", "coverage_min_theta",
    "coverage_estimate_theta", "residual_noise_var", "refine", "uncertainty",
    "library_version", "MIN_SAMPLES",
]

__version__ = "%d.%d.%d" % (_sfit.VERSION_MAJOR, _sfit.VERSION_MINOR, _sfit.VERSION_PATCH)
library_version = __version__
MIN_SAMPLES = _sfit.MIN_SAMPLES


def _float(x, what):
    """float(x); a number beyond float range (float(10**400) raises
    OverflowError) is an ArgError like every other bad option value."""
    try:
        return float(x)
    except OverflowError:
        raise _arg_error("%s: number out of range" % what) from None


def _int(x, what):
    """int(x) of an int or an integral float; 1.5, NaN and Inf are an
    ArgError (int() would truncate 1.5 to 1)."""
    if isinstance(x, (float, _np.floating)) and not float(x).is_integer():
        raise _arg_error("%s must be an integer, got %r" % (what, x))
    return int(x)


def _rebuild(cls, state):
    """Unpickle a result (see _Record.__reduce__)."""
    obj = cls.__new__(cls)
    for k in cls.__slots__:
        object.__setattr__(obj, k, state.get(k))
    return obj


class _Record:
    """Base of the result types: attributes from a dict, a short repr.
    Read-only; copy.copy, copy.deepcopy and pickle work."""

    __slots__ = ()
    _repr_fields: tuple = ()

    def __init__(self, d):
        if not isinstance(d, _Mapping):
            raise TypeError("%s(d): d must be a mapping of the fields, not %s"
                            % (type(self).__name__, type(d).__name__))
        for k in self.__slots__:
            object.__setattr__(self, k, d.get(k))

    def __setattr__(self, name, value):
        raise AttributeError("sfit results are read-only")

    def __reduce__(self):
        return (_rebuild, (type(self), {k: getattr(self, k) for k in self.__slots__}))

    def to_dict(self) -> dict:
        """The fields as a dict (arrays are copied)."""
        return {k: (v.copy() if isinstance(v, _np.ndarray) else v)
                for k, v in ((k, getattr(self, k)) for k in self.__slots__)
                if not k.startswith("_")}

    def __repr__(self):
        parts = []
        for k in self._repr_fields:
            v = getattr(self, k)
            if isinstance(v, _np.ndarray):
                v = _np.array2string(v, precision=6, separator=", ")
            parts.append("%s=%s" % (k, v))
        return "%s(%s)" % (type(self).__name__, ", ".join(parts))


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


def _arg_error(message):
    e = ArgError(message)
    e.status, e.code, e.message, e.n, e.rejected = "bad_argument", -1, message, None, None
    return e


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


# ---------------------------------------------------------------------------
# Functional joint centre (present when the C library has sfit_joint.h)
# ---------------------------------------------------------------------------

def _points3(points, what):
    """(..., 3) real numbers as float64, else ArgError (np.asarray(None,
    float) would be a NaN)."""
    try:
        a = _np.asarray(points)
    except (TypeError, ValueError) as e:
        raise _arg_error("%s: not an array of numbers (%s)" % (what, e)) from None
    if a.dtype.kind not in "fiu":
        raise _arg_error("%s: dtype %s is not a real number type" % (what, a.dtype))
    if a.ndim < 1 or a.shape[-1] != 3:
        raise _arg_error("%s: expected shape (..., 3), got %r" % (what, a.shape))
    return a.astype(_np.float64)


class Pose(_Record):
    """A rigid pose x_global = rotation @ x_segment + translation: rotation
    (3, 3) proper (det +1), translation (3,), rms (registration residual over
    the markers used), used (markers seen)."""

    __slots__ = ("rotation", "translation", "rms", "used")
    _repr_fields = __slots__

    def to_global(self, points):
        """Map (..., 3) segment-frame points to the global frame (float64;
        a NaN point maps to NaN)."""
        return _points3(points, "Pose.to_global") @ self.rotation.T + self.translation

    def to_segment(self, points):
        """Map (..., 3) global points to the segment frame (float64; a NaN
        point maps to NaN)."""
        return (_points3(points, "Pose.to_segment") - self.translation) @ self.rotation


class JointResult(_Record):
    """A functional joint centre.

    center, axis, eigenvalues: in the parent's template (segment) frame;
    radii (K,): each child marker's radius (distance to the axis for a
    hinge; 0 for a marker skipped for too few samples); marker_n (K,);
    n, markers, skipped, trust_ratio, leontief_ratio, flags, flags_mask,
    method, mode (as MultiResult); frames (accepted), rejected_frames,
    residual_mean / residual_max (parent registration RMS). From
    :func:`joint_center` also: center_global (F, 3) and axis_global (F, 3)
    (NaN in frames whose parent cannot be registered), valid (F,) bool,
    cluster (the parent template used), label_swaps (the label swaps found
    within the parent and within the child markers, see
    :func:`joint_center`; None from :meth:`Joint.solve`).
    With method "default", "score" or "sara" (the pair of segments,
    docs/pair.md): center_cov (3, 3, parent frame), axis_cov (3, 3, hinge;
    else None), center_child, axis_child, marker_noise_var (and _parent,
    _child), noise_source ("registration_residuals" or "given"), untrusted,
    reason, misfit, model_rms, child_cluster; center_cov_model (the part of
    center_cov from skin motion linear in the joint angle) and skin_rms,
    skin_ratio (that motion's size at the joint and its test statistic);
    axis_cov_model (hinge: the part of axis_cov from an out-of-axis rotation
    in step with the flexion) and wobble_rms; info (facts, not faults:
    "axis_free" on a ball, "skin_motion"); flags is then the pair's list
    of names ("untrusted", "few_frames", "small_motion", "axis_free",
    "ambiguous", "misfit", "no_noise"); radii, marker_n, n, markers are None.
    With method "mgdk" from :func:`joint_center`: center_cov (3, 3; None
    when it cannot be computed; MGDK's own bias at a small range of motion
    is not in it), marker_noise_var and noise_source ("given" or
    "registration_residuals" of the parent cluster), untrusted, reason
    ("none" or "leontief_ratio"), as `sfit joint --method mgdk --json`.
    zero_missing: marker samples at exactly (0, 0, 0) taken as missing;
    note: why the method differs from the one asked (else None).
    """

    __slots__ = ("center", "axis", "eigenvalues", "radii", "marker_n", "n", "markers",
                 "skipped", "trust_ratio", "leontief_ratio", "flags", "flags_mask", "method",
                 "mode", "frames", "rejected_frames", "residual_mean", "residual_max",
                 "center_global", "axis_global", "valid", "cluster", "label_swaps", "_raw",
                 "center_cov", "axis_cov", "center_child", "axis_child", "marker_noise_var",
                 "marker_noise_var_parent", "marker_noise_var_child", "noise_source",
                 "untrusted", "reason", "misfit", "model_rms", "child_cluster", "zero_missing",
                 "note", "center_cov_model", "axis_cov_model", "skin_rms", "skin_ratio",
                 "wobble_rms", "info")
    _repr_fields = ("center", "radii", "mode", "frames", "rejected_frames", "flags")


# ----------------------------------------------------------------- C3D files
class C3D(_Record):
    """A C3D recording read by :func:`read_c3d` (the CLI's reader, docs/c3d.md).

    Attributes:
        labels: list of the points' labels (a duplicate renamed ``LABEL#2``).
        rate: frames per second; units: "mm", "m", ...
        points: (frames, points, 3) float64 array holding the stored float32
            values; NaN where a sample is invalid (negative residual).
        first_frame: the file's number of its first frame.
        processor: "Intel", "DEC" or "MIPS"; storage: "float" or "integer";
        scale: POINT:SCALE.
        analog_channels, analog_per_frame, analog_rate: the analog layout.
        zero_samples: valid samples at exactly (0, 0, 0) (some systems write
            a missing marker that way; not changed here).
        warnings: what was read differently from what one source says.
        sources: where each count came from (header, parameter, file size).
    """

    __slots__ = ("labels", "rate", "units", "points", "first_frame", "processor", "storage",
                 "scale", "analog_channels", "analog_per_frame", "analog_rate", "zero_samples",
                 "warnings", "sources")
    _repr_fields = ("labels", "rate", "units", "first_frame", "processor", "storage")

    def __repr__(self):
        n = self.points.shape if isinstance(self.points, _np.ndarray) else None
        return "C3D(%d points, %s frames, %s Hz, %r, %s %s, %d warnings)" % (
            len(self.labels or ()), n[0] if n else "?", self.rate, self.units, self.processor,
            self.storage, len(self.warnings or ()))


def _path(p, what):
    import os as _os
    try:
        return _os.fspath(p)
    except TypeError:
        raise TypeError("%s: a path (str, bytes or os.PathLike), not %s"
                        % (what, type(p).__name__)) from None


def read_c3d(path) -> C3D:
    """Read a C3D file: labels, rate, units, points (frames, points, 3) with
    NaN where invalid, warnings. OSError if it cannot be read; ValueError
    (with the reader's message) if it is malformed or refused."""
    d = _sfit._c3d_read(_path(path, "read_c3d"))
    n, p = d["frames"], d["npoints"]
    pts = _np.frombuffer(d["xyz"], dtype=_np.float32).astype(_np.float64).reshape(n, p, 3)
    return C3D(dict(labels=d["labels"], rate=d["rate"], units=d["units"], points=pts,
                    first_frame=d["first_frame"], processor=d["processor_name"],
                    storage=d["storage"], scale=d["scale"], analog_channels=d["analog_channels"],
                    analog_per_frame=d["analog_per_frame"], analog_rate=d["analog_rate"],
                    zero_samples=d["zero_samples"], warnings=d["warnings"],
                    sources=d["sources"]))


def _added(src, points, prefix, what):
    """(names, float32 bytes, prefix) of the points to add."""
    rec = read_c3d(src)
    nframes = rec.points.shape[0]
    if prefix is None:  # the subject prefix every label shares
        pre = {lab[:lab.rfind(":") + 1] for lab in rec.labels}
        prefix = pre.pop() if len(pre) == 1 else ""
    elif not isinstance(prefix, str):
        raise TypeError("%s: prefix must be a str or None" % what)
    if points is None:
        return [], b"", prefix
    if not isinstance(points, _Mapping) or len(points) == 0:
        raise _arg_error("%s: points must be a non-empty mapping name -> (frames, 3) array" % what)
    names, arrs = [], []
    for name, arr in points.items():
        if not isinstance(name, str):
            raise _arg_error("%s: point names must be str" % what)
        try:
            a = _np.asarray(arr)
        except (TypeError, ValueError) as e:
            raise _arg_error("%s: point %r: %s" % (what, name, e)) from None
        if a.dtype.kind not in "iuf" or a.shape != (nframes, 3):
            raise _arg_error("%s: point %r must be a real (%d, 3) array (the file's frames)"
                             % (what, name, nframes))
        a = a.astype(_np.float64)
        if _np.isinf(a).any():
            raise _arg_error("%s: point %r: coordinates must be finite (NaN = not placed)"
                             % (what, name))
        with _np.errstate(over="ignore"):
            a32 = a.astype(_np.float32)
        if _np.isinf(a32).any():
            raise _arg_error("%s: point %r: a coordinate beyond float32's range" % (what, name))
        names.append(name)
        arrs.append(a32)
    xyz = _np.ascontiguousarray(_np.stack(arrs, axis=1), dtype=_np.float32)
    return names, xyz.tobytes(), prefix


def write_c3d(src, dst, points, prefix=None, descriptions=None) -> bool:
    """Write ``dst``: the C3D recording ``src`` with ``points`` added.

    Args:
        src, dst: paths (dst is overwritten).
        points: mapping label -> (frames, 3) array in the file's units and lab
            frame; NaN in a frame: the point is missing there (residual -1).
        prefix: put before every new label; None (default): the subject
            prefix ("P01:") every label of src shares, else none.
        descriptions: None, or a mapping label -> text for POINT:DESCRIPTIONS
            (when the file has descriptions; a label not in it gets none).

    Nothing else changes: every parameter, event, point sample and analog
    word is kept, in the file's processor format (docs/c3d.md). Returns True
    when the file's integer storage could not hold a new point and the file
    was written with float storage.
    """
    s, d = _path(src, "write_c3d"), _path(dst, "write_c3d")
    names, raw, pre = _added(s, points, prefix, "write_c3d")
    descs = None
    if descriptions is not None:
        if not isinstance(descriptions, _Mapping):
            raise _arg_error("write_c3d: descriptions must be a mapping label -> str")
        descs = [descriptions.get(n, "") for n in names]
        if not all(isinstance(t, str) for t in descs):
            raise _arg_error("write_c3d: descriptions must be a mapping label -> str")
    return bool(_sfit._c3d_write(s, d, names, raw, pre, False, descs))


def write_trc(src, dst, points=None, prefix=None) -> None:
    """Write ``dst``, an OpenSim TRC marker file: every marker of the C3D
    recording ``src`` and the ``points`` added (as :func:`write_c3d`).
    Frame# counts from 1, Time = (Frame# - 1) / rate; a missing sample is
    three blank cells."""
    s, d = _path(src, "write_trc"), _path(dst, "write_trc")
    names, raw, pre = _added(s, points, prefix, "write_trc")
    _sfit._c3d_write(s, d, names, raw, pre, True)


__all__ += ["C3D", "read_c3d", "write_c3d", "write_trc"]


CLUSTER_MAX_MARKERS = _sfit.CLUSTER_MAX_MARKERS
JOINT_MAX_CHILD = _sfit.JOINT_MAX_CHILD


class Cluster(_sfit.Cluster):
    """Template of a rigid marker cluster (3..CLUSTER_MAX_MARKERS markers).

    ``Cluster(template)`` takes (M, 3) positions in the segment frame;
    ``Cluster.from_frames(frames)`` builds one from measured frames
    ((M, 3) or (F, M, 3), NaN = occluded; segment frame = centroid origin,
    global axes of the first complete frame). ``register(frame)`` gives
    the least-squares :class:`Pose` of one (M, 3) frame (NaN markers skipped).
    """

    __slots__ = ()

    @classmethod
    def from_frames(cls, frames) -> "Cluster":
        """Template averaged over measured frames (frames_used tells how many)."""
        return cls._from_frames(frames)

    def register(self, frame) -> Pose:
        """Pose of the template on one (M, 3) measured frame."""
        return Pose(self._register(frame))


class Joint(_sfit.Joint):
    """Streaming functional joint centre: register the parent cluster in
    every frame, express the child markers in the parent frame, accumulate
    one moments state per child marker, solve the common centre (MGDK).

    ``Joint(parent: Cluster, n_child, noise_var=None, noise_cov=None,
    mode="auto", weight="equal", planar_ratio=0.0, marker_noise_var=None)``:
    noise_var / noise_cov are the noise of a child marker in the parent
    frame; marker_noise_var is instead the variance of every measured
    marker coordinate, which the library propagates through the parent
    pose for each child marker (``noise_cov(marker_var)`` shows the
    average over the markers); ``add(parent, child)`` one frame
    ((Mp, 3), (K, 3)) or many ((F, Mp, 3), (F, K, 3)), NaN = occluded,
    returns the frames accepted (frames whose parent cannot be registered
    are skipped and counted in ``rejected_frames``); ``fit()``
    (``sfit_joint_fit``; ``solve()`` is the 0.2 name of it);
    ``center_at(result, parent_frames)``; ``frames``; ``reset()``.
    """

    __slots__ = ()

    def add(self, parent, child) -> int:
        """Add one frame or F frames; returns how many were accepted."""
        return self._add(parent, child)

    def fit(self) -> JointResult:
        """The joint centre from the frames so far (parent template frame):
        sfit_joint_fit."""
        return JointResult(self._solve())

    solve = fit  # the 0.2 name, kept for existing code

    def center_at(self, result: JointResult, parent):
        """Centre and axis in the global frame, per frame of ``parent``
        ((Mp, 3) or (F, Mp, 3)): (centers (F, 3), axes (F, 3), valid (F,));
        NaN rows where the parent cannot be registered."""
        raw = getattr(result, "_raw", None)
        if not isinstance(raw, bytes):
            raise _arg_error("Joint.center_at: result must be a JointResult of fit()")
        return self._center_at(raw, parent)


def _runs(frames):
    """[(first, last), ...] of the sorted frame indices."""
    runs = []
    for f in frames.tolist():
        if runs and runs[-1][1] == f - 1:
            runs[-1][1] = f
        else:
            runs.append([f, f])
    return [tuple(r) for r in runs]


def _label_swaps(frames, repair):
    """The CLI's label-swap check (tools/sfit/cli_swaps.c) over one
    cluster's (F, M, 3) frames: (the frames to use, the report). Input
    that is not such an array (or has too many markers or frames) is
    returned as it is with the report None: the joint's own checks then
    reject it as before."""
    try:
        a = _np.asarray(frames)
        ok = (a.dtype.kind in "fiu" and a.ndim == 3 and a.shape[-1] == 3
              and 1 <= a.shape[1] <= 8 and a.shape[0] < 2 ** 32)
    except Exception:  # the hostile object's error: the joint reports it
        return frames, None
    if not ok:
        return frames, None
    with _np.errstate(all="ignore"):
        buf = _np.array(a, dtype=_np.float32, order="C", copy=True)
    raw = _sfit._label_swaps(buf, buf.shape[0], buf.shape[1], bool(repair))
    status = _np.frombuffer(raw["status"], dtype=_np.int16).astype(_np.int64)
    rep = {k: raw[k] for k in ("checked", "why", "frames_checked", "noise",
                               "decidable_above", "no_fit_above", "swapped_frames")}
    swaps, undecidable = [], []
    for c, (lab, moved, count, pattern, decidable) in enumerate(raw["candidates"]):
        if c == 0:
            continue
        moved_labels = [u for u in range(len(lab)) if lab[u] != u]
        true = [lab[u] for u in moved_labels]
        if count > 0:
            fr = _np.nonzero(status == c)[0]
            swaps.append({"labels": moved_labels, "true": true, "count": int(count),
                          "frames": fr, "runs": _runs(fr)})
        if raw["checked"] and not decidable:
            undecidable.append({"labels": moved_labels, "true": true,
                                "pattern_change": pattern})
    no_fit, amb = _np.nonzero(status == -2)[0], _np.nonzero(status == -3)[0]
    rep.update(swaps=swaps, undecidable=undecidable, status=status,
               rejected={"count": int(len(no_fit) + len(amb)), "no_fit": no_fit,
                         "ambiguous": amb})
    return (buf if repair else frames), rep

_PAIR_ERRORS = {-1: ArgError, -2: TooFewError, -3: NotPosDefError, -4: NoConvergenceError,
                -5: DegenerateError, -6: NonFiniteError, -7: RangeError}


def _cluster_of(template, frames):
    """A segment's template: template itself (a Cluster), a Cluster of its
    points, or (None) Cluster.from_frames(frames)."""
    if template is None:
        return Cluster.from_frames(frames)
    if isinstance(template, _sfit.Cluster):
        return template
    return Cluster(template)


def _pair_center(parent, child_arr, cl, child_template, method, mode, marker_noise_var,
                 label_swaps=None, zero_missing=0):
    """joint_center with the pair of segments (sfit_pair.h via _sfit._pair_solve)."""
    if mode not in ("auto", "sphere", "planar"):
        raise _arg_error("joint_center: mode must be auto, sphere or planar")
    if child_arr.shape[1] < 3:
        raise _arg_error("joint_center: method %r needs 3 child markers (a cluster); "
                         "use method='mgdk'" % method)
    ccl = _cluster_of(child_template, child_arr)
    if marker_noise_var is None or (isinstance(marker_noise_var, str)
                                    and marker_noise_var == "auto"):
        noise, var = 0, 0.0
    else:
        noise, var = 1, _float(marker_noise_var, "marker_noise_var")
        if not (var >= 0.0) or var == float("inf"):
            raise _arg_error("joint_center: marker_noise_var must be 'auto' or a finite value >= 0")
    imode = 2 if (method == "sara" or mode == "planar") else \
        1 if (mode == "sphere" or method == "score") else 0
    code, d, rejected = _sfit._pair_solve(parent, child_arr, cl.positions, ccl.positions,
                                          0 if method == "default" else 1, imode, noise, var)
    if code != 0:
        e = _PAIR_ERRORS.get(code, Error)("joint_center (%s): %s" % (method, _sfit.status_name(code)))
        e.status, e.code, e.message, e.n, e.rejected = (_sfit.status_name(code), code,
                                                        str(e), None, rejected)
        raise e
    # R c + t and R a of the parent's pose in every frame, in one C loop
    cg, ag, valid = cl._place(parent, tuple(d["center"]), tuple(d["axis"]))
    d.update(method=method, rejected_frames=rejected, center_global=cg, axis_global=ag,
             valid=valid, cluster=cl, child_cluster=ccl, label_swaps=label_swaps,
             zero_missing=zero_missing, note=None)
    return JointResult(d)

def _zero_missing(frames):
    """(frames with every sample at exactly (0, 0, 0) set to NaN, how many):
    how some systems write "missing" (the CLI's C3D reader does the same).
    Input that is not a real (F, M, 3) array is returned as it is."""
    try:
        a = _np.asarray(frames)
    except Exception:  # the hostile object's error: the joint reports it
        return frames, 0
    if a.dtype.kind not in "fiu" or a.ndim != 3 or a.shape[-1] != 3 or a.shape[0] >= 2 ** 32:
        return frames, 0  # the joint's own checks report it
    try:
        z = _np.asarray(a == 0)
        if z.shape != a.shape:
            return frames, 0
        z = z.all(axis=2)
    except Exception:  # the hostile object's error: the joint reports it
        return frames, 0
    n = int(z.sum())
    if n == 0:
        return frames, 0
    b = _np.array(a, dtype=_np.float64)
    b[z] = _np.nan
    return b, n

def joint_center(parent, child, template=None, noise_var=None, noise_cov=None, mode="auto",
                 weight="equal", marker_noise_var=None, method="default",
                 child_template=None, repair_swaps=True, zero_is_missing=True) -> JointResult:
    """Functional joint centre from trajectories.

    Args:
        parent: (F, Mp, 3) parent-segment markers (global frame), NaN = occluded.
        child: (F, K, 3) child-segment markers, NaN = occluded.
        template: None (built from the parent frames, Cluster.from_frames),
            a Cluster, or (Mp, 3) positions in the parent's segment frame.
        noise_var, noise_cov, mode, weight: as :func:`fit_multi` (noise of a
            child marker in the parent frame).
        marker_noise_var: variance of each measured marker coordinate
            instead; the library propagates it through the parent pose.
        repair_swaps: label swaps within the parent markers and within the
            child markers (3 to 8 of them) are found from their distances
            as `sfit joint` finds them (docs/swaps.md): True (default)
            exchanges the labels back and drops the frames of a cluster
            whose distances fit no labelling (its markers taken as not
            seen); False only reports them.
            With a pair method: None or "auto" (default) = from the two
            clusters' registration residuals, or the given variance.
        method: the pair of segments (docs/pair.md): "default" (the
            default, as `sfit joint`'s: SCoRE / SARA with the bias
            removed and, for a ball, each frame weighted by its
            residual's noise covariance; a covariance and flags; with
            fewer than 3 child markers the multi-marker fit, with a
            note, as the CLI), "score" (plain SCoRE; with mode="planar"
            SARA), "sara" (plain SARA); or "mgdk" (the multi-marker
            fit, this function's default before 0.4). noise_var /
            noise_cov / weight belong to mgdk.
        zero_is_missing: True (default): marker samples at exactly
            (0, 0, 0) are taken as missing and counted in zero_missing
            (as `sfit joint` reads a C3D).
        child_template: pair methods: None (Cluster.from_frames of the
            child), a Cluster or (Mc, 3) positions.

    Returns:
        JointResult (centre in the parent frame) with center_global and
        axis_global (F, 3) per frame (NaN where the parent is not
        registrable), valid (F,) and label_swaps: {"repair": bool,
        "parent": report, "child": report}, a report (None for input
        that is not (F, M, 3)) holding checked, why, frames_checked,
        noise (the distance noise), decidable_above, no_fit_above,
        swapped_frames, swaps (each: labels and true, marker indices
        within the cluster: the point labelled labels[i] is marker
        true[i]; count, frames, runs), rejected (count, no_fit,
        ambiguous: frame indices), undecidable (labels, true,
        pattern_change) and status (F,) per frame (-1 not checked, 0 as
        given, -2 no labelling fits, -3 ambiguous, > 0 a swap).
    """
    nzero = 0
    if zero_is_missing:
        parent, n1 = _zero_missing(parent)
        child, n2 = _zero_missing(child)
        nzero = n1 + n2
    parent, swaps_p = _label_swaps(parent, repair_swaps)
    child, swaps_c = _label_swaps(child, repair_swaps)
    label_swaps = {"repair": bool(repair_swaps), "parent": swaps_p, "child": swaps_c}
    cl = _cluster_of(template, parent)
    try:
        child_arr = _np.asarray(child)
    except (TypeError, ValueError):
        child_arr = None
    k = child_arr.shape[1] if child_arr is not None and child_arr.ndim == 3 else -1
    if k < 1:
        raise _arg_error("joint_center: child must be (frames, markers, 3)")
    if not isinstance(method, str) or method not in ("mgdk", "default", "score", "sara"):
        raise _arg_error("joint_center: method must be mgdk, default, score or sara")
    note = None
    if method != "mgdk":
        if noise_var is not None or noise_cov is not None:
            raise _arg_error("joint_center: noise_var / noise_cov are the mgdk noise of a "
                             "child marker; give marker_noise_var with method %r" % method)
        if method == "default" and k < 3:
            note = "fewer than 3 child markers: no child cluster, the multi-marker fit (mgdk)"
        else:
            return _pair_center(parent, child_arr, cl, child_template, method, mode,
                                marker_noise_var, label_swaps, nzero)
    if isinstance(marker_noise_var, str) and marker_noise_var == "auto":
        marker_noise_var = None
    j = Joint(cl, k, noise_var=noise_var, noise_cov=noise_cov, mode=mode, weight=weight,
              marker_noise_var=marker_noise_var)
    j.add(parent, child_arr)
    res = j.solve()
    c, a, v = j.center_at(res, parent)
    d = {k2: getattr(res, k2) for k2 in JointResult.__slots__}
    d.update(center_global=c, axis_global=a, valid=v, cluster=cl, label_swaps=label_swaps,
             zero_missing=nzero, note=note)
    # the centre's covariance as `sfit joint --method mgdk` reports it
    vg = -1.0 if marker_noise_var is None else float(marker_noise_var)
    code, cov, var = j._center_cov(res._raw, parent, child_arr, vg)
    untrusted = "untrusted" in (res.flags or [])
    d.update(center_cov=cov if code == 0 else None, marker_noise_var=var,
             noise_source="given" if vg >= 0.0 else "registration_residuals",
             untrusted=untrusted, reason="leontief_ratio" if untrusted else "none")
    return JointResult(d)

__all__ += ["Cluster", "Joint", "Pose", "JointResult", "joint_center",
            "CLUSTER_MAX_MARKERS", "JOINT_MAX_CHILD"]


# ---------------------------------------------------------------------------
# A lab session (docs/session.md): the CLI's session model, `sfit calibrate`
# and `sfit apply` on arrays and files, from the same C code (session_py.c).
# ---------------------------------------------------------------------------

def _text_or_file(x, what):
    if isinstance(x, (bytes, str)) and "\n" not in (x if isinstance(x, str) else x.decode("latin-1")) \
            and _os.path.exists(x):
        with open(x, "rb") as f:
            x = f.read()
    elif hasattr(x, "__fspath__"):
        with open(x, "rb") as f:
            x = f.read()
    if isinstance(x, bytes):
        x = x.decode("latin-1")
    if not isinstance(x, str):
        raise _arg_error("%s: a path or the text itself expected" % what)
    return x


def session_model(model) -> dict:
    """Parse a session model (docs/session.md): ``model`` is a path or the
    text. Returns {"root", "segments": [{"name", "markers"}], "joints":
    [{"name", "parent", "child", "type", "points", "pattern"}]}; an "auto"
    joint lists its name and the two axis-point names. A bad model raises
    ValueError with the line and the reason."""
    import json as _json
    return _json.loads(_sfit._session_model(_text_or_file(model, "session_model")))


def _marker(labels, name):
    if name in labels:
        return labels.index(name)
    hits = [i for i, lab in enumerate(labels) if lab.rsplit(":", 1)[-1] == name]
    return hits[0] if len(hits) == 1 else -1


def _trial_markers(trial, names, what):
    """(frames, len(names), 3) float32 of a trial: a C3D path or a mapping
    label -> (frames, 3); the units ("" for a mapping without "units")."""
    if isinstance(trial, _Mapping):
        arrs = []
        for n in names:
            if n not in trial:
                raise _arg_error("%s: marker %s not in the trial" % (what, n))
            try:
                a = _np.asarray(trial[n], dtype=_np.float64)
            except (TypeError, ValueError) as e:
                raise _arg_error("%s: marker %s: %s" % (what, n, e))
            if a.ndim != 2 or a.shape[1] != 3 or a.shape[0] < 1:
                raise _arg_error("%s: marker %s must be (frames, 3)" % (what, n))
            arrs.append(a)
        if len({a.shape[0] for a in arrs}) != 1:
            raise _arg_error("%s: the markers have different frame counts" % what)
        xyz = _np.stack(arrs, axis=1)
        units = str(trial.get("units", "")) if isinstance(trial.get("units", ""), str) else ""
    else:
        c = read_c3d(trial)
        idx = [_marker(c.labels, n) for n in names]
        if min(idx) < 0:
            raise _arg_error("%s: marker %s not in %s" % (what, names[idx.index(min(idx))], trial))
        xyz = _np.array(c.points[:, idx, :], dtype=_np.float64)
        units = c.units
    if _np.isinf(xyz).any() or (_np.abs(_np.nan_to_num(xyz)) >= 2.0 ** 60).any():
        raise _arg_error("%s: a coordinate is infinite or huge" % what)
    xyz[(xyz == 0).all(axis=2)] = _np.nan  # (0, 0, 0) is how some systems write "missing"
    return _np.ascontiguousarray(xyz, dtype=_np.float32), units


def calibrate(model, trials, out=None) -> dict:
    """Calibrate every joint of a session model from its functional trial,
    as ``sfit calibrate`` does (docs/session.md).

    Args:
        model: a path to a session model, or its text.
        trials: a list of C3D paths (each joint takes the one whose basename
            its pattern matches), or a mapping trial name -> C3D path or
            mapping marker label -> (frames, 3) array (then the name is
            matched; an optional "units" entry gives the units).
        out: None, or a path: the session JSON is written there too.

    Returns the session (the JSON of ``sfit calibrate`` as a dict of plain
    lists and numbers, so that ``json.dump`` saves it as it is and
    :func:`apply_session` takes it back): per joint the parent markers'
    template, the centre (and hinge axis) in that frame, center_cov,
    semi_axes_95, rotation_range_deg, flags and verdict. A joint
    without a matching trial, with a missing marker or whose fit fails
    raises ValueError naming it.
    """
    import fnmatch as _fn
    import json as _json
    text = _text_or_file(model, "calibrate")
    m = session_model(text)
    if isinstance(trials, (str, bytes)) or not isinstance(trials, (_Mapping, list, tuple)):
        raise _arg_error("calibrate: trials must be a list of paths or a mapping")
    items = list(trials.items()) if isinstance(trials, _Mapping) else [(t, t) for t in trials]
    for name, _t in items:
        if not isinstance(name, str) and not hasattr(name, "__fspath__"):
            raise _arg_error("calibrate: a trial name must be a str or a path")
    seg = {s["name"]: s["markers"] for s in m["segments"]}
    session = None
    for k, j in enumerate(m["joints"]):
        if not j["pattern"]:
            raise _arg_error("calibrate: joint %s has no trial pattern" % j["name"])
        hits = [(n, t) for n, t in items if _fn.fnmatch(_os.path.basename(_os.fspath(n)), j["pattern"])]
        if not hits:
            raise _arg_error("calibrate: %s: no trial matches %s" % (j["name"], j["pattern"]))
        name, trial = hits[0]
        names = seg[j["parent"]] + seg[j["child"]]
        xyz, units = _trial_markers(trial, names, "calibrate: " + j["name"])
        one = _json.loads(_sfit._session_calibrate(text, k, xyz, xyz.shape[0], units,
                                                   _os.fspath(name)))
        if session is None:
            session = one
        else:
            if one["units"] != session["units"]:
                raise _arg_error("calibrate: %s is in %r, the others in %r"
                                 % (name, one["units"], session["units"]))
            session["joints"] += one["joints"]
    if session is None:
        raise _arg_error("calibrate: the model has no joint")
    if out is not None:
        with open(out, "w") as f:
            _json.dump(session, f)
    return session


def _numeric_list(v):
    """True for a non-empty list of numbers, or of such lists (a vector or a
    matrix of the session JSON)."""
    if not isinstance(v, list) or not v:
        return False
    if all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v):
        return True
    return all(isinstance(x, list) and x and all(isinstance(y, (int, float)) and not isinstance(y, bool)
                                                for y in x) for x in v) and len({len(x) for x in v}) == 1


def _session_json(o):
    """json.dumps default: the arrays of a session from :func:`calibrate`."""
    if isinstance(o, _np.ndarray):
        return o.tolist()
    raise TypeError("%s is not JSON serializable" % type(o).__name__)


def apply_session(session, trial, out=None, trc=None) -> dict:
    """Place every joint of a calibrated session in every frame of a trial,
    as ``sfit apply`` does (docs/session.md).

    Args:
        session: the dict of :func:`calibrate`, or a path to a session JSON.
        trial: a C3D path, or a mapping marker label -> (frames, 3) array.
        out, trc: with a C3D trial, write the trial with the points added
            (:func:`write_c3d`) and / or a TRC file.

    Returns a dict point label -> (frames, 3) array (NaN where the parent
    shows fewer than 3 markers), "invalid": {joint name: frames not
    placed} and "placement": {joint name: what the placement adds to the
    centre's uncertainty, the "placement" object of ``sfit apply --json``:
    cov_frame, cov_mean, total_cov_frame (with the calibration's
    center_cov_model), their 95 % semi-axes, marker_sigma, ...}. A hinge
    gives its centre and two axis points 100 mm (in the trial's units)
    either side.
    """
    import json as _json
    if isinstance(session, _Mapping):
        try:
            text = _json.dumps(session, allow_nan=False, default=_session_json)
        except (TypeError, ValueError) as e:
            raise _arg_error("apply_session: the session is not JSON: %s" % e)
    else:
        text = _text_or_file(session, "apply_session")
    try:
        s = _json.loads(text)
    except ValueError as e:
        raise _arg_error("apply_session: the session is not JSON: %s" % e)
    if not isinstance(s, dict) or not isinstance(s.get("joints"), list):
        raise _arg_error("apply_session: not an sfit session")
    res = {}
    invalid = {}
    placement = {}
    descriptions = {}
    for k, j in enumerate(s["joints"]):
        if not isinstance(j, dict) or not isinstance(j.get("parent_markers"), list):
            raise _arg_error("apply_session: joint %d is malformed" % k)
        xyz, units = _trial_markers(trial, [str(n) for n in j["parent_markers"]], "apply_session")
        d = {"m": 0.1, "cm": 10.0}.get(units, 100.0)
        raw, pc = _sfit._session_place(text, k, xyz, xyz.shape[0], d)
        placement[j["name"]] = {k: (_np.asarray(v, dtype=_np.float64) if _numeric_list(v) else v)
                                for k, v in _json.loads(pc).items()}
        pts = _np.frombuffer(raw, dtype=_np.float32).reshape(xyz.shape[0], -1, 3).astype(_np.float64)
        for i, name in enumerate(j["points"]):
            res[name] = pts[:, i, :]
            pd = j.get("point_descriptions")
            if isinstance(pd, list) and i < len(pd) and isinstance(pd[i], str):
                descriptions[name] = pd[i]
        invalid[j["name"]] = int(_np.isnan(pts[:, 0, 0]).sum())
    if out is not None or trc is not None:
        if isinstance(trial, _Mapping):
            raise _arg_error("apply_session: out and trc need a C3D trial")
        if out is not None:
            write_c3d(trial, out, res, descriptions=descriptions)
        if trc is not None:
            write_trc(trial, trc, res)
    res["invalid"] = invalid
    res["placement"] = placement
    return res


__all__ += ["session_model", "calibrate", "apply_session"]


# ---------------------------------------------------------------------------
# The joint between two IMUs (sfit_imu.h, docs/imu.md)
# ---------------------------------------------------------------------------

# The library's flag bits (sfit_imu.h), their names and the reason in words
# (the same words as `sfit imu-joint`).
_IMU_FLAGS = (
    (0x10000, "low_rotation", "a sensor hardly rotates: its joint position is not determined"),
    (0x20000, "low_variety",
     "too little variety of motion: a joint position is uncertain beyond the accepted SD"),
    (0x40000, "slip",
     "the residual is far above the sensors' noise: a sensor slips, or the joint is not one"),
    (0x80000, "ambiguous", "ball and hinge cannot be told apart"),
)


class ImuJointResult(_Record):
    """The joint between two IMUs (:func:`imu_joint`).

    joint: "ball" or "hinge". r1, r2 (m): the joint centre in each sensor's
    frame (ball) or the point of the hinge axis nearest each sensor (hinge);
    r1_cov, r2_cov (3, 3, m^2). axis1, axis2: the hinge axis in each frame
    (unit; axis2 the same physical direction), axis1_cov, axis2_cov (rank 2);
    None for a ball. acc_bias1, acc_bias2 (m/s^2): the accelerometer biases
    estimated. resid_rms, noise_rms (m/s^2): the constraint's residual and
    what the sensors' noise predicts; hinge_ratio, line_sd (m), line_ratio:
    the evidence for the joint type; rate_rms1, rate_rms2 (rad/s); n
    (samples), used (kept samples the solve used); flags (names), untrusted
    (bool), reason (words; None when trusted), flags_mask (the library's bits).
    """

    __slots__ = ("joint", "r1", "r2", "r1_cov", "r2_cov", "axis1", "axis2", "axis1_cov",
                 "axis2_cov", "acc_bias1", "acc_bias2", "resid_rms", "noise_rms",
                 "hinge_ratio", "line_sd", "line_ratio", "rate_rms1", "rate_rms2", "n", "used",
                 "flags", "untrusted", "reason", "flags_mask")
    _repr_fields = ("joint", "r1", "r2", "untrusted")


def imu_joint(acc1, gyr1, acc2, gyr2, rate) -> ImuJointResult:
    """The joint between two IMUs on two segments (sfit_imu.h).

    acc1, gyr1, acc2, gyr2: (N, 3) arrays of each sensor's specific force
    (m/s^2) and angular rate (rad/s), in its own frame, sampled together at
    ``rate`` Hz. Returns an :class:`ImuJointResult`: a ball joint's centre
    in each sensor's frame, or a hinge's axis and its point nearest each
    sensor, with covariances and flags. Raises ArgError (bad rate or
    shapes), NonFiniteError / RangeError (a refused sample: the message
    names its index), TooFewError, DegenerateError, NoConvergenceError.
    """
    rate = _float(rate, "imu_joint: rate")
    arrs = []
    for a, what in ((acc1, "acc1"), (gyr1, "gyr1"), (acc2, "acc2"), (gyr2, "gyr2")):
        a = _points3(a, "imu_joint: " + what)
        if a.ndim != 2:
            raise _arg_error("imu_joint: %s: expected shape (N, 3), got %r" % (what, a.shape))
        arrs.append(a)
    if len({a.shape[0] for a in arrs}) != 1:
        raise _arg_error("imu_joint: acc1, gyr1, acc2, gyr2 must have the same length")
    code, d, k = _sfit._imu_joint(*arrs, rate)
    if code != 0:
        what = "imu_joint: %s" % _sfit.status_name(code)
        if k >= 0:
            what += " (sample %d refused)" % k
        e = _PAIR_ERRORS.get(code, Error)(what)
        e.status, e.code, e.message, e.n, e.rejected = (_sfit.status_name(code), code,
                                                        str(e), None, None)
        raise e
    mask = d["flags_mask"]
    d["flags"] = [name for bit, name, _ in _IMU_FLAGS if mask & bit]
    d["untrusted"] = bool(mask & 0x1)
    d["reason"] = "; ".join(r for bit, _, r in _IMU_FLAGS if mask & bit) if mask & 0x1 else None
    if d["joint"] != "hinge":
        d["axis1"] = d["axis2"] = d["axis1_cov"] = d["axis2_cov"] = None
    return ImuJointResult(d)


__all__ += ["ImuJointResult", "imu_joint"]
