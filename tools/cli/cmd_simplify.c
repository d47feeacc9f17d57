/* resurf simplify IN -o OUT: edge-collapse simplification with the new vertices restored onto the smooth surface
 * of IN (resurf_simplify(), resurf_simplify_lods()). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char usage[] =
    "usage: resurf simplify IN -o OUT (--ratio R | --triangles N | --error E | --error-rel E | --levels R,...)\n"
    "                       [options]\n\n"
    "Simplifies IN by edge collapses (Garland-Heckbert quadrics) and restores every new vertex onto the smooth\n"
    "surface IN approximates (Semenova, Savchenko, Hagiwara). Several targets may be given: the first one reached\n"
    "stops. Prints the counts reached and the measured distance to IN, both ways (samples and vertices of the\n"
    "result to IN, and of IN to the result) and the symmetric max of the two, and the UV error if IN has UVs.\n\n"
    "  -o, --output OUT          the result (format from the extension; refuses to overwrite IN)\n"
    "  --ratio R                 keep at most R x the triangles of IN, R in [0, 1]\n"
    "  --triangles N             keep at most N triangles\n"
    "  --error E                 never collapse where the estimated error exceeds E (mesh units)\n"
    "  --error-rel E             the same relative to IN's bounding-box diagonal\n"
    "  --levels R1,R2,...        a chain of levels of detail at these ratios (non-increasing, in (0, 1]), each\n"
    "                            simplified from the previous one and restored onto IN; level I (1-based) of\n"
    "                            -o STEM.EXT is written to STEM_lodI.EXT (OUT itself is not written)\n"
    "  --placement P             quadric (default) or midpoint\n"
    "  --restore MODE            measured (default: each level made inline and plain; inline kept where it is\n"
    "                            as near IN in max and mean), inline (after every collapse), post (once at the\n"
    "                            end), none\n"
    "  --sag-offset S            move restored vertices outward by S x the local chord sag so that the facets\n"
    "                            straddle the surface; 0 keeps them on it (default: the library's)\n"
    "  --lock-border             border vertices never move\n"
    "  --keep-fins               keep triangles over the same three positions as another (default: a pair\n"
    "                            facing opposite ways goes whole, a same-facing repeat goes alone; a\n"
    "                            free-standing double-sided sheet is simplified as one side and written with\n"
    "                            both)\n"
    "  --attached-sheets S       such a sheet attached along a line (a crest, a fin): choose (default: with\n"
    "                            --restore measured, each level made with it dropped and kept, the one as near\n"
    "                            IN in max and mean kept; else drop), drop, keep (its line then holds still)\n"
    "  --min-angle DEG           refuse collapses that make a triangle angle smaller than DEG (default off)\n"
    "  --max-normal-change DEG   refuse collapses that turn a triangle by more than DEG (default: the library's)\n"
    "  --attribute-weights N,UV,C[,S]  weights of normals, texture coordinates, colours and skin influences\n"
    "                            in the collapse cost (0 = that attribute off; default 0,0.25,0.25,1.4)\n"
    "  --feature-angle DEG       an edge whose triangles turn by more than DEG is a crease: kept, never\n"
    "                            restored across (default: the library's; 180 = none)\n"
    "  --corner-angle DEG        a border turning by more than DEG makes a corner that never moves\n"
    "                            (default: the library's; 180 = none)\n"
    "  --weld-tolerance R        vertices closer than R x the diagonal are one position (copies a rounding\n"
    "                            apart; default: the library's, 1e-8; 0 = exact copies only)\n"
    "  --samples N               samples of the result measured against IN, and of IN against the result, for\n"
    "                            the report (0 = none)\n"
    "  --threads N               worker threads, 0 = all cores (default); the result is the same for any N\n"
    "  --json                    print the report as JSON on stdout\n"
    "  --format FMT              read IN as obj|ply|off|stl whatever its name says\n" CLI_MAX_TRIANGLES_HELP;

static const char *const placement_names[RESURF_PLACEMENT_COUNT] = {"quadric", "midpoint"};

enum { MAX_LEVELS = 32 };

/* STEM_lodI.EXT for OUT = STEM.EXT (the extension is what follows the last '.' of the file name). */
static char *level_path(const char *out, size_t level)
{
    const char *slash = strrchr(out, '/');
    const char *dot = strrchr(out, '.');
    if (!dot || (slash && dot < slash) || dot == (slash ? slash + 1 : out))
        dot = out + strlen(out);
    size_t need = strlen(out) + 32;
    char *path = malloc(need);
    if (path)
        snprintf(path, need, "%.*s_lod%zu%s", (int)(dot - out), out, level, dot);
    return path;
}

static void print_text(const char *out, const resurf_simplify_report *r)
{
    printf("output               %s\n", out);
    printf("triangles            %zu -> %zu\n", r->input_triangles, r->triangles);
    printf("vertices             %zu (%zu positions)\n", r->vertices, r->positions);
    printf("collapses            %zu\n", r->collapses);
    printf("dropped fins         %zu\n", r->dropped_fins);
    printf("stopped by           %s\n", cli_stop_names[r->stop]);
    printf("max distance to IN   %.9g (%.3g of the diagonal; two-sided)\n", r->max_distance, r->max_distance_rel);
    printf("mean distance to IN  %.9g (%.3g of the diagonal; two-sided)\n", r->mean_distance,
           r->mean_distance_rel);
    printf("  result -> IN       max %.9g, mean %.9g\n", r->result_to_input_max, r->result_to_input_mean);
    printf("  IN -> result       max %.9g, mean %.9g\n", r->input_to_result_max, r->input_to_result_mean);
    if (!isnan(r->uv_error_mean))
        printf("UV error             mean %.9g, 95th percentile %.9g (TEXCOORD_0)\n", r->uv_error_mean,
               r->uv_error_p95);
    printf("max error estimate   %.9g\n", r->max_error_estimate);
    printf("restored             %zu (left alone %zu; made %s)\n", r->restored, r->restore_left,
           cli_restore_names[r->restore_used]);
    if (r->attached_sheets_used == RESURF_SHEETS_KEEP)
        printf("attached sheets      kept\n");
    printf("blocked: link        %zu\n", r->blocked_link);
    printf("blocked: flip        %zu\n", r->blocked_flip);
    printf("blocked: min angle   %zu\n", r->blocked_min_angle);
    printf("blocked: distance    %zu\n", r->blocked_distance);
    printf("blocked: border      %zu\n", r->blocked_border);
    printf("blocked: seam        %zu\n", r->blocked_seam);
    printf("blocked: feature     %zu\n", r->blocked_feature);
    printf("blocked: non-manif.  %zu\n", r->blocked_nonmanifold);
    printf("skipped: over error  %zu\n", r->skipped_error);
}

static void print_json_report(const char *out, const resurf_simplify_report *r)
{
    printf("{\"output\": ");
    cli_json_string(stdout, out);
    printf(", \"input_triangles\": %zu, \"input_positions\": %zu, \"triangles\": %zu, \"vertices\": %zu, "
           "\"positions\": %zu, \"collapses\": %zu, \"dropped_fins\": %zu, \"stop\": \"%s\", \"max_distance\": ",
           r->input_triangles, r->input_positions, r->triangles, r->vertices, r->positions, r->collapses,
           r->dropped_fins, cli_stop_names[r->stop]);
    cli_json_number(stdout, r->max_distance);
    printf(", \"mean_distance\": ");
    cli_json_number(stdout, r->mean_distance);
    printf(", \"max_distance_rel\": ");
    cli_json_number(stdout, r->max_distance_rel);
    printf(", \"mean_distance_rel\": ");
    cli_json_number(stdout, r->mean_distance_rel);
    printf(", \"result_to_input_max\": ");
    cli_json_number(stdout, r->result_to_input_max);
    printf(", \"result_to_input_mean\": ");
    cli_json_number(stdout, r->result_to_input_mean);
    printf(", \"input_to_result_max\": ");
    cli_json_number(stdout, r->input_to_result_max);
    printf(", \"input_to_result_mean\": ");
    cli_json_number(stdout, r->input_to_result_mean);
    printf(", \"uv_error_mean\": ");
    cli_json_number(stdout, r->uv_error_mean);
    printf(", \"uv_error_p95\": ");
    cli_json_number(stdout, r->uv_error_p95);
    printf(", \"diagonal\": ");
    cli_json_number(stdout, r->diagonal);
    printf(", \"max_error_estimate\": ");
    cli_json_number(stdout, r->max_error_estimate);
    printf(", \"restore_used\": \"%s\", \"attached_sheets_used\": \"%s\"", cli_restore_names[r->restore_used],
           cli_sheet_names[r->attached_sheets_used]);
    printf(", \"restored\": %zu, \"restore_left\": %zu, \"blocked\": {\"link\": %zu, \"flip\": %zu, \"min_angle\": %zu, "
           "\"distance\": %zu, \"border\": %zu, \"seam\": %zu, \"feature\": %zu, \"nonmanifold\": %zu}, "
           "\"skipped_error\": %zu}",
           r->restored, r->restore_left, r->blocked_link, r->blocked_flip, r->blocked_min_angle,
           r->blocked_distance, r->blocked_border, r->blocked_seam, r->blocked_feature, r->blocked_nonmanifold,
           r->skipped_error);
}

int cmd_simplify(int argc, char **argv)
{
    static const struct option options[] = {
        {"output", required_argument, NULL, 'o'},
        {"ratio", required_argument, NULL, 'r'},
        {"triangles", required_argument, NULL, 'n'},
        {"error", required_argument, NULL, 'e'},
        {"error-rel", required_argument, NULL, 'E'},
        {"levels", required_argument, NULL, 'L'},
        {"placement", required_argument, NULL, 'p'},
        {"restore", required_argument, NULL, 'R'},
        {"sag-offset", required_argument, NULL, 'S'},
        {"lock-border", no_argument, NULL, 'b'},
        {"keep-fins", no_argument, NULL, 'k'},
        {"attached-sheets", required_argument, NULL, 'A'},
        {"min-angle", required_argument, NULL, 'a'},
        {"max-normal-change", required_argument, NULL, 'N'},
        {"attribute-weights", required_argument, NULL, 'W'},
        {"feature-angle", required_argument, NULL, 'F'},
        {"corner-angle", required_argument, NULL, 'C'},
        {"weld-tolerance", required_argument, NULL, 'w'},
        {"samples", required_argument, NULL, 's'},
        {"threads", required_argument, NULL, 't'},
        {"json", no_argument, NULL, 'j'},
        {"format", required_argument, NULL, 'f'},
        CLI_MAX_TRIANGLES_OPTION,
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    const char *out = NULL;
    resurf_format format = RESURF_FORMAT_AUTO;
    int json = 0, has_target = 0, choice = 0;
    double levels[MAX_LEVELS];
    size_t level_count = 0;
    unsigned long n = 0;
    resurf_simplify_options o = resurf_simplify_options_default();
    int rc = CLI_OK;
    cli_getopt_reset();
    for (int c; (c = cli_getopt("simplify", argc, argv, "ho:", options)) != -1;) {
        switch (c) {
        case 'o':
            out = optarg;
            break;
        case 'r':
            if (cli_parse_double("simplify", "ratio", optarg, &o.target_ratio))
                return CLI_USAGE;
            if (!(o.target_ratio >= 0 && o.target_ratio <= 1))
                return cli_usage("simplify", "--ratio must be in [0, 1], not %s", optarg);
            has_target = 1;
            break;
        case 'n':
            if (cli_parse_unsigned("simplify", "triangles", optarg, &n))
                return CLI_USAGE;
            o.target_triangles = n;
            has_target = 1;
            break;
        case 'e':
        case 'E':
            if (cli_parse_double("simplify", c == 'e' ? "error" : "error-rel", optarg,
                                 c == 'e' ? &o.max_error : &o.max_error_rel))
                return CLI_USAGE;
            if (!((c == 'e' ? o.max_error : o.max_error_rel) > 0))
                return cli_usage("simplify", "--%s must be positive, not %s", c == 'e' ? "error" : "error-rel",
                                 optarg);
            has_target = 1;
            break;
        case 'L':
            if (cli_parse_levels("simplify", optarg, levels, MAX_LEVELS, &level_count))
                return CLI_USAGE;
            break;
        case 'p':
            if (cli_parse_choice("simplify", "placement", optarg, placement_names, RESURF_PLACEMENT_COUNT, &choice))
                return CLI_USAGE;
            o.placement = (resurf_placement)choice;
            break;
        case 'R':
            if (cli_parse_choice("simplify", "restore", optarg, cli_restore_names, RESURF_RESTORE_MODE_COUNT, &choice))
                return CLI_USAGE;
            o.restore = (resurf_restore_mode)choice;
            break;
        case 'S':
            if (cli_parse_double("simplify", "sag-offset", optarg, &o.sag_offset))
                return CLI_USAGE;
            if (!(o.sag_offset >= 0 && o.sag_offset <= 4))
                return cli_usage("simplify", "--sag-offset must be in [0, 4], not %s", optarg);
            break;
        case 'b':
            o.lock_border = true;
            break;
        case 'k':
            o.drop_fins = false;
            break;
        case 'A':
            if (cli_parse_choice("simplify", "attached-sheets", optarg, cli_sheet_names, RESURF_SHEETS_COUNT, &choice))
                return CLI_USAGE;
            o.attached_sheets = (resurf_attached_sheets)choice;
            break;
        case 'a':
            if (cli_parse_double("simplify", "min-angle", optarg, &o.min_angle_deg))
                return CLI_USAGE;
            if (!(o.min_angle_deg >= 0 && o.min_angle_deg < 60))
                return cli_usage("simplify", "--min-angle must be in [0, 60), not %s", optarg);
            break;
        case 'N':
            if (cli_parse_angle("simplify", "max-normal-change", optarg, &o.max_normal_change_deg))
                return CLI_USAGE;
            break;
        case 'W':
            if (cli_parse_attribute_weights("simplify", optarg, &o))
                return CLI_USAGE;
            break;
        case 'F':
            if (cli_parse_angle("simplify", "feature-angle", optarg, &o.feature_angle_deg))
                return CLI_USAGE;
            break;
        case 'C':
            if (cli_parse_angle("simplify", "corner-angle", optarg, &o.corner_angle_deg))
                return CLI_USAGE;
            break;
        case 'w':
            if (cli_parse_weld_tolerance("simplify", optarg, &o.weld_tolerance_rel))
                return CLI_USAGE;
            break;
        case 's':
            if (cli_parse_unsigned("simplify", "samples", optarg, &n))
                return CLI_USAGE;
            o.measure_samples = n;
            break;
        case 't':
            if (cli_parse_threads("simplify", optarg, &o.threads))
                return CLI_USAGE;
            break;
        case 'j':
            json = 1;
            break;
        default:
            if ((rc = cli_shared_option("simplify", usage, c, &format)) != CLI_NEXT)
                return rc;
        }
    }
    if (argc - optind != 1)
        return cli_usage("simplify", "expected one input mesh IN");
    if (!out)
        return cli_usage("simplify", "missing -o OUT");
    if (!has_target && !level_count)
        return cli_usage("simplify", "give a target: --ratio, --triangles, --error, --error-rel or --levels");
    if (level_count && (o.target_ratio > 0 || o.target_triangles))
        return cli_usage("simplify", "--levels sets the targets; --ratio and --triangles do not go with it");
    if (resurf_format_from_path(out) == RESURF_FORMAT_AUTO)
        return cli_usage("simplify", "cannot tell the format of '%s' from its name (.obj, .ply, .off, .stl)", out);
    const char *input = argv[optind];

    size_t outputs = level_count ? level_count : 1;
    char *paths[MAX_LEVELS] = {NULL};
    rc = CLI_OK;
    for (size_t i = 0; i < outputs && rc == CLI_OK; ++i) {
        paths[i] = level_count ? level_path(out, i + 1) : strdup(out);
        if (!paths[i])
            rc = cli_fail("out of memory");
        else if (cli_check_output(paths[i], &input, 1))
            rc = CLI_FAILED;
    }
    resurf_mesh *mesh = NULL;
    if (rc == CLI_OK && cli_load(input, format, &mesh))
        rc = CLI_FAILED;

    resurf_mesh *results[MAX_LEVELS] = {NULL};
    resurf_simplify_report reports[MAX_LEVELS];
    if (rc == CLI_OK) {
        o.progress = cli_progress();
        resurf_error error;
        resurf_status s = level_count ? resurf_simplify_lods(mesh, levels, level_count, &o, results, reports, &error)
                                      : resurf_simplify(mesh, &o, &results[0], &reports[0], &error);
        cli_progress_done();
        if (s != RESURF_OK)
            rc = cli_fail_error(&error);
    }
    for (size_t i = 0; i < outputs && rc == CLI_OK; ++i)
        if (cli_save(results[i], paths[i], NULL))
            rc = CLI_FAILED;
    if (rc == CLI_OK) {
        if (json) {
            printf("{\"input\": ");
            cli_json_string(stdout, input);
            printf(", \"placement\": \"%s\", \"restore\": \"%s\", \"levels\": [", placement_names[o.placement],
                   cli_restore_names[o.restore]);
            for (size_t i = 0; i < outputs; ++i) {
                if (i)
                    printf(", ");
                print_json_report(paths[i], &reports[i]);
            }
            printf("]}\n");
        } else {
            printf("input                %s\n", input);
            for (size_t i = 0; i < outputs; ++i) {
                if (level_count)
                    printf("\nlevel %zu (ratio %g)\n", i + 1, levels[i]);
                print_text(paths[i], &reports[i]);
            }
        }
    }
    for (size_t i = 0; i < outputs; ++i) {
        resurf_mesh_free(results[i]);
        free(paths[i]);
    }
    resurf_mesh_free(mesh);
    return rc;
}
