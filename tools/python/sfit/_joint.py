# SPDX-License-Identifier: MIT
"""sfit: the functional joint centre (Cluster, Joint, joint_center).

Private: the public names are re-exported by sfit/__init__.py (the one
place that lists them) and documented in sfit/__init__.pyi."""
from __future__ import annotations

import numpy as _np

from . import _sfit
from ._base import _PAIR_ERRORS, _Record, _arg_error, _float, _points3
from ._sfit import Error

# ---------------------------------------------------------------------------
# Functional joint centre (present when the C library has sfit_joint.h)
# ---------------------------------------------------------------------------

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
    """The label-swap check of `sfit joint` (tools/lab/swaps.c) over one
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
