# SPDX-License-Identifier: MIT
"""sfit: C3D files (read_c3d, write_c3d, write_trc).

Private: the public names are re-exported by sfit/__init__.py (the one
place that lists them) and documented in sfit/__init__.pyi."""
from __future__ import annotations

from collections.abc import Mapping as _Mapping

import numpy as _np

from . import _sfit
from ._base import _Record, _arg_error

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
