/* resurf lod IN -o OUT: a chain of levels of detail of every triangle primitive of a scene (glTF, or a mesh file),
 * each level simplified with inline restoration onto the ORIGINAL surface and the MSFT_lod screen coverage taken
 * from the measured errors (both by resurf_scene_build_lods()), written as one glTF with MSFT_lod, one file per
 * level, or side by side (resurf_scene_save()). This file only parses arguments and prints the table. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char usage[] =
    "usage: resurf lod IN -o OUT [--levels 0.5,0.25,0.1] [--draco|--no-draco]\n"
    "                 [--layout msft_lod|files|side-by-side] [--json] [options]\n\n"
    "Builds levels of detail of every triangle primitive of IN (.gltf, .glb, .drc, or a mesh file as a one-mesh\n"
    "scene): each level keeps at most R x the triangles, is simplified from the previous level and restored onto\n"
    "the smooth surface of the ORIGINAL mesh. A mesh shown by several nodes is simplified once. Primitives with\n"
    "morph targets stay at full detail (with a warning); points and lines are copied. Everything else of the\n"
    "scene (nodes, materials, textures, skins, animations, extensions) is kept. Prints per level the triangles,\n"
    "the measured error (largest distance to the original surface, relative to the bounding-box diagonal) and\n"
    "the bytes of geometry.\n\n"
    "  -o, --output OUT       .glb, .gltf or .drc (a .drc holds one mesh: use --layout files)\n"
    "  --levels R1,R2,...     ratios of the levels, non-increasing in (0, 1] (default 0.5,0.25,0.1)\n"
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
    "  --attribute-weights N,UV,C  weights of normals, texture coordinates and colours in the collapse cost\n"
    "                         (0 = that attribute off; default 0,0.25,0.25)\n"
    "  --threads N            worker threads, 0 = all cores (default)\n"
    "  --preview SHEET.png    also draw every level with its error, as 'resurf preview' does\n"
    "  --preview-size WxH     the sheet's size (default 1600x900)\n"
    "  --json                 print the table as JSON on stdout\n" CLI_MAX_TRIANGLES_HELP CLI_LENIENT_HELP;

enum { MAX_LEVELS = RESURF_SCENE_MAX_LEVELS - 1 };

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
        {"attribute-weights", required_argument, NULL, 'W'},
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
    size_t ratio_count = 3;
    int json = 0, allow_missing_images = 0;
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
            break;
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
        case 'W':
            if (cli_parse_attribute_weights("lod", optarg, &sim))
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

    resurf_load_options lo = resurf_load_options_default();
    lo.max_triangles = cli_max_triangles();
    lo.lenient = cli_lenient();
    lo.allow_missing_images = allow_missing_images;
    resurf_error error;
    resurf_scene *scene = NULL;
    lo.progress = cli_progress();
    resurf_status s = resurf_scene_load(input, &lo, &scene, &error);
    cli_progress_done();
    if (s != RESURF_OK)
        return cli_fail_error(&error);
    for (size_t i = 0; i < resurf_scene_warning_count(scene); ++i)
        fprintf(stderr, "resurf: warning: %s\n", resurf_scene_warning(scene, i));

    /* Every triangle primitive's chain and each mesh's MSFT_screencoverage, in one library call. */
    for (size_t p = 0; p < resurf_scene_primitive_count(scene); ++p) {
        resurf_scene_primitive info;
        resurf_scene_primitive_info(scene, p, &info, NULL);
        if (info.kind == RESURF_PRIMITIVE_MORPHED)
            fprintf(stderr, "resurf: warning: %s has morph targets: kept at full detail\n", info.name);
    }
    resurf_scene_lod_options lod = resurf_scene_lod_options_default();
    lod.pixels = pixels;
    lod.screen_height = height;
    lod.progress = cli_progress();
    resurf_scene_lod_report lod_report;
    int rc = CLI_OK;
    s = resurf_scene_build_lods(scene, ratios, ratio_count, &sim, &lod, &lod_report, NULL, &error);
    cli_progress_done();
    if (s != RESURF_OK)
        rc = cli_fail_error(&error);
    resurf_scene_save_report report;
    if (rc == CLI_OK && !cli_interrupted()) {
        so.progress = cli_progress();
        s = resurf_scene_save(scene, out, &so, &report, &error);
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
                cli_json_number(stdout, k ? ratios[k - 1] : 1.0);
                printf(", \"triangles\": %zu, \"error_rel\": ", report.level_triangles[k]);
                cli_json_number(stdout, lod_report.level_error_rel[k]);
                printf(", \"bytes\": %zu}", report.level_bytes[k]);
            }
            printf("], \"dropped_extensions\": %zu}\n", report.dropped_extensions);
        } else {
            printf("%-6s %-6s %12s %14s %12s\n", "level", "ratio", "triangles", "error (rel)", "bytes");
            for (size_t k = 0; k < report.levels; ++k)
                printf("%-6zu %-6g %12zu %14.3e %12zu\n", k, k ? ratios[k - 1] : 1.0, report.level_triangles[k],
                       lod_report.level_error_rel[k], report.level_bytes[k]);
            printf("wrote %s (%s%s, %zu file%s, %zu bytes)\n", out, layouts[so.layout], so.draco ? ", Draco" : "",
                   report.files, report.files == 1 ? "" : "s", report.total_bytes);
        }
    }
    if (rc == CLI_OK && preview) {
        po.threads = sim.threads;
        rc = cli_write_preview(scene, preview, &po, json ? 0 : 1);
    }
    resurf_scene_free(scene);
    return rc;
}
