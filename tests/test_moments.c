/* SPDX-License-Identifier: MIT */
/**
 * @file test_moments.c
 * @brief Streaming accumulator: statistics vs the double reference on
 * far-offset data, merge == sequential adds, rejected samples leave the
 * state byte-identical, the compensated second moments, every error path.
 */
#include "test_cmocka.h"

#include <float.h>
#include <stddef.h>
#include <string.h>

#include "sfit_ref.h"

#define NMAX 20000
static double g_pts[NMAX][3];
static sfit_vec3_t g_fpts[NMAX];

/* Cap samples around a far centre, rounded to float; g_pts holds the
 * float values as doubles so the reference sees exactly the same data. */
static void make_cap(uint64_t seed, size_t n, double theta, double sigma)
{
    const double c[3] = {2100.0, -1500.0, 900.0}; /* |c| ~ 2730 mm */
    const double axis[3] = {0.267261, 0.534522, 0.801784};
    tu_rng_t g;
    size_t i;
    tu_rng_seed(&g, seed);
    for (i = 0; i < n; i++) {
        double p[3];
        tu_sample_cap(&g, c, 100.0, axis, theta, sigma, p);
        tc_to_vec3(p, &g_fpts[i]);
        tc_to_double3(&g_fpts[i], g_pts[i]);
    }
}

/* Compare stats of the accumulator with ref_moments on g_pts[0..n). The
 * tolerances are relative to the data's own scales: the mean to 2 ulps of
 * its magnitude plus 1e-6 of the spread; C to 1e-5 of its largest
 * eigenvalue; S to 1e-5 of r^3 (|S| is O(r^3); 2e-6 passes). These are
 * well above the rounding of two-level summation with N <= 2e4 and far
 * below what a wrong shift formula gives (checked: >1e-4 r^3). */
static void check_stats(const sfit_moments_t *m, size_t n)
{
    double mean[3], C[3][3], S[3], w[3], v[3][3];
    sfit_vec3_t fm, fs;
    sfit_mat3_t fc;
    int i, j;
    assert_int_equal(ref_moments(REF_C3(g_pts), n, mean, C, S), 0);
    assert_int_equal(sfit_moments_stats(m, &fm, &fc, &fs), SFIT_OK);
    ref_sym3_eig(REF_C3(C), w, v);
    for (i = 0; i < 3; i++) {
        assert_near(fm.v[i], mean[i], 2.0 * TC_FEPS * fabs(mean[i]) + 1e-6 * sqrt(w[2]), "mean");
        for (j = 0; j < 3; j++) {
            assert_near(fc.m[3 * i + j], C[i][j], 1e-5 * w[2], "C");
        }
        assert_near(fs.v[i], S[i], 1e-5 * 1e6, "S");
    }
    assert_int_equal(sfit_moments_count(m), (uint32_t)n);
}

static void test_stats_vs_reference(void **state)
{
    const double thetas[] = {0.5, 1.0, TU_PI};
    const size_t ns[] = {2, 3, 63, 64, 65, 1000, NMAX};
    size_t a, b;
    (void)state;
    for (a = 0; a < 3; a++) {
        for (b = 0; b < sizeof ns / sizeof ns[0]; b++) {
            sfit_moments_t m;
            make_cap(10 + a * 7 + b, ns[b], thetas[a], 1.0);
            assert_int_equal(sfit_moments_init(&m), SFIT_OK);
            assert_int_equal(sfit_moments_add_block(&m, g_fpts, ns[b], NULL), SFIT_OK);
            check_stats(&m, ns[b]);
        }
    }
}

/* The block fold keeps the rounding residue of the total's second moments
 * (Fast2Sum) as the next block's starting sums: over N = 2e4 samples (312
 * folds) the diagonal of C stays within 1.5 float ulps (relative 1.5
 * 2^-23: the sums' own rounding plus stats' division by N - 1) of the
 * double reference, on 8 full spheres far from the origin (0.85 measured).
 * Without the residues the error is a random walk of one rounding per
 * fold: 3.57 ulps on these seeds (checked by dropping them), so this
 * fails. */
static void test_compensated_second_moments(void **state)
{
    double worst = 0.0;
    uint64_t seed;
    (void)state;
    for (seed = 0u; seed < 8u; seed++) {
        double mean[3], C[3][3], S[3];
        sfit_moments_t m;
        sfit_mat3_t fc;
        int i;
        make_cap(200u + seed, NMAX, TU_PI, 1.0);
        assert_int_equal(sfit_moments_init(&m), SFIT_OK);
        assert_int_equal(sfit_moments_add_block(&m, g_fpts, NMAX, NULL), SFIT_OK);
        assert_int_equal(sfit_moments_stats(&m, NULL, &fc, NULL), SFIT_OK);
        assert_int_equal(ref_moments(REF_C3(g_pts), NMAX, mean, C, S), 0);
        for (i = 0; i < 3; i++) {
            const double e = fabs((double)fc.m[4 * i] - C[i][i]) / (C[i][i] * TC_FEPS);
            worst = (e > worst) ? e : worst;
        }
    }
    print_message("compensated C diagonal: worst %.2f ulps\n", worst);
    assert_true(worst <= 1.5);
}

static void test_add_equals_add_block(void **state)
{
    sfit_moments_t a, b;
    size_t i;
    (void)state;
    make_cap(3, 1000, 1.0, 2.0);
    (void)sfit_moments_init(&a);
    (void)sfit_moments_init(&b);
    for (i = 0; i < 1000; i++) {
        assert_int_equal(sfit_moments_add(&a, &g_fpts[i]), SFIT_OK);
    }
    assert_int_equal(sfit_moments_add_block(&b, g_fpts, 1000, NULL), SFIT_OK);
    assert_memory_equal(&a, &b, sizeof a); /* same operations, same bits */
}

/* The batch path keeps a run's sums in registers: from any prior state
 * (empty, mid-block, at a block's end) and in chunks of any size (one
 * sample, inside a block, exactly a block, across one or more block
 * ends), the state is bit for bit that of the same samples added one at
 * a time. */
static void test_add_block_chunks_bitwise(void **state)
{
    const size_t prior[] = {0, 1, 37, SFIT_SUM_BLOCK - 1, SFIT_SUM_BLOCK, 3 * SFIT_SUM_BLOCK + 5};
    const size_t chunk[] = {0, 1, 2, 5, SFIT_SUM_BLOCK - 1, SFIT_SUM_BLOCK, SFIT_SUM_BLOCK + 1,
                            2 * SFIT_SUM_BLOCK + 7, 333};
    size_t p, c;
    (void)state;
    make_cap(41, 2000, 1.0, 2.0);
    for (p = 0; p < sizeof prior / sizeof prior[0]; p++) {
        for (c = 0; c < sizeof chunk / sizeof chunk[0]; c++) {
            sfit_moments_t a, b;
            size_t i = 0, j;
            (void)sfit_moments_init(&a);
            (void)sfit_moments_init(&b);
            for (j = 0; j < prior[p]; j++) {
                assert_int_equal(sfit_moments_add(&a, &g_fpts[j]), SFIT_OK);
                assert_int_equal(sfit_moments_add(&b, &g_fpts[j]), SFIT_OK);
            }
            /* three chunks of this size, then one of the next size */
            for (j = 0; j < 4; j++) {
                const size_t k = (j < 3) ? chunk[c] : chunk[(c + 1) % (sizeof chunk / sizeof chunk[0])];
                size_t q;
                for (q = 0; q < k; q++) {
                    assert_int_equal(sfit_moments_add(&a, &g_fpts[prior[p] + i + q]), SFIT_OK);
                }
                assert_int_equal(sfit_moments_add_block(&b, &g_fpts[prior[p] + i], k, NULL), SFIT_OK);
                i += k;
                assert_memory_equal(&a, &b, sizeof a);
            }
        }
    }
}

/* The batch's one-test-per-coordinate screen against the full check at
 * the edges of the range: the same status and the first bad index. */
static void test_add_block_screen_edges(void **state)
{
    const float big = 134217728.0f; /* 2^SFIT_COORD_MAX_EXP */
    const float edge[][3] = {
        {134217720.0f, -134217720.0f, 0.0f}, /* largest accepted */
        {-0.0f, 1e-45f, -1e-40f},            /* zero, denormals */
        {FLT_MIN, -FLT_MIN, 1.0f},
        {big, 0, 0}, {0, -big, 0}, {0, 0, 3e38f}, {0, 0, -INFINITY},
        {NAN, big, 0}, {big, NAN, 0}, {-NAN, 0, 0}};
    const sfit_status_t want[] = {SFIT_OK, SFIT_OK, SFIT_OK, SFIT_E_RANGE, SFIT_E_RANGE,
                                  SFIT_E_RANGE, SFIT_E_NONFINITE, SFIT_E_NONFINITE,
                                  SFIT_E_NONFINITE, SFIT_E_NONFINITE};
    size_t k, pos;
    (void)state;
    make_cap(42, 10, 1.0, 1.0);
    for (k = 0; k < sizeof edge / sizeof edge[0]; k++) {
        for (pos = 0; pos < 5; pos++) {
            sfit_moments_t m, before, one;
            sfit_vec3_t blk[5];
            size_t idx = 999, i;
            memcpy(blk, g_fpts, sizeof blk);
            memcpy(blk[pos].v, edge[k], sizeof blk[pos].v);
            (void)sfit_moments_init(&m);
            (void)sfit_moments_add_block(&m, g_fpts + 5, 3, NULL);
            before = m;
            one = m;
            assert_int_equal(sfit_moments_add_block(&m, blk, 5, &idx), want[k]);
            if (want[k] == SFIT_OK) {
                assert_int_equal(idx, 999); /* written only on a rejection */
                for (i = 0; i < 5; i++) {
                    assert_int_equal(sfit_moments_add(&one, &blk[i]), SFIT_OK);
                }
                assert_memory_equal(&m, &one, sizeof m);
            } else {
                assert_int_equal(idx, pos);
                assert_memory_equal(&m, &before, sizeof m);
            }
        }
    }
    {
        /* two bad samples: the first one's status and index */
        sfit_moments_t m;
        sfit_vec3_t blk[4];
        size_t idx = 999;
        memcpy(blk, g_fpts, sizeof blk);
        blk[1].v[2] = big;
        blk[3].v[0] = NAN;
        (void)sfit_moments_init(&m);
        assert_int_equal(sfit_moments_add_block(&m, blk, 4, &idx), SFIT_E_RANGE);
        assert_int_equal(idx, 1);
        assert_int_equal(sfit_moments_count(&m), 0);
    }
}

static void test_merge_equals_sequential(void **state)
{
    const size_t splits[] = {1, 17, 64, 333, 999};
    size_t k;
    (void)state;
    make_cap(4, 1000, 0.8, 1.0);
    for (k = 0; k < sizeof splits / sizeof splits[0]; k++) {
        sfit_moments_t a, b;
        (void)sfit_moments_init(&a);
        (void)sfit_moments_init(&b);
        (void)sfit_moments_add_block(&a, g_fpts, splits[k], NULL);
        (void)sfit_moments_add_block(&b, g_fpts + splits[k], 1000 - splits[k], NULL);
        assert_int_equal(sfit_moments_merge(&a, &b), SFIT_OK);
        check_stats(&a, 1000);
        /* Adding after a merge continues correctly. */
        (void)sfit_moments_add_block(&a, g_fpts, 0, NULL);
    }
    {
        /* Merge into an empty accumulator, and merging an empty one. */
        sfit_moments_t e, a, before;
        (void)sfit_moments_init(&e);
        (void)sfit_moments_init(&a);
        (void)sfit_moments_add_block(&a, g_fpts, 1000, NULL);
        before = a;
        assert_int_equal(sfit_moments_merge(&a, &e), SFIT_OK);
        assert_memory_equal(&a, &before, sizeof a);
        assert_int_equal(sfit_moments_merge(&e, &a), SFIT_OK);
        check_stats(&e, 1000);
    }
    {
        /* Many small accumulators merged (a multi-core / multi-buffer use). */
        sfit_moments_t tot, part;
        size_t i;
        (void)sfit_moments_init(&tot);
        for (i = 0; i < 1000; i += 10) {
            (void)sfit_moments_init(&part);
            (void)sfit_moments_add_block(&part, g_fpts + i, 10, NULL);
            assert_int_equal(sfit_moments_merge(&tot, &part), SFIT_OK);
        }
        check_stats(&tot, 1000);
        /* Then add more samples after the merges. */
        make_cap(4, 1500, 0.8, 1.0);
        (void)sfit_moments_add_block(&tot, g_fpts + 1000, 500, NULL);
        check_stats(&tot, 1500);
    }
}

static void test_merge_self(void **state)
{
    sfit_moments_t a, b;
    sfit_vec3_t ma, mb, sa, sb;
    sfit_mat3_t ca, cb;
    int i;
    (void)state;
    make_cap(5, 300, 1.0, 1.0);
    (void)sfit_moments_init(&a);
    (void)sfit_moments_init(&b);
    (void)sfit_moments_add_block(&a, g_fpts, 300, NULL);
    (void)sfit_moments_add_block(&b, g_fpts, 300, NULL);
    (void)sfit_moments_add_block(&b, g_fpts, 300, NULL);
    assert_int_equal(sfit_moments_merge(&a, &a), SFIT_OK); /* aliasing */
    assert_int_equal(sfit_moments_count(&a), 600u);
    (void)sfit_moments_stats(&a, &ma, &ca, &sa);
    (void)sfit_moments_stats(&b, &mb, &cb, &sb);
    for (i = 0; i < 3; i++) {
        assert_near(ma.v[i], mb.v[i], 1e-3, "self-merge mean");
        assert_near(sa.v[i], sb.v[i], 1e-4 * 1e6, "self-merge S");
    }
    for (i = 0; i < 9; i++) {
        assert_near(ca.m[i], cb.m[i], 1e-5 * 3000.0, "self-merge C");
    }
}

/* Samples near the coordinate range whose spread is of the order of the
 * coordinates' own spacing (8 at 2^26..2^27): each block's end moves the
 * origin to the mean rounded to that grid, and the residue e is as large
 * as the spread. The fold must move the total's sums by n e e^T too; with
 * a first-order move C_xx was 15 % low at 49 + 133 samples and M2 failed
 * Cauchy-Schwarz, so that merging the accumulator was refused (a stress
 * run of merges found it). Two points P, Q: C is rank one, a known
 * answer; stats within check_stats's tolerances of the double reference,
 * and the accumulator merges into an empty one. */
static void test_fold_spread_at_grid(void **state)
{
    const float p[3] = {-134217712.0f, -134217696.0f, 134217712.0f};
    const float q[3] = {-134217696.0f, -134217720.0f, 134217712.0f};
    const size_t nps[] = {1, 15, 49, 63, 64, 65, 100};
    const size_t nqs[] = {1, 14, 133, 200};
    size_t a, b, i;
    (void)state;
    for (a = 0; a < sizeof nps / sizeof nps[0]; a++) {
        for (b = 0; b < sizeof nqs / sizeof nqs[0]; b++) {
            const size_t n = nps[a] + nqs[b];
            sfit_moments_t m, e;
            (void)sfit_moments_init(&m);
            for (i = 0; i < n; i++) {
                const float *x = (i < nps[a]) ? p : q;
                memcpy(g_fpts[i].v, x, sizeof g_fpts[i].v);
                tc_to_double3(&g_fpts[i], g_pts[i]);
                assert_int_equal(sfit_moments_add(&m, &g_fpts[i]), SFIT_OK);
            }
            check_stats(&m, n);
            (void)sfit_moments_init(&e);
            assert_int_equal(sfit_moments_merge(&e, &m), SFIT_OK);
            check_stats(&e, n);
        }
    }
}

static void test_rejected_sample_leaves_state(void **state)
{
    const float bad[][3] = {
        {NAN, 0, 0}, {0, INFINITY, 0}, {0, 0, -INFINITY}, {1e30f, 0, 0},
        {0, -1.5e8f, 0}, {0, 0, 134217728.0f /* 2^27 */}, {-NAN, 1e30f, 0}};
    const sfit_status_t want[] = {SFIT_E_NONFINITE, SFIT_E_NONFINITE, SFIT_E_NONFINITE,
                                  SFIT_E_RANGE, SFIT_E_RANGE, SFIT_E_RANGE, SFIT_E_NONFINITE};
    size_t k, stage;
    (void)state;
    make_cap(6, 200, 1.0, 1.0);
    /* Empty, mid-block, and exactly at a block boundary. */
    for (stage = 0; stage < 3; stage++) {
        const size_t nprior = (stage == 0) ? 0 : (stage == 1) ? 37 : SFIT_SUM_BLOCK;
        for (k = 0; k < sizeof bad / sizeof bad[0]; k++) {
            sfit_moments_t m, before;
            sfit_vec3_t x;
            size_t idx = 12345;
            sfit_vec3_t blk[3];
            memset(&m, 0, sizeof m);
            (void)sfit_moments_init(&m);
            (void)sfit_moments_add_block(&m, g_fpts, nprior, NULL);
            before = m;
            memcpy(x.v, bad[k], sizeof x.v);
            assert_int_equal(sfit_moments_add(&m, &x), want[k]);
            assert_memory_equal(&m, &before, sizeof m);
            /* A block with one bad sample in the middle adds nothing. */
            blk[0] = g_fpts[150];
            blk[1] = x;
            blk[2] = g_fpts[151];
            assert_int_equal(sfit_moments_add_block(&m, blk, 3, &idx), want[k]);
            assert_int_equal(idx, 1);
            assert_memory_equal(&m, &before, sizeof m);
        }
    }
    {
        /* Largest accepted coordinate: just below 2^27. */
        sfit_moments_t m;
        sfit_vec3_t x = {{134217720.0f, -134217720.0f, 0.0f}};
        (void)sfit_moments_init(&m);
        assert_int_equal(sfit_moments_add(&m, &x), SFIT_OK);
    }
}

static void test_counter_limit(void **state)
{
    sfit_moments_t m, before, other;
    sfit_vec3_t blk[2];
    (void)state;
    make_cap(7, 10, 1.0, 1.0);
    (void)sfit_moments_init(&m);
    (void)sfit_moments_add_block(&m, g_fpts, 10, NULL);
    /* White-box: pretend the total already holds UINT32_MAX - 11 samples so
     * the next add reaches the limit. */
    m.tot.n = UINT32_MAX - 11u;
    assert_int_equal(sfit_moments_count(&m), UINT32_MAX - 1u);
    assert_int_equal(sfit_moments_add(&m, &g_fpts[0]), SFIT_OK);
    assert_int_equal(sfit_moments_count(&m), UINT32_MAX);
    before = m;
    assert_int_equal(sfit_moments_add(&m, &g_fpts[1]), SFIT_E_RANGE);
    assert_memory_equal(&m, &before, sizeof m);
    blk[0] = g_fpts[1];
    blk[1] = g_fpts[2];
    assert_int_equal(sfit_moments_add_block(&m, blk, 2, NULL), SFIT_E_RANGE);
    assert_memory_equal(&m, &before, sizeof m);
    (void)sfit_moments_init(&other);
    (void)sfit_moments_add(&other, &g_fpts[3]);
    assert_int_equal(sfit_moments_merge(&m, &other), SFIT_E_RANGE);
    assert_memory_equal(&m, &before, sizeof m);
    /* a corrupted src (valid count, a non-finite total or origin) is
     * refused, dst unchanged: merged, it made every later fit of dst fail */
    {
        sfit_moments_t dst, src;
        int k;
        make_cap(8, 120, 1.0, 0.5);
        for (k = 0; k < 3; k++) {
            (void)sfit_moments_init(&dst);
            (void)sfit_moments_add_block(&dst, g_fpts, 20, NULL);
            (void)sfit_moments_init(&src);
            (void)sfit_moments_add_block(&src, &g_fpts[20], 100, NULL);
            if (k == 0) {
                src.origin[1] = NAN;
            } else if (k == 1) {
                src.tot.m3[2] = INFINITY;
            } else {
                src.blk.m2[4] = NAN;
            }
            before = dst;
            assert_int_equal(sfit_moments_merge(&dst, &src), SFIT_E_RANGE);
            assert_memory_equal(&dst, &before, sizeof dst);
        }
    }
}

/* Issue 32: sfit_moments_merge refuses a source that would make the
 * destination unusable (stats / fit SFIT_E_RANGE for good), the
 * destination unchanged bit for bit. The reproducer (a valid
 * source with origin[0] = 1e20f), then random finite garbage in each of
 * the 29 words of a valid source (fixed seed; float words: random finite
 * bit patterns, or the valid value scaled by up to +-2^64; counts: random
 * 32-bit values). Either the merge is refused (SFIT_E_RANGE, dst
 * unchanged) or dst stays usable: stats SFIT_OK and no fit SFIT_E_RANGE,
 * also after more valid samples. */
static void check_usable(const sfit_moments_t *m)
{
    sfit_vec3_t mean, sv;
    sfit_mat3_t c;
    sfit_result_t r;
    sfit_fit_cfg_t cfg = sfit_fit_cfg_default;
    int i;
    assert_int_equal(sfit_moments_stats(m, &mean, &c, &sv), SFIT_OK);
    for (i = 0; i < 9; i++) {
        assert_true(isfinite(c.m[i]));
    }
    assert_true(sfit_fit_moments(m, NULL, &r) != SFIT_E_RANGE);
    cfg.mode = SFIT_MODE_SPHERE;
    cfg.eigen = true;
    assert_true(sfit_fit_moments(m, &cfg, &r) != SFIT_E_RANGE);
}

static void test_merge_refuses_garbage(void **state)
{
    sfit_moments_t dst, src, before, bad;
    tu_rng_t g;
    int w, t, refused = 0, accepted = 0;
    (void)state;
    make_cap(32, 400, 1.0, 0.5);
    (void)sfit_moments_init(&dst);
    (void)sfit_moments_add_block(&dst, g_fpts, 100, NULL);
    (void)sfit_moments_init(&src);
    (void)sfit_moments_add_block(&src, &g_fpts[100], 150, NULL); /* tot and an open block */
    /* The reproducer. */
    bad = src;
    bad.origin[0] = 1e20f;
    before = dst;
    assert_int_equal(sfit_moments_merge(&dst, &bad), SFIT_E_RANGE);
    assert_memory_equal(&dst, &before, sizeof dst);
    check_usable(&dst);
    /* Random finite garbage in each word of the source. */
    tu_rng_seed(&g, 3202u);
    for (w = 0; w < (int)(sizeof src / sizeof(uint32_t)); w++) {
        const size_t off = (size_t)w * sizeof(uint32_t);
        const int is_count = (off == offsetof(sfit_moments_t, tot.n)
                              || off == offsetof(sfit_moments_t, blk.n));
        for (t = 0; t < 300; t++) {
            uint32_t u;
            sfit_moments_t d2;
            sfit_status_t st;
            bad = src;
            if (is_count) {
                u = (uint32_t)(tu_rng_uniform(&g) * 4294967296.0);
                if (t % 3 == 0) {
                    u &= 0xFFFu; /* small counts too */
                }
            } else if (t % 2 == 0) {
                do {
                    u = (uint32_t)(tu_rng_uniform(&g) * 4294967296.0);
                } while (((u >> 23) & 0xFFu) == 0xFFu); /* finite */
            } else {
                float v;
                memcpy(&v, (const unsigned char *)&src + off, sizeof v);
                v = (float)((double)v * ldexp(2.0 * tu_rng_uniform(&g) - 1.0,
                                              (int)(64.0 * tu_rng_uniform(&g))));
                memcpy(&u, &v, sizeof u);
            }
            memcpy((unsigned char *)&bad + off, &u, sizeof u);
            d2 = dst;
            st = sfit_moments_merge(&d2, &bad);
            if (st != SFIT_OK) {
                assert_int_equal(st, SFIT_E_RANGE);
                assert_memory_equal(&d2, &dst, sizeof d2);
                refused++;
                continue;
            }
            accepted++;
            check_usable(&d2);
            assert_int_equal(sfit_moments_add_block(&d2, &g_fpts[250], 150, NULL), SFIT_OK);
            check_usable(&d2);
        }
    }
    print_message("garbage merges: %d refused, %d accepted (usable)\n", refused, accepted);
    assert_true(refused > 1000 && accepted > 1000);
}

static void test_contract(void **state)
{
    sfit_moments_t m;
    sfit_vec3_t x = {{1, 2, 3}}, mean, s;
    sfit_mat3_t c;
    (void)state;
    assert_int_equal(sfit_moments_init(NULL), SFIT_E_ARG);
    assert_int_equal(sfit_moments_reset(NULL), SFIT_E_ARG);
    assert_int_equal(sfit_moments_init(&m), SFIT_OK);
    assert_int_equal(sfit_moments_add(NULL, &x), SFIT_E_ARG);
    assert_int_equal(sfit_moments_add(&m, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_moments_add_block(NULL, &x, 1, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_moments_add_block(&m, NULL, 1, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_moments_add_block(&m, NULL, 0, NULL), SFIT_OK);
    assert_int_equal(sfit_moments_merge(NULL, &m), SFIT_E_ARG);
    assert_int_equal(sfit_moments_merge(&m, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_moments_count(NULL), 0u);
    assert_int_equal(sfit_moments_stats(NULL, &mean, &c, &s), SFIT_E_ARG);
    assert_int_equal(sfit_moments_stats(&m, &mean, &c, &s), SFIT_E_TOO_FEW);
    assert_int_equal(sfit_moments_add(&m, &x), SFIT_OK);
    assert_int_equal(sfit_moments_stats(&m, &mean, &c, &s), SFIT_E_TOO_FEW);
    assert_int_equal(sfit_moments_add(&m, &x), SFIT_OK);
    assert_int_equal(sfit_moments_stats(&m, NULL, NULL, NULL), SFIT_OK);
    assert_int_equal(sfit_moments_stats(&m, &mean, &c, &s), SFIT_OK);
    assert_vec3_near(mean.v, ((const double[3]){1, 2, 3}), 0.0, "mean of equal samples");
    /* reset forgets everything: byte-identical to a fresh init. */
    {
        sfit_moments_t fresh;
        (void)sfit_moments_init(&fresh);
        assert_int_equal(sfit_moments_reset(&m), SFIT_OK);
        assert_memory_equal(&m, &fresh, sizeof m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stats_vs_reference),
        cmocka_unit_test(test_compensated_second_moments),
        cmocka_unit_test(test_add_equals_add_block),
        cmocka_unit_test(test_add_block_chunks_bitwise),
        cmocka_unit_test(test_add_block_screen_edges),
        cmocka_unit_test(test_merge_equals_sequential),
        cmocka_unit_test(test_merge_self),
        cmocka_unit_test(test_fold_spread_at_grid),
        cmocka_unit_test(test_rejected_sample_leaves_state),
        cmocka_unit_test(test_counter_limit),
        cmocka_unit_test(test_merge_refuses_garbage),
        cmocka_unit_test(test_contract),
    };
    return cmocka_run_group_tests_name("moments", tests, NULL, NULL);
}
