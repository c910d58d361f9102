# SPDX-License-Identifier: MIT
"""sfit: a lab session (session_model, calibrate, apply_session).

Private: the public names are re-exported by sfit/__init__.py (the one
place that lists them) and documented in sfit/__init__.pyi."""
from __future__ import annotations

import os as _os
from collections.abc import Mapping as _Mapping

import numpy as _np

from . import _sfit
from ._base import _arg_error
from ._c3d import read_c3d, write_c3d, write_trc

# ---------------------------------------------------------------------------
# A lab session (docs/session.md): the CLI's session model, `sfit calibrate`
# and `sfit apply` on arrays and files, from the same C code (py_session.c).
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
