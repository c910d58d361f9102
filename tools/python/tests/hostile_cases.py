# SPDX-License-Identifier: MIT
"""The table of test_hostile.py: every public callable of the package and
its hostile cases (build_cases), family by family."""
import os
import pickle

from hostile_inputs import *  # noqa: F401,F403  (the inputs, underscored helpers too)
# ---------------------------------------------------------------------------
# The table: public callable -> cases
# ---------------------------------------------------------------------------

def build_cases():
    T = {}
    c0 = sfit.fit(P).center

    # --- functions over samples -------------------------------------------
    T["fit"] = (points_cases(lambda x: sfit.fit(x), huge=True)
                + number_cases(lambda v: sfit.fit(P, noise_var=v))
                + [("noise_var 'auto'", lambda: sfit.fit(P, noise_var="auto"), "ok"),
                   ("noise_var 'bogus'", lambda: sfit.fit(P, noise_var="bogus"), sfit.ArgError),
                   ("noise_var True", lambda: sfit.fit(P, noise_var=True), sfit.ArgError),
                   ("noise_var 1e6", lambda: sfit.fit(P, noise_var=1e6), sfit.Error),
                   ("noise_var and noise_cov", lambda: sfit.fit(P, noise_var=1e-3,
                                                                noise_cov=np.eye(3)), sfit.ArgError),
                   ("auto and noise_cov", lambda: sfit.fit(P, noise_var="auto",
                                                           noise_cov=np.eye(3)), sfit.ArgError),
                   ("refine=True", lambda: sfit.fit(P, refine=True), "ok"),
                   ("refine + noise_var", lambda: sfit.fit(P, refine=True, noise_var=1e-3), sfit.ArgError),
                   ("refine planar", lambda: sfit.fit(P, refine=True, mode="planar"), sfit.ArgError),
                   ("refine on circle", lambda: sfit.fit(circle(), refine=True), None),
                   ("refine raising __bool__", lambda: sfit.fit(P, refine=RaisingFloat()), HostileError),
                   ("auto on circle", lambda: sfit.fit(circle(), noise_var="auto"), None),
                   ("planar on sphere", lambda: sfit.fit(P, mode="planar"), None),
                   ("sphere on circle", lambda: sfit.fit(circle(), mode="sphere"), None),
                   ("planar_ratio nan", lambda: sfit.fit(P, planar_ratio=NAN), sfit.ArgError),
                   ("planar_ratio -1", lambda: sfit.fit(P, planar_ratio=-1), sfit.ArgError),
                   ("planar_ratio 0.5", lambda: sfit.fit(P, planar_ratio=0.5), sfit.ArgError),
                   ("planar_ratio str", lambda: sfit.fit(P, planar_ratio="bogus"), ValueError),
                   ("planar_ratio None", lambda: sfit.fit(P, planar_ratio=None), TypeError),
                   ("gate 4", lambda: sfit.fit(P, gate=4.0), "ok"),
                   ("gate 4 + noise_var", lambda: sfit.fit(P, gate=4.0, noise_var=1e-4), "ok")]
                + [(f"gate={g!r}", lambda g=g: sfit.fit(P, gate=g), sfit.ArgError)
                   for g in (0, 1, 1.0, -3, NAN, INF, "bogus", object(), RaisingFloat(), [4.0])]
                + [("gate + auto", lambda: sfit.fit(P, gate=4.0, noise_var="auto"), sfit.ArgError),
                   ("gate + refine", lambda: sfit.fit(P, gate=4.0, refine=True), sfit.ArgError),
                   ("gate on garbage", lambda: sfit.fit(np.full((30, 3), NAN), gate=3.0), sfit.TooFewError),
                   ("unknown keyword", lambda: sfit.fit(P, bogus=1), TypeError)]
                + mode_cases(lambda m: sfit.fit(P, mode=m))
                + cov_cases(lambda v: sfit.fit(P, noise_cov=v)))

    def mk_list(x):
        return [x, sphere(seed=6)]
    multi = points_cases(lambda x: sfit.fit_multi(mk_list(x)))
    # a marker with too few valid rows is skipped (documented), not an error
    multi = [(lab, fn, ("ok" if exp in (sfit.TooFewError, sfit.Error) else exp))
             if lab in ("(0, 3)", "[]", "MIN_SAMPLES - 1", "all NaN", "all 1e30", "coincident",
                        "collinear") else (lab, fn, exp) for lab, fn, exp in multi]
    multi = [(lab, fn, None if lab == "coincident" or lab == "collinear" else exp)
             for lab, fn, exp in multi]
    T["fit_multi"] = (
        multi
        + [("empty list", lambda: sfit.fit_multi([]), sfit.TooFewError),
           ("None", lambda: sfit.fit_multi(None), sfit.ArgError),
           ("str", lambda: sfit.fit_multi("abc"), sfit.ArgError),
           ("dict", lambda: sfit.fit_multi({0: P}), sfit.ArgError),
           ("2-D array", lambda: sfit.fit_multi(P), sfit.ArgError),
           ("(M, N, 3)", lambda: sfit.fit_multi(np.stack([P, sphere(seed=6)])), "ok"),
           ("(M, N, 3) big-endian", lambda: sfit.fit_multi(np.stack([P, sphere(seed=6)]).astype(">f8")), "ok"),
           ("(M, 0, 3)", lambda: sfit.fit_multi(np.zeros((2, 0, 3))), sfit.TooFewError),
           ("(0, N, 3)", lambda: sfit.fit_multi(np.zeros((0, 5, 3))), sfit.TooFewError),
           ("generator", lambda: sfit.fit_multi(x for x in (P, sphere(seed=6))), "ok"),
           ("raising sequence", lambda: sfit.fit_multi(RaisingSequence()), sfit.ArgError),
           ("lying sequence", lambda: sfit.fit_multi(LyingSequence()), sfit.ArgError),
           ("list cleared by __array__", lambda: _multi_mutating("clear"), None),
           ("list grown by __array__", lambda: _multi_mutating("grow"), None),
           ("list item replaced by __array__", lambda: _multi_mutating("replace"), None),
           ("weight 'bogus'", lambda: sfit.fit_multi([P, P], weight="bogus"), sfit.ArgError),
           ("weight None", lambda: sfit.fit_multi([P, P], weight=None), TypeError),
           ("weight 'samples'", lambda: sfit.fit_multi([P, P], weight="samples"), "ok"),
           ("weight with NUL", lambda: sfit.fit_multi([P, P], weight="equal\0"), ValueError),
           ("noise_var 'auto'", lambda: sfit.fit_multi([P, P], noise_var="auto"), sfit.ArgError),
           ("planar_ratio nan", lambda: sfit.fit_multi([P, P], planar_ratio=NAN), sfit.ArgError)]
        + number_cases(lambda v: sfit.fit_multi([P, P], noise_var=v))
        + mode_cases(lambda m: sfit.fit_multi([P, P], mode=m))
        + cov_cases(lambda v: sfit.fit_multi([P, P], noise_cov=v)))

    T["calibrate_noise"] = (
        points_cases(lambda x: sfit.calibrate_noise(x, (1.0, 2.0, 3.0), 10.0), allow_one=True,
                     centred=True)
        + vec3_cases(lambda v: sfit.calibrate_noise(P, v, 10.0))
        + number_cases(lambda v: sfit.calibrate_noise(P, (1.0, 2.0, 3.0), v), expect_bad=sfit.Error))
    # calibrate_noise accepts one (3,) sample but needs MIN_SAMPLES: TooFew is fine too
    # a known sphere needs no geometry from the samples: few or degenerate
    # samples may calibrate
    relax = ("MIN_SAMPLES - 1", "coincident", "collinear")
    T["calibrate_noise"] = [(lab, fn, None if lab.startswith("(3,)") or lab in relax else exp)
                            for lab, fn, exp in T["calibrate_noise"]]
    T["calibration_std"] = (
        number_cases(lambda v: sfit.calibration_std(v, 10.0, 100), expect_bad=sfit.Error)
        + number_cases(lambda v: sfit.calibration_std(0.1, v, 100), expect_bad=sfit.Error)
        + [("n=0", lambda: sfit.calibration_std(0.1, 10.0, 0), sfit.Error),
           ("n=-1", lambda: sfit.calibration_std(0.1, 10.0, -1), sfit.Error),
           ("n=2**32", lambda: sfit.calibration_std(0.1, 10.0, 2 ** 32), sfit.Error),
           ("n=2**64+100", lambda: sfit.calibration_std(0.1, 10.0, 2 ** 64 + 100), sfit.Error),
           ("n=2**70", lambda: sfit.calibration_std(0.1, 10.0, 2 ** 70), sfit.Error),
           ("n=1.5", lambda: sfit.calibration_std(0.1, 10.0, 1.5), sfit.ArgError),
           ("n=100.0", lambda: sfit.calibration_std(0.1, 10.0, 100.0), "ok"),
           ("n=inf", lambda: sfit.calibration_std(0.1, 10.0, INF), sfit.ArgError),
           ("n=nan", lambda: sfit.calibration_std(0.1, 10.0, NAN), ValueError),
           ("n=None", lambda: sfit.calibration_std(0.1, 10.0, None), TypeError),
           ("n=str", lambda: sfit.calibration_std(0.1, 10.0, "x"), ValueError),
           ("n raising", lambda: sfit.calibration_std(0.1, 10.0, RaisingFloat()), None)])
    for name in ("coverage_eigs", "coverage_max_sigma"):
        fn = getattr(sfit, name)
        T[name] = (
            [(f"kind={k!r}", lambda k=k, fn=fn: fn(k, 1.0, 1.0), None if k is None else
              (TypeError, ValueError)) for k in ("sphere", "", None, b"cap", 1, "cap\0")]
            + number_cases(lambda v, fn=fn: fn("cap", v, 1.0), expect_bad=sfit.Error)
            + number_cases(lambda v, fn=fn: fn("arc", 1.0, v), expect_bad=sfit.Error)
            + [("theta 3.2", lambda fn=fn: fn("cap", 3.2, 1.0), sfit.Error),
               ("ok", lambda fn=fn: fn("arc", 1.0, 2.0), "ok")])
    T["coverage_min_theta"] = (
        [(f"kind={k!r}", lambda k=k: sfit.coverage_min_theta(k, 0.1), None)
         for k in ("sphere", "", None, 1)]
        + number_cases(lambda v: sfit.coverage_min_theta("cap", v), expect_bad=sfit.Error)
        + number_cases(lambda v: sfit.coverage_min_theta("arc", v), expect_bad=sfit.Error))
    T["coverage_estimate_theta"] = (
        [(f"kind={k!r}", lambda k=k: sfit.coverage_estimate_theta(k, [1.0, 2.0, 3.0]), None)
         for k in ("sphere", "", None, 1)]
        + vec3_cases(lambda v: sfit.coverage_estimate_theta("cap", v))
        + vec3_cases(lambda v: sfit.coverage_estimate_theta("arc", v))
        + [("negative eig", lambda: sfit.coverage_estimate_theta("arc", [-1.0, 1.0, 2.0]), None),
           ("descending", lambda: sfit.coverage_estimate_theta("cap", [3.0, 2.0, 1.0]), None),
           ("zeros", lambda: sfit.coverage_estimate_theta("cap", [0.0, 0.0, 0.0]), None)])
    T["residual_noise_var"] = (
        [(lab, fn, None if lab in relax else exp) for lab, fn, exp in
         points_cases(lambda x: sfit.residual_noise_var(x, c0, 10.0), centred=True)]
        + vec3_cases(lambda v: sfit.residual_noise_var(P, v, 10.0))
        + number_cases(lambda v: sfit.residual_noise_var(P, c0, v), expect_bad=sfit.Error))
    T["refine"] = (
        points_cases(lambda x: sfit.refine(x, c0), centred=True)
        + vec3_cases(lambda v: sfit.refine(P, v))
        + number_cases(lambda v: sfit.refine(P, c0, 0, v), expect_bad=sfit.Error)
        + [(f"max_iters={m!r}", lambda m=m: sfit.refine(P, c0, m), exp)
           for m, exp in ((-1, sfit.ArgError), (2 ** 64 + 1, "ok"), (2 ** 70, "ok"),
                          (NAN, sfit.ArgError), (None, TypeError), ("x", ValueError), (1, "ok"),
                          (2.5, sfit.ArgError), (INF, sfit.ArgError), (3.0, "ok"),
                          (10 ** 6, "ok"), (RaisingFloat(), None))])
    T["uncertainty"] = (
        points_cases(lambda x: sfit.uncertainty(x, c0, 10.0, 1e-3), centred=True)
        + points_cases(lambda x: sfit.uncertainty(x, c0), centred=True)
        + vec3_cases(lambda v: sfit.uncertainty(P, v, 10.0, 1e-3))
        + vec3_cases(lambda v: sfit.uncertainty(P, v))
        + number_cases(lambda v: sfit.uncertainty(P, c0, v, 1e-3), expect_bad=sfit.Error)
        + number_cases(lambda v: sfit.uncertainty(P, c0, 10.0, v))
        + [("noise_var without radius", lambda: sfit.uncertainty(P, c0, None, 1e-3), sfit.ArgError),
           ("noise_var 'auto'", lambda: sfit.uncertainty(P, c0, 10.0, "auto"), sfit.ArgError)])

    # --- Moments -------------------------------------------------------------
    def fresh_m():
        return sfit.Moments(P)

    def bare_m():
        return sfit.Moments.__new__(sfit.Moments)  # __init__ never called

    T["Moments"] = (points_cases(lambda x: sfit.Moments(x), allow_one=True)
                    + [("no args", lambda: sfit.Moments(), "ok"),
                       ("two args", lambda: sfit.Moments(P, P), TypeError),
                       ("bad keyword", lambda: sfit.Moments(pts=P), TypeError),
                       ("re-__init__ with garbage",
                        lambda: state_case("re-init", fresh_m(), moments_state,
                                           lambda m: m.__init__(np.ones((4, 2))))[1](), sfit.ArgError),
                       ("re-__init__ with None", lambda: _reinit(fresh_m(), None), "ok"),
                       ("subclass", lambda: type("M", (sfit.Moments,), {})(P), "ok")])
    # Moments(x) with too few samples is a valid (empty or short) accumulator
    # Moments(None) is the documented empty accumulator; few samples are fine
    T["Moments"] = [(lab, fn, "ok" if exp in (sfit.TooFewError, sfit.Error) or lab == "None" else exp)
                    for lab, fn, exp in T["Moments"]]
    T["Moments.add"] = (
        [(lab, (lambda fn=fn: fn()), "ok" if _ok_like(exp) or exp in (sfit.TooFewError, sfit.Error) else exp)
         for lab, fn, exp in points_cases(
             lambda x: state_case("add", fresh_m(), moments_state, lambda m: m.add(x))[1](),
             allow_one=True, huge=True)]
        + [("before __init__", lambda: bare_m().add(P), "ok")])
    T["Moments.merge"] = [
        ("self", lambda: (lambda m: m.merge(m))(fresh_m()), None),
        ("None", lambda: fresh_m().merge(None), sfit.ArgError),
        ("Incremental", lambda: fresh_m().merge(sfit.Incremental()), sfit.ArgError),
        ("array", lambda: fresh_m().merge(P), sfit.ArgError),
        ("bare", lambda: fresh_m().merge(bare_m()), "ok"),
        ("into bare", lambda: bare_m().merge(fresh_m()), "ok"),
        ("subclass", lambda: fresh_m().merge(type("M", (sfit.Moments,), {})(P)), "ok"),
        ("C base", lambda: fresh_m().merge(sfit._sfit.Moments(P)), "ok")]
    T["Moments.reset"] = [("fresh", lambda: fresh_m().reset(), None),
                          ("bare", lambda: bare_m().reset(), None),
                          ("arg", lambda: fresh_m().reset(1), TypeError)]
    T["Moments.copy"] = [
        ("fresh", lambda: fresh_m().copy(), "ok"), ("bare", lambda: bare_m().copy(), "ok"),
        ("subclass", lambda: type("M", (sfit.Moments,), {})(P).copy(), "ok"),
        ("subclass __new__ -> int", lambda: _evil_instance(sfit.Moments, 42).copy(), TypeError),
        ("subclass __new__ -> Incremental",
         lambda: _evil_instance(sfit.Moments, sfit.Incremental()).copy(), TypeError),
        ("subclass __init__ needs args",
         lambda: type("M", (sfit.Moments,), {"__init__": lambda self, a, b: None})
         .__new__(type("M", (sfit.Moments,), {"__init__": lambda self, a, b: None})).copy(), None),
        ("pickle", lambda: pickle.dumps(fresh_m()), TypeError),
        ("copy.copy", lambda: __import__("copy").copy(fresh_m()), TypeError)]
    T["Moments.stats"] = [("fresh", lambda: fresh_m().stats(), "ok"),
                          ("bare", lambda: bare_m().stats(), sfit.TooFewError),
                          ("one sample", lambda: sfit.Moments(P[0]).stats(), sfit.TooFewError),
                          ("coincident", lambda: sfit.Moments(np.ones((20, 3))).stats(), None),
                          ("1e7 offset", lambda: sfit.Moments(P + 1e7).stats(), None)]
    for meth in ("fit", "solve"):
        T["Moments." + meth] = (
            [("fresh", lambda meth=meth: getattr(fresh_m(), meth)(), "ok"),
             ("bare", lambda meth=meth: getattr(bare_m(), meth)(), sfit.TooFewError),
             ("noise_var 'auto'", lambda meth=meth: getattr(fresh_m(), meth)(noise_var="auto"),
              sfit.ArgError),
             ("coincident", lambda meth=meth: getattr(sfit.Moments(np.ones((20, 3))), meth)(), sfit.Error),
             ("after failed fit", lambda meth=meth: _after_error(
                 fresh_m(), lambda m: getattr(m, meth)(mode="cube"), lambda m: getattr(m, meth)()), "ok"),
             ("planar_ratio nan", lambda meth=meth: getattr(fresh_m(), meth)(planar_ratio=NAN),
              sfit.ArgError)]
            + number_cases(lambda v, meth=meth: getattr(fresh_m(), meth)(noise_var=v))
            + mode_cases(lambda m, meth=meth: getattr(fresh_m(), meth)(mode=m))
            + cov_cases(lambda v, meth=meth: getattr(fresh_m(), meth)(noise_cov=v)))
    T["Moments.calibrate_noise"] = (
        vec3_cases(lambda v: fresh_m().calibrate_noise(v, 10.0))
        + number_cases(lambda v: fresh_m().calibrate_noise(c0, v), expect_bad=sfit.Error)
        + [("bare", lambda: bare_m().calibrate_noise(c0, 10.0), sfit.TooFewError)])
    T["Moments.uncertainty"] = (
        vec3_cases(lambda v: fresh_m().uncertainty(v, 10.0, 1e-3))
        + number_cases(lambda v: fresh_m().uncertainty(c0, v, 1e-3), expect_bad=sfit.Error)
        + number_cases(lambda v: fresh_m().uncertainty(c0, 10.0, v))
        + [("bare", lambda: bare_m().uncertainty(c0, 10.0, 1e-3), sfit.Error),
           ("estimated raising", lambda: fresh_m().uncertainty(c0, 10.0, 1e-3, RaisingFloat()),
            HostileError)])
    for prop in ("count", "rejected"):
        T["Moments." + prop] = [("fresh", lambda prop=prop: getattr(fresh_m(), prop), "ok"),
                                ("bare", lambda prop=prop: getattr(bare_m(), prop), "ok"),
                                ("set", lambda prop=prop: setattr(fresh_m(), prop, 5),
                                 AttributeError)]

    # --- Incremental -------------------------------------------------------
    def fresh_i(**kw):
        s = sfit.Incremental(**kw)
        s.start(P)
        return s

    def bare_i():
        return sfit.Incremental.__new__(sfit.Incremental)

    T["Incremental"] = (number_cases(lambda v: sfit.Incremental(noise_var=v))
                        + cov_cases(lambda v: sfit.Incremental(noise_cov=v), solves=False)
                        + [("noise_var 'auto'", lambda: sfit.Incremental(noise_var="auto"), sfit.ArgError),
                           ("both", lambda: sfit.Incremental(1e-3, np.eye(3)), sfit.ArgError),
                           ("re-__init__ with garbage", lambda: state_case(
                               "re-init", fresh_i(), incr_state,
                               lambda s: s.__init__(noise_var=-1))[1](), sfit.ArgError),
                           ("three args", lambda: sfit.Incremental(1, 2, 3), TypeError),
                           ("subclass", lambda: type("I", (sfit.Incremental,), {})(1e-4).start(P), "ok"),
                           ("subclass without super().__init__", lambda: type(
                               "I", (sfit.Incremental,), {"__init__": lambda self: None})().update(P),
                            "ok"),
                           ("pickle", lambda: pickle.dumps(fresh_i()), TypeError)])
    T["Incremental.start"] = (
        [(lab, fn, "ok" if isinstance(exp, Same) else exp) for lab, fn, exp in points_cases(
            lambda x: state_case("start", fresh_i(), incr_state, lambda s: s.start(x))[1]())]
        + [("before __init__", lambda: bare_i().start(P), "ok"),
           ("with noise 1e6", lambda: sfit.Incremental(noise_var=1e6).start(P), sfit.Error)])
    T["Incremental.add"] = (
        [(lab, fn, "ok" if _ok_like(exp) or exp in (sfit.TooFewError, sfit.Error) else exp)
         for lab, fn, exp in points_cases(
             lambda x: state_case("add", fresh_i(), incr_state, lambda s: s.add(x))[1](),
             allow_one=True)]
        + [("before __init__", lambda: bare_i().add(P), "ok")])
    T["Incremental.update"] = (
        [(lab, fn, None if isinstance(exp, Same) or lab.startswith("(3,)") else exp)
         for lab, fn, exp in points_cases(lambda x: sfit.Incremental().update(x), allow_one=True)]
        + [("before __init__", lambda: bare_i().update(P), "ok"),
           ("after failed add", lambda: _after_error(fresh_i(), lambda s: s.add("x"),
                                                      lambda s: s.update(P[0])), "ok")])
    for meth in ("fit", "estimate"):  # estimate: the 0.2 name of fit
        T["Incremental." + meth] = [
            ("fresh", lambda meth=meth: getattr(fresh_i(), meth)(), "ok"),
            ("empty", lambda meth=meth: getattr(sfit.Incremental(), meth)(), sfit.TooFewError),
            ("bare", lambda meth=meth: getattr(bare_i(), meth)(), sfit.TooFewError),
            ("coincident", lambda meth=meth: _est_after(np.ones((20, 3)), meth), sfit.Error),
            ("collinear", lambda meth=meth: _est_after(
                np.outer(np.arange(20.0), [1.0, 2.0, 3.0]), meth), sfit.Error),
            ("circle", lambda meth=meth: _est_after(circle(), meth), None)]
    T["Incremental.track"] = (
        [(lab, fn, None if _ok_like(exp) or exp in (sfit.TooFewError, sfit.Error) else exp)
         for lab, fn, exp in points_cases(lambda x: sfit.Incremental().track(x))]
        + [("before __init__", lambda: bare_i().track(P), "ok"),
           ("with noise 1e6", lambda: sfit.Incremental(noise_var=1e6).track(P), None)])
    T["Incremental.reset"] = [("fresh", lambda: fresh_i().reset(), None),
                              ("bare", lambda: bare_i().reset(), None),
                              ("arg", lambda: fresh_i().reset(1), TypeError)]
    for prop in ("count", "rejected"):
        T["Incremental." + prop] = [("fresh", lambda prop=prop: getattr(fresh_i(), prop), "ok"),
                                    ("bare", lambda prop=prop: getattr(bare_i(), prop), "ok"),
                                    ("set", lambda prop=prop: setattr(fresh_i(), prop, 5),
                                     AttributeError)]

    # --- result records ------------------------------------------------------
    res = {"FitResult": sfit.fit(P), "MultiResult": sfit.fit_multi([P, P]),
           "NoiseEstimate": sfit.calibrate_noise(P, c0, 10.0),
           "Uncertainty": sfit.uncertainty(P, c0, 10.0, 1e-3), "RefineResult": sfit.refine(P, c0),
           "Estimate": fresh_i().estimate(), "Track": sfit.Incremental().track(P)}
    res["C3D"] = sfit.read_c3d(_C3D_HIP)
    _imu_cases(T, res)
    if HAVE_JOINT:
        tpl, par, chi = _joint_data()
        res["Pose"] = sfit.Cluster(tpl).register(par[0])
        res["JointResult"] = sfit.joint_center(par, chi, mode="planar")
    for name, r in res.items():
        cls = getattr(sfit, name)
        T[name] = [("None", lambda cls=cls: cls(None), TypeError),
                   ("int", lambda cls=cls: cls(5), TypeError),
                   ("str", lambda cls=cls: cls("abc"), TypeError),
                   ("empty dict", lambda cls=cls: cls({}), None),
                   ("no args", lambda cls=cls: cls(), TypeError),
                   ("setattr", lambda r=r: setattr(r, "n", 1), AttributeError),
                   ("pickle round trip", lambda r=r: _pickle_equal(r), None if name == "JointResult"
                    else "ok")]
        T[name + ".to_dict"] = [("real", lambda r=r: r.to_dict(), "ok"),
                                ("of empty", lambda cls=cls: cls({}).to_dict(), None),
                                ("arg", lambda r=r: r.to_dict(1), TypeError)]

    if HAVE_JOINT:
        _joint_cases(T, res)
    _c3d_cases(T)
    _session_cases(T)
    return T


def _imu_cases(T, res):
    """imu_joint and ImuJointResult: shapes, types, rates, garbage values."""
    t = np.arange(400) / 200.0
    w = np.stack([np.sin(3 * t), np.cos(2 * t), np.sin(t)], axis=1) * 2.0
    a = np.stack([np.cos(t), np.sin(2 * t), 9.81 + 0 * t], axis=1)

    def call(x=None, which=0, rate=200.0):
        args = [a, w, a[:, ::-1], w[:, ::-1]]
        if x is not None:
            args[which] = x
        return sfit.imu_joint(*args, rate)
    T["imu_joint"] = (
        [("plain", lambda: call(), None),
         ("(N, 2)", lambda: call(a[:, :2]), sfit.ArgError),
         ("(N, 3, 1)", lambda: call(a[:, :, None]), sfit.ArgError),
         ("(3,)", lambda: call(a[0]), sfit.ArgError),
         ("lengths differ", lambda: call(w[:-1], 1), sfit.ArgError),
         ("None", lambda: call(None, 2) if False else sfit.imu_joint(None, w, a, w, 200.0),
          sfit.ArgError),
         ("str", lambda: sfit.imu_joint("abc", w, a, w, 200.0), sfit.ArgError),
         ("complex", lambda: call(a.astype(complex)), sfit.ArgError),
         ("object", lambda: sfit.imu_joint(a, w, a, object(), 200.0), sfit.ArgError),
         ("empty", lambda: sfit.imu_joint(*(np.zeros((0, 3)),) * 4, 200.0), sfit.TooFewError),
         ("NaN sample", lambda: call(np.where(np.arange(400)[:, None] == 7, np.nan, a)),
          sfit.NonFiniteError),
         ("1e30 sample", lambda: call(a * 1e30), sfit.RangeError),
         ("int32", lambda: call(np.rint(a).astype(np.int32)), None),
         ("float16", lambda: call(a.astype(np.float16)), None),
         ("big-endian", lambda: call(a.astype(">f8")), None),
         ("list", lambda: call(a.tolist()), None),
         ("all zero", lambda: sfit.imu_joint(*(np.zeros((400, 3)),) * 4, 200.0), None),
         ("1e4 rates", lambda: call(np.full((400, 3), 1e4), 1), None),
         ("unknown keyword", lambda: sfit.imu_joint(a, w, a, w, 200.0, bogus=1), TypeError)]
        + number_cases(lambda v: call(rate=v)))
    res["ImuJointResult"] = call()


_SRC = os.environ.get("SFIT_SOURCE_DIR", os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                       "..", "..", ".."))
_C3D_HIP = os.path.join(_SRC, "tests", "data", "c3d", "biobuddy_right_hip.c3d")
_C3D_CASES = os.path.join(_SRC, "tests", "data", "c3d", "cases")


def _c3d_cases(T):
    """read_c3d, write_c3d, write_trc: bad paths, malformed files, bad points."""
    import pathlib
    import tempfile
    tmp = tempfile.mkdtemp(prefix="sfit_hostile_c3d_")
    hip = _C3D_HIP
    with open(hip, "rb") as f:
        head = f.read(600)
    trunc = os.path.join(tmp, "trunc.c3d")
    with open(trunc, "wb") as f:
        f.write(head)
    empty = os.path.join(tmp, "empty.c3d")
    open(empty, "wb").close()
    out = os.path.join(tmp, "out.c3d")
    nowhere = os.path.join(tmp, "no", "such", "dir", "out.c3d")
    nf = 1690
    good = {"JC": np.tile([100.0, 200.0, 300.0], (nf, 1))}
    T["read_c3d"] = [
        ("hip", lambda: sfit.read_c3d(hip), "ok"),
        ("bytes path", lambda: sfit.read_c3d(hip.encode()), "ok"),
        ("pathlib", lambda: sfit.read_c3d(pathlib.Path(hip)), "ok"),
        ("None", lambda: sfit.read_c3d(None), TypeError),
        ("int", lambda: sfit.read_c3d(5), TypeError),
        ("NUL in path", lambda: sfit.read_c3d("a\0b"), ValueError),
        ("missing file", lambda: sfit.read_c3d(os.path.join(tmp, "none.c3d")), OSError),
        ("directory", lambda: sfit.read_c3d(tmp), (OSError, ValueError)),
        ("empty file", lambda: sfit.read_c3d(empty), ValueError),
        ("truncated", lambda: sfit.read_c3d(trunc), ValueError),
        ("analog conflict", lambda: sfit.read_c3d(os.path.join(_C3D_CASES, "analog_ambiguous.c3d")),
         ValueError),
        ("not a C3D file", lambda: sfit.read_c3d(__file__), ValueError)]
    for fn in ("write_c3d", "write_trc"):
        w = getattr(sfit, fn)
        T[fn] = [
            ("one point", lambda w=w: w(hip, out, good), "ok"),
            ("prefix", lambda w=w: w(hip, out, good, prefix="S1:"), "ok"),
            ("NaN frames", lambda w=w: w(hip, out, {"A": np.where(np.arange(nf)[:, None] % 3 == 0,
                                                                  np.nan, 1.0) * np.ones((nf, 3))}), "ok"),
            ("int dtype", lambda w=w: w(hip, out, {"A": np.ones((nf, 3), dtype=np.int16)}), "ok"),
            ("points list", lambda w=w: w(hip, out, [1, 2, 3]), sfit.ArgError),
            ("points {}", lambda w=w: w(hip, out, {}), sfit.ArgError),
            ("name int", lambda w=w: w(hip, out, {5: good["JC"]}), sfit.ArgError),
            ("name empty", lambda w=w: w(hip, out, {"": good["JC"]}), ValueError),
            ("name with tab", lambda w=w: w(hip, out, {"a\tb": good["JC"]}), ValueError),
            ("name 300 chars", lambda w=w: w(hip, out, {"x" * 300: good["JC"]}), ValueError),
            ("wrong frames", lambda w=w: w(hip, out, {"A": np.ones((nf - 1, 3))}), sfit.ArgError),
            ("(F, 2)", lambda w=w: w(hip, out, {"A": np.ones((nf, 2))}), sfit.ArgError),
            ("Inf", lambda w=w: w(hip, out, {"A": np.full((nf, 3), np.inf)}), sfit.ArgError),
            ("1e39", lambda w=w: w(hip, out, {"A": np.full((nf, 3), 1e39)}), sfit.ArgError),
            ("complex", lambda w=w: w(hip, out, {"A": np.ones((nf, 3), complex)}), sfit.ArgError),
            ("object", lambda w=w: w(hip, out, {"A": object()}), sfit.ArgError),
            ("str array", lambda w=w: w(hip, out, {"A": "abc"}), sfit.ArgError),
            ("__array__ raises", lambda w=w: w(hip, out, {"A": RaisingArray()}), HostileError),
            ("prefix int", lambda w=w: w(hip, out, good, prefix=5), TypeError),
            ("prefix 100 chars", lambda w=w: w(hip, out, good, prefix="p" * 100), ValueError),
            ("src missing", lambda w=w: w(os.path.join(tmp, "none.c3d"), out, good), OSError),
            ("src malformed", lambda w=w: w(trunc, out, good), ValueError),
            ("dst nowhere", lambda w=w: w(hip, nowhere, good), OSError),
            ("dst None", lambda w=w: w(hip, None, good), TypeError),
            ("no args", lambda w=w: w(), TypeError)]
    T["write_trc"].append(("no points", lambda: sfit.write_trc(hip, out), "ok"))



def _session_data(frames=120):
    """A synthetic session on arrays: a still pelvis of 4 markers, a thigh
    of 3 markers turning about a ball joint at (0, 0, -100)."""
    pel = np.array([[100.0, 80, 0], [100, -80, 0], [-60, 60, 10], [-60, -60, 10]])
    loc = np.array([[0.0, 60, -300], [50, 0, -250], [-40, -30, -420]])
    t = np.arange(frames) * 0.11
    out = {}
    thigh = []
    for f in range(frames):
        a, b = 0.5 * np.sin(t[f]), 0.4 * np.cos(1.7 * t[f])
        ra = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
        rb = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
        thigh.append((ra @ rb @ (loc - [0, 0, -100]).T).T + [0, 0, -100])
    thigh = np.array(thigh)
    for k, n in enumerate(["P1", "P2", "P3", "P4"]):
        out[n] = np.tile(pel[k], (frames, 1))
    for k, n in enumerate(["T1", "T2", "T3"]):
        out[n] = thigh[:, k]
    return out


_SESSION_MODEL = ("segment pelvis P1,P2,P3,P4\nsegment thigh T1,T2,T3\n"
                  "joint hip pelvis thigh ball HJC trial*\n")


def _session_cases(T):
    """session_model, calibrate, apply_session: bad models, sessions, trials."""
    import copy
    import tempfile
    tmp = tempfile.mkdtemp(prefix="sfit_hostile_session_")
    data = _session_data()
    path = os.path.join(tmp, "model.txt")
    with open(path, "w") as f:
        f.write(_SESSION_MODEL)
    good = {"trial1": data}
    T["session_model"] = [
        ("text", lambda: sfit.session_model(_SESSION_MODEL), "ok"),
        ("path", lambda: sfit.session_model(path), "ok"),
        ("bytes", lambda: sfit.session_model(_SESSION_MODEL.encode()), "ok"),
        ("None", lambda: sfit.session_model(None), sfit.ArgError),
        ("int", lambda: sfit.session_model(5), sfit.ArgError),
        ("unknown keyword", lambda: sfit.session_model("bone a A,B,C\n"), ValueError),
        ("NUL", lambda: sfit.session_model("segment a A,B,C\0\n"), ValueError),
        ("long line", lambda: sfit.session_model("#" * 5000 + "\n"), ValueError),
        ("cycle", lambda: sfit.session_model("segment a A,B,C\nsegment b D,E,F\njoint j a b ball P\n"
                                             "joint k b a ball Q\n"), ValueError),
        ("empty", lambda: sfit.session_model(""), ValueError)]
    sess = sfit.calibrate(_SESSION_MODEL, good)
    T["calibrate"] = [
        ("arrays", lambda: sfit.calibrate(_SESSION_MODEL, good), "ok"),
        ("model path", lambda: sfit.calibrate(path, good), "ok"),
        ("trials str", lambda: sfit.calibrate(_SESSION_MODEL, "trial1"), sfit.ArgError),
        ("trials None", lambda: sfit.calibrate(_SESSION_MODEL, None), sfit.ArgError),
        ("no match", lambda: sfit.calibrate(_SESSION_MODEL, {"other": data}), sfit.ArgError),
        ("marker missing", lambda: sfit.calibrate(_SESSION_MODEL, {"trial1": {k: v for k, v in data.items()
                                                                              if k != "T2"}}), sfit.ArgError),
        ("(F, 2) marker", lambda: sfit.calibrate(_SESSION_MODEL, {"trial1": dict(data, T1=data["T1"][:, :2])}),
         sfit.ArgError),
        ("frame counts differ", lambda: sfit.calibrate(_SESSION_MODEL, {"trial1": dict(data, T1=data["T1"][:5])}),
         sfit.ArgError),
        ("Inf", lambda: sfit.calibrate(_SESSION_MODEL, {"trial1": dict(data, T1=data["T1"] + np.inf)}),
         sfit.ArgError),
        ("1e300", lambda: sfit.calibrate(_SESSION_MODEL, {"trial1": dict(data, T1=data["T1"] * 1e300)}),
         sfit.ArgError),
        ("all NaN", lambda: sfit.calibrate(_SESSION_MODEL, {"trial1": {k: v * np.nan for k, v in data.items()}}),
         ValueError),
        ("still child", lambda: sfit.calibrate(_SESSION_MODEL, {"trial1": dict(
            data, T1=np.tile(data["T1"][0], (120, 1)), T2=np.tile(data["T2"][0], (120, 1)),
            T3=np.tile(data["T3"][0], (120, 1)))}), ValueError),
        ("str array", lambda: sfit.calibrate(_SESSION_MODEL, {"trial1": dict(data, T1="abc")}), sfit.ArgError),
        ("bad model", lambda: sfit.calibrate("segment a A\n", good), ValueError),
        ("no pattern", lambda: sfit.calibrate(_SESSION_MODEL.replace(" trial*", ""), good), sfit.ArgError)]

    def broken(**kw):
        s = copy.deepcopy(sess)
        s["joints"][0].update(kw)
        return s
    T["apply_session"] = [
        ("arrays", lambda: sfit.apply_session(sess, data), "ok"),
        ("session file", lambda: sfit.apply_session(_write_json(tmp, sess), data), "ok"),
        ("session None", lambda: sfit.apply_session(None, data), sfit.ArgError),
        ("session {}", lambda: sfit.apply_session({}, data), sfit.ArgError),
        ("not JSON", lambda: sfit.apply_session("{not json", data), sfit.ArgError),
        ("centre NaN", lambda: sfit.apply_session(broken(center=[np.nan, 0, 0]), data), sfit.ArgError),
        ("centre short", lambda: sfit.apply_session(broken(center=[1, 2]), data), ValueError),
        ("centre 1e40", lambda: sfit.apply_session(broken(center=[1e40, 0, 0]), data), ValueError),
        ("template collinear", lambda: sfit.apply_session(
            broken(template=[[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]]), data), ValueError),
        ("markers not a list", lambda: sfit.apply_session(broken(parent_markers="P1"), data), sfit.ArgError),
        ("marker missing", lambda: sfit.apply_session(sess, {k: v for k, v in data.items() if k != "P1"}),
         sfit.ArgError),
        ("object session", lambda: sfit.apply_session({"joints": [object()]}, data), sfit.ArgError),
        ("out with arrays", lambda: sfit.apply_session(sess, data, out=os.path.join(tmp, "x.c3d")), sfit.ArgError)]


def _write_json(tmp, obj):
    import json
    p = os.path.join(tmp, "session.json")
    with open(p, "w") as f:
        json.dump(obj, f)
    return p

def _joint_cases(T, res):
    tpl, par, chi = _joint_data()
    pose = res["Pose"]
    for meth in ("to_global", "to_segment"):
        T["Pose." + meth] = [
            ("(N, 3)", lambda meth=meth: getattr(pose, meth)(P), "ok"),
            ("(3,)", lambda meth=meth: getattr(pose, meth)(P[0]), "ok"),
            ("None", lambda meth=meth: getattr(pose, meth)(None), (TypeError, ValueError)),
            ("str", lambda meth=meth: getattr(pose, meth)("abc"), (TypeError, ValueError)),
            ("(N, 2)", lambda meth=meth: getattr(pose, meth)(P[:, :2]), ValueError),
            ("object", lambda meth=meth: getattr(pose, meth)(object()), sfit.ArgError),
            ("__array__ raises", lambda meth=meth: getattr(pose, meth)(RaisingArray()), HostileError)]

    def cl():
        return sfit.Cluster(tpl)

    def bare_cl():
        return sfit.Cluster.__new__(sfit.Cluster)

    def frames_cases(call, allow_one, base=par, one=False):
        """An argument of (F, M, 3) frames (one=True: a single (M, 3)
        frame; allow_one: (M, 3) is also accepted as one frame)."""
        f = np.asarray(base[0] if one else base, dtype=np.float64)
        mx = sfit.CLUSTER_MAX_MARKERS + 1
        many = np.zeros(f.shape[:-2] + (mx, 3)) + np.arange(mx)[:, None] * [1.0, 0.5, 0.25]
        many[..., 1] = np.arange(mx) ** 2
        c = [("float32", lambda: call(f.astype(np.float32)), "ok"),
             ("fortran", lambda: call(np.asfortranarray(f)), "ok"),
             ("negative stride", lambda: call(_negative_stride(f)), "ok"),
             ("big-endian", lambda: call(f.astype(">f8")), "ok"),
             ("list", lambda: call(f.tolist()), "ok"),
             ("int", lambda: call(np.rint(f).astype(np.int32)), "ok"),
             ("None", lambda: call(None), sfit.ArgError),
             ("str", lambda: call("abc"), sfit.ArgError),
             ("object", lambda: call(object()), sfit.ArgError),
             ("__array__ raises", lambda: call(RaisingArray()), sfit.ArgError),
             ("__array__ -> str", lambda: call(GarbageArray("x")), sfit.ArgError),
             ("complex", lambda: call(f.astype(complex)), sfit.ArgError),
             ("bool", lambda: call(f > 0), sfit.ArgError),
             ("object dtype", lambda: call(f.astype(object)), sfit.ArgError),
             ("(..., 2)", lambda: call(f[..., :2]), sfit.ArgError),
             ("(..., 4)", lambda: call(np.concatenate([f, f[..., :1]], axis=-1)), sfit.ArgError),
             ("4-D", lambda: call(f.reshape((1,) * (5 - f.ndim) + f.shape)[0]), sfit.ArgError),
             ("(3,)", lambda: call(f.reshape(-1, 3)[0]), sfit.ArgError),
             ("no frames / no markers", lambda: call(f[:0]), None),
             ("(..., 0, 3)", lambda: call(f[..., :0, :]), sfit.Error),
             ("NaN entry", lambda: call(_with_row(f, (1, 1), NAN)), None),
             ("all NaN", lambda: call(np.full_like(f, NAN)), None),
             ("Inf entry", lambda: call(_with_row(f, (1, 1), INF)), None),
             ("1e38 entry", lambda: call(_with_row(f, (1, 1), 1e38)), None),
             ("-1e38 entry", lambda: call(_with_row(f, (1, 1), -1e38)), None),
             ("2**27 entry", lambda: call(_with_row(f, (1, 1), 2.0 ** 27)), None),
             ("1e300 entry", lambda: call(_with_row(f, (1, 1), 1e300)), None),
             ("coincident", lambda: call(np.ones_like(f)), None),
             ("collinear", lambda: call(np.broadcast_to(
                 np.outer(np.arange(f.shape[-2], dtype=float), [1.0, 2.0, 3.0]), f.shape)), None),
             ("too many markers", lambda: call(many), sfit.ArgError)]
        if not one:
            c.append(("(M, 3) one frame", lambda: call(f[0]), None if allow_one else sfit.ArgError))
            c.append(("2**32 + 1 frames (broadcast view)",
                      lambda: call(np.broadcast_to(f[:1], (2 ** 32 + 1,) + f.shape[1:])),
                      sfit.RangeError))
        return c

    T["Cluster"] = (
        frames_cases(lambda x: sfit.Cluster(x), True, one=True)
        + [("None", lambda: sfit.Cluster(None), sfit.ArgError),
           ("no args", lambda: sfit.Cluster(), TypeError),
           ("two markers", lambda: sfit.Cluster(tpl[:2]), sfit.Error),
           ("(F, M, 3)", lambda: sfit.Cluster(par), sfit.ArgError),
           ("re-__init__ with garbage", lambda: _reinit_cluster(cl(), tpl[:, :2]), sfit.ArgError),
           ("re-__init__ with 2 markers", lambda: _reinit_cluster(cl(), tpl[:2]), sfit.Error),
           ("pickle", lambda: pickle.dumps(cl()), TypeError)])
    T["Cluster.from_frames"] = (
        frames_cases(lambda x: sfit.Cluster.from_frames(x), True)
        + [("subclass", lambda: type("C", (sfit.Cluster,), {}).from_frames(par), "ok"),
           ("subclass __new__ -> list", lambda: _sub_new_returns(sfit.Cluster, [1, 2]).from_frames(par),
            TypeError),
           ("subclass __new__ -> Moments",
            lambda: _sub_new_returns(sfit.Cluster, sfit.Moments()).from_frames(par), TypeError),
           ("subclass __init__ raises", lambda: type("C", (sfit.Cluster,), {
               "__init__": lambda self, *a: (_ for _ in ()).throw(HostileError("init"))})
            .from_frames(par), None)])
    T["Cluster.register"] = (
        frames_cases(lambda x: cl().register(x), True, one=True)
        + [("(F, M, 3)", lambda: cl().register(par), sfit.ArgError),
           ("wrong marker count", lambda: cl().register(par[0, :3]), sfit.ArgError),
           ("bare cluster", lambda: bare_cl().register(par[0]), sfit.ArgError),
           ("bare cluster, (0, 3)", lambda: bare_cl().register(np.zeros((0, 3))), sfit.Error)])
    for prop in ("positions", "count", "frames_used"):
        T["Cluster." + prop] = [("fresh", lambda prop=prop: getattr(cl(), prop), "ok"),
                                ("bare", lambda prop=prop: getattr(bare_cl(), prop), "ok"),
                                ("set", lambda prop=prop: setattr(cl(), prop, 5), AttributeError)]

    def jt(**kw):
        j = sfit.Joint(cl(), 2, **kw)
        j.add(par, chi)
        return j

    def bare_j():
        return sfit.Joint.__new__(sfit.Joint)

    def joint_state(j):
        try:
            r = j.solve()
            s = (r.center.tobytes(), r.radii.tobytes())
        except sfit.Error as e:
            s = e.status
        return (j.frames, j.rejected_frames, s)

    T["Joint"] = (
        number_cases(lambda v: sfit.Joint(cl(), 2, noise_var=v))
        + number_cases(lambda v: sfit.Joint(cl(), 2, marker_noise_var=v))
        + cov_cases(lambda v: sfit.Joint(cl(), 2, noise_cov=v), solves=False)
        + mode_cases(lambda m: sfit.Joint(cl(), 2, mode=m))
        + [(f"n_child={k!r}", lambda k=k: sfit.Joint(cl(), k), exp)
           for k, exp in ((0, sfit.ArgError), (-1, (sfit.ArgError, OverflowError)),
                          (sfit.JOINT_MAX_CHILD + 1, sfit.ArgError), (2 ** 64 + 1, sfit.ArgError),
                          (1.5, TypeError), (None, TypeError), ("2", TypeError),
                          (True, None))]
        + [("parent None", lambda: sfit.Joint(None, 2), sfit.ArgError),
           ("parent array", lambda: sfit.Joint(tpl, 2), sfit.ArgError),
           ("parent bare cluster", lambda: sfit.Joint(bare_cl(), 2), sfit.ArgError),
           ("weight bogus", lambda: sfit.Joint(cl(), 2, weight="bogus"), sfit.ArgError),
           ("planar_ratio nan", lambda: sfit.Joint(cl(), 2, planar_ratio=NAN), sfit.ArgError),
           ("noise_var 'auto'", lambda: sfit.Joint(cl(), 2, noise_var="auto"), sfit.ArgError),
           ("marker + noise_var", lambda: sfit.Joint(cl(), 2, noise_var=1, marker_noise_var=1),
            sfit.ArgError),
           ("re-__init__ with garbage", lambda: state_case(
               "re-init", jt(), joint_state, lambda j: j.__init__(cl(), 0))[1](), sfit.ArgError),
           ("re-__init__ with a bad option", lambda: state_case(
               "re-init", jt(), joint_state, lambda j: j.__init__(cl(), 2, mode="cube"))[1](),
            sfit.ArgError),
           ("pickle", lambda: pickle.dumps(jt()), TypeError),
           ("subclass", lambda: type("J", (sfit.Joint,), {})(cl(), 2).add(par, chi), "ok")])
    chi1 = chi  # (F, 2, 3)
    T["Joint.add"] = (
        [(lab, fn, exp) for lab, fn, exp in frames_cases(
            lambda x: state_case("add parent", jt(), joint_state, lambda j: j.add(x, chi1))[1](),
            True)]
        + [(lab, fn, exp) for lab, fn, exp in frames_cases(
            lambda x: state_case("add child", jt(), joint_state, lambda j: j.add(par, x))[1](),
            True, base=chi)]
        + [("frame count mismatch", lambda: jt().add(par, chi[:-1]), sfit.ArgError),
           ("one vs many", lambda: jt().add(par[0], chi), sfit.ArgError),
           ("child count mismatch", lambda: jt().add(par, chi[:, :1]), sfit.ArgError),
           ("before __init__", lambda: bare_j().add(par, chi), sfit.ArgError),
           ("after failed __init__", lambda: _after_failed_joint_init(cl()), sfit.ArgError),
           ("one arg", lambda: jt().add(par), TypeError)])
    for meth in ("solve", "fit"):
        T["Joint." + meth] = [("fresh", lambda meth=meth: getattr(jt(mode="planar"), meth)(), "ok"),
                              ("auto", lambda meth=meth: getattr(jt(), meth)(), None),
                              ("empty", lambda meth=meth: getattr(sfit.Joint(cl(), 2), meth)(),
                               sfit.TooFewError),
                              ("before __init__", lambda meth=meth: getattr(bare_j(), meth)(),
                               sfit.ArgError),
                              ("twice", lambda meth=meth: (lambda j: (getattr(j, meth)(),
                                                                      getattr(j, meth)()))(
                                  jt(mode="planar")), "ok")]
    jres = jt(mode="planar").solve()
    T["Joint.center_at"] = (
        frames_cases(lambda x: jt(mode="planar").center_at(jres, x), True)
        + [("result None", lambda: jt().center_at(None, par), sfit.ArgError),
           ("foreign raw bytes", lambda: jt().center_at(_fake_result(jres, b"\xff"), par), None),
           ("NaN raw bytes", lambda: jt().center_at(_fake_result(jres, NAN), par), None),
           ("short raw bytes", lambda: jt().center_at(_fake_result(jres, b"x"), par), sfit.ArgError),
           ("raw str", lambda: jt().center_at(_fake_result(jres, "abc"), par), sfit.ArgError),
           ("wrong marker count", lambda: jt().center_at(jres, par[:, :3]), sfit.ArgError),
           ("before __init__", lambda: bare_j().center_at(jres, par), sfit.ArgError)])
    T["Joint.noise_cov"] = (number_cases(lambda v: jt().noise_cov(v))
                            + [("before __init__", lambda: bare_j().noise_cov(0.1), sfit.ArgError),
                               ("empty joint", lambda: sfit.Joint(cl(), 2).noise_cov(0.1), None)])
    T["Joint.reset"] = [("fresh", lambda: jt().reset(), None), ("bare", lambda: bare_j().reset(), None),
                        ("arg", lambda: jt().reset(1), TypeError)]
    for prop in ("frames", "rejected_frames"):
        T["Joint." + prop] = [("fresh", lambda prop=prop: getattr(jt(), prop), "ok"),
                              ("bare", lambda prop=prop: getattr(bare_j(), prop), "ok"),
                              ("set", lambda prop=prop: setattr(jt(), prop, 5), AttributeError)]
    T["joint_center"] = (
        frames_cases(lambda x: sfit.joint_center(x, chi, mode="planar"), False)
        + frames_cases(lambda x: sfit.joint_center(par, x, mode="planar"), False, base=chi)
        + [("template Cluster", lambda: sfit.joint_center(par, chi, cl(), mode="planar"), "ok"),
           ("template array", lambda: sfit.joint_center(par, chi, tpl, mode="planar"), "ok"),
           ("template garbage", lambda: sfit.joint_center(par, chi, "abc"), sfit.ArgError),
           ("template bare cluster", lambda: sfit.joint_center(par, chi, bare_cl()), sfit.ArgError),
           ("child (F, 0, 3)", lambda: sfit.joint_center(par, chi[:, :0]), sfit.ArgError),
           ("child None", lambda: sfit.joint_center(par, None), sfit.ArgError),
           ("child __array__ raises", lambda: sfit.joint_center(par, RaisingArray()), None),
           ("frame count mismatch", lambda: sfit.joint_center(par, chi[:-1]), sfit.ArgError),
           ("repair_swaps False", lambda: sfit.joint_center(par, chi, repair_swaps=False), "ok"),
           ("repair_swaps None", lambda: sfit.joint_center(par, chi, repair_swaps=None), "ok")]
        + mode_cases(lambda m: sfit.joint_center(par, chi, mode=m))
        + number_cases(lambda v: sfit.joint_center(par, chi, noise_var=v)))


# --- helpers of the table ---------------------------------------------------

def _evil_instance(base, value):
    cls = _sub_new_returns(base, value)
    obj = base.__new__(cls)
    base.__init__(obj, P)
    return obj


def _reinit(m, arg):
    m.__init__(arg)
    return m


def _reinit_cluster(c, arg):
    before = c.positions.tobytes(), c.count, c.frames_used
    try:
        c.__init__(arg)
    finally:
        after = c.positions.tobytes(), c.count, c.frames_used
        if after != before:
            raise AssertionError("Cluster re-__init__ with garbage changed the template")


def _after_error(obj, bad, good):
    try:
        bad(obj)
    except ALLOWED:
        pass
    else:
        raise AssertionError("the bad call did not raise")
    return good(obj)


def _est_after(x, meth="fit"):
    s = sfit.Incremental()
    s.add(x)
    return getattr(s, meth)()


def _after_failed_joint_init(c):
    j = sfit.Joint.__new__(sfit.Joint)
    try:
        j.__init__(c, 0)
    except sfit.ArgError:
        pass
    return j.add(np.zeros((2, 4, 3)), np.zeros((2, 2, 3)))


def _fake_result(res, raw):
    d = {k: getattr(res, k) for k in type(res).__slots__}
    if isinstance(raw, float):
        raw = np.full(len(res._raw) // 4, raw, dtype=np.float32).tobytes()
    elif raw == b"\xff":
        raw = b"\xff" * len(res._raw)
    d["_raw"] = raw
    return type(res)(d)


def _multi_mutating(how):
    lst = []

    class Mutator:
        def __array__(self, dtype=None, copy=None):
            if how == "clear":
                lst.clear()
            elif how == "grow":
                lst.extend([P] * 100)
            else:
                lst[:] = [object()] * len(lst)
            import gc
            gc.collect()
            return P

    lst[:] = [Mutator(), Mutator(), P, np.array(P), sphere(seed=9), sphere(seed=10)]
    return sfit.fit_multi(lst)


def _pickle_equal(r):
    r2 = pickle.loads(pickle.dumps(r))
    assert type(r2) is type(r)
    for k in type(r).__slots__:
        a, b = getattr(r, k), getattr(r2, k)
        if isinstance(a, np.ndarray):
            assert np.array_equal(a, b, equal_nan=True), k
        elif k not in ("cluster",):
            assert a == b or (a != a and b != b), k
    return r2


# Everything above, underscored names too, for the next file's "import *".
__all__ = [n for n in dir() if not n.startswith("__")]
