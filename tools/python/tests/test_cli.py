# SPDX-License-Identifier: MIT
"""sfit.fit / fit_multi equal the CLI's JSON (`sfit fit --json`) on the same
float samples: every field, bit for bit in float32, including the errors."""
import os

import numpy as np
import pytest

import sfit
from conftest import DATA_DIR, data_files, read_csv_f32

OPTIONS = {
    "gdke": ([], {}),
    "auto": (["--noise-var", "auto"], {"noise_var": "auto"}),
    "refine": (["--refine"], {"refine": True}),
    "auto_refine": (["--noise-var", "auto", "--refine"], {"noise_var": "auto", "refine": True}),
    "iso": (["--noise-var", "0.5"], {"noise_var": 0.5}),
    "iso_small": (["--noise-var", "1e-6"], {"noise_var": 1e-6}),
    "cov": (["--noise-cov", "0.5,0.4,0.3,0.01,0.02,0.03"],
            {"noise_cov": [0.5, 0.4, 0.3, 0.01, 0.02, 0.03]}),
    "sphere": (["--mode", "sphere"], {"mode": "sphere"}),
    "planar": (["--mode", "planar"], {"mode": "planar"}),
    "planar_iso": (["--mode", "planar", "--noise-var", "1e-6"], {"mode": "planar", "noise_var": 1e-6}),
    "gate": (["--gate", "4"], {"gate": 4.0}),
}


ERRORS = []  # (file, option, status) of the cases where both failed


def f32(x):
    return np.float32(x)


def assert_same_as_cli(j, r):
    """Compare a CLI JSON object with a FitResult / MultiResult, in float32."""
    assert j["status"] == "ok"
    assert r.method == j["method"]
    assert r.mode == j["mode"]
    assert r.n == j["n"]
    assert r.rejected == j["rejected"]
    assert np.array_equal(r.center.astype(np.float32), np.array(j["center"], dtype=np.float32))
    if "radius" in j:
        assert f32(r.radius) == f32(j["radius"])
    assert np.array_equal(r.eigenvalues.astype(np.float32),
                          np.array(j["eigenvalues"], dtype=np.float32))
    assert f32(r.trust_ratio) == f32(j["trust_ratio"])
    assert f32(r.leontief_ratio) == f32(j["leontief_ratio"])
    assert r.flags == j["flags"]
    if "axis" in j:
        assert np.array_equal(r.axis.astype(np.float32), np.array(j["axis"], dtype=np.float32))


def assert_single_extra(j, r):
    if j["noise_var"] is None:
        assert r.noise_var is None
    else:
        assert f32(r.noise_var) == f32(j["noise_var"])
    assert r.noise_estimated == j["noise_estimated"]
    assert r.iterations == j["iterations"]
    assert r.outliers == j["outliers"]
    assert r.noise_capped == j["noise_capped"]
    if j["center_cov"] is None:
        assert r.center_cov is None and r.radius_var is None
    else:
        assert np.array_equal(np.asarray(r.center_cov, dtype=np.float32),
                              np.array(j["center_cov"], dtype=np.float32))
        assert f32(r.radius_var) == f32(j["radius_var"])


def run_both(cli, path, pts, opt):
    args, kw = OPTIONS[opt]
    j = cli(*args, path)
    try:
        r = sfit.fit(pts, **kw)
    except sfit.Error as e:
        assert j["status"] == e.status, (j, e)
        assert j["n"] == e.n and j["rejected"] == e.rejected
        ERRORS.append((path, opt, e.status))
        return j, None
    assert_same_as_cli(j, r)
    assert_single_extra(j, r)
    return j, r


@pytest.mark.parametrize("opt", sorted(OPTIONS))
@pytest.mark.parametrize("path", data_files(), ids=lambda p: os.path.relpath(p, DATA_DIR))
def test_real_data_equals_cli(cli, path, opt):
    pts = read_csv_f32(path)
    run_both(cli, path, pts, opt)


def test_float64_input_rounds_like_the_cli(cli):
    """Reading the CSV in float64 (np.loadtxt) and letting sfit round gives the
    CLI's result too (double rounding never bites at 10 digits here)."""
    path = os.path.join(DATA_DIR, "mocap", "hip_right", "RTHI1.csv")
    pts64 = np.loadtxt(path, delimiter=",", skiprows=1)
    assert np.array_equal(pts64.astype(np.float32), read_csv_f32(path))
    j = cli(path)
    assert_same_as_cli(j, sfit.fit(pts64))


@pytest.mark.parametrize("opt", sorted(OPTIONS))
def test_synthetic_float_samples_equal_cli(cli, tmp_path, rng, opt):
    """Random float32 samples far from the origin, written with 9 significant
    digits (exact round trip), some rows NaN / Inf / out of range."""
    import ref
    x = ref.sphere_samples(rng, 700, (2000.0, -1500.0, 900.0), 120.0, 0.8, half_angle=1.0,
                           axis=(1, 2, 3)).astype(np.float32)
    if opt.startswith("planar"):
        x[:, 2] = np.float32(900.0) + rng.normal(0, 0.01, len(x)).astype(np.float32)
    x[5] = [np.nan, 1, 2]
    x[17] = [np.inf, 0, 0]
    x[30] = [3e8, 0, 0]  # >= 2**27: out of range
    path = tmp_path / "s.csv"
    with open(path, "w") as f:
        f.write("x,y,z\n")
        for row in x:
            f.write(",".join("%.9g" % v for v in row) + "\n")
    assert np.array_equal(read_csv_f32(path), x, equal_nan=True)
    j, r = run_both(cli, str(path), x, opt)
    assert j.get("rejected") == 3


def test_multi_equals_cli(cli):
    root = os.path.join(DATA_DIR, "mocap")
    for joint in ("hip_right", "knee_right", "elbow_right"):
        folder = os.path.join(root, joint)
        files = sorted(os.path.join(folder, f) for f in os.listdir(folder))
        markers = [read_csv_f32(f) for f in files]
        for args, kw in (([], {}), (["--weight", "samples"], {"weight": "samples"}),
                         (["--mode", "planar"], {"mode": "planar"}),
                         (["--noise-var", "1e-6"], {"noise_var": 1e-6})):
            j = cli(*args, *files)
            try:
                r = sfit.fit_multi(markers, **kw)
            except sfit.Error as e:
                assert j["status"] == e.status
                continue
            assert_same_as_cli(j, r)
            assert r.weight == j["weight"]
            for k, m in enumerate(j["markers"]):
                assert r.marker_n[k] == m["n"]
                if m["radius"] is None:
                    assert r.radii[k] == 0.0
                else:
                    assert f32(r.radii[k]) == f32(m["radius"])


def test_error_status_equals_cli(cli, tmp_path):
    """Collinear samples: the CLI and the binding report the same status."""
    path = tmp_path / "line.csv"
    x = np.stack([np.arange(10.0), 2 * np.arange(10.0), np.zeros(10)], axis=1).astype(np.float32)
    np.savetxt(path, x, delimiter=",", fmt="%.9g")
    j = cli(str(path))
    with pytest.raises(sfit.DegenerateError) as ei:
        sfit.fit(x)
    assert j["status"] == ei.value.status == "degenerate"


def test_most_cases_are_successes():
    """The comparisons above are mostly of results, not of matching errors
    (runs after them: pytest keeps file order)."""
    n_cases = len(data_files()) * len(OPTIONS) + len(OPTIONS)
    assert len(ERRORS) < n_cases // 4, ERRORS
