/* SPDX-License-Identifier: MIT */
/**
 * @file cli.h
 * @brief Shared pieces of the `sfit` command-line tool: CSV streaming,
 * rejection bookkeeping, JSON helpers, and the sub-command entry points.
 */
#ifndef SFIT_CLI_H
#define SFIT_CLI_H

#include <stdio.h>

#include "sfit/sfit.h"

#define CLI_LINE_MAX 1024
#define CLI_REPORT_MAX 10 /* rejected lines listed in the human summary */

/** Exit codes shared by every sub-command. */
enum { CLI_OK = 0, CLI_FAIL = 1, CLI_USAGE = 2, CLI_IO = 3 };

/** Per-sample consumer: returns SFIT_OK or the reason the sample is rejected. */
typedef sfit_status_t (*cli_sample_fn)(void *ctx, const sfit_vec3_t *x);

typedef struct cli_input {
    unsigned long lines;    /**< data lines seen (header and blank lines excluded) */
    unsigned long accepted; /**< samples the consumer accepted */
    unsigned long rejected; /**< lines that did not parse or were rejected */
    unsigned long bad_line[CLI_REPORT_MAX];
    const char *bad_why[CLI_REPORT_MAX];
} cli_input_t;

/** Parse exactly n comma-separated floats (whole string); 0 on success. */
int cli_parse_floats(const char *s, float *out, int n);

/**
 * Stream the CSV file `path` ('-' = stdin) sample by sample into fn(ctx, x).
 * An optional header (first line that does not parse) is skipped; other
 * lines that do not parse, and samples fn rejects, are counted in `in`.
 * Returns 0, or -1 if the file cannot be opened.
 */
int cli_read_csv(const char *path, cli_sample_fn fn, void *ctx, cli_input_t *in);

/** sfit_moments_add as a cli_sample_fn (ctx is a sfit_moments_t *). */
sfit_status_t cli_add_to_moments(void *ctx, const sfit_vec3_t *x);

/** List the rejected lines of `in` on stderr. */
void cli_report_rejects(const char *file, const cli_input_t *in);

/** A readable explanation of a status, for "message" and stderr. */
const char *cli_status_message(sfit_status_t st);

/** Print a JSON array of 3 floats (round-trip precision). */
void cli_print_vec(const float *v);

/** Print {"status":...,"message":...} for a failure and return CLI_FAIL. */
int cli_json_error(const char *status, const char *message);

/**
 * Stream `file` into a fresh accumulator; list rejected lines on stderr
 * unless json. Returns 0, or CLI_IO after reporting an open failure.
 */
int cli_read_moments(const char *file, int json, sfit_moments_t *acc, cli_input_t *in);

/**
 * Report a failed computation: JSON {"status","message","n","rejected"} or a
 * line on stderr naming `what`. message NULL = cli_status_message(st).
 * Returns CLI_FAIL.
 */
int cli_report_failure(sfit_status_t st, const char *what, const char *message, int json,
                       const cli_input_t *in);

/** Report that `file` cannot be opened (JSON io_error or stderr); returns CLI_IO. */
int cli_open_failed(const char *file, int json);

/**
 * Map a sub-command parser's result to an exit: 0 (go on) gives -1; 1
 * (--help) prints usage on stdout and gives CLI_OK; anything else prints
 * usage on stderr and gives CLI_USAGE.
 */
int cli_parse_outcome(int parse_rc, void (*usage)(FILE *));

/** One positional FILE argument: rejects unknown options and a second FILE (0 ok). */
int cli_positional(const char *arg, const char **file);

/** Sub-commands: argv[0] is the sub-command name. */
int cli_cmd_fit(int argc, char **argv);
int cli_cmd_noise(int argc, char **argv);
int cli_cmd_coverage(int argc, char **argv);
int cli_cmd_track(int argc, char **argv);

#endif /* SFIT_CLI_H */
