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

# The families, one private module each (as the C binding has one file per
# family, tools/python/src/py_*.c); this file only re-exports their names.
from . import _base, _c3d, _fit, _imu, _joint, _session
from ._base import _rebuild  # noqa: F401  (pickles of results name sfit._rebuild)
from ._fit import (  # noqa: F401  (re-exported)
    Estimate,
    FitResult,
    Incremental,
    Moments,
    MultiResult,
    NoiseEstimate,
    RefineResult,
    Track,
    Uncertainty,
    calibrate_noise,
    calibration_std,
    coverage_eigs,
    coverage_estimate_theta,
    coverage_max_sigma,
    coverage_min_theta,
    fit,
    fit_multi,
    refine,
    residual_noise_var,
    uncertainty,
)
from ._c3d import C3D, read_c3d, write_c3d, write_trc  # noqa: F401  (re-exported)
from ._joint import (  # noqa: F401  (re-exported)
    CLUSTER_MAX_MARKERS,
    JOINT_MAX_CHILD,
    Cluster,
    Joint,
    JointResult,
    Pose,
    joint_center,
)
from ._session import apply_session, calibrate, session_model  # noqa: F401  (re-exported)
from ._imu import ImuJointResult, imu_joint  # noqa: F401  (re-exported)

__all__ = [
    "Error", "ArgError", "TooFewError", "NotPosDefError", "NoConvergenceError",
    "DegenerateError", "NonFiniteError", "RangeError",
    "FitResult", "MultiResult", "NoiseEstimate", "Uncertainty", "RefineResult", "Estimate",
    "Track", "fit", "fit_multi", "Moments", "Incremental", "calibrate_noise",
    "calibration_std", "coverage_eigs", "coverage_max_sigma", "coverage_min_theta",
    "coverage_estimate_theta", "residual_noise_var", "refine", "uncertainty",
    "library_version", "MIN_SAMPLES",
]
__all__ += ["C3D", "read_c3d", "write_c3d", "write_trc"]
__all__ += ["Cluster", "Joint", "Pose", "JointResult", "joint_center",
            "CLUSTER_MAX_MARKERS", "JOINT_MAX_CHILD"]
__all__ += ["session_model", "calibrate", "apply_session"]
__all__ += ["ImuJointResult", "imu_joint"]

__version__ = "%d.%d.%d" % (_sfit.VERSION_MAJOR, _sfit.VERSION_MINOR, _sfit.VERSION_PATCH)
library_version = __version__
MIN_SAMPLES = _sfit.MIN_SAMPLES


def _adopt(*modules):
    """Every class and function of the private modules belongs to sfit, as
    when they were written here: help(), repr and pickle name sfit.X."""
    for m in modules:
        for obj in vars(m).values():
            if isinstance(obj, type) or callable(obj) and hasattr(obj, "__code__"):
                if getattr(obj, "__module__", None) == m.__name__:
                    obj.__module__ = __name__


_adopt(_base, _fit, _c3d, _joint, _session, _imu)
del _adopt
