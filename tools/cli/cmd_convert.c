/* resurf convert IN OUT: between OBJ, PLY, OFF and STL, keeping what the target format can hold. */
#include "cli.h"

static const char usage[] =
    "usage: resurf convert IN OUT [--from FMT] [--to FMT] [--ascii] [--max-triangles N]\n\n"
    "Converts a mesh between OBJ, PLY, OFF and STL (chosen by extension unless --from/--to say otherwise),\n"
    "keeping the attributes the target format can hold. OUT is written to a temporary file and renamed into\n"
    "place; writing onto IN is refused.\n\n"
    "  --from FMT   read IN as obj|ply|off|stl\n"
    "  --to FMT     write OUT as obj|ply|off|stl\n"
    "  --ascii      PLY and STL: write text instead of binary\n"
    CLI_MAX_TRIANGLES_HELP;

int cmd_convert(int argc, char **argv)
{
    static const struct option options[] = {
        {"from", required_argument, NULL, 'f'},
        {"to", required_argument, NULL, 't'},
        {"ascii", no_argument, NULL, 'a'},
        CLI_MAX_TRIANGLES_OPTION,
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    resurf_format from = RESURF_FORMAT_AUTO;
    resurf_save_options save = resurf_save_options_default();
    int rc = CLI_OK;
    cli_getopt_reset();
    for (int c; (c = cli_getopt("convert", argc, argv, "h", options)) != -1;) {
        switch (c) {
        case 'f':
            if ((from = resurf_format_from_name(optarg)) == RESURF_FORMAT_AUTO)
                return cli_usage("convert", "unknown format '%s'", optarg);
            break;
        case 't':
            if ((save.format = resurf_format_from_name(optarg)) == RESURF_FORMAT_AUTO)
                return cli_usage("convert", "unknown format '%s'", optarg);
            break;
        case 'a':
            save.binary = false;
            break;
        default:
            if ((rc = cli_shared_option("convert", usage, c, NULL)) != CLI_NEXT)
                return rc;
        }
    }
    if (argc - optind != 2)
        return cli_usage("convert", "expected IN and OUT");
    const char *in = argv[optind], *out = argv[optind + 1];
    if (save.format == RESURF_FORMAT_AUTO && resurf_format_from_path(out) == RESURF_FORMAT_AUTO)
        return cli_usage("convert", "cannot tell the format of '%s' from its name; use --to", out);
    if (cli_check_output(out, &in, 1))
        return CLI_FAILED;
    resurf_mesh *mesh = NULL;
    if (cli_load(in, from, &mesh))
        return CLI_FAILED;
    rc = cli_save(mesh, out, &save) ? CLI_FAILED : CLI_OK;
    resurf_mesh_free(mesh);
    return rc;
}
