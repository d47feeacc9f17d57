/* Helpers shared by the resurf commands: errors, option parsing, output safety, progress bar, JSON. */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"

int cli_fail(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("resurf: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return CLI_FAILED;
}

int cli_fail_error(const resurf_error *error)
{
    /* A cancel after an interrupt is not a failure to describe: main() reports the interrupt once. */
    if (error->status == RESURF_ERR_CANCELLED && cli_interrupted())
        return CLI_FAILED;
    char text[1024];
    resurf_format_error(text, sizeof text, error);
    return cli_fail("%s", text);
}

int cli_usage(const char *command, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "resurf %s: ", command);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, " (see 'resurf %s --help')\n", command);
    va_end(ap);
    return CLI_USAGE;
}

void cli_getopt_reset(void)
{
    optind = 0; /* 0 makes GNU getopt start over, argument permutation included */
    opterr = 0;
}

int cli_getopt(const char *command, int argc, char **argv, const char *shortopts, const struct option *longopts)
{
    int c = getopt_long(argc, argv, shortopts, longopts, NULL);
    if (c == '?') {
        const char *arg = argv[optind - 1];
        if (optopt)
            cli_usage(command, "option '-%c' is unknown or needs a value", optopt);
        else
            cli_usage(command, "option '%s' is unknown or needs a value", arg);
    } else if (c == ':') {
        cli_usage(command, "option '%s' needs a value", argv[optind - 1]);
        c = '?';
    }
    return c;
}

int cli_parse_double(const char *command, const char *option, const char *text, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || *end || errno || !isfinite(v))
        return cli_usage(command, "--%s needs a number, not '%s'", option, text);
    *out = v;
    return 0;
}

int cli_parse_angle(const char *command, const char *option, const char *text, double *out)
{
    double v = 0;
    if (cli_parse_double(command, option, text, &v))
        return CLI_USAGE;
    if (!(v > 0 && v <= 180))
        return cli_usage(command, "--%s must be in (0, 180], not %s", option, text);
    *out = v;
    return 0;
}

int cli_parse_weld_tolerance(const char *command, const char *text, double *out)
{
    double v = 0;
    if (cli_parse_double(command, "weld-tolerance", text, &v))
        return CLI_USAGE;
    if (!(v >= 0 && v <= 1e-3))
        return cli_usage(command, "--weld-tolerance must be in [0, 1e-3], not %s", text);
    *out = v;
    return 0;
}

int cli_parse_choice(const char *command, const char *option, const char *text, const char *const *names, int count,
                     int *out)
{
    for (int k = 0; k < count; ++k)
        if (!strcmp(text, names[k])) {
            *out = k;
            return 0;
        }
    char list[160] = "";
    for (int k = 0; k < count; ++k) {
        strncat(list, names[k], sizeof list - strlen(list) - 1);
        if (k + 1 < count)
            strncat(list, ", ", sizeof list - strlen(list) - 1);
    }
    return cli_usage(command, "unknown --%s '%s' (%s)", option, text, list);
}

const char *const cli_restore_names[RESURF_RESTORE_MODE_COUNT] = {"inline", "post", "none", "measured"};
const char *const cli_stop_names[RESURF_STOP_COUNT] = {"target", "error", "blocked"};
const char *const cli_sheet_names[RESURF_SHEETS_COUNT] = {"choose", "drop", "keep"};

int cli_parse_unsigned(const char *command, const char *option, const char *text, unsigned long *out)
{
    char *end = NULL;
    errno = 0;
    unsigned long v = strtoul(text, &end, 10);
    if (end == text || *end || errno || text[0] == '-')
        return cli_usage(command, "--%s needs a whole number, not '%s'", option, text);
    *out = v;
    return 0;
}

/* Same file: same device and inode (follows links and catches different spellings of one path). */
static int same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) != 0 || stat(b, &sb) != 0)
        return 0;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

int cli_check_output(const char *output, const char *const *inputs, int input_count)
{
    for (int i = 0; i < input_count; ++i)
        if (inputs[i] && (strcmp(output, inputs[i]) == 0 || same_file(output, inputs[i])))
            return cli_fail("%s: refusing to overwrite an input file", output);
    return 0;
}

/* ---- interrupts ---------------------------------------------------------------------------------------------- */

/* The only thing a handler may safely do here: note the signal. The library notices through the progress
 * callback, at its next report (a bounded interval), and cleans up on its own thread. */
static volatile sig_atomic_t interrupted_by;

static void note_signal(int signo) { interrupted_by = signo; }

void cli_install_signal_handlers(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = note_signal;
    sigemptyset(&sa.sa_mask);
    /* No SA_RESTART: a read blocked on a pipe returns EINTR, and the library asks the progress callback whether
     * to go on. SA_RESETHAND: a second signal takes the default action, in case something does not notice. */
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

int cli_interrupted(void) { return (int)interrupted_by; }

/* ---- progress bar -------------------------------------------------------------------------------------------- */

typedef struct bar_state {
    int active;
    int last_permille;
    resurf_stage last_stage;
} bar_state;

static bar_state bar; /* the CLI is single-threaded; the library itself keeps no such state */

static int draw_bar(resurf_stage stage, double fraction)
{
    int permille = (int)(fraction * 1000);
    if (bar.active && stage == bar.last_stage && permille / 5 == bar.last_permille / 5 && permille < 1000)
        return 0;
    bar.active = 1;
    bar.last_stage = stage;
    bar.last_permille = permille;
    int filled = (int)(fraction * 30);
    char cells[31];
    for (int i = 0; i < 30; ++i)
        cells[i] = i < filled ? '#' : '.';
    cells[30] = 0;
    fprintf(stderr, "\r%-10s [%s] %5.1f%%", resurf_stage_name(stage), cells, fraction * 100);
    fflush(stderr);
    return 0;
}

static bool on_progress(void *user, resurf_stage stage, double fraction)
{
    if (interrupted_by)
        return true;
    if (user)
        draw_bar(stage, fraction);
    return false;
}

resurf_progress cli_progress(void)
{
    static int terminal = -1;
    if (terminal < 0)
        terminal = isatty(fileno(stderr));
    resurf_progress p = {on_progress, terminal ? (void *)&bar : NULL}; /* user: where to draw, or NULL */
    return p;
}

void cli_progress_done(void)
{
    if (bar.active)
        fputc('\n', stderr);
    bar.active = 0;
}

/* ---- load / save --------------------------------------------------------------------------------------------- */

static size_t max_triangles = 100000000; /* resurf_load_options_default()'s, until --max-triangles says */

int cli_set_max_triangles(const char *command, const char *text)
{
    unsigned long n = 0;
    if (cli_parse_unsigned(command, "max-triangles", text, &n))
        return CLI_USAGE;
    max_triangles = n;
    return 0;
}

static bool lenient = false; /* resurf_load_options_default()'s, until --lenient says */

void cli_set_lenient(void) { lenient = true; }

bool cli_lenient(void) { return lenient; }

int cli_load(const char *path, resurf_format format, resurf_mesh **out)
{
    if (interrupted_by)
        return CLI_FAILED;
    resurf_load_options options = resurf_load_options_default();
    options.format = format;
    options.max_triangles = max_triangles;
    options.progress = cli_progress();
    resurf_error error;
    resurf_status s = resurf_mesh_load(path, &options, out, &error);
    cli_progress_done();
    return s == RESURF_OK ? 0 : cli_fail_error(&error);
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    if (n < k)
        return 0;
    for (size_t i = 0; i < k; ++i)
        if ((s[n - k + i] | 0x20) != suffix[i])
            return 0;
    return 1;
}

int cli_is_scene(const char *path)
{
    return ends_with(path, ".gltf") || ends_with(path, ".glb") || ends_with(path, ".drc");
}

int cli_load_scene(const char *path, bool allow_missing_images, resurf_scene **out)
{
    *out = NULL;
    if (interrupted_by)
        return CLI_FAILED;
    resurf_load_options lo = resurf_load_options_default();
    lo.max_triangles = max_triangles;
    lo.lenient = cli_lenient();
    lo.allow_missing_images = allow_missing_images;
    lo.progress = cli_progress();
    resurf_error error;
    resurf_status s = resurf_scene_load(path, &lo, out, &error);
    cli_progress_done();
    if (s != RESURF_OK)
        return cli_fail_error(&error);
    for (size_t i = 0; i < resurf_scene_warning_count(*out); ++i)
        fprintf(stderr, "resurf: warning: %s\n", resurf_scene_warning(*out, i));
    return 0;
}

int cli_load_world(const char *path, int level, resurf_mesh **out)
{
    resurf_scene *scene = NULL;
    if (cli_load_scene(path, false, &scene))
        return CLI_FAILED;
    resurf_error error;
    resurf_status s = resurf_scene_world_mesh(scene, level, NULL, out, &error);
    resurf_scene_free(scene);
    return s == RESURF_OK ? 0 : cli_fail_error(&error);
}

int cli_save(const resurf_mesh *mesh, const char *path, const resurf_save_options *options)
{
    if (interrupted_by)
        return CLI_FAILED; /* the user asked to stop: write nothing, not even a complete file */
    resurf_save_options so = options ? *options : resurf_save_options_default();
    if (!so.progress.fn)
        so.progress = cli_progress();
    resurf_error error;
    resurf_status s = resurf_mesh_save(mesh, path, &so, &error);
    cli_progress_done();
    return s == RESURF_OK ? 0 : cli_fail_error(&error);
}

/* ---- JSON ---------------------------------------------------------------------------------------------------- */

void cli_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

void cli_json_number(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.17g", v);
    else
        fputs("null", f);
}

int cli_shared_option(const char *command, const char *usage, int option, resurf_format *format)
{
    switch (option) {
    case 'f':
        if (!format)
            return CLI_USAGE;
        if ((*format = resurf_format_from_name(optarg)) == RESURF_FORMAT_AUTO)
            return cli_usage(command, "unknown format '%s'", optarg);
        return CLI_NEXT;
    case 'T':
        return cli_set_max_triangles(command, optarg) ? CLI_USAGE : CLI_NEXT;
    case CLI_OPT_LENIENT:
        cli_set_lenient();
        return CLI_NEXT;
    case 'h':
        fputs(usage, stdout);
        return CLI_OK;
    default:
        return CLI_USAGE;
    }
}

int cli_check_mesh_output(const char *command, const char *output, const char *const *inputs, int input_count)
{
    if (!output)
        return cli_usage(command, "missing -o OUT");
    if (resurf_format_from_path(output) == RESURF_FORMAT_AUTO)
        return cli_usage(command, "cannot tell the format of '%s' from its name (.obj, .ply, .off, .stl)", output);
    return cli_check_output(output, inputs, input_count) ? CLI_FAILED : 0;
}

int cli_parse_threads(const char *command, const char *text, unsigned *out)
{
    unsigned long n = 0;
    if (cli_parse_unsigned(command, "threads", text, &n))
        return CLI_USAGE;
    if (n > 256)
        return cli_usage(command, "--threads %lu is more than 256", n);
    *out = (unsigned)n;
    return 0;
}

int cli_parse_levels(const char *command, const char *text, double *out, size_t max, size_t *count)
{
    size_t n = 0;
    const char *s = text;
    for (;;) {
        char *end;
        double r = strtod(s, &end);
        if (end == s || !(r > 0 && r <= 1) || (n && r > out[n - 1]) || n == max)
            return cli_usage(command, "--levels wants up to %zu ratios in (0, 1], non-increasing, separated by "
                             "commas: '%s'", max, text);
        out[n++] = r;
        if (*end == 0)
            break;
        if (*end != ',')
            return cli_usage(command, "--levels: unexpected '%c' in '%s'", *end, text);
        s = end + 1;
    }
    *count = n;
    return 0;
}

int cli_parse_attribute_weights(const char *command, const char *text, resurf_simplify_options *o)
{
    double w[4] = {0, 0, 0, o->skin_weight};
    const char *s = text;
    int k = 0;
    for (;; ++k) {
        char *end;
        w[k] = strtod(s, &end);
        int last = *end == 0 && k >= 2;
        if (end == s || !(w[k] >= 0 && w[k] < HUGE_VAL) || (!last && (*end != ',' || k == 3)))
            return cli_usage(command, "--attribute-weights wants three or four weights >= 0 (normals, texcoords, "
                             "colours[, skin influences]) separated by commas: '%s'", text);
        if (last)
            break;
        s = end + 1;
    }
    o->normal_weight = w[0];
    o->texcoord_weight = w[1];
    o->color_weight = w[2];
    o->skin_weight = w[3];
    return 0;
}

double cli_seconds(void)
{
    struct timespec t;
    return clock_gettime(CLOCK_MONOTONIC, &t) == 0 ? (double)t.tv_sec + 1e-9 * (double)t.tv_nsec : 0;
}
