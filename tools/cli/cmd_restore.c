/* resurf restore ORIGINAL PROCESSED -o OUT: moves the vertices of a processed mesh back onto the smooth surface
 * the original approximates (resurf_restore()). */
#include <string.h>

#include "cli.h"

static const char usage[] =
    "usage: resurf restore ORIGINAL PROCESSED -o OUT [options]\n\n"
    "Moves the vertices of PROCESSED (a smoothed, remeshed or simplified version of ORIGINAL) back onto the\n"
    "smooth surface that ORIGINAL approximates (Semenova, Savchenko, Hagiwara). Connectivity and attributes of\n"
    "PROCESSED stay; prints what was done.\n\n"
    "  -o, --output OUT          the restored mesh (format from the extension; refuses to overwrite an input)\n"
    "  --preset paper|default    start from the paper's settings or resurf's default (default); the options\n"
    "                            below change single settings, whatever their order\n"
    "  --normals SCHEME          vertex normals of ORIGINAL: inverse-area (the paper), area, angle, max,\n"
    "                            jet (default)\n"
    "  --input-normals MODE      ORIGINAL's own normals: ignore, creases (default: split normals mark creases),\n"
    "                            use (also take them as the vertex normals)\n"
    "  --side RULE               max/min choice of the paper's formula: curvature (default), local\n"
    "  --displacement FORMULA    paper (formula (2)) or normal-section (default)\n"
    "  --step K                  k in p += k sum(delta_j) N_opt, in (0, 1]; paper 1/6, default 1/3\n"
    "  --iterations N            steps per vertex (the most, with --tolerance); paper 5, default 10\n"
    "  --tolerance T             stop a vertex once its step is below T x the local edge length; 0 = off\n"
    "  --crease-angle DEG        dihedral angle above which an edge is a crease; 180 = none; default 60\n"
    "  --outside POLICY          no root inside the closest triangle: neighbours (default), least, keep\n"
    "  --no-boundary             do not keep vertices near open boundaries on the boundary curve\n"
    "  --far-factor F            leave vertices farther than F x the local edge length; default 4\n"
    "  --threads N               worker threads, 0 = all cores (default); the result is the same for any N\n"
    "  --json                    print the report as JSON on stdout\n"
    "  --format FMT              read both inputs as obj|ply|off|stl whatever their names say\n" CLI_MAX_TRIANGLES_HELP;

static const char *const normal_names[RESURF_NORMALS_COUNT] = {"inverse-area", "area", "angle", "max", "jet"};
static const char *const side_names[RESURF_SIDE_COUNT] = {"curvature", "local"};
static const char *const displacement_names[RESURF_DISPLACEMENT_COUNT] = {"paper", "normal-section"};
static const char *const outside_names[RESURF_OUTSIDE_COUNT] = {"neighbours", "least", "keep"};
static const char *const input_names[RESURF_INPUT_NORMALS_COUNT] = {"ignore", "creases", "use"};

/* Settings given on the command line, applied over the preset once all options are read. */
typedef struct overrides {
    int normals, side, displacement, outside, input_normals; /* -1: not given */
    int boundary;                                            /* -1: not given, else 0 */
    int has_step, has_iterations, has_tolerance, has_crease, has_far, has_threads;
    double step, tolerance, crease, far;
    unsigned iterations, threads;
} overrides;

static void print_text(const char *original, const char *processed, const char *out,
                       const resurf_restore_report *r)
{
    printf("original             %s\n", original);
    printf("processed            %s\n", processed);
    printf("output               %s\n", out);
    printf("vertices             %zu\n", r->vertices);
    printf("moved                %zu\n", r->moved);
    printf("mean displacement    %.9g\n", r->mean_displacement);
    printf("max displacement     %.9g\n", r->max_displacement);
    printf("on boundary curves   %zu\n", r->on_boundary);
    printf("on crease curves     %zu\n", r->on_crease);
    printf("least-outside root   %zu\n", r->used_least_outside);
    printf("left: far from M     %zu\n", r->left_far);
    printf("left: no inside root %zu\n", r->left_outside);
    printf("left: non-finite     %zu\n", r->left_nonfinite);
}

static void print_json(const char *original, const char *processed, const char *out,
                       const resurf_restore_options *o, const resurf_restore_report *r)
{
    printf("{\"original\": ");
    cli_json_string(stdout, original);
    printf(", \"processed\": ");
    cli_json_string(stdout, processed);
    printf(", \"output\": ");
    cli_json_string(stdout, out);
    printf(", \"options\": {\"normals\": \"%s\", \"side\": \"%s\", \"displacement\": \"%s\", \"step\": ",
           normal_names[o->normals == RESURF_NORMALS_AUTO ? RESURF_NORMALS_JET : o->normals], /* AUTO's meaning here */
           side_names[o->side_rule], displacement_names[o->displacement]);
    cli_json_number(stdout, o->step);
    printf(", \"iterations\": %u, \"tolerance\": ", o->iterations);
    cli_json_number(stdout, o->tolerance_rel);
    printf(", \"crease_angle_deg\": ");
    cli_json_number(stdout, o->crease_angle_deg);
    printf(", \"input_normals\": \"%s\", \"outside\": \"%s\", \"boundary\": %s, \"far_factor\": ",
           input_names[o->input_normals], outside_names[o->outside], o->boundary ? "true" : "false");
    cli_json_number(stdout, o->far_factor);
    printf("}, \"vertices\": %zu, \"moved\": %zu, \"mean_displacement\": ", r->vertices, r->moved);
    cli_json_number(stdout, r->mean_displacement);
    printf(", \"max_displacement\": ");
    cli_json_number(stdout, r->max_displacement);
    printf(", \"on_boundary\": %zu, \"on_crease\": %zu, \"used_least_outside\": %zu, \"left_far\": %zu, "
           "\"left_outside\": %zu, \"left_nonfinite\": %zu}\n",
           r->on_boundary, r->on_crease, r->used_least_outside, r->left_far, r->left_outside, r->left_nonfinite);
}

int cmd_restore(int argc, char **argv)
{
    static const struct option options[] = {
        {"output", required_argument, NULL, 'o'},
        {"preset", required_argument, NULL, 'p'},
        {"normals", required_argument, NULL, 'n'},
        {"input-normals", required_argument, NULL, 'I'},
        {"side", required_argument, NULL, 's'},
        {"displacement", required_argument, NULL, 'd'},
        {"step", required_argument, NULL, 'k'},
        {"iterations", required_argument, NULL, 'i'},
        {"tolerance", required_argument, NULL, 'e'},
        {"crease-angle", required_argument, NULL, 'c'},
        {"outside", required_argument, NULL, 'O'},
        {"no-boundary", no_argument, NULL, 'B'},
        {"far-factor", required_argument, NULL, 'F'},
        {"threads", required_argument, NULL, 't'},
        {"json", no_argument, NULL, 'j'},
        {"format", required_argument, NULL, 'f'},
        CLI_MAX_TRIANGLES_OPTION,
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    const char *out = NULL;
    resurf_format format = RESURF_FORMAT_AUTO;
    int json = 0, paper = 0;
    overrides ov = {.normals = -1, .side = -1, .displacement = -1, .outside = -1, .input_normals = -1,
                    .boundary = -1};
    unsigned long n = 0;
    int rc = CLI_OK;
    cli_getopt_reset();
    for (int c; (c = cli_getopt("restore", argc, argv, "ho:", options)) != -1;) {
        switch (c) {
        case 'o':
            out = optarg;
            break;
        case 'p':
            if (!strcmp(optarg, "paper"))
                paper = 1;
            else if (!strcmp(optarg, "default"))
                paper = 0;
            else
                return cli_usage("restore", "unknown --preset '%s' (paper, default)", optarg);
            break;
        case 'n':
            if (cli_parse_choice("restore", "normals", optarg, normal_names, RESURF_NORMALS_COUNT, &ov.normals))
                return CLI_USAGE;
            break;
        case 'I':
            if (cli_parse_choice("restore", "input-normals", optarg, input_names, RESURF_INPUT_NORMALS_COUNT,
                                 &ov.input_normals))
                return CLI_USAGE;
            break;
        case 's':
            if (cli_parse_choice("restore", "side", optarg, side_names, RESURF_SIDE_COUNT, &ov.side))
                return CLI_USAGE;
            break;
        case 'd':
            if (cli_parse_choice("restore", "displacement", optarg, displacement_names, RESURF_DISPLACEMENT_COUNT,
                                 &ov.displacement))
                return CLI_USAGE;
            break;
        case 'O':
            if (cli_parse_choice("restore", "outside", optarg, outside_names, RESURF_OUTSIDE_COUNT, &ov.outside))
                return CLI_USAGE;
            break;
        case 'k':
            if (cli_parse_double("restore", "step", optarg, &ov.step))
                return CLI_USAGE;
            if (!(ov.step > 0 && ov.step <= 1))
                return cli_usage("restore", "--step must be in (0, 1], not %s", optarg);
            ov.has_step = 1;
            break;
        case 'i':
            if (cli_parse_unsigned("restore", "iterations", optarg, &n))
                return CLI_USAGE;
            if (n < 1 || n > 1000)
                return cli_usage("restore", "--iterations must be in 1..1000, not %s", optarg);
            ov.iterations = (unsigned)n, ov.has_iterations = 1;
            break;
        case 'e':
            if (cli_parse_double("restore", "tolerance", optarg, &ov.tolerance))
                return CLI_USAGE;
            if (!(ov.tolerance >= 0))
                return cli_usage("restore", "--tolerance must be >= 0, not %s", optarg);
            ov.has_tolerance = 1;
            break;
        case 'c':
            if (cli_parse_double("restore", "crease-angle", optarg, &ov.crease))
                return CLI_USAGE;
            if (!(ov.crease >= 0 && ov.crease <= 180))
                return cli_usage("restore", "--crease-angle must be in [0, 180], not %s", optarg);
            ov.has_crease = 1;
            break;
        case 'B':
            ov.boundary = 0;
            break;
        case 'F':
            if (cli_parse_double("restore", "far-factor", optarg, &ov.far))
                return CLI_USAGE;
            if (!(ov.far > 0))
                return cli_usage("restore", "--far-factor must be positive, not %s", optarg);
            ov.has_far = 1;
            break;
        case 't':
            if (cli_parse_threads("restore", optarg, &ov.threads))
                return CLI_USAGE;
            ov.has_threads = 1;
            break;
        case 'j':
            json = 1;
            break;
        default:
            if ((rc = cli_shared_option("restore", usage, c, &format)) != CLI_NEXT)
                return rc;
        }
    }
    if (argc - optind != 2)
        return cli_usage("restore", "expected ORIGINAL and PROCESSED");
    const char *inputs[2] = {argv[optind], argv[optind + 1]};
    if ((rc = cli_check_mesh_output("restore", out, inputs, 2)))
        return rc;

    resurf_restore_options o = paper ? resurf_restore_options_paper() : resurf_restore_options_default();
    if (ov.normals >= 0)
        o.normals = (resurf_normal_scheme)ov.normals;
    if (ov.side >= 0)
        o.side_rule = (resurf_side_rule)ov.side;
    if (ov.displacement >= 0)
        o.displacement = (resurf_displacement)ov.displacement;
    if (ov.outside >= 0)
        o.outside = (resurf_outside_policy)ov.outside;
    if (ov.input_normals >= 0)
        o.input_normals = (resurf_input_normals)ov.input_normals;
    if (ov.boundary >= 0)
        o.boundary = ov.boundary != 0;
    if (ov.has_step)
        o.step = ov.step;
    if (ov.has_iterations)
        o.iterations = ov.iterations;
    if (ov.has_tolerance)
        o.tolerance_rel = ov.tolerance;
    if (ov.has_crease)
        o.crease_angle_deg = ov.crease;
    if (ov.has_far)
        o.far_factor = ov.far;
    if (ov.has_threads)
        o.threads = ov.threads;

    resurf_mesh *original = NULL, *processed = NULL;
    if (cli_load(inputs[0], format, &original))
        return CLI_FAILED;
    if (cli_load(inputs[1], format, &processed)) {
        resurf_mesh_free(original);
        return CLI_FAILED;
    }
    o.progress = cli_progress();
    resurf_restore_report report;
    resurf_error error;
    resurf_status s = resurf_restore(original, processed, &o, &report, &error);
    cli_progress_done();
    rc = CLI_OK;
    if (s != RESURF_OK)
        rc = cli_fail_error(&error);
    else if (cli_save(processed, out, NULL))
        rc = CLI_FAILED;
    else if (json)
        print_json(inputs[0], inputs[1], out, &o, &report);
    else
        print_text(inputs[0], inputs[1], out, &report);
    resurf_mesh_free(original);
    resurf_mesh_free(processed);
    return rc;
}
