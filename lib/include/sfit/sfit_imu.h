/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_imu.h
 * @brief The joint between two IMUs: joint centre (ball) or hinge axis in
 * each sensor's frame, from angular rates and specific forces, streamed.
 * @defgroup sfit_imu IMU joint
 * @{
 *
 * Two IMUs on two segments joined by a ball joint or a hinge, sampled
 * together at a known rate. The joint's acceleration is the same seen from
 * both sensors, so its norm is too (Seel, Raisch, Schauer 2012, 2014):
 * |a1 + G(w1, w1') r1| = |a2 + G(w2, w2') r2|, G(w, w') r = w x (w x r) +
 * w' x r, with r_i the joint centre in sensor i's frame. For a hinge,
 * |w1 x j1| = |w2 x j2| gives the axis j_i in each frame.
 *
 * Streaming form: sfit_imu_add() differentiates the rate by a central
 * derivative (a cubic fitted to a ring of 2 h + 1 samples, so a sample
 * enters h samples late) and keeps one sample of each window of the stream in a buffer of
 * SFIT_IMU_KEEP, drawn with a probability proportional to |w1|^2 + |w2|^2
 * (a weighted reservoir: the fast samples say most, yet a periodic motion
 * does not collapse onto the phases of its peaks); the windows double when
 * the buffer is full, so the kept samples cover the whole recording.
 * sfit_imu_solve() runs Gauss-Newton on the kept samples: r1, r2 and the
 * two accelerometer biases (with a prior of cfg.acc_bias_sd), the axes from
 * an algebraic lifting (j j^T is linear in the squared constraint) refined
 * by Gauss-Newton, the joint type from the hinge residual. Each sensor's
 * rate is also integrated into its orientation, kept with each kept
 * sample: the relative rotation of the two sensors (aligned on the joint's
 * specific force, a linear drift removed) gives the best fixed axis and
 * the angle the motion leaves it by (wobble_deg), a hinge where the rates'
 * test fails (a wobble faster than the flexion).
 *
 * Derivation and notes: docs/api.md#imu; user page docs/imu.md.
 */
#ifndef SFIT_IMU_H
#define SFIT_IMU_H

#include <stdbool.h>
#include <stdint.h>

#include "sfit_config.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Flags of an IMU joint result (with ::SFIT_FLAG_UNTRUSTED). */
enum sfit_imu_flag {
    SFIT_IMU_FLAG_LOW_ROTATION = 0x10000u, /**< A sensor's rms rate is below cfg.min_rate:
                                                its joint position is not determined. */
    SFIT_IMU_FLAG_LOW_VARIETY = 0x20000u,  /**< A joint position's standard deviation
                                                (sqrt of its covariance's trace; for a
                                                hinge, of the centre's in the plane normal
                                                to the axis) exceeds cfg.max_pos_sd: too
                                                little variety of motion for the wanted
                                                precision. */
    SFIT_IMU_FLAG_SLIP = 0x40000u,         /**< The residual is cfg.slip_ratio times the
                                                noise the sensors' noise predicts: a
                                                sensor slips, or the joint is not one. */
    SFIT_IMU_FLAG_AMBIGUOUS = 0x80000u,    /**< Ball and hinge cannot be told apart: the
                                                position along the axes' line is neither
                                                as certain as the others (line_ratio <
                                                cfg.ball_line) nor free with the hinge
                                                constraint holding. */
    SFIT_IMU_FLAG_AXIS_OFF = 0x100000u,    /**< A hinge whose axes (from the rates) and the
                                                line along which the accelerometers leave the
                                                joint free (result line_off) disagree by more
                                                than cfg.hinge_off: rates off the axis in step
                                                with the flexion (a wobble at the gait's
                                                frequency) bias the axes. */
    SFIT_IMU_FLAG_WOBBLE = 0x200000u       /**< A hinge whose axes (from the rates) do not fit
                                                the accelerometers: the joint's specific force
                                                along them differs between the sensors
                                                cfg.wobble_ratio times more (result
                                                force_ratio) than along the axes fitted to it.
                                                The axis turns in the segments in step with
                                                the flexion: no fixed axis describes the
                                                motion to a few degrees. */
};

/** @brief Options. Defaults: ::sfit_imu_cfg_default. */
typedef struct sfit_imu_cfg {
    float diff_span;   /**< Half-width of the rate's derivative (s); 0.04. The
                            half-width h in samples is round(diff_span rate) in
                            1..SFIT_IMU_DIFF_MAX; the derivative is the slope of a cubic
                            fitted to the 2 h + 1 samples (h = 1: the central difference). */
    float gyr_noise;   /**< Gyroscope noise per sample (rad/s); 0.005. */
    float acc_noise;   /**< Accelerometer noise per sample (m/s^2); 0.02. */
    float acc_bias_sd; /**< Prior standard deviation of each accelerometer bias component
                            (m/s^2); 0.02 (a bias up to 0.05 in magnitude, any
                            direction). 0: no bias estimated. */
    float min_rate;    /**< rms angular rate (rad/s) below which a sensor is flagged
                            ::SFIT_IMU_FLAG_LOW_ROTATION; 0.3. */
    float max_pos_sd;  /**< Largest accepted joint position SD (m); 0.006. */
    float slip_ratio;  /**< Residual rms over predicted noise above which ::SFIT_IMU_FLAG_SLIP; 3. */
    float hinge_ratio; /**< Largest hinge residual rms over rms rate of a hinge; 0.07. */
    float hinge_line;  /**< A joint whose position along the line of the hinge axes is
                            this many times less certain than along the other directions
                            (result line_ratio) is a hinge, when hinge_ratio holds too; 8. */
    float ball_line;   /**< ... below this a ball; between, or a free line without the
                            hinge constraint: ::SFIT_IMU_FLAG_AMBIGUOUS; 5. */
    float hinge_off;   /**< Largest sine of the angle between a hinge's axes and the freest
                            line of the joint position (result line_off), in (0, 1]; above
                            it ::SFIT_IMU_FLAG_AXIS_OFF; 0.0523 (3 degrees). */
    float wobble_ratio; /**< Largest result force_ratio of a trusted hinge, >= 1; above it
                            ::SFIT_IMU_FLAG_WOBBLE; 1.5. */
    float hinge_wobble; /**< Largest result wobble_deg (degrees) of a hinge found from the
                            relative rotation (when the rates' hinge test above fails, as
                            with a wobble faster than the flexion); 3. */
} sfit_imu_cfg_t;

/** @brief The default options. */
extern const sfit_imu_cfg_t sfit_imu_cfg_default;

/** @brief One time-aligned sample of both sensors (m/s^2, rad/s, each in its frame). */
typedef struct sfit_imu_sample {
    sfit_vec3_t acc1, gyr1, acc2, gyr2;
} sfit_imu_sample_t;

/** @brief State. Members are private. */
typedef struct sfit_imu {
    sfit_imu_cfg_t cfg;
    float rate;                                  /**< Sample rate (Hz). */
    float dscale;                                /**< The derivative's first weight. */
    float dw[SFIT_IMU_DIFF_MAX];                 /**< Its weights (rate included). */
    uint32_t n;                                  /**< Samples added. */
    uint32_t nd;                                 /**< Samples differentiated. */
    uint32_t stride;                             /**< Window length (samples). */
    uint32_t wpos;                               /**< Samples in the open window. */
    uint32_t nfull;                              /**< Closed windows kept. */
    uint32_t h;                                  /**< Half-width of the difference. */
    uint32_t head;                               /**< Next ring slot. */
    uint32_t rng;                                /**< xorshift state of the selection. */
    float wsum1, wsum2;                          /**< Sums of |w1|^2, |w2|^2. */
    float q1[4], q2[4];                          /**< Each sensor's orientation against its
                                                      first differentiated sample (unit
                                                      quaternion, the rates integrated). */
    float wlast[6];                              /**< The last differentiated rates. */
    float ring[2 * SFIT_IMU_DIFF_MAX + 1][12];   /**< a1, w1, a2, w2 of the last samples. */
    float keep[SFIT_IMU_KEEP][27];               /**< a1, w1, w1', a2, w2, w2', q1, q2, and
                                                      the sample's index. */
    float score[SFIT_IMU_KEEP];                  /**< Sum of the weights of each kept
                                                      sample's window. */
    uint8_t order[SFIT_IMU_KEEP];                /**< Slots in time order. */
} sfit_imu_t;

/** @brief Result. Written only on SFIT_OK; finite. */
typedef struct sfit_imu_result {
    uint32_t n;              /**< Samples added. */
    uint32_t used;           /**< Kept samples the solve used. */
    bool hinge;              /**< The joint type from the data: true = hinge. */
    sfit_vec3_t r1, r2;      /**< Ball: the joint centre in each sensor's frame (m).
                                  Hinge: the point of the axis nearest each sensor. */
    sfit_mat3_t r1_cov, r2_cov;       /**< Their covariances (m^2); a hinge's: the
                                           centre's in the plane normal to the axis plus
                                           the axis's carried through the projection. */
    sfit_vec3_t axis1, axis2;         /**< Hinge: unit axis in each frame, axis1's
                                           largest component positive, axis2 the same
                                           physical direction; ball: the best hinge fit
                                           (for information). */
    sfit_mat3_t axis1_cov, axis2_cov; /**< Their covariances (rank 2, rad^2): the
                                           estimate's, plus the wobble's share (the
                                           wobble's variance over the kept samples'
                                           effective number, normal to the axis:
                                           docs/imu.md). */
    sfit_vec3_t acc_bias1, acc_bias2; /**< Estimated accelerometer biases (m/s^2). */
    float resid_rms;         /**< rms of |a1 + G1 r1| - |a2 + G2 r2| (m/s^2). */
    float noise_rms;         /**< The rms the sensors' noise predicts for it (m/s^2). */
    float hinge_ratio;       /**< Hinge residual rms over the rms rate. */
    float wobble_deg;        /**< rms angle (degrees) by which the relative rotation of the
                                  two sensors (their integrated rates, aligned on the joint's
                                  specific force, a linear gyroscope drift removed) moves the
                                  best fixed axis off itself: about 2 for a hinge with 2
                                  degrees of wobble at any frequency, several for a ball;
                                  0 when it cannot be computed. */
    float line_sd;           /**< SD of the joint position along the line of the hinge
                                  axes (m): large for a hinge, small for a ball. */
    float line_ratio;        /**< line_sd over the rms SD of the other five directions
                                  of (r1, r2). */
    float line_off;          /**< Sine of the angle between the line of the hinge axes
                                  and the freest line of the joint position (the top
                                  eigenvector of the covariance of (r1, r2)). */
    float force_ratio;       /**< rms of u1.j1 - u2.j2 (u_i the joint's specific force in
                                  sensor i's frame, a_i - b_i + G_i r_i) at the rates' axes
                                  over its rms at the axes fitted to it (floored at the
                                  noise's prediction): about 1 for a hinge, large when the
                                  axis moves in the segments with the flexion. */
    float rate_rms1, rate_rms2; /**< rms angular rate of each sensor (rad/s). */
    uint32_t flags;          /**< ::SFIT_FLAG_UNTRUSTED and SFIT_IMU_FLAG_* bits. */
} sfit_imu_result_t;

/**
 * @brief Start a joint estimate.
 * @param[out] s     State.
 * @param[in]  rate  Sample rate (Hz), > 0 and finite.
 * @param[in]  cfg   Options, NULL for ::sfit_imu_cfg_default.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  NULL s, rate not a positive finite number, or an option out of
 *                     range (negative or non-finite; diff_span, gyr_noise, acc_noise,
 *                     min_rate, max_pos_sd, slip_ratio, hinge_ratio, ball_line <= 0;
 *                     hinge_line < ball_line; hinge_off not in (0, 1]; wobble_ratio
 *                     below 1; hinge_wobble <= 0)
 */
sfit_status_t sfit_imu_init(sfit_imu_t *s, float rate, const sfit_imu_cfg_t *cfg);

/**
 * @brief Add one sample of both sensors.
 * @param[in,out] s  State.
 * @param[in]     x  Sample.
 * @retval SFIT_OK           success
 * @retval SFIT_E_ARG        NULL pointer, or a state not from sfit_imu_init()
 * @retval SFIT_E_NONFINITE  a NaN or Inf value (state unchanged)
 * @retval SFIT_E_RANGE      a |value| above 1e4, or the sample counter is full (state unchanged)
 * @par Cost about 290 FLOPs and 1360 instructions per sample on a Cortex-M4F
 * (tools/flopcount: imu_add, amortised); the sample that fills the buffer
 * moves SFIT_IMU_KEEP bytes more (imu_add_compact).
 */
sfit_status_t sfit_imu_add(sfit_imu_t *s, const sfit_imu_sample_t *x);

/**
 * @brief Solve for the joint from the kept samples (repeatable; the state is not changed).
 * @param[in]  s    State.
 * @param[out] out  Result; written only on SFIT_OK.
 * @retval SFIT_OK                success (check out->flags)
 * @retval SFIT_E_ARG             NULL pointer, or a state not from sfit_imu_init()
 * @retval SFIT_E_TOO_FEW         fewer than 32 kept samples
 * @retval SFIT_E_DEGENERATE      the normal matrix is singular (no motion at all)
 * @retval SFIT_E_NO_CONVERGENCE  Gauss-Newton still moving after SFIT_IMU_GN_ITERS
 * @retval SFIT_E_RANGE           a non-finite intermediate (a corrupted state)
 * @par Cost about 2.8 MFLOPs with a full buffer on a ball joint (tools/flopcount: imu_solve;
 * most of it the rates' hinge fit, which a ball runs to SFIT_IMU_GN_ITERS), 3.3 kB stack.
 */
sfit_status_t sfit_imu_solve(const sfit_imu_t *s, sfit_imu_result_t *out);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_IMU_H */
