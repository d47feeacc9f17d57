/* resurf preview IN -o SHEET.png: a picture of every level of detail of a scene (or mesh) with its error, drawn by
 * resurf_preview_render() and written by resurf_preview_save_png(). This file only parses arguments and prints the
 * table; cli_write_preview() is shared with `resurf lod --preview`. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char usage[] =
    "usage: resurf preview IN -o SHEET.png [--view V] [--yaw DEG] [--pitch DEG] [--wireframe] [--heatmap]\n"
    "                     [--size WxH] [--background COLOUR] [options]\n\n"
    "Draws one picture per level of detail of IN (.gltf, .glb, .drc or a mesh file), all from the same camera,\n"
    "shaded with each level's own normals, with the level, its triangles, its error (the two-sided distance to\n"
    "level 0 measured as 'resurf compare' does, relative to the diagonal and in scene units) and its screen\n"
    "coverage under each. The levels are those of MSFT_lod (as 'resurf lod' writes them). Nodes are drawn with\n"
    "their transforms, surfaces with their material's base colour and PNG or JPEG base-colour texture (an image\n"
    "that cannot be decoded: the colour alone, with a warning). The same input and options give the same PNG\n"
    "bytes on any thread count.\n\n"
    "  -o, --output SHEET.png the picture (written atomically)\n"
    "  --view V               three-quarter (default), front (from +z), side (from +x), top (from +y) or iso\n"
    "  --yaw DEG, --pitch DEG turn the camera about the vertical, raise it: added to the view's angles\n"
    "  --wireframe            draw the triangles' edges\n"
    "  --heatmap              a second picture per level coloured by the distance to level 0's surface, with a\n"
    "                         colour bar in scene units\n"
    "  --size WxH             the sheet in pixels (default 1600x900; at most 16384 a side, 67108864 in all)\n"
    "  --background COLOUR    RRGGBB or RRGGBBAA in hex (a leading # is allowed), or white (default), black,\n"
    "                         transparent\n"
    "  --samples N            sample points per surface for the error (default 10000; 0 = vertices only)\n"
    "  --no-error             do not measure the errors (faster; the labels then show none)\n"
    "  --threads N            worker threads, 0 = all cores (default)\n" CLI_MAX_TRIANGLES_HELP CLI_LENIENT_HELP;

int cli_parse_preview_size(const char *command, const char *option, const char *text, resurf_preview_options *o)
{
    char *end = NULL;
    unsigned long w = strtoul(text, &end, 10);
    if (end == text || (*end != 'x' && *end != 'X'))
        return cli_usage(command, "--%s needs WxH, not '%s'", option, text);
    const char *rest = end + 1;
    unsigned long h = strtoul(rest, &end, 10);
    if (end == rest || *end || w > 1000000 || h > 1000000 || !isdigit((unsigned char)text[0]) ||
        !isdigit((unsigned char)rest[0]))
        return cli_usage(command, "--%s needs WxH, not '%s'", option, text);
    o->width = (unsigned)w;
    o->height = (unsigned)h;
    return 0;
}

static int parse_background(const char *text, unsigned char rgba[4])
{
    static const struct {
        const char *name;
        unsigned char rgba[4];
    } names[] = {{"white", {255, 255, 255, 255}}, {"black", {0, 0, 0, 255}}, {"transparent", {0, 0, 0, 0}}};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (!strcmp(text, names[i].name)) {
            memcpy(rgba, names[i].rgba, 4);
            return 0;
        }
    const char *hex = text[0] == '#' ? text + 1 : text;
    size_t n = strlen(hex);
    if (n != 6 && n != 8)
        return cli_usage("preview", "--background needs RRGGBB, RRGGBBAA, white, black or transparent, not '%s'",
                         text);
    for (size_t i = 0; i < n; ++i)
        if (!isxdigit((unsigned char)hex[i]))
            return cli_usage("preview", "--background needs hex digits, not '%s'", text);
    rgba[3] = 255;
    for (size_t i = 0; i < n / 2; ++i) {
        char byte[3] = {hex[2 * i], hex[2 * i + 1], 0};
        rgba[i] = (unsigned char)strtoul(byte, NULL, 16);
    }
    return 0;
}

int cli_write_preview(const resurf_scene *scene, const char *path, const resurf_preview_options *options,
                      int verbosity)
{
    resurf_preview_image image;
    resurf_preview_report report;
    resurf_error error;
    resurf_preview_options o = *options;
    o.progress = cli_progress();
    resurf_status s = resurf_preview_render(scene, &o, &image, &report, &error);
    cli_progress_done();
    if (s != RESURF_OK)
        return cli_fail_error(&error);
    s = cli_interrupted() ? RESURF_ERR_CANCELLED : resurf_preview_save_png(&image, path, &error);
    resurf_preview_image_free(&image);
    if (s == RESURF_ERR_CANCELLED)
        return CLI_FAILED;
    if (s != RESURF_OK)
        return cli_fail_error(&error);
    if (report.textures_undrawn)
        fprintf(stderr, "resurf: warning: %s: %zu base-colour image%s drawn as the material's colour alone; %s\n",
                path, report.textures_undrawn, report.textures_undrawn == 1 ? "" : "s", report.texture_warning);
    if (verbosity >= 2) {
        printf("%-6s %12s %14s %14s %10s\n", "level", "triangles", "error (rel)", "error", "coverage");
        for (size_t k = 0; k < report.levels; ++k) {
            printf("%-6zu %12zu %14.3e %14.3e ", k, report.level_triangles[k], report.level_error_rel[k],
                   report.level_error[k]);
            if (report.level_coverage[k] < 0)
                printf("%10s\n", "-");
            else
                printf("%10.4g\n", report.level_coverage[k]);
        }
        if (o.heatmap)
            printf("heat map: 0 .. %.3e scene units\n", report.heat_max);
    }
    if (verbosity >= 1)
        printf("wrote %s (%u x %u, %zu level%s)\n", path, o.width, o.height, report.levels,
               report.levels == 1 ? "" : "s");
    return CLI_OK;
}

int cmd_preview(int argc, char **argv)
{
    static const struct option options[] = {
        {"output", required_argument, NULL, 'o'},
        {"view", required_argument, NULL, 'v'},
        {"yaw", required_argument, NULL, 'y'},
        {"pitch", required_argument, NULL, 'p'},
        {"wireframe", no_argument, NULL, 'w'},
        {"heatmap", no_argument, NULL, 'm'},
        {"size", required_argument, NULL, 's'},
        {"background", required_argument, NULL, 'b'},
        {"samples", required_argument, NULL, 'S'},
        {"no-error", no_argument, NULL, 'E'},
        {"threads", required_argument, NULL, 't'},
        CLI_MAX_TRIANGLES_OPTION,
        CLI_LENIENT_OPTION,
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    static const char *const views[] = {"three-quarter", "front", "side", "top", "iso"};
    const char *out = NULL;
    resurf_preview_options o = resurf_preview_options_default();
    unsigned long n;
    cli_getopt_reset();
    for (int c; (c = cli_getopt("preview", argc, argv, "ho:", options)) != -1;) {
        switch (c) {
        case 'o': out = optarg; break;
        case 'v': {
            size_t k = 0;
            while (k < RESURF_PREVIEW_VIEW_COUNT && strcmp(optarg, views[k]))
                ++k;
            if (k == RESURF_PREVIEW_VIEW_COUNT)
                return cli_usage("preview", "unknown --view '%s' (three-quarter, front, side, top, iso)", optarg);
            o.view = (resurf_preview_view)k;
            break;
        }
        case 'y':
            if (cli_parse_double("preview", "yaw", optarg, &o.yaw_deg))
                return CLI_USAGE;
            break;
        case 'p':
            if (cli_parse_double("preview", "pitch", optarg, &o.pitch_deg))
                return CLI_USAGE;
            break;
        case 'w': o.wireframe = true; break;
        case 'm': o.heatmap = true; break;
        case 's':
            if (cli_parse_preview_size("preview", "size", optarg, &o))
                return CLI_USAGE;
            break;
        case 'b':
            if (parse_background(optarg, o.background))
                return CLI_USAGE;
            break;
        case 'S':
            if (cli_parse_unsigned("preview", "samples", optarg, &n))
                return CLI_USAGE;
            o.compare_samples = n;
            break;
        case 'E': o.measure = false; break;
        case 't':
            if (cli_parse_threads("preview", optarg, &o.threads))
                return CLI_USAGE;
            break;
        case 'T':
            if (cli_set_max_triangles("preview", optarg))
                return CLI_USAGE;
            break;
        case CLI_OPT_LENIENT: cli_set_lenient(); break;
        case 'h': fputs(usage, stdout); return CLI_OK;
        default: return CLI_USAGE;
        }
    }
    if (argc - optind != 1)
        return cli_usage("preview", "expected one input IN");
    if (!out)
        return cli_usage("preview", "missing -o SHEET.png");
    size_t len = strlen(out);
    if (len < 4 || strcmp(out + len - 4, ".png"))
        return cli_usage("preview", "SHEET must end in .png: '%s'", out);
    const char *input = argv[optind];
    if (cli_check_output(out, &input, 1))
        return CLI_FAILED;

    resurf_scene *scene = NULL;
    /* a missing image is drawn untextured: the sheet shows the geometry, with the loader's warning */
    if (cli_load_scene(input, true, &scene))
        return CLI_FAILED;
    int rc = cli_write_preview(scene, out, &o, 2);
    resurf_scene_free(scene);
    return rc;
}
