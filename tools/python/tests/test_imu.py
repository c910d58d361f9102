# SPDX-License-Identifier: MIT
"""sfit.imu_joint (sfit_imu.h) against `sfit imu-joint` on the same trials
(written by the C test's generator, test_imu --write-csv: noise, biases and
the truth of tests/test_imu.c): the same numbers, the truth within the
documented tolerances, and the errors."""
import json
import math
import os
import subprocess

import numpy as np
import pytest

import sfit

CLI = os.environ.get("SFIT_CLI")
GEN = os.path.join(os.path.dirname(os.path.dirname(CLI)), "tests", "test_imu") if CLI else None

pytestmark = pytest.mark.skipif(not GEN or not os.path.exists(GEN),
                                reason="needs the build's sfit and tests/test_imu (SFIT_CLI)")


def _trial(tmp_path, kind, seed):
    path = str(tmp_path / ("%s.csv" % kind))
    truth = json.loads(subprocess.run([GEN, "--write-csv", path, kind, str(seed)], check=True,
                                      capture_output=True, text=True).stdout)
    a = np.loadtxt(path, delimiter=",", skiprows=1)
    cli = json.loads(subprocess.run([CLI, "imu-joint", "--json", path], check=True,
                                    capture_output=True, text=True).stdout)
    rate = 1.0 / np.mean(np.diff(a[:, 0]))
    return a, rate, truth, cli


def _angle(a, b):
    c = abs(np.dot(a, b)) / np.linalg.norm(a) / np.linalg.norm(b)
    return math.degrees(math.acos(min(1.0, c)))


def test_ball_matches_cli_and_truth(tmp_path):
    a, rate, truth, cli = _trial(tmp_path, "ball", 4242)
    r = sfit.imu_joint(a[:, 1:4], a[:, 4:7], a[:, 7:10], a[:, 10:13], rate)
    assert r.joint == "ball" == cli["joint"]
    assert r.axis1 is None and cli["axis1"] is None
    assert r.untrusted is False and r.reason is None and r.flags == []
    for k in ("r1", "r2", "r1_cov", "r2_cov", "acc_bias1", "acc_bias2"):
        assert np.allclose(getattr(r, k), cli[k], rtol=1e-5, atol=1e-9), k
    assert np.linalg.norm(r.r1 - truth["r1"]) < 0.01 and np.linalg.norm(r.r2 - truth["r2"]) < 0.01
    assert r.n == 4000 and r.used >= 64
    assert "ImuJointResult(joint=ball" in repr(r)


def test_hinge(tmp_path):
    a, rate, truth, cli = _trial(tmp_path, "hinge", 4243)
    r = sfit.imu_joint(a[:, 1:4], a[:, 4:7], a[:, 7:10], a[:, 10:13], rate)
    assert r.joint == "hinge" == cli["joint"]
    assert _angle(r.axis1, truth["axis1"]) < 3.0 and _angle(r.axis2, truth["axis2"]) < 3.0
    assert np.allclose(r.axis1, cli["axis1"], rtol=1e-5, atol=1e-7)
    assert np.linalg.norm(r.r1 - truth["point1"]) < 0.01
    assert r.axis1_cov.shape == (3, 3)


def test_hinge_fits_the_accelerometers(tmp_path):
    a, rate, _, cli = _trial(tmp_path, "hinge", 4243)
    r = sfit.imu_joint(a[:, 1:4], a[:, 4:7], a[:, 7:10], a[:, 10:13], rate)
    assert r.force_ratio == pytest.approx(cli["force_ratio"], rel=1e-5)
    assert r.force_ratio < 1.5 and "wobble" not in r.flags


def test_instep_wobble_is_untrusted(tmp_path):
    """Both wobbles in step with the flexion: the rate axes (6.8 degrees off)
    do not fit the accelerometers: the wobble flag, as the CLI says it."""
    a, rate, truth, cli = _trial(tmp_path, "instep", 4326)
    r = sfit.imu_joint(a[:, 1:4], a[:, 4:7], a[:, 7:10], a[:, 10:13], rate)
    assert r.joint == "hinge" == cli["joint"]
    assert _angle(r.axis1, truth["axis1"]) > 3.0
    assert r.force_ratio == pytest.approx(cli["force_ratio"], rel=1e-5) and r.force_ratio > 1.5
    assert r.untrusted is True and r.flags == ["wobble"] == cli["flags"]["names"]
    assert r.reason == cli["flags"]["reason"] and "in step with the flexion" in r.reason


def test_still_is_untrusted(tmp_path):
    a, rate, _, cli = _trial(tmp_path, "still", 4244)
    r = sfit.imu_joint(a[:, 1:4], a[:, 4:7], a[:, 7:10], a[:, 10:13], rate)
    assert r.untrusted is True and "low_rotation" in r.flags
    assert r.reason == cli["flags"]["reason"]
    assert r.flags == cli["flags"]["names"]


def test_errors():
    z = np.zeros((100, 3))
    with pytest.raises(sfit.ArgError):
        sfit.imu_joint(z, z, z, z, 0.0)
    with pytest.raises(ValueError):
        sfit.imu_joint(z, z, z, np.zeros((99, 3)), 200.0)
    with pytest.raises(ValueError):
        sfit.imu_joint(z, z, z, np.zeros((100, 2)), 200.0)
    bad = z.copy()
    bad[42, 1] = np.nan
    with pytest.raises(sfit.NonFiniteError, match="sample 42"):
        sfit.imu_joint(bad, z, z, z, 200.0)
    with pytest.raises(sfit.TooFewError):
        sfit.imu_joint(z[:10], z[:10], z[:10], z[:10], 200.0)


def test_fast_wobble_is_a_hinge_by_its_angle(tmp_path):
    """Wobbles of 2 degrees at 2 and 3 times the flexion's frequency: the
    rates' hinge test fails, the relative rotation stays about 2 degrees
    from its best fixed axis (wobble_deg): a trusted hinge, as the CLI says."""
    a, rate, truth, cli = _trial(tmp_path, "fast", 4327)
    r = sfit.imu_joint(a[:, 1:4], a[:, 4:7], a[:, 7:10], a[:, 10:13], rate)
    assert r.joint == "hinge" == cli["joint"] and r.untrusted is False
    assert r.hinge_ratio > 0.07
    assert r.wobble_deg == pytest.approx(cli["wobble_deg"], rel=1e-5) and 1.5 < r.wobble_deg < 2.5
    assert _angle(r.axis1, truth["axis1"]) < 3.0 and _angle(r.axis2, truth["axis2"]) < 3.0
    assert np.linalg.norm(r.r1 - truth["point1"]) < 0.01
