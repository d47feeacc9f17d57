/* The restorer's services over the original mesh M, built once before any point is restored (restore.c projects
 * the points): the options, then in phase order the exact weld of M, its crease and boundary edges, each vertex's
 * fans between creases, the quiet triangles of walk_closest's shortcut, the normals (and curvatures) on M split
 * along the creases, the feature curves and the triangles that can carry a root. restore.c's file comment says what
 * each of them is for. */
#include <stdlib.h>
#include <string.h>

#include "restore_internal.h"
#include "union_find.h"

enum { BLOCK_SETUP = 8192 }; /* parallel block of the set-up loops (cheap elements) */

/* cos² of the largest angle (150°) a triangle may have to take part in crease detection (see reliable_normal). */
static const double sliver_cos2 = 0.75;

/* ---- options ------------------------------------------------------------------------------------------------- */

resurf_restore_options resurf_restore_options_default(void)
{
    resurf_restore_options o;
    memset(&o, 0, sizeof o);
    o.struct_size = sizeof o;
    o.normals = RESURF_NORMALS_AUTO;
    o.side_rule = RESURF_SIDE_CURVATURE;
    o.displacement = RESURF_DISPLACEMENT_NORMAL_SECTION;
    o.step = 1.0 / 3.0;
    o.iterations = 10;
    o.tolerance_rel = 1e-6;
    o.crease_angle_deg = 60;
    o.input_normals = RESURF_INPUT_NORMALS_CREASES;
    o.far_factor = 4;
    o.outside = RESURF_OUTSIDE_NEIGHBOURS;
    o.boundary = true;
    o.threads = 0;
    return o;
}

resurf_restore_options resurf_restore_options_paper(void)
{
    resurf_restore_options o = resurf_restore_options_default();
    o.normals = RESURF_NORMALS_INVERSE_AREA;
    o.side_rule = RESURF_SIDE_CURVATURE;
    o.displacement = RESURF_DISPLACEMENT_PAPER;
    o.step = 1.0 / 6.0;
    o.iterations = 5;
    o.tolerance_rel = 0;
    return o;
}

resurf_status resurfi_restore_check_options(const resurf_restore_options *o, resurf_error *error)
{
    RESURFI_CHECK_OPTIONS_ALLOC(o, resurf_restore_options, error);
    if (!o)
        return RESURF_OK; /* the defaults */
    const char *bad = NULL;
    if ((unsigned)o->normals >= RESURF_NORMALS_COUNT && o->normals != RESURF_NORMALS_AUTO)
        bad = "normals is not a resurf_normal_scheme";
    else if ((unsigned)o->side_rule >= RESURF_SIDE_COUNT)
        bad = "side_rule is not a resurf_side_rule";
    else if ((unsigned)o->displacement >= RESURF_DISPLACEMENT_COUNT)
        bad = "displacement is not a resurf_displacement";
    else if ((unsigned)o->outside >= RESURF_OUTSIDE_COUNT)
        bad = "outside is not a resurf_outside_policy";
    else if (!(o->step > 0 && o->step <= 1))
        bad = "step must be in (0, 1]";
    else if (o->iterations < 1 || o->iterations > 1000)
        bad = "iterations must be in 1..1000";
    else if (!(o->tolerance_rel >= 0 && isfinite(o->tolerance_rel)))
        bad = "tolerance_rel must be finite and >= 0";
    else if (!(o->crease_angle_deg >= 0 && o->crease_angle_deg <= 180))
        bad = "crease_angle_deg must be in [0, 180]";
    else if (!(o->far_factor > 0)) /* INFINITY: never far */
        bad = "far_factor must be > 0";
    else if ((unsigned)o->input_normals >= RESURF_INPUT_NORMALS_COUNT)
        bad = "input_normals is not a resurf_input_normals";
    if (bad)
        return resurfi_error(error, RESURF_ERR_INVALID_OPTIONS, "resurf_restore_options: %s", bad);
    return RESURF_OK;
}

/* ---- building M's services, in phase order ------------------------------------------------------------------- */


static vec3 face_normal(const resurfi_restorer *r, size_t t)
{
    const uint32_t *i = r->tris + 3 * t;
    return v3_normalize(v3_tri_cross(position(r, i[0]), position(r, i[1]), position(r, i[2])));
}

/* Is the face normal of t meaningful for a dihedral angle? The normal of a triangle whose corners lie on a curved
 * surface is the surface normal near its circumcentre, which for a flat sliver (an angle near 180°) lies far
 * outside the triangle: on irregular meshes of smooth surfaces such slivers have normals tens of degrees off, and
 * taking their edges for creases would split the normals around them. With every angle at most 150° the
 * circumcentre is within one longest edge of the triangle; needles (a tiny angle, two long sides) are fine. */
static int reliable_normal(const resurfi_restorer *r, size_t t)
{
    const uint32_t *i = r->tris + 3 * t;
    vec3 p[3] = {position(r, i[0]), position(r, i[1]), position(r, i[2])};
    for (int k = 0; k < 3; ++k) {
        vec3 u = v3_sub(p[(k + 1) % 3], p[k]), v = v3_sub(p[(k + 2) % 3], p[k]);
        double uv = v3_dot(u, v), l2 = v3_len2(u) * v3_len2(v);
        if (!(l2 > 0) || (uv < 0 && uv * uv > sliver_cos2 * l2))
            return 0;
    }
    return 1;
}

/* Phase 1: refuse what cannot be processed, weld exactly, index the triangles by position id. */
static resurf_status weld_original(resurfi_restorer *r, const resurf_mesh *m, const uint32_t *welded,
                                   size_t welded_count, resurf_error *error)
{
    if (m->triangle_count == 0)
        return resurfi_error(error, RESURF_ERR_INVALID_MESH, "the original mesh has no triangles");
    for (size_t t = 0; t < m->triangle_count; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t v = m->indices[3 * t + k];
            if (v >= m->vertex_count)
                return resurfi_error(error, RESURF_ERR_INVALID_MESH,
                                     "original triangle %zu refers to vertex %u of %zu", t, v, m->vertex_count);
            if (!v3_finite(resurfi_position(m, v)))
                return resurfi_error(error, RESURF_ERR_INVALID_MESH, "original vertex %u has a non-finite position",
                                     v);
        }
    uint32_t *own_remap = NULL;
    const uint32_t *remap = welded;
    size_t distinct = welded_count;
    if (!welded) {
        if (!(own_remap = resurfi_alloc(&r->alloc, m->vertex_count, sizeof *own_remap)))
            return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory welding the original mesh");
        resurf_status s = resurfi_weld_exact(&r->alloc, m->positions, m->vertex_count, own_remap, &distinct);
        if (s != RESURF_OK) {
            resurfi_free(&r->alloc, own_remap);
            return resurfi_error(error, s, "cannot weld the original mesh");
        }
        remap = own_remap;
    }
    r->triangle_count = m->triangle_count;
    /* A position's id is its first vertex, so M's positions serve in place (M outlives the restorer) and only the
     * triangles need new ids; duplicates become vertices without faces. Positions are numbered by first
     * appearance, so ids keep the order of the weld's numbering, and without duplicates M's indices serve too. */
    r->positions = m->positions;
    r->position_count = m->vertex_count;
    if (distinct == m->vertex_count) {
        r->tris = m->indices;
        resurfi_free(&r->alloc, own_remap);
        return RESURF_OK;
    }
    uint32_t *first = resurfi_alloc(&r->alloc, distinct, sizeof *first);
    r->own_tris = resurfi_alloc(&r->alloc, m->triangle_count, 3 * sizeof(uint32_t));
    if (!first || !r->own_tris) {
        resurfi_free(&r->alloc, own_remap);
        resurfi_free(&r->alloc, first);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory welding the original mesh");
    }
    for (size_t v = m->vertex_count; v-- > 0;)
        first[remap[v]] = (uint32_t)v;
    for (size_t i = 0; i < 3 * m->triangle_count; ++i)
        r->own_tris[i] = first[remap[m->indices[i]]];
    r->tris = r->own_tris;
    resurfi_free(&r->alloc, own_remap);
    resurfi_free(&r->alloc, first);
    return RESURF_OK;
}


/* Do the two faces of edge e carry different input normals at one of its ends? */
static int split_input_normals(const resurfi_restorer *r, const resurf_mesh *m, uint32_t e, uint32_t f, uint32_t g)
{
    for (int end = 0; end < 2; ++end) {
        uint32_t v = r->adj.edge_vertices[2 * (size_t)e + end];
        int cf = corner_of(r, f, v), cg = corner_of(r, g, v);
        uint32_t af = m->indices[3 * (size_t)f + cf], ag = m->indices[3 * (size_t)g + cg];
        if (af == ag)
            continue;
        vec3 nf = v3_normalize(v3_load(m->normals + 3 * (size_t)af));
        vec3 ng = v3_normalize(v3_load(m->normals + 3 * (size_t)ag));
        if (v3_len2(nf) > 0 && v3_len2(ng) > 0 && v3_finite(nf) && v3_finite(ng) && v3_dot(nf, ng) < RESURFI_SAME_NORMAL_COS)
            return 1;
    }
    return 0;
}

/* The set-up phases below run their per-element loops on the restorer's threads; each element writes only its own
 * outputs from inputs no other element writes, so the results do not depend on the thread count. */
typedef struct setup_job {
    resurfi_restorer *r;
    const resurf_mesh *m;
    double crease_cos;
    int by_angle, by_normals;
    double *face_normals; /* 3 per triangle (classify_edges) */
    uint8_t *reliable;    /* per triangle: reliable_normal (classify_edges) */
    size_t max_degree;    /* split_fans: the most faces of a position */
    uint32_t *fan_scratch; /* split_fans: 2 max_degree per worker */
    uint32_t *fan_base;   /* split_fans: per position, its fan count, then its first fan id */
} setup_job;

static unsigned setup_threads(const resurfi_restorer *r) { return resurfi_thread_count(r->opt.threads); }

static void setup_for(const resurfi_restorer *r, size_t count, int (*fn)(void *, size_t, size_t, unsigned),
                      void *ctx)
{
    resurfi_parallel_for(count, BLOCK_SETUP, setup_threads(r), fn, ctx);
}

/* Each face's unit normal and reliability once, rather than once per side in the edge loop. */
static int face_normals_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const setup_job *j = ctx;
    for (size_t t = begin; t < end; ++t) {
        v3_store(j->face_normals + 3 * t, face_normal(j->r, t));
        j->reliable[t] = (uint8_t)reliable_normal(j->r, t);
    }
    return 0;
}

static int classify_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const setup_job *j = ctx;
    resurfi_restorer *r = j->r;
    const resurfi_adjacency *adj = &r->adj;
    for (size_t e = begin; e < end; ++e) {
        uint32_t nf = resurfi_edge_face_count(adj, (uint32_t)e);
        const uint32_t *faces = adj->edge_faces + adj->edge_face_offset[e];
        if (nf == 1) {
            if (r->opt.boundary)
                r->edge_kind[e] = FEATURE_BOUNDARY;
        } else if (nf == 2) {
            int crease = 0;
            if (j->by_angle && j->reliable[faces[0]] && j->reliable[faces[1]]) {
                vec3 a = v3_load(j->face_normals + 3 * (size_t)faces[0]);
                vec3 b = v3_load(j->face_normals + 3 * (size_t)faces[1]);
                crease = v3_dot(a, b) < j->crease_cos;
            }
            if (!crease && j->by_normals)
                crease = split_input_normals(r, j->m, (uint32_t)e, faces[0], faces[1]);
            if (crease)
                r->edge_kind[e] = FEATURE_CREASE;
        }
    }
    return 0;
}

/* Quiet positions, for walk_closest's shortcut: the faces around form one closed fan (a disc: one fan of
 * split_fans, every neighbour in exactly two of its faces) whose unit face normals all lie within QUIET_DEG of
 * their mean. Then any two of them are less than 2 QUIET_DEG < 90° apart, so projected onto the plane of one face,
 * every face keeps its orientation; and an embedded closed fan whose faces all keep their orientation winds once
 * around its vertex (two sheets over the same direction would have to swap heights somewhere on the way round, and
 * there they would cross), so the other faces' projections lie outside that face. */
static const double QUIET_DEG = 39;

/* The quiet test but for "one fan" (mark_quiet adds that once split_fans has run): every neighbour in exactly two
 * faces, and the unit face normals within QUIET_DEG of their mean. Runs in classify_edges, while the face normals
 * are at hand. */
static int quiet_geometry_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const setup_job *j = ctx;
    const resurfi_restorer *r = j->r;
    const resurfi_adjacency *adj = &r->adj;
    const double cos_quiet = cos(QUIET_DEG * (M_PI / 180.0));
    for (size_t v = begin; v < end; ++v) {
        const uint32_t *faces = adj->vertex_faces + adj->vertex_face_offset[v];
        uint32_t n = adj->vertex_face_offset[v + 1] - adj->vertex_face_offset[v];
        int ok = n >= 3;
        vec3 mean = v3(0, 0, 0);
        for (uint32_t i = 0; i < n && ok; ++i) {
            size_t f = faces[i];
            int k = corner_of(r, faces[i], (uint32_t)v);
            if (k < 0) { /* (v is a corner of each of its faces) */
                ok = 0;
                break;
            }
            /* every neighbour in exactly two faces: both edges of f at v have two faces */
            uint32_t e0 = adj->face_edges[3 * f + (uint32_t)k], e1 = adj->face_edges[3 * f + (uint32_t)(k + 2) % 3];
            ok = e0 != UINT32_MAX && e1 != UINT32_MAX && resurfi_edge_face_count(adj, e0) == 2 &&
                 resurfi_edge_face_count(adj, e1) == 2;
            vec3 fn = v3_load(j->face_normals + 3 * f);
            ok = ok && v3_len2(fn) > 0;
            mean = v3_add(mean, fn);
        }
        double len = v3_len(mean);
        for (uint32_t i = 0; i < n && ok; ++i)
            ok = v3_dot(v3_load(j->face_normals + 3 * (size_t)faces[i]), mean) >= cos_quiet * len;
        r->quiet_position[v] = (uint8_t)ok;
    }
    return 0;
}

/* Phase 2: topology, crease and boundary edges. */
static resurf_status classify_edges(resurfi_restorer *r, const resurf_mesh *m, resurf_error *error)
{
    resurf_status s = resurfi_adjacency_build_edges(&r->alloc, r->tris, r->triangle_count, r->position_count, &r->adj);
    if (s != RESURF_OK)
        return resurfi_error(error, s, "cannot build the original mesh's adjacency");
    const resurfi_adjacency *adj = &r->adj;
    r->edge_kind = resurfi_calloc(&r->alloc, adj->edge_count ? adj->edge_count : 1, 1);
    if (!r->edge_kind)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory classifying edges");
    setup_job j = {.r = r,
                   .m = m,
                   .crease_cos = cos(r->opt.crease_angle_deg * (M_PI / 180.0)),
                   .by_angle = r->opt.crease_angle_deg < 180,
                   .by_normals = r->opt.input_normals != RESURF_INPUT_NORMALS_IGNORE && m->normals};
    /* The face normals serve the crease test and the quiet fans' (quiet_geometry_block) */
    j.face_normals = resurfi_alloc(&r->alloc, r->triangle_count ? r->triangle_count : 1, 3 * sizeof(double));
    j.reliable = resurfi_alloc(&r->alloc, r->triangle_count ? r->triangle_count : 1, 1);
    r->quiet_position = resurfi_alloc(&r->alloc, r->position_count ? r->position_count : 1, 1);
    if (!j.face_normals || !j.reliable || !r->quiet_position) {
        resurfi_free(&r->alloc, j.face_normals);
        resurfi_free(&r->alloc, j.reliable);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory classifying edges");
    }
    setup_for(r, r->triangle_count, face_normals_block, &j);
    setup_for(r, adj->edge_count, classify_block, &j);
    setup_for(r, r->position_count, quiet_geometry_block, &j);
    resurfi_free(&r->alloc, j.face_normals);
    resurfi_free(&r->alloc, j.reliable);
    return RESURF_OK;
}

/* Phase 3, per position v: number v's fans 0, 1, ... in the order of their lowest face, give each of v's corners the
 * number of its fan and put the count in fan_base[v]. Vertices own their corners: blocks write disjoint entries. */
static int fans_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    const setup_job *j = ctx;
    resurfi_restorer *r = j->r;
    const resurfi_adjacency *adj = &r->adj;
    uint32_t *parent = j->fan_scratch + 2 * j->max_degree * worker, *fan_id = parent + j->max_degree;
    for (size_t v = begin; v < end; ++v) {
        const uint32_t *faces = adj->vertex_faces + adj->vertex_face_offset[v];
        uint32_t n = adj->vertex_face_offset[v + 1] - adj->vertex_face_offset[v];
        for (uint32_t i = 0; i < n; ++i)
            parent[i] = i;
        for (uint32_t i = 0; i < n; ++i) {
            size_t f = faces[i];
            for (int side = 0; side < 3; ++side) {
                uint32_t a = r->tris[3 * f + side], b = r->tris[3 * f + (side + 1) % 3];
                uint32_t e = adj->face_edges[3 * f + side];
                if ((a != v && b != v) || e == UINT32_MAX || resurfi_edge_face_count(adj, e) != 2 ||
                    r->edge_kind[e] == FEATURE_CREASE)
                    continue;
                const uint32_t *ef = adj->edge_faces + adj->edge_face_offset[e];
                if (ef[0] != f) /* the edge's faces are sorted: join each pair once, from its lower face */
                    continue;
                uint32_t g = ef[1];
                for (uint32_t k = i + 1; k < n; ++k) /* v's faces are sorted too, and few */
                    if (faces[k] == g) {
                        resurfi_uf_union(parent, i, k);
                        break;
                    }
            }
        }
        for (uint32_t i = 0; i < n; ++i)
            fan_id[i] = UINT32_MAX;
        uint32_t count = 0;
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t root = resurfi_uf_find(parent, i);
            if (fan_id[root] == UINT32_MAX)
                fan_id[root] = count++;
            int k = corner_of(r, faces[i], (uint32_t)v);
            r->corner_split[3 * (size_t)faces[i] + k] = fan_id[root];
        }
        j->fan_base[v] = count;
    }
    return 0;
}

/* Phase 3, per triangle: a vertex's fan number plus the fans of all lower positions is the fan's id. */
static int fan_ids_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const setup_job *j = ctx;
    resurfi_restorer *r = j->r;
    for (size_t i = 3 * begin; i < 3 * end; ++i)
        if (r->corner_split[i] != UINT32_MAX)
            r->corner_split[i] += j->fan_base[r->tris[i]];
    return 0;
}

/* Phase 3: split every vertex into its fans (faces connected across manifold, non-crease edges ending there) and
 * give each corner the id of its fan, numbered position by position. Triangles the adjacency ignores (a repeated
 * position) take the vertex's first fan, or a fan of their own. */
static resurf_status split_fans(resurfi_restorer *r, resurf_error *error)
{
    const resurfi_adjacency *adj = &r->adj;
    size_t nt = r->triangle_count, nv = r->position_count;
    unsigned threads = setup_threads(r);
    size_t max_degree = 1;
    for (size_t v = 0; v < nv; ++v) {
        size_t d = adj->vertex_face_offset[v + 1] - adj->vertex_face_offset[v];
        max_degree = d > max_degree ? d : max_degree;
    }
    setup_job j = {.r = r, .max_degree = max_degree};
    r->corner_split = resurfi_alloc(&r->alloc, nt, 3 * sizeof(uint32_t));
    j.fan_scratch = resurfi_alloc(&r->alloc, (size_t)threads * 2 * max_degree, sizeof(uint32_t));
    j.fan_base = resurfi_alloc(&r->alloc, nv, sizeof(uint32_t));
    if (!r->corner_split || !j.fan_scratch || !j.fan_base) {
        resurfi_free(&r->alloc, j.fan_scratch);
        resurfi_free(&r->alloc, j.fan_base);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory splitting crease fans");
    }
    /* Corners of valid triangles all get a fan below; only ignored triangles (3 fewer vertex-face entries each)
     * need the mark. */
    int ignored = adj->vertex_face_offset[nv] != 3 * nt;
    if (ignored)
        memset(r->corner_split, 0xff, nt * 3 * sizeof(uint32_t));
    setup_for(r, nv, fans_block, &j);
    uint32_t next = 0;
    for (size_t v = 0; v < nv; ++v) {
        uint32_t count = j.fan_base[v];
        j.fan_base[v] = next;
        next += count;
    }
    setup_for(r, nt, fan_ids_block, &j);
    resurfi_free(&r->alloc, j.fan_scratch);
    resurfi_free(&r->alloc, j.fan_base);
    /* corners of ignored triangles, in triangle order */
    for (size_t t = 0; t < nt && ignored; ++t)
        for (int k = 0; k < 3; ++k) {
            if (r->corner_split[3 * t + k] != UINT32_MAX)
                continue;
            uint32_t v = r->tris[3 * t + k];
            uint32_t first = adj->vertex_face_offset[v], last = adj->vertex_face_offset[v + 1];
            if (first < last) {
                uint32_t f = adj->vertex_faces[first];
                r->corner_split[3 * t + k] = r->corner_split[3 * (size_t)f + corner_of(r, f, v)];
            } else {
                r->corner_split[3 * t + k] = next++;
            }
        }
    r->split_count = next;
    return RESURF_OK;
}

/* A quiet position's faces must also form one fan of split_fans. */
static int quiet_fan_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const setup_job *j = ctx;
    const resurfi_restorer *r = j->r;
    const resurfi_adjacency *adj = &r->adj;
    for (size_t v = begin; v < end; ++v) {
        if (!r->quiet_position[v])
            continue;
        const uint32_t *faces = adj->vertex_faces + adj->vertex_face_offset[v];
        uint32_t n = adj->vertex_face_offset[v + 1] - adj->vertex_face_offset[v];
        uint32_t split = r->corner_split[3 * (size_t)faces[0] + (uint32_t)corner_of(r, faces[0], (uint32_t)v)];
        for (uint32_t i = 1; i < n; ++i)
            if (r->corner_split[3 * (size_t)faces[i] + (uint32_t)corner_of(r, faces[i], (uint32_t)v)] != split) {
                r->quiet_position[v] = 0;
                break;
            }
    }
    return 0;
}

static int quiet_triangle_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    const setup_job *j = ctx;
    const resurfi_restorer *r = j->r;
    for (size_t t = begin; t < end; ++t) {
        const uint32_t *i = r->tris + 3 * t;
        r->quiet[t] = (uint8_t)(r->quiet_position[i[0]] && r->quiet_position[i[1]] && r->quiet_position[i[2]]);
    }
    return 0;
}

/* Phase 3 (with the edges still there): the quiet triangles, those whose corners are all quiet positions. */
static resurf_status mark_quiet(resurfi_restorer *r, resurf_error *error)
{
    r->quiet = resurfi_alloc(&r->alloc, r->triangle_count ? r->triangle_count : 1, 1);
    if (!r->quiet)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory marking quiet triangles");
    setup_job j = {.r = r};
    setup_for(r, r->position_count, quiet_fan_block, &j);
    setup_for(r, r->triangle_count, quiet_triangle_block, &j);
    resurfi_free(&r->alloc, r->quiet_position);
    r->quiet_position = NULL;
    return RESURF_OK;
}

/* With RESURF_INPUT_NORMALS_USE: each fan's normal is the sum of the input normals of its corners (a fan never mixes
 * different ones: a split marks a crease), normalised; fans whose input normals are all zero or not finite keep
 * the estimated normal. */
static resurf_status take_input_normals(resurfi_restorer *r, const resurf_mesh *m)
{
    size_t ns = r->split_count;
    double *sum = resurfi_calloc(&r->alloc, ns ? ns : 1, 3 * sizeof(double));
    if (!sum)
        return RESURF_ERR_OUT_OF_MEMORY;
    for (size_t i = 0; i < 3 * r->triangle_count; ++i) {
        vec3 n = v3_normalize(v3_load(m->normals + 3 * (size_t)m->indices[i]));
        if (!v3_finite(n))
            continue;
        double *acc = sum + 3 * (size_t)r->corner_split[i];
        acc[0] += n.x, acc[1] += n.y, acc[2] += n.z;
    }
    for (size_t v = 0; v < ns; ++v) {
        vec3 n = v3_normalize(v3_load(sum + 3 * v));
        if (v3_len2(n) > 0)
            v3_store(r->split_normals + 3 * v, n);
    }
    resurfi_free(&r->alloc, sum);
    return RESURF_OK;
}

/* Phase 4: normals (and, when the side rule needs them, curvatures) on the mesh split along the creases. */
static resurf_status estimate_normals(resurfi_restorer *r, const resurf_mesh *m, resurf_error *error)
{
    size_t ns = r->split_count, nt = r->triangle_count;
    int curvatures = r->opt.side_rule == RESURF_SIDE_CURVATURE && r->opt.displacement == RESURF_DISPLACEMENT_PAPER;
    /* The 1-ring schemes read the positions through the triangles; the jet and the curvatures need them copied per
     * split vertex. */
    int in_place = r->opt.normals != RESURF_NORMALS_JET && !curvatures;
    double *split_positions = in_place ? NULL : resurfi_alloc(&r->alloc, ns ? ns : 1, 3 * sizeof(double));
    r->split_normals = resurfi_calloc(&r->alloc, ns ? ns : 1, 3 * sizeof(double));
    if ((!in_place && !split_positions) || !r->split_normals) {
        resurfi_free(&r->alloc, split_positions);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory estimating normals");
    }
    resurf_status s;
    if (in_place) {
        s = resurfi_vertex_normals_split(r->positions, r->tris, r->corner_split, ns, nt, r->opt.normals,
                                         r->split_normals);
    } else {
        for (size_t i = 0; i < 3 * nt; ++i)
            memcpy(split_positions + 3 * (size_t)r->corner_split[i], r->positions + 3 * (size_t)r->tris[i],
                   3 * sizeof(double));
        s = resurfi_vertex_normals(&r->alloc, split_positions, ns, r->corner_split, nt, r->opt.normals,
                                   r->split_normals);
    }
    if (s != RESURF_OK) {
        resurfi_free(&r->alloc, split_positions);
        return resurfi_error(error, s, "cannot estimate the original mesh's vertex normals");
    }
    if (r->opt.input_normals == RESURF_INPUT_NORMALS_USE && m->normals && take_input_normals(r, m) != RESURF_OK) {
        resurfi_free(&r->alloc, split_positions);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory taking the input normals");
    }
    if (curvatures) {
        r->k1 = resurfi_alloc(&r->alloc, ns ? ns : 1, sizeof(double));
        r->k2 = resurfi_alloc(&r->alloc, ns ? ns : 1, sizeof(double));
        r->dir1 = resurfi_alloc(&r->alloc, ns ? ns : 1, 3 * sizeof(double));
        r->dir2 = resurfi_alloc(&r->alloc, ns ? ns : 1, 3 * sizeof(double));
        if (!r->k1 || !r->k2 || !r->dir1 || !r->dir2)
            s = RESURF_ERR_OUT_OF_MEMORY;
        else
            s = resurfi_principal_curvatures(&r->alloc, split_positions, ns, r->corner_split, nt, r->split_normals,
                                             r->k1, r->k2, r->dir1, r->dir2);
        if (s != RESURF_OK) {
            resurfi_free(&r->alloc, split_positions);
            return resurfi_error(error, s, "cannot estimate the original mesh's curvatures");
        }
    }
    resurfi_free(&r->alloc, split_positions);
    return RESURF_OK;
}

/* Each triangle side's kind from its edge's. */
static int side_kind_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    resurfi_restorer *r = ((const setup_job *)ctx)->r;
    for (size_t t = begin; t < end; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t e = r->adj.face_edges[3 * t + (size_t)k];
            if (e != UINT32_MAX)
                r->side_kind[t] |= (uint8_t)(r->edge_kind[e] << (2 * k));
        }
    return 0;
}

/* Phase 5: per position, the mean length of its edges (the local edge length), its feature edges and the
 * feature-curve tangent. */
static resurf_status trace_features(resurfi_restorer *r, resurf_error *error)
{
    const resurfi_adjacency *adj = &r->adj;
    size_t nv = r->position_count, ne = adj->edge_count;
    r->local_length = resurfi_calloc(&r->alloc, nv, sizeof(double));
    r->feature_offset = resurfi_calloc(&r->alloc, nv + 1, sizeof(uint32_t));
    uint32_t *edge_count = resurfi_calloc(&r->alloc, nv, sizeof(uint32_t));
    if (!r->local_length || !r->feature_offset || !edge_count) {
        resurfi_free(&r->alloc, edge_count);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory tracing feature curves");
    }
    for (size_t e = 0; e < ne; ++e) {
        uint32_t a = adj->edge_vertices[2 * e], b = adj->edge_vertices[2 * e + 1];
        double l = v3_dist(position(r, a), position(r, b));
        r->local_length[a] += l, r->local_length[b] += l;
        ++edge_count[a], ++edge_count[b];
        if (r->edge_kind[e])
            ++r->feature_offset[a + 1], ++r->feature_offset[b + 1];
    }
    for (size_t v = 0; v < nv; ++v) {
        if (edge_count[v])
            r->local_length[v] /= edge_count[v];
        r->feature_offset[v + 1] += r->feature_offset[v];
    }
    size_t nf = r->feature_offset[nv];
    r->feature_vertex = resurfi_alloc(&r->alloc, nf ? nf : 1, sizeof(uint32_t));
    r->feature_kind = resurfi_alloc(&r->alloc, nf ? nf : 1, 1);
    r->tangent = resurfi_calloc(&r->alloc, nf ? nf : 1, 3 * sizeof(double));
    if (!r->feature_vertex || !r->feature_kind || !r->tangent) {
        resurfi_free(&r->alloc, edge_count);
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory tracing feature curves");
    }
    memset(edge_count, 0, nv * sizeof(uint32_t)); /* now the fill cursor */
    for (size_t e = 0; e < ne; ++e) {
        if (!r->edge_kind[e])
            continue;
        uint32_t a = adj->edge_vertices[2 * e], b = adj->edge_vertices[2 * e + 1];
        uint32_t ia = r->feature_offset[a] + edge_count[a]++, ib = r->feature_offset[b] + edge_count[b]++;
        r->feature_vertex[ia] = b, r->feature_kind[ia] = r->edge_kind[e];
        r->feature_vertex[ib] = a, r->feature_kind[ib] = r->edge_kind[e];
    }
    resurfi_free(&r->alloc, edge_count);
    /* Tangents where the curve passes smoothly: two feature edges of one kind, turning by at most the crease
     * angle. The circle through prev, v, next has the tangent e1/|e1|² + e2/|e2|² at v (e1 = v − prev,
     * e2 = next − v). */
    double corner_cos = cos(r->opt.crease_angle_deg * (M_PI / 180.0));
    for (size_t v = 0; v < nv; ++v) {
        uint32_t first = r->feature_offset[v];
        if (r->feature_offset[v + 1] - first != 2 || r->feature_kind[first] != r->feature_kind[first + 1])
            continue;
        vec3 p = position(r, (uint32_t)v);
        vec3 e1 = v3_sub(p, position(r, r->feature_vertex[first]));
        vec3 e2 = v3_sub(position(r, r->feature_vertex[first + 1]), p);
        double l1 = v3_len2(e1), l2 = v3_len2(e2);
        if (!(l1 > 0 && l2 > 0) || v3_dot(e1, e2) < corner_cos * sqrt(l1 * l2))
            continue;
        v3_store(r->tangent + 3 * (size_t)first, v3_normalize(v3_add(v3_scale(e1, 1 / l1), v3_scale(e2, 1 / l2))));
    }
    /* The query needs each triangle side's kind only: the edge arrays go (about 45 bytes per triangle). */
    r->side_kind = resurfi_calloc(&r->alloc, r->triangle_count ? r->triangle_count : 1, 1);
    if (!r->side_kind)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory tracing feature curves");
    setup_job j = {.r = r};
    setup_for(r, r->triangle_count, side_kind_block, &j);
    resurfi_adjacency_drop_edges(&r->adj);
    resurfi_free(&r->alloc, r->edge_kind);
    r->edge_kind = NULL;
    return RESURF_OK;
}

/* Phase 6: which triangles can carry a root. A zero-area triangle (a T-junction sliver, a collapsed face), one
 * with a corner that has no normal (a vertex of zero-area faces only) or one whose corner normals are 90° or more
 * apart gives no meaningful optimal direction; the search then goes to the triangles around it. */
static int usable_block(void *ctx, size_t begin, size_t end, unsigned worker)
{
    (void)worker;
    resurfi_restorer *r = ((const setup_job *)ctx)->r;
    for (size_t t = begin; t < end; ++t) {
        const uint32_t *i = r->tris + 3 * t;
        vec3 a = position(r, i[0]), b = position(r, i[1]), c = position(r, i[2]);
        double longest2 = dmax(dmax(v3_dist2(a, b), v3_dist2(b, c)), v3_dist2(c, a));
        int ok = v3_len2(v3_tri_cross(a, b, c)) > 1e-24 * longest2 * longest2;
        vec3 n[3];
        for (int k = 0; k < 3 && ok; ++k) {
            n[k] = v3_load(r->split_normals + 3 * (size_t)r->corner_split[3 * t + k]);
            ok = v3_len2(n[k]) > 0;
        }
        /* corners whose normals are 90° or more apart describe no single smooth sheet (a fold, flipped faces of a
         * scan): the interpolated normal turns through the plane of the triangle and its lines go anywhere */
        for (int k = 0; k < 3 && ok; ++k)
            ok = v3_dot(n[k], n[(k + 1) % 3]) > 0;
        r->usable[t] = (uint8_t)ok;
    }
    return 0;
}

static resurf_status mark_usable(resurfi_restorer *r, resurf_error *error)
{
    r->usable = resurfi_alloc(&r->alloc, r->triangle_count, 1);
    if (!r->usable)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory marking triangles");
    setup_job j = {.r = r};
    setup_for(r, r->triangle_count, usable_block, &j);
    return RESURF_OK;
}

void resurfi_restorer_free(resurfi_restorer *r)
{
    if (!r)
        return;
    const resurf_allocator alloc = r->alloc; /* the struct holding it goes last */
    resurfi_free(&alloc, r->own_tris);
    resurfi_adjacency_free(&r->adj);
    resurfi_bvh_free(r->bvh);
    resurfi_free(&alloc, r->corner_split);
    resurfi_free(&alloc, r->split_normals);
    resurfi_free(&alloc, r->k1);
    resurfi_free(&alloc, r->k2);
    resurfi_free(&alloc, r->dir1);
    resurfi_free(&alloc, r->dir2);
    resurfi_free(&alloc, r->local_length);
    resurfi_free(&alloc, r->edge_kind);
    resurfi_free(&alloc, r->feature_offset);
    resurfi_free(&alloc, r->feature_vertex);
    resurfi_free(&alloc, r->feature_kind);
    resurfi_free(&alloc, r->side_kind);
    resurfi_free(&alloc, r->tangent);
    resurfi_free(&alloc, r->usable);
    resurfi_free(&alloc, r->quiet);
    resurfi_free(&alloc, r->quiet_position);
    resurfi_free(&alloc, r);
}

resurf_status resurfi_restorer_create(const resurf_mesh *original, const resurf_restore_options *options,
                                      resurfi_restorer **out, resurf_error *error)
{
    return resurfi_restorer_create_ex(original, options, 1, NULL, 0, out, error);
}

resurf_status resurfi_restorer_create_ex(const resurf_mesh *original, const resurf_restore_options *options,
                                         int with_tree, const uint32_t *remap, size_t distinct,
                                         resurfi_restorer **out, resurf_error *error)
{
    if (!out)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "out is NULL");
    *out = NULL;
    if (!original)
        return resurfi_error(error, RESURF_ERR_INVALID_ARGUMENT, "the original mesh is NULL");
    resurf_status s = resurfi_restore_check_options(options, error);
    if (s != RESURF_OK)
        return s;
    const resurf_allocator *alloc = resurfi_allocator_of(options ? options->allocator : NULL, original);
    resurfi_restorer *r = resurfi_calloc(alloc, 1, sizeof *r);
    if (!r)
        return resurfi_error(error, RESURF_ERR_OUT_OF_MEMORY, "out of memory creating the restorer");
    if (alloc)
        r->alloc = *alloc;
    r->opt = options ? *options : resurf_restore_options_default();
    if (r->opt.normals == RESURF_NORMALS_AUTO) /* resurf_restore's own choice (the simplifier makes its own first) */
        r->opt.normals = RESURF_NORMALS_JET;
    if ((s = weld_original(r, original, remap, distinct, error)) == RESURF_OK && (s = classify_edges(r, original, error)) == RESURF_OK &&
        (s = split_fans(r, error)) == RESURF_OK && (s = mark_quiet(r, error)) == RESURF_OK &&
        (s = estimate_normals(r, original, error)) == RESURF_OK &&
        (s = trace_features(r, error)) == RESURF_OK && (s = mark_usable(r, error)) == RESURF_OK && with_tree) {
        s = resurfi_bvh_build_threads(&r->alloc, r->positions, r->position_count, r->tris, r->triangle_count,
                                      r->opt.threads, &r->bvh);
        if (s != RESURF_OK)
            resurfi_error(error, s, "cannot build the original mesh's BVH");
    }
    if (s != RESURF_OK) {
        resurfi_restorer_free(r);
        return s;
    }
    *out = r;
    return RESURF_OK;
}

const resurfi_bvh *resurfi_restorer_bvh(const resurfi_restorer *r) { return r->bvh; }
