/* Tests of src/mesh_arrays.c: meshes from the caller's strided arrays and back (resurf_mesh_from_arrays,
 * resurf_mesh_to_arrays). The truth is the caller's own buffer: every value must come back bit for bit, bytes
 * between attributes must stay untouched, and every wrong input must fail with a message naming what is wrong. */
#include <math.h>
#include <string.h>

#include "testutil.h"

/* A game-style interleaved vertex: 32 bytes. */
typedef struct vertex {
    float pos[3];
    float normal[3];
    float uv[2];
} vertex;

/* A square pyramid, 5 vertices and 6 triangles (4 sides and the base as two), drawn from above:
 *
 *    3 ------- 2
 *    |  \   /  |      apex 4 at (0, 0, 1) over the centre,
 *    |    4    |      base corners 0..3 at z = 0, counter-clockwise from (-1,-1)
 *    |  /   \  |
 *    0 ------- 1
 *
 * Values are chosen with fractions that are not exact in binary (0.1, 1/3) so that a float→double→float round trip
 * that lost a bit would show. */
static void pyramid(vertex v[5], uint16_t idx[18])
{
    static const float p[5][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0.1f, 1.0f / 3, 1}};
    for (int i = 0; i < 5; ++i) {
        memcpy(v[i].pos, p[i], sizeof v[i].pos);
        float len = sqrtf(p[i][0] * p[i][0] + p[i][1] * p[i][1] + p[i][2] * p[i][2]);
        for (int c = 0; c < 3; ++c)
            v[i].normal[c] = p[i][c] / len;
        v[i].uv[0] = 0.1f * (float)i;
        v[i].uv[1] = 1.0f - 0.3f * (float)i;
    }
    static const uint16_t t[18] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 0, 2, 1, 0, 3, 2};
    memcpy(idx, t, sizeof t);
}

static resurf_mesh_arrays interleaved(const vertex *v, size_t n, const uint16_t *idx, size_t index_count)
{
    resurf_mesh_arrays a = resurf_mesh_arrays_default();
    a.vertex_count = n;
    a.positions.data = v[0].pos;
    a.positions.stride = sizeof(vertex);
    a.normals.data = v[0].normal;
    a.normals.stride = sizeof(vertex);
    a.texcoords[0].data = v[0].uv;
    a.texcoords[0].stride = sizeof(vertex);
    a.indices = idx;
    a.index_type = RESURF_INDEX_UINT16;
    a.index_count = index_count;
    return a;
}

START_TEST(arrays_interleaved_float_stride_32_round_trip)
{
    vertex v[5];
    uint16_t idx[18];
    pyramid(v, idx);
    ck_assert_uint_eq(sizeof(vertex), 32);
    resurf_mesh_arrays a = interleaved(v, 5, idx, 18);
    resurf_mesh *m = NULL;
    resurf_error e;
    ck_assert_int_eq(resurf_mesh_from_arrays(&a, &m, &e), RESURF_OK);
    ck_assert_int_eq(e.status, RESURF_OK);
    ck_assert_uint_eq(m->vertex_count, 5);
    ck_assert_uint_eq(m->triangle_count, 6);
    ck_assert_ptr_nonnull(m->normals);
    ck_assert_uint_eq(m->texcoord_count, 1);
    ck_assert_ptr_null(m->colors);
    /* float → double is exact: every double equals its float. */
    for (int i = 0; i < 5; ++i)
        for (int c = 0; c < 3; ++c) {
            ck_assert(m->positions[3 * i + c] == (double)v[i].pos[c]);
            ck_assert(m->normals[3 * i + c] == (double)v[i].normal[c]);
            if (c < 2)
                ck_assert(m->texcoords[0][2 * i + c] == (double)v[i].uv[c]);
        }
    for (int i = 0; i < 18; ++i)
        ck_assert_uint_eq(m->indices[i], idx[i]);
    /* The pyramid is one closed, consistently oriented surface: the order of the indices came through. */
    resurf_validate_report val;
    ck_assert_int_eq(resurf_mesh_validate(m, &val, NULL), RESURF_OK);
    ck_assert_uint_eq(val.boundary_edges, 0);
    ck_assert_uint_eq(val.inconsistent_edges, 0);

    /* Back into a fresh interleaved buffer of the same layout: byte for byte the caller's. */
    vertex back[5];
    uint16_t back_idx[18];
    memset(back, 0xAB, sizeof back);
    resurf_mesh_arrays_out o = resurf_mesh_arrays_out_default();
    o.vertex_capacity = 5;
    o.positions.data = back[0].pos;
    o.positions.stride = sizeof(vertex);
    o.normals.data = back[0].normal;
    o.normals.stride = sizeof(vertex);
    o.texcoords[0].data = back[0].uv;
    o.texcoords[0].stride = sizeof(vertex);
    o.indices = back_idx;
    o.index_type = RESURF_INDEX_UINT16;
    o.index_capacity = 18;
    ck_assert_int_eq(resurf_mesh_to_arrays(m, &o, &e), RESURF_OK);
    ck_assert_int_eq(memcmp(back, v, sizeof v), 0);
    ck_assert_int_eq(memcmp(back_idx, idx, sizeof idx), 0);
    resurf_mesh_free(m);
}
END_TEST

/* Doubles with padding between vertices (stride 40 for 24 bytes of data) and uint32 indices: kept exactly, and
 * the padding bytes of the output are never written. */
START_TEST(arrays_double_with_padding_keeps_bits_and_padding)
{
    enum { STRIDE = 40 };
    unsigned char in[4 * STRIDE];
    memset(in, 0, sizeof in);
    const double p[4][3] = {{0.1, 0.2, 0.3}, {1e-300, -0.0, 1.0 / 3}, {12345.678901234567, 2, 3}, {-1, -2, -3}};
    for (int i = 0; i < 4; ++i)
        memcpy(in + i * STRIDE + 8, p[i], sizeof p[i]); /* 8 bytes of header per vertex, as a game might have */
    const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    resurf_mesh_arrays a = resurf_mesh_arrays_default();
    a.vertex_count = 4;
    a.positions.data = in + 8;
    a.positions.type = RESURF_COMPONENT_DOUBLE;
    a.positions.stride = STRIDE;
    a.indices = idx;
    a.index_count = 6;
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_from_arrays(&a, &m, NULL), RESURF_OK);
    ck_assert_int_eq(memcmp(m->positions, p, sizeof p), 0);
    ck_assert_int_eq(memcmp(m->indices, idx, sizeof idx), 0);

    unsigned char out[4 * STRIDE];
    uint32_t out_idx[6];
    memset(out, 0x5A, sizeof out);
    resurf_mesh_arrays_out o = resurf_mesh_arrays_out_default();
    o.vertex_capacity = 4;
    o.positions.data = out + 8;
    o.positions.type = RESURF_COMPONENT_DOUBLE;
    o.positions.stride = STRIDE;
    o.indices = out_idx;
    o.index_capacity = 6;
    ck_assert_int_eq(resurf_mesh_to_arrays(m, &o, NULL), RESURF_OK);
    for (int i = 0; i < 4; ++i) {
        ck_assert_int_eq(memcmp(out + i * STRIDE + 8, p[i], sizeof p[i]), 0);
        for (int b = 0; b < 8; ++b) /* header bytes before the positions */
            ck_assert_uint_eq(out[i * STRIDE + b], 0x5A);
        for (int b = 32; b < STRIDE; ++b) /* padding after them */
            ck_assert_uint_eq(out[i * STRIDE + b], 0x5A);
    }
    ck_assert_int_eq(memcmp(out_idx, idx, sizeof idx), 0);
    /* Tightly packed float output (stride 0) rounds each double to the nearest float. */
    float packed[12];
    resurf_mesh_arrays_out f = resurf_mesh_arrays_out_default();
    f.vertex_capacity = 4;
    f.positions.data = packed;
    ck_assert_int_eq(resurf_mesh_to_arrays(m, &f, NULL), RESURF_OK);
    for (int i = 0; i < 12; ++i)
        ck_assert(packed[i] == (float)p[i / 3][i % 3]);
    ck_assert(signbit(packed[4])); /* -0.0 stays negative zero */
    resurf_mesh_free(m);
}
END_TEST

/* UNORM8 RGBA colours and UNORM16 texcoords: value / max in the mesh, the same integers back. RGB gets alpha 1. */
START_TEST(arrays_unorm_colors_and_texcoords)
{
    const uint8_t rgba[3][4] = {{0, 128, 255, 7}, {1, 2, 3, 254}, {200, 100, 50, 0}};
    const uint16_t uv[3][2] = {{0, 65535}, {12345, 1}, {32768, 65534}};
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t idx[3] = {0, 1, 2};
    resurf_mesh_arrays a = resurf_mesh_arrays_default();
    a.vertex_count = 3;
    a.positions.data = pos;
    a.colors.data = rgba;
    a.colors.type = RESURF_COMPONENT_UNORM8;
    a.texcoords[0].data = uv;
    a.texcoords[0].type = RESURF_COMPONENT_UNORM16;
    a.indices = idx;
    a.index_count = 3;
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_from_arrays(&a, &m, NULL), RESURF_OK);
    ck_assert_uint_eq(m->color_components, 4);
    for (int i = 0; i < 3; ++i) {
        for (int c = 0; c < 4; ++c)
            ck_assert_double_eq_tol(m->colors[4 * i + c], rgba[i][c] / 255.0, 1e-15);
        for (int c = 0; c < 2; ++c)
            ck_assert_double_eq_tol(m->texcoords[0][2 * i + c], uv[i][c] / 65535.0, 1e-15);
    }
    uint8_t rgba_back[3][4];
    uint16_t uv_back[3][2];
    resurf_mesh_arrays_out o = resurf_mesh_arrays_out_default();
    o.vertex_capacity = 3;
    o.colors.data = rgba_back;
    o.colors.type = RESURF_COMPONENT_UNORM8;
    o.texcoords[0].data = uv_back;
    o.texcoords[0].type = RESURF_COMPONENT_UNORM16;
    ck_assert_int_eq(resurf_mesh_to_arrays(m, &o, NULL), RESURF_OK);
    ck_assert_int_eq(memcmp(rgba_back, rgba, sizeof rgba), 0);
    ck_assert_int_eq(memcmp(uv_back, uv, sizeof uv), 0);
    resurf_mesh_free(m);

    /* RGB floats: opaque, and color_components says 3. */
    const float rgb[9] = {0.25f, 0.5f, 0.75f, 1, 0, 0, 0, 1, 0};
    a = resurf_mesh_arrays_default();
    a.vertex_count = 3;
    a.positions.data = pos;
    a.colors.data = rgb;
    a.color_components = 3;
    ck_assert_int_eq(resurf_mesh_from_arrays(&a, &m, NULL), RESURF_OK);
    ck_assert_uint_eq(m->color_components, 3);
    ck_assert(m->colors[0] == 0.25 && m->colors[1] == 0.5 && m->colors[2] == 0.75 && m->colors[3] == 1.0);
    ck_assert(m->colors[7] == 1.0 && m->colors[11] == 1.0);
    ck_assert_uint_eq(m->triangle_count, 0);
    resurf_mesh_free(m);
}
END_TEST

/* Expects a failure with the given status and a message containing `want`; *out_mesh must be NULL. */
static void expect_from_fails(const resurf_mesh_arrays *a, resurf_status status, const char *want)
{
    resurf_mesh *m = (resurf_mesh *)(uintptr_t)1; /* must be reset */
    resurf_error e;
    resurf_status s = resurf_mesh_from_arrays(a, &m, &e);
    ck_assert_msg(s == status, "status %s, wanted %s (%s)", resurf_status_string(s), resurf_status_string(status),
                  e.message);
    ck_assert_int_eq(e.status, status);
    ck_assert_ptr_null(m);
    ck_assert_msg(strstr(e.message, want), "message '%s' lacks '%s'", e.message, want);
}

START_TEST(arrays_from_every_error_named)
{
    vertex v[5];
    uint16_t idx[18];
    pyramid(v, idx);
    resurf_mesh_arrays a;
    resurf_mesh *m = NULL;

    ck_assert_int_eq(resurf_mesh_from_arrays(NULL, &m, NULL), RESURF_ERR_INVALID_ARGUMENT);
    a = interleaved(v, 5, idx, 18);
    ck_assert_int_eq(resurf_mesh_from_arrays(&a, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);

    memset(&a, 0, sizeof a); /* hand-zeroed, not from _default() */
    expect_from_fails(&a, RESURF_ERR_INVALID_OPTIONS, "resurf_mesh_arrays was not initialised");

    a = interleaved(v, 5, idx, 18);
    a.positions.data = NULL;
    expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT, "positions.data is NULL for 5 vertices");

    a = interleaved(v, 5, idx, 18);
    a.indices = NULL;
    expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT, "indices is NULL for index_count 18");

    a = interleaved(v, 5, idx, 17);
    expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT, "index_count 17 is not a multiple of 3");

    a = interleaved(v, 5, idx, 18);
    a.index_type = (resurf_index_type)7;
    expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT, "unknown index_type 7");

    a = interleaved(v, 5, idx, 18);
    a.normals.stride = 8;
    expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT,
                      "normals: stride 8 is smaller than one element (12 bytes: 3 floats)");

    a = interleaved(v, 5, idx, 18);
    a.positions.type = RESURF_COMPONENT_DOUBLE; /* a double position needs 24 bytes */
    a.positions.stride = 16;
    expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT,
                      "positions: stride 16 is smaller than one element (24 bytes: 3 doubles)");

    a = interleaved(v, 5, idx, 18);
    a.texcoords[0].stride = 4;
    expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT,
                      "texcoords[0]: stride 4 is smaller than one element (8 bytes: 2 floats)");

    a = interleaved(v, 5, idx, 18);
    a.positions.type = RESURF_COMPONENT_UNORM8;
    expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT,
                      "positions: component type unorm8 is not allowed (float or double only)");

    a = interleaved(v, 5, idx, 18);
    a.normals.type = (resurf_component_type)42;
    expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT, "normals: unknown component type 42");

    a = interleaved(v, 5, idx, 18);
    a.texcoords[2] = a.texcoords[0];
    expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT,
                      "texcoords[2] is given without texcoords[1] (sets must be numbered from 0)");

    a = interleaved(v, 5, idx, 18);
    a.colors.data = v[0].normal;
    a.colors.stride = sizeof(vertex);
    a.color_components = 2;
    expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT, "colors: color_components is 2 (3 or 4)");

    if (SIZE_MAX > UINT32_MAX) {
        a = interleaved(v, 5, idx, 18);
        a.vertex_count = (size_t)UINT32_MAX + 1;
        expect_from_fails(&a, RESURF_ERR_INVALID_ARGUMENT, "vertex_count 4294967296 is above 2^32 - 1");
    }

    /* An index out of range names the triangle, its indices and the vertex count. */
    uint16_t bad[18];
    memcpy(bad, idx, sizeof bad);
    bad[4] = 9;
    a = interleaved(v, 5, bad, 18);
    expect_from_fails(&a, RESURF_ERR_INVALID_MESH,
                      "triangle 1 (indices 3..5) refers to vertex 9, but there are 5 vertices");

    /* Non-finite values name the attribute, the vertex and the component. */
    vertex w[5];
    memcpy(w, v, sizeof w);
    w[2].pos[1] = NAN;
    a = interleaved(w, 5, idx, 18);
    expect_from_fails(&a, RESURF_ERR_INVALID_MESH, "positions: vertex 2, component 1 is nan");
    memcpy(w, v, sizeof w);
    w[3].normal[2] = -INFINITY;
    a = interleaved(w, 5, idx, 18);
    expect_from_fails(&a, RESURF_ERR_INVALID_MESH, "normals: vertex 3, component 2 is -inf");
    memcpy(w, v, sizeof w);
    w[1].uv[0] = INFINITY;
    a = interleaved(w, 5, idx, 18);
    expect_from_fails(&a, RESURF_ERR_INVALID_MESH, "texcoords[0]: vertex 1, component 0 is inf");

    /* Zero vertices and zero indices is a valid, empty mesh. */
    a = resurf_mesh_arrays_default();
    ck_assert_int_eq(resurf_mesh_from_arrays(&a, &m, NULL), RESURF_OK);
    ck_assert_uint_eq(m->vertex_count, 0);
    ck_assert_uint_eq(m->triangle_count, 0);
    resurf_mesh_free(m);
}
END_TEST

/* Expects resurf_mesh_to_arrays to fail as said, and the caller's buffers (sentinel-filled) to be untouched. */
static void expect_to_fails(const resurf_mesh *m, const resurf_mesh_arrays_out *o, resurf_status status,
                            const char *want, const unsigned char *buf, size_t size)
{
    resurf_error e;
    resurf_status s = resurf_mesh_to_arrays(m, o, &e);
    ck_assert_msg(s == status, "status %s, wanted %s (%s)", resurf_status_string(s), resurf_status_string(status),
                  e.message);
    ck_assert_msg(strstr(e.message, want), "message '%s' lacks '%s'", e.message, want);
    for (size_t i = 0; i < size; ++i)
        ck_assert_msg(buf[i] == 0xCD, "byte %zu of the caller's buffer was written by a failing call", i);
}

START_TEST(arrays_to_every_error_named_and_nothing_written)
{
    resurf_mesh *m = tu_tetrahedron(); /* 4 vertices, 4 triangles, no normals */
    unsigned char buf[256];
    memset(buf, 0xCD, sizeof buf);
    resurf_mesh_arrays_out o = resurf_mesh_arrays_out_default();
    o.vertex_capacity = 4;
    o.positions.data = buf;
    o.indices = buf + 64;
    o.index_capacity = 12;

    ck_assert_int_eq(resurf_mesh_to_arrays(NULL, &o, NULL), RESURF_ERR_INVALID_ARGUMENT);
    ck_assert_int_eq(resurf_mesh_to_arrays(m, NULL, NULL), RESURF_ERR_INVALID_ARGUMENT);
    resurf_mesh_arrays_out z;
    memset(&z, 0, sizeof z);
    expect_to_fails(m, &z, RESURF_ERR_INVALID_OPTIONS, "was not initialised", buf, sizeof buf);

    resurf_mesh_arrays_out c = o;
    c.vertex_capacity = 3;
    expect_to_fails(m, &c, RESURF_ERR_INVALID_ARGUMENT, "vertex_capacity 3 is less than the mesh's 4 vertices", buf,
                    sizeof buf);
    c = o;
    c.index_capacity = 4; /* the usual mistake: the triangle count */
    expect_to_fails(m, &c, RESURF_ERR_INVALID_ARGUMENT,
                    "index_capacity 4 is less than the mesh's 12 indices (3 per triangle)", buf, sizeof buf);
    c = o;
    c.normals.data = buf + 128;
    expect_to_fails(m, &c, RESURF_ERR_INVALID_ARGUMENT, "the mesh has no normals", buf, sizeof buf);
    c = o;
    c.texcoords[1].data = buf + 128;
    expect_to_fails(m, &c, RESURF_ERR_INVALID_ARGUMENT, "the mesh has no texcoords[1]", buf, sizeof buf);
    c = o;
    c.positions.stride = 11;
    expect_to_fails(m, &c, RESURF_ERR_INVALID_ARGUMENT,
                    "positions: stride 11 is smaller than one element (12 bytes: 3 floats)", buf, sizeof buf);
    c = o;
    c.positions.type = RESURF_COMPONENT_UNORM16;
    expect_to_fails(m, &c, RESURF_ERR_INVALID_ARGUMENT, "positions: component type unorm16 is not allowed", buf,
                    sizeof buf);

    /* A coordinate beyond float's range: LIMIT, naming it; asking for double works. */
    m->positions[3 * 2 + 1] = 1e300;
    expect_to_fails(m, &o, RESURF_ERR_LIMIT,
                    "positions: vertex 2, component 1 = 1e+300 is beyond float's range (ask for double)", buf,
                    sizeof buf);
    c = o;
    c.positions.type = RESURF_COMPONENT_DOUBLE;
    double d[12];
    c.positions.data = d;
    c.indices = NULL;
    ck_assert_int_eq(resurf_mesh_to_arrays(m, &c, NULL), RESURF_OK);
    ck_assert(d[7] == 1e300);
    m->positions[3 * 2 + 1] = 0;

    /* An index out of range in the mesh. */
    m->indices[5] = 4;
    expect_to_fails(m, &o, RESURF_ERR_INVALID_MESH, "triangle 1 refers to vertex 4, but there are 4 vertices", buf,
                    sizeof buf);
    resurf_mesh_free(m);

    /* 16-bit indices cannot name vertex 65536. */
    resurf_mesh *big = NULL;
    ck_assert_int_eq(resurf_mesh_create(65537, 1, 0, &big, NULL), RESURF_OK);
    big->indices[0] = 0, big->indices[1] = 1, big->indices[2] = 65536;
    uint16_t small[3] = {0xCDCD, 0xCDCD, 0xCDCD};
    resurf_mesh_arrays_out s = resurf_mesh_arrays_out_default();
    s.indices = small;
    s.index_type = RESURF_INDEX_UINT16;
    s.index_capacity = 3;
    expect_to_fails(big, &s, RESURF_ERR_LIMIT, "triangle 0 refers to vertex 65536, beyond uint16 indices",
                    (const unsigned char *)small, sizeof small);
    resurf_mesh_free(big);
}
END_TEST

/* The arrays are copied: the caller may change or free them at once, the mesh keeps its values. */
START_TEST(arrays_mesh_owns_a_copy)
{
    vertex *v = malloc(5 * sizeof *v);
    uint16_t *idx = malloc(18 * sizeof *idx);
    pyramid(v, idx);
    const double apex_x = v[4].pos[0];
    resurf_mesh_arrays a = interleaved(v, 5, idx, 18);
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_from_arrays(&a, &m, NULL), RESURF_OK);
    memset(v, 0xFF, 5 * sizeof *v);
    free(v);
    free(idx);
    ck_assert(m->positions[12] == apex_x);
    ck_assert_uint_eq(m->indices[17], 2);
    resurf_mesh_free(m);
}
END_TEST

/* A counting allocator over the C heap: live blocks and total allocations. */
typedef struct counter {
    long live, total;
    long fail_at; /* the allocation (0-based) that returns NULL; -1 = none */
} counter;
static void *count_alloc(void *user, size_t size)
{
    counter *c = user;
    if (c->total++ == c->fail_at)
        return NULL;
    c->live++;
    return malloc(size);
}
static void *count_realloc(void *user, void *block, size_t size)
{
    (void)user;
    return realloc(block, size);
}
static void count_release(void *user, void *block)
{
    counter *c = user;
    c->live--;
    free(block);
}

/* The mesh comes from the caller's allocator, records it, and gives every block back to it when freed. */
START_TEST(arrays_use_the_callers_allocator)
{
    vertex v[5];
    uint16_t idx[18];
    pyramid(v, idx);
    counter c = {0, 0, -1};
    resurf_allocator alloc = {count_alloc, count_realloc, count_release, &c};
    resurf_mesh_arrays a = interleaved(v, 5, idx, 18);
    a.allocator = &alloc;
    resurf_mesh *m = NULL;
    ck_assert_int_eq(resurf_mesh_from_arrays(&a, &m, NULL), RESURF_OK);
    ck_assert_int_ge(c.total, 5); /* the struct, positions, indices, normals, texcoords */
    ck_assert_int_eq(c.live, c.total);
    ck_assert_ptr_eq(m->allocator.user, &c);
    resurf_mesh_free(m);
    ck_assert_int_eq(c.live, 0);

    /* Each allocation failing in turn: OUT_OF_MEMORY, no mesh, nothing left allocated. */
    const long needed = c.total;
    for (long k = 0; k < needed; ++k) {
        c = (counter){0, 0, k};
        expect_from_fails(&a, RESURF_ERR_OUT_OF_MEMORY, "out of memory");
        ck_assert_int_eq(c.live, 0);
    }

    resurf_allocator half = {count_alloc, NULL, count_release, &c};
    a.allocator = &half;
    expect_from_fails(&a, RESURF_ERR_INVALID_OPTIONS, "the allocator needs allocate, reallocate and release");
    ck_assert_int_eq(c.live, 0);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("mesh_arrays");
    TCase *tc = tcase_create("arrays");
    tcase_add_test(tc, arrays_interleaved_float_stride_32_round_trip);
    tcase_add_test(tc, arrays_double_with_padding_keeps_bits_and_padding);
    tcase_add_test(tc, arrays_unorm_colors_and_texcoords);
    tcase_add_test(tc, arrays_from_every_error_named);
    tcase_add_test(tc, arrays_to_every_error_named_and_nothing_written);
    tcase_add_test(tc, arrays_mesh_owns_a_copy);
    tcase_add_test(tc, arrays_use_the_callers_allocator);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
