/* SPDX-License-Identifier: MIT */
/**
 * @file cli_joint.h
 * @brief The CLI side of a joint run (lab/joint_run.h) shared by `sfit
 * joint` and `sfit skeleton`: its options, usage lines and printing, and
 * the printing of the label-swap check (lab/swaps.h).
 */
#ifndef SFIT_CLI_JOINT_H
#define SFIT_CLI_JOINT_H

#include "cli.h"
#include "joint_run.h"
#include "swaps.h"

/** --frames F:L into a joint_run_opts_t (a cli_opt_fn_t). */
const char *cli_joint_frames_opt(void *dst, const char *v);

/** --method default|score|sara|mgdk into a joint_run_opts_t (a cli_opt_fn_t). */
const char *cli_joint_method_opt(void *dst, const char *v);

/** The JSON members after "center"...: the pair's center_cov, axis_cov, noise, reason;
 *  for the multi-marker fit (mgdk) its center_cov, the marker noise used, reason. */
void cli_joint_print_pair_json(const joint_run_out_t *out);

/** The result's flags as a JSON array (the pair's, or the multi-marker fit's). */
void cli_joint_print_flags_json(const joint_run_out_t *out);

/** Text lines: 95 % semi-axes (mm), noise figure and source, flags (pair or mgdk). */
void cli_joint_print_pair_text(const joint_run_out_t *out, const char *units, const char *indent);

/** --noise-var V|auto into a joint_run_opts_t (a cli_opt_fn_t). */
const char *cli_joint_noise_opt(void *dst, const char *v);

/**
 * The cli_opt_t entries of the options shared by joint and skeleton
 * (--frames F:L, --noise-var V|auto, --mode auto|sphere|planar) for the
 * joint_run_opts_t *J; a missing value is "NAME needs a value".
 */
#define CLI_JOINT_OPTS(J)                                                                   \
    {.name = "--frames", .kind = CLI_OPT_FN, .dst = (J), .fn = cli_joint_frames_opt,       \
     .needs = 1},                                                                          \
    {.name = "--noise-var", .kind = CLI_OPT_FN, .dst = (J), .fn = cli_joint_noise_opt,     \
     .needs = 1},                                                                          \
    {.name = "--mode", .kind = CLI_OPT_MODE, .dst = &(J)->mode, .needs = 1,                \
     .err = "--mode is auto, sphere or planar"},                                           \
    {.name = "--no-repair-swaps", .kind = CLI_OPT_FLAG, .dst = &(J)->no_repair_swaps},    \
    {.name = "--method", .kind = CLI_OPT_FN, .dst = (J), .fn = cli_joint_method_opt,       \
     .needs = 1}

/** The usage lines of the shared joint options. */
#define CLI_JOINT_USAGE                                                                     \
    "  --frames F:L     use frames F to L (0-based, both included; default: all)\n"        \
    "  --noise-var V    the multi-marker fit (mgdk) made unbiased: V = noise variance\n" \
    "                   of each measured marker coordinate (unit^2), propagated\n"       \
    "                   through the parent pose\n"                                        \
    "  --noise-var auto the child markers' noise in the parent frame, estimated per\n"   \
    "                   marker (self-calibrated UGDK) and pooled\n"                       \
    "  --mode M         auto (default): ball joint, or hinge when the markers' arcs are\n" \
    "                   near-planar; sphere / planar force one\n"                       \
    "  --no-repair-swaps report label swaps within a cluster but leave the frames as\n"  \
    "                   they are (default: exchange the labels back; reject frames\n"     \
    "                   whose distances fit no labelling)\n"                            \
    "  --method M       default: SCoRE / SARA from the two clusters' poses with the\n"    \
    "                   bias removed (marker noise from the registration residuals;\n"  \
    "                   needs 3 child markers, else mgdk); score, sara: as published;\n"\
    "                   mgdk: one sphere per child marker in the parent's frame,\n"    \
    "                   sharing their centre (the multi-marker sphere fit)\n"

/** Print ,"label_swaps":{...} (names: parent markers, then child markers). */
void cli_swaps_json(const swaps_joint_t *s, const char *const *names, int np);

/** Print the human report, each line starting with `lead` for the first
 * and `indent` for the others (both the same width). */
void cli_swaps_human(const swaps_joint_t *s, const char *const *names, int np,
                     const char *units, const char *lead, const char *indent);

#endif /* SFIT_CLI_JOINT_H */
