/* resurf smooth IN -o OUT: the smoothing filters of resurf_smooth() (the processed meshes M' of the paper). */
#include <string.h>

#include "cli.h"

static const char usage[] =
    "usage: resurf smooth IN -o OUT [--method METHOD] [--iterations N] [--lambda L] [--mu M]\n"
    "                             [--max-triangles N]\n\n"
    "Smooths the positions of a mesh; connectivity and attributes stay. Attribute seams move together,\n"
    "boundary and non-manifold vertices stay fixed. Normals are written as they were read (not recomputed).\n\n"
    "  -o, --output OUT    the smoothed mesh (format from the extension; refuses to overwrite IN)\n"
    "  --method METHOD     laplacian (default): umbrella with uniform weights, step lambda\n"
    "                      taubin: lambda|mu steps with uniform weights (hardly shrinks)\n"
    "                      taubin-cot: lambda|mu steps with cotangent weights\n"
    "                      bilaplacian: umbrella of the umbrella (Kobbelt), step lambda <= 0.5\n"
    "  --iterations N      default 10 (a Taubin iteration is one lambda and one mu step)\n"
    "  --lambda L          step in (0, 1]; default 0.5 (laplacian, bilaplacian), 0.33 (taubin)\n"
    "  --mu M              Taubin's negative step in [-1, 0); default -0.34\n"
    "  --format FMT        read IN as obj|ply|off|stl whatever its name says\n"
    CLI_MAX_TRIANGLES_HELP;

static int parse_method(const char *text, resurf_smooth_method *out)
{
    for (int k = 0; k < RESURF_SMOOTH_COUNT; ++k)
        if (!strcmp(text, resurf_smooth_method_name((resurf_smooth_method)k))) {
            *out = (resurf_smooth_method)k;
            return 0;
        }
    return cli_usage("smooth", "unknown method '%s' (laplacian, taubin, taubin-cot, bilaplacian)", text);
}

int cmd_smooth(int argc, char **argv)
{
    static const struct option options[] = {
        {"output", required_argument, NULL, 'o'},
        {"method", required_argument, NULL, 'm'},
        {"iterations", required_argument, NULL, 'i'},
        {"lambda", required_argument, NULL, 'l'},
        {"mu", required_argument, NULL, 'u'},
        {"format", required_argument, NULL, 'f'},
        CLI_MAX_TRIANGLES_OPTION,
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    const char *out = NULL;
    resurf_format format = RESURF_FORMAT_AUTO;
    resurf_smooth_options so = resurf_smooth_options_default();
    unsigned long n = 0;
    int rc = CLI_OK;
    cli_getopt_reset();
    for (int c; (c = cli_getopt("smooth", argc, argv, "ho:", options)) != -1;) {
        switch (c) {
        case 'o':
            out = optarg;
            break;
        case 'm':
            if (parse_method(optarg, &so.method))
                return CLI_USAGE;
            break;
        case 'i':
            if (cli_parse_unsigned("smooth", "iterations", optarg, &n))
                return CLI_USAGE;
            if (n > 1000000)
                return cli_usage("smooth", "--iterations %lu is more than 1000000", n);
            so.iterations = (unsigned)n;
            break;
        case 'l':
            if (cli_parse_double("smooth", "lambda", optarg, &so.lambda))
                return CLI_USAGE;
            if (!(so.lambda > 0 && so.lambda <= 1))
                return cli_usage("smooth", "--lambda must be in (0, 1], not %s", optarg);
            break;
        case 'u':
            if (cli_parse_double("smooth", "mu", optarg, &so.mu))
                return CLI_USAGE;
            if (!(so.mu >= -1 && so.mu < 0))
                return cli_usage("smooth", "--mu must be in [-1, 0), not %s", optarg);
            break;
        default:
            if ((rc = cli_shared_option("smooth", usage, c, &format)) != CLI_NEXT)
                return rc;
        }
    }
    if (argc - optind != 1)
        return cli_usage("smooth", "expected one input mesh IN");
    if (so.method == RESURF_SMOOTH_BILAPLACIAN && so.lambda > 0.5)
        return cli_usage("smooth", "--lambda must be at most 0.5 for bilaplacian");
    const char *in = argv[optind];
    if ((rc = cli_check_mesh_output("smooth", out, &in, 1)))
        return rc;

    resurf_mesh *mesh = NULL;
    if (cli_load(in, format, &mesh))
        return CLI_FAILED;
    so.progress = cli_progress();
    resurf_error error;
    resurf_status s = resurf_smooth(mesh, &so, &error);
    cli_progress_done();
    rc = CLI_OK;
    if (s != RESURF_OK)
        rc = cli_fail_error(&error);
    else if (cli_save(mesh, out, NULL))
        rc = CLI_FAILED;
    resurf_mesh_free(mesh);
    return rc;
}
