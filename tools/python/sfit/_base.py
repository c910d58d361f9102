# SPDX-License-Identifier: MIT
"""sfit: what the families share: number checks, the result base class, ArgError.

Private: the public names are re-exported by sfit/__init__.py (the one
place that lists them) and documented in sfit/__init__.pyi."""
from __future__ import annotations

from collections.abc import Mapping as _Mapping

import numpy as _np

from ._sfit import (ArgError, DegenerateError, NoConvergenceError, NonFiniteError,
                    NotPosDefError, RangeError, TooFewError)

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


def _arg_error(message):
    e = ArgError(message)
    e.status, e.code, e.message, e.n, e.rejected = "bad_argument", -1, message, None, None
    return e


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


# the library's status codes (the C functions that return a code) and their errors
_PAIR_ERRORS = {-1: ArgError, -2: TooFewError, -3: NotPosDefError, -4: NoConvergenceError,
                -5: DegenerateError, -6: NonFiniteError, -7: RangeError}
