/* resurf compare REF TEST: surface distances, vertex distances, triangle quality and normal deviation
 * (resurf_compare), as a table or JSON, and optionally TEST coloured by its vertices' distance to REF. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char usage[] =
    "usage: resurf compare REF TEST [--json] [--samples N] [--seed S] [--threads N] [--level K]\n"
    "                      [--heatmap OUT.ply] [--heatmap-max D] [--max-triangles N]\n\n"
    "Measures how far TEST's surface is from REF's: two-sided Hausdorff, mean and RMS distance (area-uniform\n"
    "samples plus all vertices and every triangle's centroid and edge midpoints, exact point-triangle\n"
    "distances), each one-sided direction, the distances of TEST's vertices to REF's surface, TEST's triangle\n"
    "quality (smallest angle, mean smallest angle, share of triangles under 10 degrees), the mean angle\n"
    "between TEST's face normals and REF's and, when both carry texture coordinates (set 0), the UV error at\n"
    "TEST's samples (mean and 95th percentile of the distance in texture space to REF's UV at the closest\n"
    "point). Distances are given in the meshes' units and relative to REF's bounding-box diagonal. The\n"
    "figures depend only on the inputs, --samples and --seed, not on the thread count. A scene (.gltf, .glb,\n"
    ".drc) is measured whole in world space: every instance of every triangle primitive, node transforms\n"
    "applied, as 'resurf lod' measures its levels.\n\n"
    "  --json             machine-readable output on stdout\n"
    "  --samples N        random points per surface, besides the vertices and facet points (default 200000)\n"
    "  --seed S           sample seed (default 1)\n"
    "  --threads N        worker threads (default 0 = all cores)\n"
    "  --level K          TEST a scene: measure its level of detail K (MSFT_lod, as 'resurf lod' writes it;\n"
    "                     default 0, full detail) against REF's full detail\n"
    "  --heatmap OUT.ply  write TEST with vertex colours from its vertices' distance to REF:\n"
    "                     blue (0) - cyan - green - yellow - red (the largest distance, or --heatmap-max)\n"
    "  --heatmap-max D    distance shown as red (default: the largest vertex distance); larger ones are red too\n"
    "  --format FMT       read both meshes as obj|ply|off|stl whatever their names say\n"
    CLI_MAX_TRIANGLES_HELP CLI_LENIENT_HELP;

/* Blue → cyan → green → yellow → red for t in [0, 1]: a ramp whose hue tells the distance at a glance. */
static void ramp(double t, double rgb[3])
{
    if (!(t > 0))
        t = 0;
    if (t > 1)
        t = 1;
    double s = t * 4;
    int seg = s >= 4 ? 3 : (int)s;
    double f = s - seg;
    switch (seg) {
    case 0: rgb[0] = 0, rgb[1] = f, rgb[2] = 1; break;       /* blue → cyan */
    case 1: rgb[0] = 0, rgb[1] = 1, rgb[2] = 1 - f; break;   /* cyan → green */
    case 2: rgb[0] = f, rgb[1] = 1, rgb[2] = 0; break;       /* green → yellow */
    default: rgb[0] = 1, rgb[1] = 1 - f, rgb[2] = 0; break;  /* yellow → red */
    }
}

static int write_heatmap(const resurf_mesh *test, const double *distance, double scale, const char *path)
{
    resurf_mesh *h = NULL;
    resurf_error error;
    if (resurf_mesh_create(test->vertex_count, test->triangle_count, RESURF_ATTR_COLORS, &h, &error) != RESURF_OK)
        return cli_fail_error(&error);
    memcpy(h->positions, test->positions, 3 * test->vertex_count * sizeof(double));
    memcpy(h->indices, test->indices, 3 * test->triangle_count * sizeof(uint32_t));
    h->color_components = 3;
    for (size_t v = 0; v < test->vertex_count; ++v) {
        ramp(scale > 0 ? distance[v] / scale : 0, h->colors + 4 * v);
        h->colors[4 * v + 3] = 1;
    }
    resurf_save_options so = resurf_save_options_default();
    so.format = RESURF_FORMAT_PLY;
    int rc = cli_save(h, path, &so);
    resurf_mesh_free(h);
    return rc ? CLI_FAILED : CLI_OK;
}

/* name, value, and whether it is a length (printed with its relative figure too). */
typedef struct row {
    const char *name;
    double value;
    int length;
} row;

static size_t make_rows(const resurf_compare_report *m, row *rows)
{
    size_t n = 0;
    rows[n++] = (row){"hausdorff", m->hausdorff, 1};
    rows[n++] = (row){"mean", m->mean, 1};
    rows[n++] = (row){"rms", m->rms, 1};
    rows[n++] = (row){"test_to_ref_max", m->test_to_ref_max, 1};
    rows[n++] = (row){"test_to_ref_mean", m->test_to_ref_mean, 1};
    rows[n++] = (row){"ref_to_test_max", m->ref_to_test_max, 1};
    rows[n++] = (row){"ref_to_test_mean", m->ref_to_test_mean, 1};
    rows[n++] = (row){"vertex_max", m->vertex_max, 1};
    rows[n++] = (row){"vertex_mean", m->vertex_mean, 1};
    rows[n++] = (row){"min_angle_deg", m->min_angle_deg, 0};
    rows[n++] = (row){"mean_min_angle_deg", m->mean_min_angle_deg, 0};
    rows[n++] = (row){"share_below_10deg", m->share_below_10deg, 0};
    rows[n++] = (row){"mean_normal_deviation_deg", m->mean_normal_deviation_deg, 0};
    rows[n++] = (row){"uv_error_mean", m->uv_error_mean, 0};
    rows[n++] = (row){"uv_error_p95", m->uv_error_p95, 0};
    return n;
}

static void print_text(const char *ref, const char *test, const resurf_compare_report *m, size_t samples)
{
    printf("REF   %s\nTEST  %s\n", ref, test);
    printf("REF bounding-box diagonal %.9g; %zu samples per surface plus the vertices\n\n", m->diagonal, samples);
    printf("%-28s %16s %16s\n", "distance", "absolute", "relative");
    row rows[16];
    size_t n = make_rows(m, rows);
    for (size_t i = 0; i < n; ++i) {
        if (!rows[i].length)
            continue;
        printf("%-28s %16.9g ", rows[i].name, rows[i].value);
        if (m->diagonal > 0)
            printf("%16.9g\n", rows[i].value / m->diagonal);
        else
            printf("%16s\n", "-"); /* a single point as REF: nothing to be relative to */
    }
    printf("\nTEST triangle quality and normals\n");
    printf("%-28s %16.6f\n", "min angle (deg)", m->min_angle_deg);
    printf("%-28s %16.6f\n", "mean smallest angle (deg)", m->mean_min_angle_deg);
    printf("%-28s %15.4f%%\n", "triangles under 10 deg", 100 * m->share_below_10deg);
    printf("%-28s %16.6f\n", "mean normal deviation (deg)", m->mean_normal_deviation_deg);
    if (!isnan(m->uv_error_mean)) {
        printf("\nUV error (TEXCOORD_0, texture space, at TEST's samples)\n");
        printf("%-28s %16.9g\n", "mean", m->uv_error_mean);
        printf("%-28s %16.9g\n", "95th percentile", m->uv_error_p95);
    }
}

static void print_json(const char *ref, const char *test, const resurf_compare_report *m, size_t samples, uint64_t seed)
{
    printf("{\"ref\": ");
    cli_json_string(stdout, ref);
    printf(", \"test\": ");
    cli_json_string(stdout, test);
    printf(", \"samples\": %zu, \"seed\": %llu, \"diagonal\": ", samples, (unsigned long long)seed);
    cli_json_number(stdout, m->diagonal);
    row rows[16];
    size_t n = make_rows(m, rows);
    for (size_t i = 0; i < n; ++i) {
        printf(", \"%s\": ", rows[i].name);
        cli_json_number(stdout, rows[i].value);
        if (rows[i].length) {
            printf(", \"%s_rel\": ", rows[i].name);
            cli_json_number(stdout, m->diagonal > 0 ? rows[i].value / m->diagonal : NAN); /* null: no scale */
        }
    }
    printf("}\n");
}

int cmd_compare(int argc, char **argv)
{
    static const struct option options[] = {
        {"json", no_argument, NULL, 'j'},
        {"samples", required_argument, NULL, 's'},
        {"seed", required_argument, NULL, 'e'},
        {"threads", required_argument, NULL, 't'},
        {"heatmap", required_argument, NULL, 'm'},
        {"heatmap-max", required_argument, NULL, 'x'},
        {"format", required_argument, NULL, 'f'},
        {"level", required_argument, NULL, 'L'},
        CLI_MAX_TRIANGLES_OPTION,
        CLI_LENIENT_OPTION,
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    int json = 0, level = -1;
    const char *heatmap = NULL;
    double heatmap_max = 0;
    resurf_format format = RESURF_FORMAT_AUTO;
    resurf_compare_options co = resurf_compare_options_default();
    unsigned long n = 0;
    int rc = CLI_OK;
    cli_getopt_reset();
    for (int c; (c = cli_getopt("compare", argc, argv, "h", options)) != -1;) {
        switch (c) {
        case 'j':
            json = 1;
            break;
        case 's':
            if (cli_parse_unsigned("compare", "samples", optarg, &n))
                return CLI_USAGE;
            if (n > 1000000000ul)
                return cli_usage("compare", "--samples %lu is more than 10^9", n);
            co.samples = n;
            break;
        case 'e':
            if (cli_parse_unsigned("compare", "seed", optarg, &n))
                return CLI_USAGE;
            co.seed = n;
            break;
        case 't':
            if (cli_parse_threads("compare", optarg, &co.threads))
                return CLI_USAGE;
            break;
        case 'm':
            heatmap = optarg;
            break;
        case 'L':
            if (cli_parse_unsigned("compare", "level", optarg, &n))
                return CLI_USAGE;
            if (n >= RESURF_SCENE_MAX_LEVELS)
                return cli_usage("compare", "--level must be below %d, not %s", RESURF_SCENE_MAX_LEVELS, optarg);
            level = (int)n;
            break;
        case 'x':
            if (cli_parse_double("compare", "heatmap-max", optarg, &heatmap_max))
                return CLI_USAGE;
            if (!(heatmap_max > 0))
                return cli_usage("compare", "--heatmap-max must be positive, not %s", optarg);
            break;
        default:
            if ((rc = cli_shared_option("compare", usage, c, &format)) != CLI_NEXT)
                return rc;
        }
    }
    if (argc - optind != 2)
        return cli_usage("compare", "expected REF and TEST");
    const char *inputs[2] = {argv[optind], argv[optind + 1]};
    if (heatmap && cli_check_output(heatmap, inputs, 2))
        return CLI_FAILED;

    int scene[2];
    for (int i = 0; i < 2; ++i)
        scene[i] = format == RESURF_FORMAT_AUTO && cli_is_scene(inputs[i]);
    if (level >= 0 && !scene[1])
        return cli_usage("compare", "--level needs TEST to be a scene (.gltf, .glb, .drc)");

    resurf_mesh *ref = NULL, *test = NULL;
    if (scene[0] ? cli_load_world(inputs[0], 0, &ref) : cli_load(inputs[0], format, &ref))
        return CLI_FAILED;
    if (scene[1] ? cli_load_world(inputs[1], level > 0 ? level : 0, &test) : cli_load(inputs[1], format, &test)) {
        resurf_mesh_free(ref);
        return CLI_FAILED;
    }
    rc = CLI_OK;
    double *distance = malloc((test->vertex_count ? test->vertex_count : 1) * sizeof *distance);
    resurf_compare_report m;
    resurf_error error;
    co.progress = cli_progress();
    if (!distance) {
        rc = cli_fail("out of memory");
    } else if (resurf_compare(ref, test, &co, &m, distance, &error) != RESURF_OK) {
        cli_progress_done();
        rc = cli_fail_error(&error);
    } else {
        cli_progress_done();
        if (json)
            print_json(inputs[0], inputs[1], &m, co.samples, co.seed);
        else
            print_text(inputs[0], inputs[1], &m, co.samples);
        if (heatmap)
            rc = write_heatmap(test, distance, heatmap_max > 0 ? heatmap_max : m.vertex_max, heatmap);
    }
    free(distance);
    resurf_mesh_free(ref);
    resurf_mesh_free(test);
    return rc;
}
