/* The resurf command-line tool: shared helpers for the commands. The CLI only parses arguments and calls the
 * public API (resurf.h); it never reaches into the library's internals.
 * Exit status: 0 success, 1 the work failed (bad input, I/O), 2 usage error, 128 + N interrupted by signal N
 * (SIGINT 130, SIGTERM 143). Errors: one line on stderr,
 * "resurf: FILE: what is wrong". */
#ifndef RESURF_CLI_H
#define RESURF_CLI_H

#include <getopt.h>
#include <stdbool.h>
#include <stdio.h>

#include "resurf/resurf.h"

enum { CLI_OK = 0, CLI_FAILED = 1, CLI_USAGE = 2 };

typedef struct cli_command {
    const char *name;
    const char *summary;
    int (*run)(int argc, char **argv); /* argv[0] is the command name */
} cli_command;

int cmd_info(int argc, char **argv);
int cmd_convert(int argc, char **argv);
int cmd_restore(int argc, char **argv);
int cmd_smooth(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_simplify(int argc, char **argv);
int cmd_lod(int argc, char **argv);
int cmd_preview(int argc, char **argv);

/* Renders scene's preview sheet with options and writes it to path (a PNG); prints on stdout the table of levels
 * (verbosity 2) and "wrote PATH" (1 and 2), nothing with 0. Returns CLI_OK or CLI_FAILED after printing the error.
 * (cmd_preview.c) */
int cli_write_preview(const resurf_scene *scene, const char *path, const resurf_preview_options *options,
                      int verbosity);
/* --size WxH into options->width and height (the library checks the range); CLI_USAGE after an error, else 0. */
int cli_parse_preview_size(const char *command, const char *option, const char *text, resurf_preview_options *o);

/* Prints "resurf: <message>" on stderr and returns CLI_FAILED. */
int cli_fail(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Prints "resurf: <formatted error>" on stderr and returns CLI_FAILED. */
int cli_fail_error(const resurf_error *error);
/* Prints "resurf COMMAND: <message>" and a hint to --help on stderr, returns CLI_USAGE. */
int cli_usage(const char *command, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Runs getopt_long over argv with our own messages; returns the option, -1 at the end, or '?' after printing a
 * usage error (the caller returns CLI_USAGE). Call cli_getopt_reset() before the first call of a command. */
void cli_getopt_reset(void);
int cli_getopt(const char *command, int argc, char **argv, const char *shortopts, const struct option *longopts);

/* Parse a number option; on failure print a usage error and return CLI_USAGE, else 0. */
int cli_parse_double(const char *command, const char *option, const char *text, double *out);
int cli_parse_unsigned(const char *command, const char *option, const char *text, unsigned long *out);
/* An angle option in degrees, in (0, 180]. */
int cli_parse_angle(const char *command, const char *option, const char *text, double *out);
/* --weld-tolerance: resurf_simplify_options.weld_tolerance_rel, in [0, 1e-3]. */
int cli_parse_weld_tolerance(const char *command, const char *text, double *out);

/* An option naming one of names[0..count): its index in *out; else a usage error listing them, CLI_USAGE. */
int cli_parse_choice(const char *command, const char *option, const char *text, const char *const *names, int count,
                     int *out);
/* The names of resurf_restore_mode, in its order (simplify and lod --restore, their reports). */
extern const char *const cli_restore_names[RESURF_RESTORE_MODE_COUNT];
extern const char *const cli_sheet_names[RESURF_SHEETS_COUNT];
/* The names of resurf_simplify_stop, in its order (simplify and lod reports). */
extern const char *const cli_stop_names[RESURF_STOP_COUNT];

/* --threads N: 0 (all cores) .. 256. */
int cli_parse_threads(const char *command, const char *text, unsigned *out);
/* --levels R1,R2,...: up to max ratios in (0, 1], non-increasing. */
int cli_parse_levels(const char *command, const char *text, double *out, size_t max, size_t *count);
/* --attribute-weights N,UV,C: the simplifier's normal_weight, texcoord_weight, color_weight (each >= 0). */
int cli_parse_attribute_weights(const char *command, const char *text, resurf_simplify_options *o);

/* Refuses (prints, returns CLI_FAILED) when output names the same file as one of the inputs; else 0. */
int cli_check_output(const char *output, const char *const *inputs, int input_count);

/* Interrupts. cli_install_signal_handlers() makes SIGINT and SIGTERM set a flag and nothing else (a second one
 * kills as usual). The progress callback of cli_progress() returns non-zero once the flag is set, so the running
 * library call cancels: it frees its memory, removes its temporary file and returns RESURF_ERR_CANCELLED, which
 * cli_fail_error() does not print. main() then prints "resurf: interrupted by SIGINT" and exits 128 + the signal
 * number (130, 143). cli_interrupted() is that signal number, or 0. */
void cli_install_signal_handlers(void);
int cli_interrupted(void);

/* The progress callback for every library call that takes one: it cancels after an interrupt, and draws a bar
 * on stderr when stderr is a terminal. cli_progress_done() ends the bar's line. */
resurf_progress cli_progress(void);
void cli_progress_done(void);

/* --max-triangles N, taken by every command that loads meshes: cli_load() refuses inputs with more triangles
 * (RESURF_ERR_LIMIT). The default is resurf_load_options_default()'s (100 million); 0 removes the limit.
 * Add CLI_MAX_TRIANGLES_OPTION to the command's long options and call cli_set_max_triangles() for 'T'. */
#define CLI_MAX_TRIANGLES_OPTION {"max-triangles", required_argument, NULL, 'T'}
#define CLI_MAX_TRIANGLES_HELP                                                                                  \
    "  --max-triangles N  refuse inputs with more than N triangles (default 100000000; 0 = no limit)\n"
int cli_set_max_triangles(const char *command, const char *text);

/* --lenient, taken by every command that loads scenes (info, lod, preview): a glTF document that breaks the glTF
 * 2.0 schema loads with a warning per problem instead of failing (resurf_load_options.lenient). Add
 * CLI_LENIENT_OPTION to the command's long options; cli_shared_option() takes it, or call cli_set_lenient(); the
 * command loads with lenient = cli_lenient() and prints the scene's warnings. */
enum { CLI_OPT_LENIENT = 0x100 }; /* no short option */
#define CLI_LENIENT_OPTION {"lenient", no_argument, NULL, CLI_OPT_LENIENT}
#define CLI_LENIENT_HELP                                                                                        \
    "  --lenient          accept a glTF document that breaks the glTF 2.0 schema (wrong types, missing required\n" \
    "                     properties, values out of range) with a warning per problem (default: refused)\n"
void cli_set_lenient(void);
bool cli_lenient(void);

/* The options every mesh command shares, for the `default:` of its getopt switch: 'f' (--format: sets *format;
 * pass NULL when the command has no --format), 'T' (--max-triangles), CLI_OPT_LENIENT, 'h' (--help: prints usage)
 * and anything unknown. Returns CLI_NEXT to go on parsing, CLI_OK after --help, CLI_USAGE after an error. */
enum { CLI_NEXT = -1 };
int cli_shared_option(const char *command, const char *usage, int option, resurf_format *format);

/* Checks the output of a mesh command before any work: -o given, its format known from its name (.obj, .ply,
 * .off, .stl) and not one of the inputs. Returns 0, or what the command returns (CLI_USAGE, CLI_FAILED). */
int cli_check_mesh_output(const char *command, const char *output, const char *const *inputs, int input_count);

/* Loads a mesh or prints the error; returns 0 or CLI_FAILED. Honours --max-triangles and interrupts. */
int cli_load(const char *path, resurf_format format, resurf_mesh **out);
/* Is the file a scene by its name (.gltf, .glb, .drc, any case)? */
int cli_is_scene(const char *path);
/* Loads a scene with the shared options (--max-triangles, --lenient, progress) and allow_missing_images, printing
 * its warnings, or prints the error; returns 0 or CLI_FAILED. */
int cli_load_scene(const char *path, bool allow_missing_images, resurf_scene **out);
/* Loads a scene and takes its whole scene at `level` as one world-space mesh (resurf_scene_world_mesh: every
 * instance, node transforms applied; MSFT_lod levels), or prints the error; returns 0 or CLI_FAILED. Honours
 * --max-triangles, --lenient (printing the scene's warnings) and interrupts. */
int cli_load_world(const char *path, int level, resurf_mesh **out);
/* Saves a mesh or prints the error; returns 0 or CLI_FAILED. Writes nothing after an interrupt, and installs
 * cli_progress() when options->progress has no callback (options may be NULL). */
int cli_save(const resurf_mesh *mesh, const char *path, const resurf_save_options *options);

/* JSON helpers: a string with escapes, and a number that stays valid JSON for non-finite values (null). */
void cli_json_string(FILE *f, const char *s);
void cli_json_number(FILE *f, double v);
/* A monotonic clock in seconds (for the phase times that --json reports). */
double cli_seconds(void);

#endif
