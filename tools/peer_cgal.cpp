// CGAL's edge collapse as a peer of the simplification benchmark (tools/peers.h): Lindstrom–Turk and
// Garland–Heckbert policies on a Surface_mesh, stopped at a face count. Benchmarks only; CGAL is header-only here
// (Debian's libcgal-dev), with double coordinates, as fast a configuration as CGAL offers.
#include "peers.h"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <vector>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_placement.h>

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace SMS = CGAL::Surface_mesh_simplification;
namespace PMP = CGAL::Polygon_mesh_processing;

// Stops at a face count, as the other methods do: CGAL's own Count_stop_predicate counts edges, whose relation
// to faces depends on the border.
struct Face_count_stop {
    const Mesh *mesh;
    std::size_t target;
    template <typename F, typename Profile>
    bool operator()(const F &, const Profile &, std::size_t, std::size_t) const
    {
        return mesh->number_of_faces() <= target;
    }
};

void say(char *why, std::size_t why_size, const char *text)
{
    if (why_size)
        std::snprintf(why, why_size, "%s", text);
}

// The soup as a Surface_mesh as it is; false when a face would make it non-manifold or flip its orientation.
bool build_direct(const resurf_mesh *m, Mesh &sm)
{
    sm.reserve(m->vertex_count, 3 * m->triangle_count / 2, m->triangle_count);
    for (std::size_t v = 0; v < m->vertex_count; ++v)
        sm.add_vertex(Point(m->positions[3 * v], m->positions[3 * v + 1], m->positions[3 * v + 2]));
    for (std::size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * t;
        if (sm.add_face(Mesh::Vertex_index(i[0]), Mesh::Vertex_index(i[1]), Mesh::Vertex_index(i[2])) ==
            Mesh::null_face())
            return false;
    }
    for (Mesh::Vertex_index v : sm.vertices()) // unused vertices: edge_collapse wants none
        if (sm.is_isolated(v))
            sm.remove_vertex(v);
    sm.collect_garbage();
    return true;
}

// CGAL's own repair: duplicate and degenerate faces dropped, non-manifold vertices split, orientation made
// consistent. Says how many faces it dropped and how many vertices it added.
void build_repaired(const resurf_mesh *m, Mesh &sm, char *why, std::size_t why_size)
{
    std::vector<Point> points(m->vertex_count);
    for (std::size_t v = 0; v < m->vertex_count; ++v)
        points[v] = Point(m->positions[3 * v], m->positions[3 * v + 1], m->positions[3 * v + 2]);
    std::vector<std::vector<std::size_t>> faces(m->triangle_count);
    for (std::size_t t = 0; t < m->triangle_count; ++t)
        faces[t] = {m->indices[3 * t], m->indices[3 * t + 1], m->indices[3 * t + 2]};
    PMP::repair_polygon_soup(points, faces);
    std::size_t before = points.size(), dropped = m->triangle_count - faces.size();
    PMP::orient_polygon_soup(points, faces);
    PMP::polygon_soup_to_polygon_mesh(points, faces, sm);
    char note[160];
    std::snprintf(note, sizeof note, "not a polygon mesh as given: CGAL's repair dropped %zu faces, split %zu vertices",
                  dropped, points.size() - before);
    say(why, why_size, note);
}

} // namespace

extern "C" int peer_cgal_simplify(const resurf_mesh *m, size_t target_tris, peer_cgal_policy policy,
                                  resurf_mesh **out, double *seconds, char *why, size_t why_size)
{
    *out = nullptr;
    say(why, why_size, "");
    try {
        Mesh sm;
        if (!build_direct(m, sm)) {
            sm.clear();
            build_repaired(m, sm, why, why_size);
        }
        if (!CGAL::is_valid_polygon_mesh(sm) || !CGAL::is_triangle_mesh(sm)) {
            say(why, why_size, "not a valid triangle mesh for CGAL, even after its repair");
            return 0;
        }
        Face_count_stop stop{&sm, target_tris};
        auto t0 = std::chrono::steady_clock::now();
        if (policy == PEER_CGAL_LINDSTROM_TURK) {
            SMS::edge_collapse(sm, stop,
                               CGAL::parameters::get_cost(SMS::LindstromTurk_cost<Mesh>())
                                   .get_placement(SMS::LindstromTurk_placement<Mesh>()));
        } else {
            SMS::GarlandHeckbert_plane_policies<Mesh, Kernel> gh(sm);
            SMS::edge_collapse(sm, stop, CGAL::parameters::get_cost(gh.get_cost()).get_placement(gh.get_placement()));
        }
        *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        sm.collect_garbage(); // indices 0..n-1 again

        if (resurf_mesh_create(sm.number_of_vertices(), sm.number_of_faces(), 0, out, nullptr) != RESURF_OK) {
            say(why, why_size, "out of memory");
            return 0;
        }
        for (Mesh::Vertex_index v : sm.vertices()) {
            const Point &p = sm.point(v);
            double *q = (*out)->positions + 3 * (std::size_t)v;
            q[0] = p.x();
            q[1] = p.y();
            q[2] = p.z();
        }
        uint32_t *idx = (*out)->indices;
        for (Mesh::Face_index f : sm.faces())
            for (Mesh::Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
                *idx++ = (uint32_t)v;
        return 1;
    } catch (const std::exception &e) {
        resurf_mesh_free(*out);
        *out = nullptr;
        say(why, why_size, e.what());
        return 0;
    }
}
