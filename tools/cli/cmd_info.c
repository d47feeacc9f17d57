/* resurf info FILE: counts, topology, bounds and attributes of a mesh; the content of a scene (.gltf, .glb, .drc). */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char usage[] =
    "usage: resurf info FILE [--json] [--format obj|ply|off|stl] [--max-triangles N] [--lenient]\n\n"
    "Prints vertices, triangles, distinct positions, connected components, boundary loops and edges,\n"
    "non-manifold edges and vertices, degenerate and zero-area triangles, inconsistently oriented edges,\n"
    "unreferenced vertices, the bounding box and the attributes of a mesh.\n"
    "Topology is counted over welded positions, so attribute seams are not boundaries.\n"
    "A scene (.gltf, .glb, .drc) is described instead: its scenes, nodes, meshes and primitives (triangles,\n"
    "vertices, attributes, morph targets, Draco), materials, textures, images, skins, animations, cameras and\n"
    "extensions.\n\n"
    "  --json           machine-readable output on stdout\n"
    "  --format FMT     read as FMT whatever the file name says\n"
    CLI_MAX_TRIANGLES_HELP
    CLI_LENIENT_HELP;

static void print_text(const char *path, const resurf_mesh *m, const resurf_validate_report *v, const double lo[3],
                       const double hi[3], double diagonal)
{
    printf("file                 %s\n", path);
    printf("vertices             %zu\n", v->vertex_count);
    printf("positions            %zu\n", v->position_count);
    printf("triangles            %zu\n", v->triangle_count);
    printf("components           %zu\n", v->components);
    printf("boundary loops       %zu\n", v->boundary_loops);
    printf("boundary edges       %zu\n", v->boundary_edges);
    printf("non-manifold edges   %zu\n", v->nonmanifold_edges);
    printf("non-manifold verts   %zu\n", v->nonmanifold_vertices);
    printf("degenerate faces     %zu\n", v->degenerate_triangles);
    printf("zero-area faces      %zu\n", v->zero_area_triangles);
    printf("flipped edges        %zu\n", v->inconsistent_edges);
    printf("unreferenced verts   %zu\n", v->unreferenced_vertices);
    printf("bounding box         [%.9g %.9g %.9g] .. [%.9g %.9g %.9g]\n", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    printf("diagonal             %.9g\n", diagonal);
    printf("attributes           position");
    if (m->normals)
        printf(", normal");
    for (unsigned k = 0; k < m->texcoord_count; ++k)
        if (m->texcoords[k])
            printf(", texcoord%u", k);
    if (m->colors)
        printf(", color (%u components)", m->color_components);
    for (size_t i = 0; i < m->extra_count; ++i)
        printf(", %s (%u)", m->extras[i].name, m->extras[i].components);
    printf("\n");
    if (m->group_count)
        printf("groups               %zu\n", m->group_count);
}

static void print_json(const char *path, const resurf_mesh *m, const resurf_validate_report *v, const double lo[3],
                       const double hi[3], double diagonal)
{
    printf("{\"file\": ");
    cli_json_string(stdout, path);
    printf(", \"vertices\": %zu, \"positions\": %zu, \"triangles\": %zu, \"components\": %zu, "
           "\"boundary_loops\": %zu, \"boundary_edges\": %zu, \"nonmanifold_edges\": %zu, "
           "\"nonmanifold_vertices\": %zu, \"degenerate_triangles\": %zu, \"zero_area_triangles\": %zu, "
           "\"inconsistent_edges\": %zu, \"unreferenced_vertices\": %zu",
           v->vertex_count, v->position_count, v->triangle_count, v->components, v->boundary_loops,
           v->boundary_edges, v->nonmanifold_edges, v->nonmanifold_vertices, v->degenerate_triangles,
           v->zero_area_triangles, v->inconsistent_edges, v->unreferenced_vertices);
    printf(", \"bounds\": {\"min\": [");
    for (int i = 0; i < 3; ++i) {
        cli_json_number(stdout, lo[i]);
        printf(i < 2 ? ", " : "], \"max\": [");
    }
    for (int i = 0; i < 3; ++i) {
        cli_json_number(stdout, hi[i]);
        printf(i < 2 ? ", " : "], \"diagonal\": ");
    }
    cli_json_number(stdout, diagonal);
    printf("}, \"attributes\": {\"normals\": %s, \"texcoord_sets\": %u, \"color_components\": %u, \"extras\": [",
           m->normals ? "true" : "false", m->texcoord_count, m->colors ? m->color_components : 0);
    for (size_t i = 0; i < m->extra_count; ++i) {
        printf(i ? ", {\"name\": " : "{\"name\": ");
        cli_json_string(stdout, m->extras[i].name);
        printf(", \"components\": %u}", m->extras[i].components);
    }
    printf("]}, \"groups\": %zu}\n", m->group_count);
}

/* A scene: the library's description of it. */
static int scene_info(const char *path, int json)
{
    resurf_scene *scene = NULL;
    if (cli_load_scene(path, true /* a missing image is part of what info reports ("missing") */, &scene))
        return CLI_FAILED;
    size_t length = 0;
    char *text = NULL;
    resurf_error error;
    resurf_status s = resurf_scene_describe(scene, json, NULL, 0, &length, &error);
    int rc = s == RESURF_OK ? CLI_OK : cli_fail_error(&error);
    if (rc == CLI_OK && !(text = malloc(length + 1)))
        rc = cli_fail("out of memory");
    if (rc == CLI_OK && resurf_scene_describe(scene, json, text, length + 1, &length, &error) != RESURF_OK)
        rc = cli_fail_error(&error);
    if (rc == CLI_OK && json) {
        if (length && text[length - 1] == '\n')
            text[length - 1] = 0;
        printf("{\"file\": ");
        cli_json_string(stdout, path);
        printf(", \"scene\": %s}\n", text);
    } else if (rc == CLI_OK) {
        printf("file                %s\n%s", path, text);
    }
    free(text);
    resurf_scene_free(scene);
    return rc;
}

int cmd_info(int argc, char **argv)
{
    static const struct option options[] = {
        {"json", no_argument, NULL, 'j'},
        {"format", required_argument, NULL, 'f'},
        CLI_MAX_TRIANGLES_OPTION,
        CLI_LENIENT_OPTION,
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    int json = 0;
    resurf_format format = RESURF_FORMAT_AUTO;
    int rc = CLI_OK;
    cli_getopt_reset();
    for (int c; (c = cli_getopt("info", argc, argv, "h", options)) != -1;) {
        switch (c) {
        case 'j':
            json = 1;
            break;
        default:
            if ((rc = cli_shared_option("info", usage, c, &format)) != CLI_NEXT)
                return rc;
        }
    }
    if (argc - optind != 1)
        return cli_usage("info", "expected one FILE");
    const char *path = argv[optind];
    if (format == RESURF_FORMAT_AUTO && cli_is_scene(path))
        return scene_info(path, json);

    resurf_mesh *mesh = NULL;
    if (cli_load(path, format, &mesh))
        return CLI_FAILED;
    resurf_validate_report v;
    resurf_error error;
    if (resurf_mesh_validate(mesh, &v, &error) != RESURF_OK) {
        resurf_mesh_free(mesh);
        return cli_fail_error(&error);
    }
    double lo[3], hi[3];
    double diagonal = resurf_mesh_bounds(mesh, lo, hi);
    if (json)
        print_json(path, mesh, &v, lo, hi, diagonal);
    else
        print_text(path, mesh, &v, lo, hi, diagonal);
    resurf_mesh_free(mesh);
    return CLI_OK;
}
