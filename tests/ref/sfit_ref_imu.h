/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref_imu.h
 * @brief Double-precision oracle for the joint between two IMUs (sfit_imu.h):
 * exact synthetic signals of two rigid segments joined at a point, and the
 * batch Gauss-Newton of Seel, Raisch and Schauer (2012, 2014) over every
 * sample. Independent of lib/.
 *
 * Convention: r_i is the joint centre in sensor i's frame (m), a_i the
 * specific force (m/s^2), w_i the angular rate (rad/s), all in sensor i's
 * frame. The joint's specific force seen from sensor i is
 * a_i + G(w_i, w_i') r_i with G r = w x (w x r) + w' x r, and its norm is
 * the same from both sensors.
 */
#ifndef SFIT_REF_IMU_H
#define SFIT_REF_IMU_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define REF_IMU_NF 6 /**< Most elementary rotations in a chain. */

/**
 * A motion: segment 1's orientation is the product of nf1 rotations about
 * fixed axes, segment 2's is segment 1's times nf2 more (the joint), each
 * angle off + sum_k amp_k sin(2 pi freq_k t + ph_k); each sensor is turned
 * by a constant rotation c_i in its segment. The joint moves along
 * pos0 + vel t + sum_k pamp sin(2 pi pfreq t + pph) (world, z up).
 */
typedef struct ref_imu_motion {
    int nf1, nf2;
    double axis[2 * REF_IMU_NF][3];
    double off[2 * REF_IMU_NF], amp[2 * REF_IMU_NF][2], freq[2 * REF_IMU_NF][2],
        ph[2 * REF_IMU_NF][2];
    double c1[9], c2[9]; /* sensor orientation in its segment (row-major) */
    double r1[3], r2[3]; /* the joint in each sensor's frame */
    double pos0[3], vel[3], pamp[3][2], pfreq[3][2], pph[3][2];
} ref_imu_motion_t;

/** Exact signals at time t: specific force, rate and its derivative of both sensors. */
void ref_imu_synth(const ref_imu_motion_t *m, double t, double acc[2][3], double gyr[2][3],
                   double dgyr[2][3]);

/** Seel's constraint |a1 + G1 r1| - |a2 + G2 r2| for one sample. */
double ref_imu_gap(const double a1[3], const double w1[3], const double dw1[3],
                   const double r1[3], const double a2[3], const double w2[3],
                   const double dw2[3], const double r2[3]);

/**
 * Batch Gauss-Newton for the joint position (Seel 2012, 2014): every sample,
 * six unknowns (r1, r2) from zero, normal equations solved in double.
 * w': h > 0, the central difference (w[k+h] - w[k-h]) rate / (2h); h < 0,
 * the slope of the least-squares cubic through the 2|h| + 1 samples
 * around k (|h| <= 32).
 * cov: 6x6 covariance s^2 (J^T J)^-1 with s^2 = SSR / (n - 6); rms: sqrt(SSR/n).
 * Returns 0, nonzero when the normal matrix is singular or GN does not settle.
 */
int ref_imu_ball_gn(const double (*acc1)[3], const double (*gyr1)[3], const double (*acc2)[3],
                    const double (*gyr2)[3], size_t n, double rate, int h, double r1[3],
                    double r2[3], double cov[36], double *rms);

/**
 * Batch Gauss-Newton for the hinge axes (Seel): |w1 x j1| = |w2 x j2|, each
 * axis in spherical coordinates, from several starts, the smallest cost
 * kept. j2's sign makes sum (w1.j1)(w2.j2) >= 0. rms: sqrt(SSR/n) (rad/s).
 */
int ref_imu_hinge_gn(const double (*gyr1)[3], const double (*gyr2)[3], size_t n, double j1[3],
                     double j2[3], double *rms);

/**
 * The relative motion of a motion's joint factors at time t: rel maps
 * sensor 2's frame to sensor 1's (c1^T Q c2, Q the product of the joint's
 * rotations), w the relative angular velocity (segment 2 against segment 1)
 * in sensor 1's frame (rad/s).
 */
void ref_imu_relative(const ref_imu_motion_t *m, double t, double rel[9], double w[3]);

/**
 * The best fixed axis of the true relative motion over n samples at rate:
 * the direction fixed in both segments (j2 in sensor 2's frame, j1 = its
 * image in sensor 1's) that moves least, the top singular vectors of the mean
 * relative rotation (maximising |mean(rel) j2|); wander (rad): the largest
 * angle between rel(t) j2 and j1 over the samples (0 for a hinge). f1, f2:
 * the principal direction of the relative angular velocity in each sensor's
 * frame (the top eigenvector of sum w w^T; the functional axis).
 */
void ref_imu_fixed_axis(const ref_imu_motion_t *m, size_t n, double rate, double j1[3],
                        double j2[3], double *wander, double f1[3], double f2[3]);

#ifdef __cplusplus
}
#endif

#endif /* SFIT_REF_IMU_H */
