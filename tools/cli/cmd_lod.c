/* resurf lod IN -o OUT: a chain of levels of detail of every triangle primitive of a scene (glTF, or a mesh file),
 * each level simplified with inline restoration onto the ORIGINAL surface and the MSFT_lod screen coverage taken
 * from the measured errors (both by resurf_scene_build_lods()), written as one glTF with MSFT_lod, one file per
 * level, or side by side (resurf_scene_save()). This file only parses arguments and prints the table. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char usage[] =
    "usage: resurf lod IN -o OUT [--levels 0.5,0.25,0.1] [--errors E1,E2,...] [--error E | --error-rel E]\n"
    "                 [--lock-border] [--no-share] [--draco|--no-draco] [--layout msft_lod|files|side-by-side]\n"
    "                 [--json] [options]\n\n"
    "Builds levels of detail of every triangle primitive of IN (.gltf, .glb, .drc, or a mesh file as a one-mesh\n"
    "scene): each level keeps at most R x the triangles, is simplified from the previous level and restored onto\n"
    "the smooth surface of the ORIGINAL mesh. A mesh shown by several nodes is simplified once. Morph targets\n"
    "follow every level (each vertex's deltas are the input's at its closest point); points and lines are copied.\n"
    "Everything else of the scene (nodes, materials, textures, skins, animations, extensions) is kept. A level that\n"
    "has no fewer triangles than the one before, or misses its ratio (more than 1.5 x its target + 2 triangles),\n"
    "ends the primitive's chain (a warning says which guard blocked how many collapses); a primitive with fewer\n"
    "levels shows its last one. With ratios, the scene's triangles then go where the error is: the primitive of\n"
    "the largest world error gets more, taken back from the largest others, as long as the scene keeps its count.\n"
    "Prints per level the triangles, the measured error in world space over the whole\n"
    "scene (two-sided Hausdorff distance to level 0, relative to the scene's bounding-box diagonal, and in scene\n"
    "units) and the bytes of geometry.\n\n"
    "  -o, --output OUT       .glb, .gltf or .drc (a .drc holds one mesh: use --layout files)\n"
    "  --levels R1,R2,...     ratios of the levels, non-increasing in (0, 1] (default 0.5,0.25,0.1)\n"
    "  --errors E1,E2,...     relative errors of the levels (of the scene's world diagonal), non-decreasing:\n"
    "                         level K also stops where a collapse's estimated error exceeds EK; alone, a chain by\n"
    "                         errors (each level as far as its error allows); with --levels, as many values\n"
    "  --error E              every level also stops at this estimated error, in world units\n"
    "  --error-rel E          ... relative to the scene's world bounding-box diagonal\n"
    "  --lock-border          border vertices never move or disappear\n"
    "  --no-share             every primitive at its own ratio (no triangles moved between them: faster on scenes\n"
    "                         of many primitives, and the scene's error is its worst primitive's)\n"
    "  --draco, --no-draco    KHR_draco_mesh_compression on (default) or off\n"
    "  --layout L             msft_lod (default: MSFT_lod, one file), files (OUT's name + _lodK per level, level 0\n"
    "                         the full detail) or side-by-side (all levels visible next to each other)\n"
    "  --embed                .gltf: put the binary data and the images in the file (default: NAME.bin and\n"
    "                         copies of the external images beside it; a .glb always holds its images)\n"
    "  --allow-missing-images an image file that cannot be read is a warning, not an error (the output refers\n"
    "                         to it by its uri as it was)\n"
    "  --qp/--qn/--qt/--qc/--qg BITS  Draco quantization of positions (14), normals (10), texture coordinates (12),\n"
    "                         colours (8) and other float attributes (12)\n"
    "  --compression-level N  Draco 0 (fastest) .. 10 (smallest), default 7\n"
    "  --pixels P             MSFT_lod switching: a level shows once its error covers at most P pixels (default 1)\n"
    "  --screen-height H      ... on a screen H pixels high (default 1080)\n"
    "  --attribute-weights N,UV,C[,S]  weights of normals, texture coordinates, colours and skin influences\n"
    "                         in the collapse cost (0 = that attribute off; default 0,0.25,0.25,1.4)\n"
    "  --feature-angle DEG    an edge whose triangles turn by more than DEG is a crease: kept, never restored\n"
    "                         across (default: the library's; 180 = none)\n"
    "  --corner-angle DEG     a border turning by more than DEG makes a corner that never moves (default: the\n"
    "                         library's; 180 = none)\n"
    "  --weld-tolerance R     vertices closer than R x their mesh's diagonal are one position (copies a\n"
    "                         rounding apart; default: the library's, 1e-8; 0 = exact copies only)\n"
    "  --restore MODE         measured (default: each level made with inline restoration and without; the\n"
    "                         restored one kept where it is as near IN in max and mean), inline, post or none\n"
    "  --threads N            worker threads, 0 = all cores (default)\n"
    "  --preview SHEET.png    also draw every level with its error, as 'resurf preview' does\n"
    "  --preview-size WxH     the sheet's size (default 1600x900)\n"
    "  --json                 print the table as JSON on stdout\n" CLI_MAX_TRIANGLES_HELP CLI_LENIENT_HELP;

enum { MAX_LEVELS = RESURF_SCENE_MAX_LEVELS - 1 };


/* A list of positive numbers, non-decreasing, separated by commas. */
static int parse_errors(const char *text, double *out, size_t max, size_t *count)
{
    size_t n = 0;
    const char *s = text;
    for (;;) {
        char *end;
        double r = strtod(s, &end);
        if (end == s || !(r > 0) || !isfinite(r) || (n && r < out[n - 1]) || n == max)
            return cli_usage("lod", "--errors wants up to %zu positive relative errors, non-decreasing, separated "
                             "by commas: '%s'", max, text);
        out[n++] = r;
        if (*end == 0)
            break;
        if (*end != ',')
            return cli_usage("lod", "--errors: unexpected '%c' in '%s'", *end, text);
        s = end + 1;
    }
    *count = n;
    return 0;
}

/* The guards that blocked collapses in a report, as "link 12, border 40" ("none" when none did). */
static void blocked_text(const resurf_simplify_report *r, char *dst, size_t size)
{
    const struct {
        const char *name;
        size_t n;
    } g[] = {{"link", r->blocked_link},         {"flip", r->blocked_flip},         {"min-angle", r->blocked_min_angle},
             {"distance", r->blocked_distance}, {"border", r->blocked_border},     {"seam", r->blocked_seam},
             {"feature", r->blocked_feature},   {"non-manifold", r->blocked_nonmanifold},
             {"over-error", r->skipped_error}};
    size_t o = 0;
    dst[0] = 0;
    for (size_t i = 0; i < sizeof g / sizeof *g && o < size; ++i)
        if (g[i].n)
            o += (size_t)snprintf(dst + o, size - o, "%s%s %zu", o ? ", " : "", g[i].name, g[i].n);
    if (!o)
        snprintf(dst, size, "none");
}

/* How a warning names the level of the primitives simplified together with one (resurf_scene_build_lods). */
#define UNIT_LEVEL "its unit's level (primitives that share positions go together)"

/* A primitive that level k (0-based) left without triangles, its unit's level (its primitives simplified together),
 * or SIZE_MAX: first of p's mesh, else of any (a unit may span meshes side by side). */
static size_t emptied_sibling(const resurf_scene *scene, const resurf_simplify_report *reports, size_t count,
                              size_t p, size_t k)
{
    resurf_scene_primitive info, other;
    resurf_scene_primitive_info(scene, p, &info, NULL);
    size_t any = SIZE_MAX;
    for (size_t q = 0; q < resurf_scene_primitive_count(scene); ++q) {
        resurf_scene_primitive_info(scene, q, &other, NULL);
        const resurf_mesh *m = resurf_scene_primitive_mesh(scene, q);
        if (m && m->triangle_count > 0 && reports[q * count + k].triangles == 0 &&
            reports[q * count + k].input_triangles == m->triangle_count) {
            if (other.mesh == info.mesh)
                return q;
            any = any == SIZE_MAX ? q : any;
        }
    }
    return any;
}

static void json_blocked(const resurf_simplify_report *r)
{
    printf("{\"link\": %zu, \"flip\": %zu, \"min_angle\": %zu, \"distance\": %zu, \"border\": %zu, \"seam\": %zu, "
           "\"feature\": %zu, \"nonmanifold\": %zu, \"over_error\": %zu}",
           r->blocked_link, r->blocked_flip, r->blocked_min_angle, r->blocked_distance, r->blocked_border,
           r->blocked_seam, r->blocked_feature, r->blocked_nonmanifold, r->skipped_error);
}

static int parse_bits(const char *option, const char *text, int *out)
{
    unsigned long n;
    if (cli_parse_unsigned("lod", option, text, &n))
        return CLI_USAGE;
    if (n < 1 || n > 30)
        return cli_usage("lod", "--%s must be in 1..30, not %s", option, text);
    *out = (int)n;
    return 0;
}

int cmd_lod(int argc, char **argv)
{
    static const struct option options[] = {
        {"output", required_argument, NULL, 'o'},
        {"levels", required_argument, NULL, 'L'},
        {"errors", required_argument, NULL, 'X'},
        {"error", required_argument, NULL, 'E'},
        {"error-rel", required_argument, NULL, 'R'},
        {"lock-border", no_argument, NULL, 'b'},
        {"no-share", no_argument, NULL, 'S'},
        {"draco", no_argument, NULL, 'd'},
        {"no-draco", no_argument, NULL, 'D'},
        {"layout", required_argument, NULL, 'l'},
        {"embed", no_argument, NULL, 'e'},
        {"allow-missing-images", no_argument, NULL, 'm'},
        {"qp", required_argument, NULL, '1'},
        {"qn", required_argument, NULL, '2'},
        {"qt", required_argument, NULL, '3'},
        {"qc", required_argument, NULL, '4'},
        {"qg", required_argument, NULL, '5'},
        {"compression-level", required_argument, NULL, 'c'},
        {"pixels", required_argument, NULL, 'p'},
        {"screen-height", required_argument, NULL, 'H'},
        {"threads", required_argument, NULL, 't'},
        {"restore", required_argument, NULL, 'M'},
        {"attribute-weights", required_argument, NULL, 'W'},
        {"feature-angle", required_argument, NULL, 'F'},
        {"corner-angle", required_argument, NULL, 'C'},
        {"weld-tolerance", required_argument, NULL, 'w'},
        {"json", no_argument, NULL, 'j'},
        {"preview", required_argument, NULL, 'P'},
        {"preview-size", required_argument, NULL, 'Z'},
        CLI_MAX_TRIANGLES_OPTION,
        CLI_LENIENT_OPTION,
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    const char *out = NULL, *preview = NULL;
    double ratios[MAX_LEVELS] = {0.5, 0.25, 0.1}, pixels = 1, height = 1080;
    size_t ratio_count = 3, error_count = 0;
    double errors[MAX_LEVELS], error_all = 0, error_rel_all = 0;
    int levels_given = 0;
    int json = 0, allow_missing_images = 0, share = 1;
    resurf_preview_options po = resurf_preview_options_default();
    unsigned long n;
    resurf_scene_save_options so = resurf_scene_save_options_default();
    so.draco = true;
    resurf_simplify_options sim = resurf_simplify_options_default();
    cli_getopt_reset();
    for (int c; (c = cli_getopt("lod", argc, argv, "ho:", options)) != -1;) {
        switch (c) {
        case 'o': out = optarg; break;
        case 'L':
            if (cli_parse_levels("lod", optarg, ratios, MAX_LEVELS, &ratio_count))
                return CLI_USAGE;
            levels_given = 1;
            break;
        case 'X':
            if (parse_errors(optarg, errors, MAX_LEVELS, &error_count))
                return CLI_USAGE;
            break;
        case 'E':
        case 'R': {
            double *dst = c == 'E' ? &error_all : &error_rel_all;
            if (cli_parse_double("lod", c == 'E' ? "error" : "error-rel", optarg, dst))
                return CLI_USAGE;
            if (!(*dst > 0))
                return cli_usage("lod", "--%s must be positive, not %s", c == 'E' ? "error" : "error-rel", optarg);
            break;
        }
        case 'b': sim.lock_border = true; break;
        case 'S': share = 0; break;
        case 'd': so.draco = true; break;
        case 'D': so.draco = false; break;
        case 'l':
            if (!strcmp(optarg, "msft_lod"))
                so.layout = RESURF_LOD_MSFT_LOD;
            else if (!strcmp(optarg, "files"))
                so.layout = RESURF_LOD_FILES;
            else if (!strcmp(optarg, "side-by-side"))
                so.layout = RESURF_LOD_SIDE_BY_SIDE;
            else
                return cli_usage("lod", "unknown --layout '%s' (msft_lod, files, side-by-side)", optarg);
            break;
        case 'e': so.embed_buffers = true; break;
        case 'm': allow_missing_images = 1; break;
        case '1': if (parse_bits("qp", optarg, &so.position_bits)) return CLI_USAGE; break;
        case '2': if (parse_bits("qn", optarg, &so.normal_bits)) return CLI_USAGE; break;
        case '3': if (parse_bits("qt", optarg, &so.texcoord_bits)) return CLI_USAGE; break;
        case '4': if (parse_bits("qc", optarg, &so.color_bits)) return CLI_USAGE; break;
        case '5': if (parse_bits("qg", optarg, &so.generic_bits)) return CLI_USAGE; break;
        case 'c':
            if (cli_parse_unsigned("lod", "compression-level", optarg, &n))
                return CLI_USAGE;
            if (n > 10)
                return cli_usage("lod", "--compression-level must be in 0..10, not %s", optarg);
            so.compression_level = (int)n;
            break;
        case 'p':
        case 'H': {
            double *dst = c == 'p' ? &pixels : &height;
            if (cli_parse_double("lod", c == 'p' ? "pixels" : "screen-height", optarg, dst))
                return CLI_USAGE;
            if (!(*dst > 0) || !isfinite(*dst))
                return cli_usage("lod", "--%s must be positive, not %s", c == 'p' ? "pixels" : "screen-height",
                                 optarg);
            break;
        }
        case 't':
            if (cli_parse_threads("lod", optarg, &sim.threads))
                return CLI_USAGE;
            break;
        case 'M': {
            int choice = 0;
            if (cli_parse_choice("lod", "restore", optarg, cli_restore_names, RESURF_RESTORE_MODE_COUNT, &choice))
                return CLI_USAGE;
            sim.restore = (resurf_restore_mode)choice;
            break;
        }
        case 'W':
            if (cli_parse_attribute_weights("lod", optarg, &sim))
                return CLI_USAGE;
            break;
        case 'F':
            if (cli_parse_angle("lod", "feature-angle", optarg, &sim.feature_angle_deg))
                return CLI_USAGE;
            break;
        case 'C':
            if (cli_parse_angle("lod", "corner-angle", optarg, &sim.corner_angle_deg))
                return CLI_USAGE;
            break;
        case 'w':
            if (cli_parse_weld_tolerance("lod", optarg, &sim.weld_tolerance_rel))
                return CLI_USAGE;
            break;
        case 'j': json = 1; break;
        case 'P': preview = optarg; break;
        case 'Z':
            if (cli_parse_preview_size("lod", "preview-size", optarg, &po))
                return CLI_USAGE;
            break;
        case 'T':
            if (cli_set_max_triangles("lod", optarg))
                return CLI_USAGE;
            break;
        case CLI_OPT_LENIENT: cli_set_lenient(); break;
        case 'h': fputs(usage, stdout); return CLI_OK;
        default: return CLI_USAGE;
        }
    }
    if (argc - optind != 1)
        return cli_usage("lod", "expected one input IN");
    if (error_count && error_rel_all > 0)
        return cli_usage("lod", "--errors and --error-rel both give relative errors: use one");
    if (error_count && levels_given && error_count != ratio_count)
        return cli_usage("lod", "--levels gives %zu levels and --errors %zu: give as many", ratio_count,
                         error_count);
    if (error_count && !levels_given)
        ratio_count = error_count;
    double rel_bounds[MAX_LEVELS], abs_bounds[MAX_LEVELS];
    for (size_t k = 0; k < ratio_count; ++k) {
        rel_bounds[k] = error_count ? errors[k] : error_rel_all;
        abs_bounds[k] = error_all;
    }
    const double *level_ratios = error_count && !levels_given ? NULL : ratios;
    if (!out)
        return cli_usage("lod", "missing -o OUT");
    size_t name_len = strlen(out);
    int drc = name_len >= 4 && !strcmp(out + name_len - 4, ".drc");
    if (!(name_len >= 4 && !strcmp(out + name_len - 4, ".glb")) && !(name_len >= 5 && !strcmp(out + name_len - 5, ".gltf")) &&
        !drc)
        return cli_usage("lod", "OUT must end in .glb, .gltf or .drc: '%s'", out);
    if (drc && so.layout != RESURF_LOD_FILES)
        return cli_usage("lod", "a .drc holds one level: add --layout files");
    const char *input = argv[optind];
    if (preview && (strlen(preview) < 4 || strcmp(preview + strlen(preview) - 4, ".png")))
        return cli_usage("lod", "the --preview sheet must end in .png: '%s'", preview);
    if (preview && cli_check_output(preview, &input, 1))
        return CLI_FAILED;
    size_t levels = ratio_count + 1;
    for (size_t k = 0; k < (so.layout == RESURF_LOD_FILES ? levels : 1); ++k) {
        char path[4096];
        if (so.layout == RESURF_LOD_FILES)
            resurf_scene_level_path(path, sizeof path, out, (unsigned)k);
        else
            snprintf(path, sizeof path, "%s", out);
        if (cli_check_output(path, &input, 1))
            return CLI_FAILED;
    }

    resurf_scene *scene = NULL;
    double load_start = cli_seconds();
    if (cli_load_scene(input, allow_missing_images, &scene))
        return CLI_FAILED;
    double load_seconds = cli_seconds() - load_start;
    resurf_error error;

    /* Every triangle primitive's chain and each mesh's MSFT_screencoverage, in one library call. */
    resurf_scene_lod_options lod = resurf_scene_lod_options_default();
    lod.pixels = pixels;
    lod.screen_height = height;
    lod.share_triangles = share;
    lod.progress = cli_progress();
    lod.level_max_error_rel = rel_bounds;
    lod.level_max_error = abs_bounds;
    resurf_scene_lod_report lod_report;
    int rc = CLI_OK;
    size_t prim_count = resurf_scene_primitive_count(scene);
    resurf_simplify_report *prim_reports = calloc(prim_count * ratio_count + 1, sizeof *prim_reports);
    if (!prim_reports) {
        resurf_scene_free(scene);
        return cli_fail("out of memory");
    }
    resurf_status s = resurf_scene_build_lods(scene, level_ratios, ratio_count, &sim, &lod, &lod_report, prim_reports, &error);
    cli_progress_done();
    if (s != RESURF_OK)
        rc = cli_fail_error(&error);
    /* Each chain that ended early: where, and why (the stop and the guards that blocked collapses). */
    for (size_t p = 0; p < prim_count && rc == CLI_OK; ++p) {
        resurf_scene_primitive info;
        resurf_scene_primitive_info(scene, p, &info, NULL);
        size_t k = info.lod_count;
        if (info.kind == RESURF_PRIMITIVE_OTHER || k >= ratio_count)
            continue;
        const resurf_simplify_report *r = &prim_reports[p * ratio_count + k];
        const resurf_mesh *m = resurf_scene_primitive_mesh(scene, p);
        size_t before = k ? prim_reports[p * ratio_count + k - 1].triangles : m->triangle_count;
        char blocked[256], target[64] = "";
        blocked_text(r, blocked, sizeof blocked);
        if (level_ratios)
            snprintf(target, sizeof target, " (ratio %g, target %zu triangles)", level_ratios[k],
                     (size_t)floor(level_ratios[k] * (double)m->triangle_count));
        /* A primitive simplified together with others (a unit) ends where the unit's chain ends, even when its own
         * part made its ratio (the stop and the guards are the unit's); a level its unit did not make keeps the
         * unit's counts. */
        int mesh_counts = r->input_triangles != m->triangle_count;
        /* A level with no report of its own was never made (a later choice, the scene budget's or the plain
         * pass's, ended the chain before it): say no more than that. */
        if (r->input_triangles == 0) {
            fprintf(stderr, "resurf: warning: %s: level %zu%s was not made; its chain ends at level %zu\n", info.name,
                    k + 1, target, k);
            continue;
        }
        /* Or the unit's level left one of its primitives without triangles. */
        size_t empty = lod_report.level_emptied[k + 1] ? emptied_sibling(scene, prim_reports, ratio_count, p, k)
                                                        : SIZE_MAX;
        if (!mesh_counts && empty != SIZE_MAX) {
            resurf_scene_primitive other;
            resurf_scene_primitive_info(scene, empty, &other, NULL);
            fprintf(stderr,
                    "resurf: warning: %s: level %zu%s was not made: " UNIT_LEVEL " left %s without triangles; its "
                    "chain ends at level %zu\n",
                    info.name, k + 1, target, other.name, k);
            continue;
        }
        const char *what = mesh_counts ? "was not made: " UNIT_LEVEL " stopped at"
                           : r->triangles >= before ? "could not reduce, keeping"
                           : level_ratios && (double)r->triangles <= 1.5 * level_ratios[k] * (double)m->triangle_count + 2
                               ? "reached its ratio, but " UNIT_LEVEL " did not, at"
                               : "missed its ratio at";
        fprintf(stderr,
                "resurf: warning: %s: level %zu%s %s %zu of %zu triangles (stopped: %s; blocked: %s); its chain "
                "ends at level %zu\n",
                info.name, k + 1, target, what, r->triangles, mesh_counts ? r->input_triangles : m->triangle_count,
                cli_stop_names[r->stop < RESURF_STOP_COUNT ? r->stop : 0], blocked, k);
    }
    resurf_scene_save_report report;
    double save_seconds = 0;
    if (rc == CLI_OK && !cli_interrupted()) {
        so.progress = cli_progress();
        so.threads = sim.threads;
        double save_start = cli_seconds();
        s = resurf_scene_save(scene, out, &so, &report, &error);
        save_seconds = cli_seconds() - save_start;
        cli_progress_done();
        if (s != RESURF_OK)
            rc = cli_fail_error(&error);
    } else if (rc == CLI_OK) {
        rc = CLI_FAILED;
    }
    if (rc == CLI_OK) {
        static const char *const layouts[] = {"msft_lod", "files", "side-by-side"};
        if (json) {
            printf("{\"input\": ");
            cli_json_string(stdout, input);
            printf(", \"output\": ");
            cli_json_string(stdout, out);
            printf(", \"layout\": \"%s\", \"draco\": %s, \"files\": %zu, \"bytes\": %zu, \"levels\": [", layouts[so.layout],
                   so.draco ? "true" : "false", report.files, report.total_bytes);
            for (size_t k = 0; k < report.levels; ++k) {
                printf("%s{\"level\": %zu, \"ratio\": ", k ? ", " : "", k);
                cli_json_number(stdout, k && level_ratios ? level_ratios[k - 1] : 1.0);
                printf(", \"reached\": ");
                cli_json_number(stdout, report.level_triangles[0]
                                            ? (double)report.level_triangles[k] / (double)report.level_triangles[0]
                                            : 1.0);
                printf(", \"triangles\": %zu, \"error_rel\": ", report.level_triangles[k]);
                cli_json_number(stdout, lod_report.level_error_rel[k]);
                printf(", \"error\": ");
                cli_json_number(stdout, lod_report.level_error[k]);
                printf(", \"mean_rel\": ");
                cli_json_number(stdout, lod_report.level_mean_rel[k]);
                printf(", \"to_full_rel\": ");
                cli_json_number(stdout, lod_report.level_to_full_rel[k]);
                printf(", \"from_full_rel\": ");
                cli_json_number(stdout, lod_report.level_from_full_rel[k]);
                printf(", \"unreduced\": %zu, \"missed\": %zu, \"emptied\": %zu, \"plain\": %s, \"bytes\": %zu}",
                       lod_report.level_unreduced[k], lod_report.level_missed[k], lod_report.level_emptied[k],
                       lod_report.level_plain[k] ? "true" : "false", report.level_bytes[k]);
            }
            printf("], \"diagonal\": ");
            cli_json_number(stdout, lod_report.diagonal);
            /* Each primitive's own levels: its errors in its own units against its own diagonal, and for the level
             * that ended its chain, why. */
            printf(", \"primitives\": [");
            int first = 1;
            for (size_t p = 0; p < prim_count; ++p) {
                resurf_scene_primitive info;
                resurf_scene_primitive_info(scene, p, &info, NULL);
                if (info.kind == RESURF_PRIMITIVE_OTHER)
                    continue;
                printf("%s{\"name\": ", first ? "" : ", ");
                first = 0;
                cli_json_string(stdout, info.name);
                printf(", \"triangles\": %zu, \"morphed\": %s, \"kept_levels\": %zu, \"levels\": [",
                       resurf_scene_primitive_mesh(scene, p)->triangle_count,
                       info.kind == RESURF_PRIMITIVE_MORPHED ? "true" : "false", info.lod_count);
                for (size_t k = 0; k < ratio_count && k <= info.lod_count; ++k) {
                    const resurf_simplify_report *r = &prim_reports[p * ratio_count + k];
                    printf("%s{\"level\": %zu, \"kept\": %s, \"triangles\": %zu, \"stop\": \"%s\", \"error_rel\": ",
                           k ? ", " : "", k + 1, k < info.lod_count ? "true" : "false", r->triangles,
                           cli_stop_names[r->stop < RESURF_STOP_COUNT ? r->stop : 0]);
                    cli_json_number(stdout, r->max_distance_rel);
                    printf(", \"mean_rel\": ");
                    cli_json_number(stdout, r->mean_distance_rel);
                    printf(", \"blocked\": ");
                    json_blocked(r);
                    printf("}");
                }
                printf("]}");
            }
            /* Wall-clock seconds of each phase. */
            printf("], \"morphed\": %zu, \"dropped_extensions\": %zu, \"seconds\": {\"load\": %.3f, "
                   "\"chains\": %.3f, \"errors\": %.3f, \"save\": %.3f}}\n",
                   lod_report.morphed, report.dropped_extensions, load_seconds, lod_report.chains_seconds,
                   lod_report.errors_seconds, save_seconds);
        } else {
            printf("%-6s %-6s %12s %8s %14s %14s %12s\n", "level", "ratio", "triangles", "reached", "error (rel)",
                   "error", "bytes");
            for (size_t k = 0; k < report.levels; ++k) {
                char asked[32] = "-";
                if (k == 0 || level_ratios)
                    snprintf(asked, sizeof asked, "%g", k ? level_ratios[k - 1] : 1.0);
                double reached = report.level_triangles[0]
                                     ? (double)report.level_triangles[k] / (double)report.level_triangles[0]
                                     : 1.0;
                printf("%-6zu %-6s %12zu %7.1f%% %14.3e %14.3e %12zu\n", k, asked, report.level_triangles[k],
                       100 * reached, lod_report.level_error_rel[k], lod_report.level_error[k], report.level_bytes[k]);
            }
            printf("wrote %s (%s%s, %zu file%s, %zu bytes)\n", out, layouts[so.layout], so.draco ? ", Draco" : "",
                   report.files, report.files == 1 ? "" : "s", report.total_bytes);
        }
    }
    if (rc == CLI_OK && preview) {
        po.threads = sim.threads;
        rc = cli_write_preview(scene, preview, &po, json ? 0 : 1);
    }
    free(prim_reports);
    resurf_scene_free(scene);
    return rc;
}
