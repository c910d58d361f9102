# SPDX-License-Identifier: MIT
"""sfit: the joint between two IMUs (imu_joint).

Private: the public names are re-exported by sfit/__init__.py (the one
place that lists them) and documented in sfit/__init__.pyi."""
from __future__ import annotations

from . import _sfit
from ._base import _PAIR_ERRORS, _Record, _arg_error, _float, _points3
from ._sfit import Error

# ---------------------------------------------------------------------------
# The joint between two IMUs (sfit_imu.h, docs/imu.md)
# ---------------------------------------------------------------------------

# The flag names and the reasons in words come from the extension (the host
# tools' one table, tools/lab/names.c: the same words as `sfit imu-joint`).

class ImuJointResult(_Record):
    """The joint between two IMUs (:func:`imu_joint`).

    joint: "ball" or "hinge". r1, r2 (m): the joint centre in each sensor's
    frame (ball) or the point of the hinge axis nearest each sensor (hinge);
    r1_cov, r2_cov (3, 3, m^2). axis1, axis2: the hinge axis in each frame
    (unit; axis2 the same physical direction), axis1_cov, axis2_cov (rank 2);
    None for a ball. acc_bias1, acc_bias2 (m/s^2): the accelerometer biases
    estimated. resid_rms, noise_rms (m/s^2): the constraint's residual and
    what the sensors' noise predicts; hinge_ratio, wobble_deg (degrees: the
    rms angle by which the two sensors' relative rotation leaves its best
    fixed axis), line_sd (m), line_ratio, line_off: the evidence for the
    joint type; force_ratio: the hinge axes' fit to the accelerometers
    (about 1 for a hinge; above 1.5 the ``wobble`` flag); rate_rms1,
    rate_rms2 (rad/s); n
    (samples), used (kept samples the solve used); flags (names), untrusted
    (bool), reason (words; None when trusted), flags_mask (the library's bits).
    """

    __slots__ = ("joint", "r1", "r2", "r1_cov", "r2_cov", "axis1", "axis2", "axis1_cov",
                 "axis2_cov", "acc_bias1", "acc_bias2", "resid_rms", "noise_rms",
                 "hinge_ratio", "wobble_deg", "line_sd", "line_ratio", "line_off", "force_ratio",
                 "rate_rms1", "rate_rms2", "n", "used",
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
    d["untrusted"] = bool(d["flags_mask"] & 0x1)
    if d["joint"] != "hinge":
        d["axis1"] = d["axis2"] = d["axis1_cov"] = d["axis2_cov"] = None
    return ImuJointResult(d)
