/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_joint.c
 * @brief libFuzzer harness: the rigid cluster (sfit_cluster.h) and the
 * streaming joint centre (sfit_joint.h) driven by a little program of
 * hostile frames, templates, options and garbage state bytes. After every
 * operation:
 *  - every call returns one of the sfit_status_t values;
 *  - a rejected frame / template leaves the state (template, joint) byte
 *    for byte unchanged; a failed solve / register / centre_at leaves its
 *    sentinel-filled outputs untouched;
 *  - an SFIT_OK pose is finite and a proper rotation to 1e-3, an accepted
 *    frame increments the frame count by one, every float of an SFIT_OK
 *    result is finite.
 *
 * Program format: [opcode byte][operands]...; opcodes in tests/fuzz/README.md.
 */
#include "fuzz_common.h"

#include "sfit/sfit_cluster.h"
#include "sfit/sfit_joint.h"

#define FZ_MAXM 10 /* markers per frame read (more than SFIT_CLUSTER_MAX_MARKERS) */
#define FZ_MAXF 6  /* frames of the from_frames buffer */
#define FZ_MAX_OPS 128

enum fz_jop {
    JOP_TPL_INIT = 0, /* count, samples: sfit_cluster_init */
    JOP_TPL_FRAME,    /* count, samples: sfit_cluster_from_frame */
    JOP_TPL_FRAMES,   /* nframes, count, moved frames: sfit_cluster_from_frames */
    JOP_JOINT_INIT,   /* n_child, config */
    JOP_ADD,          /* n_parent, n_child, a frame (moved template + perturbations) */
    JOP_REGISTER,     /* count, a frame: sfit_cluster_register */
    JOP_SOLVE,        /* - */
    JOP_CENTER_AT,    /* n_parent, a frame */
    JOP_GARBAGE,      /* target, offset, length, bytes: overwrite state bytes */
    JOP_RESET,        /* - */
    JOP_NULLS,        /* every entry point with NULL pointers */
    JOP_COUNT
};

typedef struct fz_jstate {
    sfit_cluster_t cl;
    sfit_joint_t j;
} fz_jstate_t;

static fz_jstate_t fz_s;
static sfit_cluster_track_t fz_trk; /* issue 30: tracked alongside every JOP_REGISTER */

/* A sample: a hostile float triple (selector bit 0) or a point near the
 * template, moved by a rotation about a byte-chosen axis and a far
 * translation (so that registrations succeed often), or NaN (occluded). */
static void fz_marker(fz_in_t *in, const float r[9], const float t[3], uint32_t i,
                      sfit_vec3_t *x)
{
    const uint8_t sel = fz_u8(in);
    int k;
    if ((sel & 3u) == 0u) {
        for (k = 0; k < 3; k++) {
            x->v[k] = fz_float(in);
        }
        return;
    }
    if ((sel & 3u) == 1u) {
        x->v[0] = NAN;
        x->v[1] = 0.0f;
        x->v[2] = 0.0f;
        return;
    }
    {
        const sfit_vec3_t *p = &fz_s.cl.pos[i % SFIT_CLUSTER_MAX_MARKERS];
        float q[3];
        for (k = 0; k < 3; k++) {
            q[k] = fz_finite(p->v[k]) ? p->v[k] : 0.0f;
            if ((sel & 4u) != 0u) {
                q[k] += ldexpf((float)(int8_t)fz_u8(in), -4);
            }
        }
        for (k = 0; k < 3; k++) {
            x->v[k] = r[3 * k] * q[0] + r[3 * k + 1] * q[1] + r[3 * k + 2] * q[2] + t[k];
        }
    }
}

/* A rigid motion from 4 bytes: rotation about one of 8 axes by a byte
 * angle, translation 2.7 m away or at the origin. */
static void fz_motion(fz_in_t *in, float r[9], float t[3])
{
    static const float axes[8][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.6f, 0.8f, 0},
                                     {0, 0.6f, 0.8f}, {0.8f, 0, 0.6f}, {0.48f, 0.6f, 0.64f},
                                     {-0.6f, 0.64f, 0.48f}};
    const uint8_t a = fz_u8(in);
    const float ang = (float)fz_u8(in) * (6.2831853f / 256.0f);
    const float *u = axes[a & 7u];
    const float c = cosf(ang), s = sinf(ang), v = 1.0f - c;
    r[0] = c + u[0] * u[0] * v;
    r[1] = u[0] * u[1] * v - u[2] * s;
    r[2] = u[0] * u[2] * v + u[1] * s;
    r[3] = u[1] * u[0] * v + u[2] * s;
    r[4] = c + u[1] * u[1] * v;
    r[5] = u[1] * u[2] * v - u[0] * s;
    r[6] = u[2] * u[0] * v - u[1] * s;
    r[7] = u[2] * u[1] * v + u[0] * s;
    r[8] = c + u[2] * u[2] * v;
    t[0] = (a & 8u) ? 1500.0f : 0.0f;
    t[1] = (a & 8u) ? -2000.0f : 0.0f;
    t[2] = (a & 8u) ? 1000.0f : 0.0f;
}

static void fz_frame(fz_in_t *in, uint32_t n, sfit_vec3_t *x)
{
    float r[9], t[3];
    uint32_t i;
    fz_motion(in, r, t);
    for (i = 0; i < n; i++) {
        fz_marker(in, r, t, i, &x[i]);
    }
}

static void fz_check_pose(const sfit_pose_t *p)
{
    int a, b, k;
    FZ_CHECK(fz_all_finite(p->r.m, 9) && fz_all_finite(p->t.v, 3), "pose not finite");
    for (a = 0; a < 3; a++) {
        for (b = 0; b < 3; b++) {
            float s = 0.0f;
            for (k = 0; k < 3; k++) {
                s += p->r.m[3 * k + a] * p->r.m[3 * k + b];
            }
            FZ_CHECK(fabsf(s - (a == b ? 1.0f : 0.0f)) < 1e-3f, "pose not orthonormal");
        }
    }
    {
        const float *m = p->r.m;
        const float det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6])
                          + m[2] * (m[3] * m[7] - m[4] * m[6]);
        FZ_CHECK(det > 0.99f, "pose is a reflection");
    }
}

static void fz_op_tpl(fz_in_t *in, int from_frame)
{
    sfit_vec3_t x[FZ_MAXM];
    sfit_cluster_t before = fz_s.cl;
    const uint32_t n = fz_u8(in) % (FZ_MAXM + 1u);
    sfit_status_t st;
    fz_frame(in, n, x);
    st = from_frame ? sfit_cluster_from_frame(&fz_s.cl, x, n)
                    : sfit_cluster_init(&fz_s.cl, x, n);
    FZ_CHECK(fz_status_defined(st), "template: undefined status");
    if (st != SFIT_OK) {
        FZ_CHECK(memcmp(&before, &fz_s.cl, sizeof before) == 0, "template changed on failure");
    } else {
        FZ_CHECK(fz_s.cl.count == n, "template count");
    }
}

static void fz_op_frames(fz_in_t *in)
{
    static sfit_vec3_t fr[FZ_MAXF * FZ_MAXM];
    sfit_cluster_t before = fz_s.cl;
    const uint32_t nf = fz_u8(in) % (FZ_MAXF + 1u);
    const uint32_t n = fz_u8(in) % (FZ_MAXM + 1u);
    size_t used;
    uint32_t f;
    sfit_status_t st;
    for (f = 0; f < nf; f++) {
        fz_frame(in, n, &fr[f * n]);
    }
    memset(&used, FZ_SENTINEL, sizeof used);
    st = sfit_cluster_from_frames(&fz_s.cl, fr, nf, n, &used);
    FZ_CHECK_OUT(st, used, "from_frames used");
    if (st != SFIT_OK) {
        FZ_CHECK(memcmp(&before, &fz_s.cl, sizeof before) == 0, "template changed on failure");
    } else {
        FZ_CHECK(used >= 1u && used <= nf, "from_frames used count");
        FZ_CHECK(fz_all_finite(&fz_s.cl.pos[0].v[0], 3u * n), "template not finite");
    }
}

static void fz_op_joint_init(fz_in_t *in)
{
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    static sfit_joint_t before;
    sfit_status_t st;
    cfg.n_child = fz_u8(in) % (SFIT_JOINT_MAX_CHILD + 2u);
    fz_cfg_decode(in, &cfg.solve.fit, 0);
    cfg.solve.weight = (sfit_multi_weight_t)(fz_u8(in) % 3u);
    cfg.noise_model = (sfit_joint_noise_t)(fz_u8(in) % 3u); /* 2 is invalid */
    before = fz_s.j;
    st = sfit_joint_init(&fz_s.j, &fz_s.cl, &cfg);
    FZ_CHECK(fz_status_defined(st), "joint_init: undefined status");
    if (st != SFIT_OK) {
        FZ_CHECK(memcmp(&before, &fz_s.j, sizeof before) == 0, "joint changed on failed init");
    } else {
        FZ_CHECK(fz_s.j.frames == 0u, "joint_init frames");
    }
}

static void fz_op_add(fz_in_t *in)
{
    static sfit_joint_t before;
    sfit_vec3_t par[FZ_MAXM], chi[SFIT_JOINT_MAX_CHILD + 1u];
    sfit_pose_t pose;
    const uint8_t sel = fz_u8(in);
    /* Mostly the state's own counts; sometimes a mismatch. */
    const uint32_t np = (sel & 1u) ? fz_u8(in) % (FZ_MAXM + 1u) : (fz_s.j.parent.count % (FZ_MAXM + 1u));
    const uint32_t nc = (sel & 2u) ? fz_u8(in) % (SFIT_JOINT_MAX_CHILD + 2u)
                                   : (fz_s.j.cfg.n_child % (SFIT_JOINT_MAX_CHILD + 2u));
    float r[9], t[3], r2[9], t2[3];
    uint32_t i, frames0;
    sfit_status_t st;
    fz_motion(in, r, t);
    fz_motion(in, r2, t2); /* the child's own motion: its markers move in the parent frame */
    for (i = 0; i < np; i++) {
        fz_marker(in, r, t, i, &par[i]);
    }
    for (i = 0; i < nc; i++) {
        fz_marker(in, r2, t2, i, &chi[i]);
    }
    before = fz_s.j;
    frames0 = fz_s.j.frames;
    memset(&pose, FZ_SENTINEL, sizeof pose);
    st = sfit_joint_add(&fz_s.j, par, np, chi, nc, &pose);
    FZ_CHECK_OUT(st, pose, "joint_add pose");
    if (st != SFIT_OK) {
        FZ_CHECK(memcmp(&before, &fz_s.j, sizeof before) == 0, "joint changed on a rejected frame");
    } else {
        FZ_CHECK(fz_s.j.frames == frames0 + 1u, "frame count");
        fz_check_pose(&pose);
    }
}

static void fz_op_register(fz_in_t *in)
{
    sfit_vec3_t x[FZ_MAXM];
    sfit_pose_t pose;
    sfit_cluster_fit_t fit;
    const sfit_cluster_t before = fz_s.cl;
    const uint32_t n = (fz_u8(in) & 1u) ? fz_u8(in) % (FZ_MAXM + 1u) : (fz_s.cl.count % (FZ_MAXM + 1u));
    sfit_status_t st;
    fz_frame(in, n, x);
    memset(&pose, FZ_SENTINEL, sizeof pose);
    memset(&fit, FZ_SENTINEL, sizeof fit);
    st = sfit_cluster_register(&fz_s.cl, x, n, &pose, &fit);
    FZ_CHECK_OUT(st, pose, "register pose");
    FZ_CHECK_OUT(st, fit, "register fit");
    FZ_CHECK(memcmp(&before, &fz_s.cl, sizeof before) == 0, "register changed the template");
    if (st == SFIT_OK) {
        fz_check_pose(&pose);
        FZ_CHECK(fz_finite(fit.rms) && fit.rms >= 0.0f && fit.used >= 3u && fit.used <= n,
                 "register fit");
    }
    /* The same frame from the previous registration's rotation (no input
     * bytes: the corpus keeps its meaning): the status of the full solve
     * (its Jacobi bound aside), a proper finite pose, the state kept on a
     * rejected frame and forgotten on a gap. */
    {
        const sfit_cluster_track_t tb = fz_trk;
        sfit_pose_t tp;
        sfit_status_t tst;
        memset(&tp, FZ_SENTINEL, sizeof tp);
        tst = sfit_cluster_track(&fz_s.cl, &fz_trk, x, n, &tp, NULL);
        FZ_CHECK_OUT(tst, tp, "track pose");
        FZ_CHECK(tst == st || st == SFIT_E_NO_CONVERGENCE, "track status differs from register");
        if (tst == SFIT_OK) {
            fz_check_pose(&tp);
            FZ_CHECK(fz_byte(&fz_trk.valid) == 1u, "track state after OK");
        } else if (tst == SFIT_E_TOO_FEW) {
            FZ_CHECK(fz_byte(&fz_trk.valid) == 0u, "track gap");
        } else {
            FZ_CHECK(memcmp(&tb, &fz_trk, sizeof tb) == 0, "track state changed by a rejected frame");
        }
    }
}

/* The per-marker noise models and the solve with them (no input bytes: the
 * corpus keeps its meaning): defined statuses, outputs untouched on
 * failure, finite on success, state unchanged. */
static void fz_noise_models(void)
{
    static sfit_joint_t before;
    sfit_multi_noise_t nl[SFIT_JOINT_MAX_CHILD];
    sfit_multi_result_t mr;
    sfit_status_t st;
    uint32_t k;
    before = fz_s.j;
    memset(nl, FZ_SENTINEL, sizeof nl);
    st = sfit_joint_marker_noise(&fz_s.j, 0.25f, nl);
    FZ_CHECK_OUT(st, nl, "marker_noise models");
    FZ_CHECK(memcmp(&before, &fz_s.j, sizeof before) == 0, "marker_noise changed the state");
    if (st != SFIT_OK) {
        return;
    }
    for (k = 0; k < fz_s.j.cfg.n_child; k++) {
        FZ_CHECK(fz_all_finite(nl[k].cov.m, 9) && fz_all_finite(nl[k].skew.v, 3),
                 "marker_noise not finite");
    }
    memset(&mr, FZ_SENTINEL, sizeof mr);
    st = sfit_multi_fit_noise(fz_s.j.child, fz_s.j.cfg.n_child, NULL, nl, &mr, NULL);
    FZ_CHECK_OUT(st, mr, "multi_fit_noise result");
    if (st == SFIT_OK) {
        sfit_mat3_t cov;
        FZ_CHECK(fz_all_finite(mr.center.v, 3) && fz_all_finite(mr.axis.v, 3),
                 "multi_fit_noise not finite");
        memset(&cov, FZ_SENTINEL, sizeof cov);
        st = sfit_multi_center_cov(fz_s.j.child, fz_s.j.cfg.n_child, NULL, &mr, 0.25f, &cov);
        FZ_CHECK_OUT(st, cov, "multi_center_cov");
        if (st == SFIT_OK) {
            FZ_CHECK(fz_all_finite(cov.m, 9), "multi_center_cov not finite");
        }
    }
}

static void fz_op_solve(void)
{
    static sfit_joint_t before;
    sfit_joint_result_t res;
    float radii[SFIT_JOINT_MAX_CHILD];
    sfit_status_t st;
    before = fz_s.j;
    memset(&res, FZ_SENTINEL, sizeof res);
    memset(radii, FZ_SENTINEL, sizeof radii);
    st = sfit_joint_fit(&fz_s.j, &res, radii);
    FZ_CHECK_OUT(st, res, "joint_solve result");
    FZ_CHECK_OUT(st, radii, "joint_solve radii");
    FZ_CHECK(memcmp(&before, &fz_s.j, sizeof before) == 0, "solve changed the state");
    if (st == SFIT_OK) {
        FZ_CHECK(fz_all_finite(res.fit.center.v, 3) && fz_all_finite(res.fit.axis.v, 3)
                     && fz_finite(res.residual_mean) && fz_finite(res.residual_max),
                 "joint result not finite");
        FZ_CHECK(fz_all_finite(radii, fz_s.j.cfg.n_child), "radii not finite");
        FZ_CHECK(res.frames == fz_s.j.frames, "result frames");
    }
    fz_noise_models();
}

static void fz_op_center_at(fz_in_t *in)
{
    sfit_joint_result_t res;
    sfit_vec3_t x[FZ_MAXM], c, a;
    const uint32_t n = fz_s.j.parent.count % (FZ_MAXM + 1u);
    sfit_status_t st;
    memset(&res, 0, sizeof res);
    if (sfit_joint_fit(&fz_s.j, &res, NULL) != SFIT_OK) {
        res.fit.center.v[0] = fz_float(in); /* a result that is not a solve's */
        res.fit.axis.v[2] = fz_float(in);
    }
    fz_frame(in, n, x);
    memset(&c, FZ_SENTINEL, sizeof c);
    memset(&a, FZ_SENTINEL, sizeof a);
    st = sfit_joint_center_at(&fz_s.j, &res, x, n, &c, &a);
    FZ_CHECK_OUT(st, c, "center_at centre");
    FZ_CHECK_OUT(st, a, "center_at axis");
    if (st == SFIT_OK) {
        FZ_CHECK(fz_all_finite(c.v, 3) && fz_all_finite(a.v, 3), "center_at not finite");
    }
    { /* the centre covariance over that one frame (child markers: the same points) */
        static sfit_joint_t before;
        sfit_vec3_t par[SFIT_CLUSTER_MAX_MARKERS], chi[SFIT_JOINT_MAX_CHILD];
        sfit_mat3_t cov;
        uint32_t k;
        memset(par, 0, sizeof par);
        memset(chi, 0, sizeof chi);
        for (k = 0; k < n && k < SFIT_CLUSTER_MAX_MARKERS; k++) {
            par[k] = x[k];
            chi[k % SFIT_JOINT_MAX_CHILD] = x[k];
        }
        before = fz_s.j;
        memset(&cov, FZ_SENTINEL, sizeof cov);
        st = sfit_joint_center_cov(&fz_s.j, &res, par, chi, 1u, 0.25f, &cov);
        FZ_CHECK_OUT(st, cov, "center_cov");
        FZ_CHECK(memcmp(&before, &fz_s.j, sizeof before) == 0, "center_cov changed the state");
        if (st == SFIT_OK) {
            FZ_CHECK(fz_all_finite(cov.m, 9), "center_cov not finite");
        }
    }
}

static void fz_op_garbage(fz_in_t *in)
{
    const uint8_t target = fz_u8(in);
    unsigned char *base = (target & 1u) ? (unsigned char *)&fz_s.j : (unsigned char *)&fz_s.cl;
    const size_t size = (target & 1u) ? sizeof fz_s.j : sizeof fz_s.cl;
    const size_t off = ((size_t)fz_u8(in) | ((size_t)fz_u8(in) << 8)) % size;
    size_t len = fz_u8(in) % 9u, k;
    for (k = 0; k < len && off + k < size; k++) {
        base[off + k] = fz_u8(in);
    }
}

static void fz_op_nulls(void)
{
    sfit_vec3_t x[4];
    sfit_pose_t pose;
    sfit_joint_result_t res;
    sfit_vec3_t c;
    memset(x, 0, sizeof x);
    memset(&pose, 0, sizeof pose);
    memset(&res, 0, sizeof res);
    FZ_CHECK(sfit_cluster_init(NULL, x, 4) == SFIT_E_ARG, "cluster_init NULL");
    FZ_CHECK(sfit_cluster_init(&fz_s.cl, NULL, 4) == SFIT_E_ARG, "cluster_init NULL tpl");
    FZ_CHECK(sfit_cluster_from_frame(NULL, x, 4) == SFIT_E_ARG, "from_frame NULL");
    FZ_CHECK(sfit_cluster_from_frames(NULL, x, 1, 4, NULL) == SFIT_E_ARG, "from_frames NULL");
    FZ_CHECK(sfit_cluster_register(NULL, x, 4, &pose, NULL) == SFIT_E_ARG, "register NULL");
    FZ_CHECK(sfit_cluster_register(&fz_s.cl, NULL, 4, &pose, NULL) == SFIT_E_ARG, "register NULL x");
    FZ_CHECK(sfit_cluster_register(&fz_s.cl, x, 4, NULL, NULL) == SFIT_E_ARG, "register NULL pose");
    FZ_CHECK(sfit_cluster_to_global(NULL, x, &c) == SFIT_E_ARG, "to_global NULL");
    FZ_CHECK(sfit_cluster_to_segment(&pose, x, NULL) == SFIT_E_ARG, "to_segment NULL");
    FZ_CHECK(sfit_joint_init(NULL, &fz_s.cl, NULL) == SFIT_E_ARG, "joint_init NULL");
    FZ_CHECK(sfit_joint_init(&fz_s.j, NULL, NULL) == SFIT_E_ARG, "joint_init NULL parent");
    FZ_CHECK(sfit_joint_reset(NULL) == SFIT_E_ARG, "reset NULL");
    FZ_CHECK(sfit_joint_add(NULL, x, 4, x, 1, NULL) == SFIT_E_ARG, "add NULL");
    FZ_CHECK(sfit_joint_add(&fz_s.j, NULL, 4, x, 1, NULL) == SFIT_E_ARG, "add NULL parent");
    FZ_CHECK(sfit_joint_add(&fz_s.j, x, 4, NULL, 1, NULL) == SFIT_E_ARG, "add NULL child");
    FZ_CHECK(sfit_joint_fit(NULL, &res, NULL) == SFIT_E_ARG, "solve NULL");
    FZ_CHECK(sfit_joint_fit(&fz_s.j, NULL, NULL) == SFIT_E_ARG, "solve NULL out");
    FZ_CHECK(sfit_joint_center_at(NULL, &res, x, 4, &c, NULL) == SFIT_E_ARG, "center_at NULL");
    FZ_CHECK(sfit_joint_center_at(&fz_s.j, NULL, x, 4, &c, NULL) == SFIT_E_ARG, "center_at NULL res");
    FZ_CHECK(sfit_joint_center_at(&fz_s.j, &res, x, 4, NULL, NULL) == SFIT_E_ARG, "center_at NULL c");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in_t in;
    int ops = 0;
    in.p = data;
    in.n = size;
    in.i = 0;
    memset(&fz_s, 0, sizeof fz_s);
    (void)sfit_cluster_track_reset(&fz_trk);
    while (fz_more(&in) && ops < FZ_MAX_OPS) {
        const uint8_t op = fz_u8(&in);
        ops++;
        switch ((enum fz_jop)(op % JOP_COUNT)) {
        case JOP_TPL_INIT: fz_op_tpl(&in, 0); break;
        case JOP_TPL_FRAME: fz_op_tpl(&in, 1); break;
        case JOP_TPL_FRAMES: fz_op_frames(&in); break;
        case JOP_JOINT_INIT: fz_op_joint_init(&in); break;
        case JOP_ADD: fz_op_add(&in); break;
        case JOP_REGISTER: fz_op_register(&in); break;
        case JOP_SOLVE: fz_op_solve(); break;
        case JOP_CENTER_AT: fz_op_center_at(&in); break;
        case JOP_GARBAGE: fz_op_garbage(&in); break;
        case JOP_RESET: {
            static sfit_joint_t before;
            sfit_status_t st;
            before = fz_s.j;
            st = sfit_joint_reset(&fz_s.j);
            FZ_CHECK(fz_status_defined(st), "reset: undefined status");
            if (st != SFIT_OK) {
                FZ_CHECK(memcmp(&before, &fz_s.j, sizeof before) == 0, "reset changed on failure");
            }
            break;
        }
        case JOP_NULLS: fz_op_nulls(); break;
        case JOP_COUNT:
        default: break;
        }
    }
    return 0;
}
