/* SPDX-License-Identifier: MIT */
/**
 * @file cli.h
 * @brief Shared pieces of the `sfit` command-line tool: the input layer
 * (delimited text, table.h; C3D, c3d.h), rejection bookkeeping, JSON
 * helpers, and the sub-command entry points.
 */
#ifndef SFIT_CLI_H
#define SFIT_CLI_H

#include <stdio.h>

#include "json_out.h"
#include "names.h"
#include "sfit/sfit.h"

#define CLI_LINE_MAX 1024
#define CLI_REPORT_MAX 10 /* rejected lines listed in the human summary */

/** Exit codes shared by every sub-command. */
enum { CLI_OK = 0, CLI_FAIL = 1, CLI_USAGE = 2, CLI_IO = 3 };

/** Per-sample consumer: returns SFIT_OK or the reason the sample is rejected. */
typedef sfit_status_t (*cli_sample_fn)(void *ctx, const sfit_vec3_t *x);

/** Input options shared by every command that reads samples (--cols). */
typedef struct cli_src {
    const char *cols; /**< --cols spec (names or 1-based indices), NULL = x,y,z */
} cli_src_t;

/**
 * If argv[*i] is a shared input option (--cols SPEC), consume it (and its
 * value) and return 1; 0 if it is not one; -1 (message on stderr) if its
 * value is missing. cli_parse calls it for the commands that read samples.
 */
int cli_input_opt(int argc, char **argv, int *i, cli_src_t *src);

/** The usage lines of the shared input options. */
#define CLI_INPUT_USAGE                                                                    \
    "  FILE  delimited text: comma, tab, semicolon or blanks (detected), optional\n"       \
    "        header naming the columns, blank cell = missing sample; '-' reads stdin\n"   \
    "  --cols A,B,C     the x,y,z columns: header names or 1-based indices\n"              \
    "                   (default: the columns named x, y, z, or the only three)\n"

typedef struct cli_input {
    unsigned long lines;    /**< data lines seen (header and blank lines excluded) */
    unsigned long accepted; /**< samples the consumer accepted */
    unsigned long rejected; /**< lines that did not parse or were rejected */
    unsigned long missing;  /**< rows with a blank selected cell (skipped) */
    unsigned long bad_line[CLI_REPORT_MAX];
    const char *bad_why[CLI_REPORT_MAX];
} cli_input_t;

/** Parse exactly n comma-separated floats (whole string); 0 on success. */
int cli_parse_floats(const char *s, float *out, int n);

/**
 * Stream the delimited file `path` ('-' = stdin) sample by sample into
 * fn(ctx, x) (table.h). The header is skipped; rows that do not parse and
 * samples fn rejects are counted in `in` (rejected), rows with a blank
 * selected cell too (missing). Returns 0; -1 if the file cannot be opened
 * (errno kept); -2 if its columns cannot be selected (message in `why`,
 * TABLE_ERR_MAX bytes).
 */
int cli_read_xyz(const char *path, const cli_src_t *src, cli_sample_fn fn, void *ctx,
                 cli_input_t *in, char *why);

/**
 * Report a cli_read_xyz failure (rc -1 or -2) for `file`: JSON
 * {"status":"io_error"|"format_error","message":...} or a line on stderr.
 * Returns CLI_IO.
 */
int cli_input_failed(int rc, const char *file, const char *why, int json);

/** sfit_moments_add as a cli_sample_fn (ctx is a sfit_moments_t *). */
sfit_status_t cli_add_to_moments(void *ctx, const sfit_vec3_t *x);

/** List the rejected lines of `in` on stderr. */
void cli_report_rejects(const char *file, const cli_input_t *in);

/** Print ,"noise_var":V,"noise_estimated":B (V null without a noise model). */
void cli_print_noise_json(int has_noise, float noise_var, int estimated);

/** Print {"status":...,"message":...} for a failure and return CLI_FAIL. */
int cli_json_error(const char *status, const char *message);

/**
 * Stream `file` into a fresh accumulator; list rejected lines on stderr
 * unless json. Returns 0, or CLI_IO after reporting an open or format failure.
 */
int cli_read_moments(const char *file, const cli_src_t *src, int json, sfit_moments_t *acc,
                     cli_input_t *in);

#define CLI_WHAT_MAX 512 /* "fit of FILE" for cli_report_failure */

/**
 * Report a failed computation: JSON {"status","message","n","rejected"} or a
 * line on stderr naming `what`. message NULL = names_status_message(st, NAMES_CLI).
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

/** auto | sphere | planar into *mode; 0, or -1 (*mode unchanged) for another word. */
int cli_parse_mode(const char *s, sfit_mode_t *mode);

/* ---- One option parser for every sub-command (cli_parse) ---- */

/** What a command option takes (cli_opt_t.kind). */
typedef enum cli_opt_kind {
    CLI_OPT_FLAG,   /**< no value: *(int *)dst = 1 */
    CLI_OPT_FLOATS, /**< n comma-separated floats, each within bounds (float *dst) */
    CLI_OPT_COUNT,  /**< a whole number >= 0, strtoul (unsigned long *dst) */
    CLI_OPT_INDEX,  /**< a whole number >= 0, strtol (long *dst) */
    CLI_OPT_MODE,   /**< auto | sphere | planar (sfit_mode_t *dst) */
    CLI_OPT_STRING, /**< the value itself, not copied (char **dst) */
    CLI_OPT_FN,     /**< fn(dst, value) */
    CLI_OPT_FN0     /**< no value: fn(dst, name) */
} cli_opt_kind_t;

/* Bounds of a CLI_OPT_FLOATS value (cli_opt_t.bounds, or-ed); NaN fails any. */
#define CLI_GE_LO 1u /**< x >= lo */
#define CLI_GT_LO 2u /**< x > lo */
#define CLI_LE_HI 4u /**< x <= hi */
#define CLI_LT_HI 8u /**< x < hi */

/** A custom option: NULL when taken, else the message of a bad value (after "sfit: "). */
typedef const char *(*cli_opt_fn_t)(void *dst, const char *value);

/** One option of a command; unset fields are 0 (designated initializers). */
typedef struct cli_opt {
    const char *name;    /**< "--gate" */
    cli_opt_kind_t kind;
    void *dst;           /**< where the value goes (type by kind); FN, FN0: fn's context */
    const char *err;     /**< message of a bad value, printed after "sfit: " */
    int *seen;           /**< set to 1 once the option is taken (NULL: not kept) */
    int required;        /**< not given: cli_args_t.required is the error */
    int needs;           /**< value missing: "NAME needs a value" (0: the unknown-option message) */
    int n;               /**< CLI_OPT_FLOATS: how many */
    unsigned bounds;     /**< CLI_OPT_FLOATS: CLI_GE_LO, ... */
    float lo, hi;        /**< CLI_OPT_FLOATS: the bounds' values */
    cli_opt_fn_t fn;     /**< CLI_OPT_FN, CLI_OPT_FN0 */
} cli_opt_t;

/** The cli_args_t fields of a command that reads one FILE (const char *F). */
#define CLI_ONE_FILE(F)                                                                     \
    .pos = &(F), .max_pos = 1, .min_pos = 1, .extra = "one FILE expected",                 \
    .missing = "FILE missing"

/** A command's arguments: its option table, --cols, the positional arguments. */
typedef struct cli_args {
    const cli_opt_t *opts; /**< the command's options (at most 32) */
    size_t nopts;
    cli_src_t *src;        /**< --cols goes here; NULL: not an option of the command */
    const char **pos;      /**< positional arguments, in order (max_pos of them) */
    int max_pos, min_pos;
    int *npos;             /**< how many were given (NULL: not kept) */
    const char *extra;     /**< message when more than max_pos are given */
    const char *missing;   /**< message when fewer than min_pos are given */
    const char *required;  /**< message when a required option is not given */
    void (*usage)(FILE *);
} cli_args_t;

/**
 * Parse argv[1..argc-1] of a sub-command in order: --help / -h, --cols (if
 * a->src), the options of the table (a value option without its value is
 * an unknown or incomplete option, or "needs a value"), an unknown option,
 * the positional arguments; then the required options and min_pos. The
 * first error is printed on stderr ("sfit: ..."). Returns -1 to go on, or
 * the exit status: CLI_OK after usage on stdout (--help), CLI_USAGE after
 * the error and usage on stderr.
 */
int cli_parse(int argc, char **argv, const cli_args_t *a);

/**
 * The command table: X(NAME, ENTRY, HELP) per command, in the order `sfit
 * --help` lists them. It declares each entry point `int ENTRY(int argc,
 * char **argv)` (argv[0] is the command's name; defined in cmd_*.c) and is
 * the only dispatcher (sfit_cli.c); tools/README.md says how to add one.
 */
#define CLI_COMMANDS(X)                                                                       \
    X("fit", cli_cmd_fit, "fit a sphere (or a circle) to x,y,z samples")                      \
    X("noise", cli_cmd_noise, "estimate the noise variance from a known sphere or point")     \
    X("track", cli_cmd_track, "incremental estimate: a new centre every K samples")           \
    X("coverage", cli_cmd_coverage,                                                           \
      "covered half-angle, largest tolerable noise, rotate further?")                         \
    X("joint", cli_cmd_joint, "functional joint centre from a C3D file or a wide table")      \
    X("skeleton", cli_cmd_skeleton,                                                           \
      "the skeleton of a session model or found in the data:\n"                               \
      "            segments, joints, tree; --bvh --trc --svg --html --json")                  \
    X("calibrate", cli_cmd_calibrate,                                                         \
      "every joint of a session model from its functional trial")                             \
    X("apply", cli_cmd_apply, "a calibrated session's joint centres written into a trial")    \
    X("c3d", cli_cmd_c3d, "what a C3D file holds; its markers as a wide table")               \
    X("imu-joint", cli_cmd_imu, "the joint between two IMUs: centre or hinge axis in each frame")

#define CLI_DECLARE_COMMAND(name, entry, help) int entry(int argc, char **argv);
CLI_COMMANDS(CLI_DECLARE_COMMAND)
#undef CLI_DECLARE_COMMAND

#endif /* SFIT_CLI_H */
