/* The shared borders of resurf_scene_build_lods: the positions that primitives of one mesh, or meshes shown side by
 * side under one world matrix, use bit for bit. Locking them keeps every level from opening a crack between the
 * parts; primitives linked this way may instead be simplified as one surface, a unit (scene_joint.c). */
#include <stdlib.h>
#include <string.h>

#include "hash.h"
#include "union_find.h"
#include "scene_lods_internal.h"

/* A position as a key: its three coordinates' bits (-0 as +0, so that equal coordinates are equal keys). */
typedef struct pos_key {
    uint64_t bits[3];
} pos_key;

static pos_key key_of(const double *p)
{
    pos_key k;
    for (int c = 0; c < 3; ++c) {
        double v = p[c] == 0 ? 0.0 : p[c];
        memcpy(&k.bits[c], &v, sizeof v);
    }
    return k;
}

static uint64_t key_hash(const pos_key *k)
{
    return resurfi_mix64(k->bits[0] ^ resurfi_mix64(k->bits[1] ^ resurfi_mix64(k->bits[2])));
}

/* One slot of the table of a mesh's positions: the first primitive that uses it, and whether another does too. */
typedef struct pos_slot {
    pos_key key;
    size_t prim;            /* SIZE_MAX: empty */
    int shared;
} pos_slot;

/* The positions that primitives of different owners use, bit for bit (prims[i] has owner[i], in 0..n-1). With
 * locks, the vertices of each rewritten primitive at such a position are locked: added to locks[p], which is
 * allocated when NULL. With linked (n entries), linked[i] becomes the first of prims that shared positions link
 * prims[i]'s owner to (itself when they link it to none). Only vertices that triangles use count. */
static resurf_status lock_shared(const resurf_scene *scene, const size_t *prims, const size_t *owner, size_t n,
                                 const resurf_allocator *alloc, uint8_t **locks, size_t *linked)
{
    size_t total = 0;
    for (size_t i = 0; i < n; ++i)
        total += scene->prims[prims[i]].mesh->vertex_count;
    for (size_t i = 0; linked && i < n; ++i)
        linked[i] = prims[i];
    if (n < 2 || total == 0)
        return RESURF_OK;
    size_t cap = 16;
    while (cap < 2 * total)
        cap *= 2;
    pos_slot *table = resurfi_alloc(alloc, cap, sizeof *table);
    uint32_t *set = resurfi_alloc(alloc, n, sizeof *set); /* union-find over the owners */
    if (!table || !set) {
        resurfi_free(alloc, table);
        resurfi_free(alloc, set);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    for (size_t i = 0; i < n; ++i)
        set[i] = (uint32_t)i;
    for (size_t i = 0; i < cap; ++i)
        table[i].prim = SIZE_MAX;
    /* Pass 1: which positions more than one owner uses; pass 2: the locks of each rewritten primitive. */
    resurf_status st = RESURF_OK;
    for (int pass = 0; pass < (locks ? 2 : 1) && st == RESURF_OK; ++pass) {
        for (size_t x = 0; x < n && st == RESURF_OK; ++x) {
            size_t p = prims[x];
            const resurf_mesh *mesh = scene->prims[p].mesh;
            if (pass == 1 && !resurfi_scene_rewritten(&scene->prims[p]))
                continue;
            uint8_t *lock = pass == 1 ? locks[p] : NULL, *made = NULL;
            size_t locked = 0;
            if (pass == 1 && !lock && !(lock = made = resurfi_calloc(alloc, mesh->vertex_count + 1, 1))) {
                st = RESURF_ERR_OUT_OF_MEMORY;
                break;
            }
            for (size_t t = 0; t < 3 * mesh->triangle_count; ++t) {
                uint32_t v = mesh->indices[t];
                pos_key k = key_of(mesh->positions + 3 * (size_t)v);
                size_t i = (size_t)key_hash(&k) & (cap - 1);
                while (table[i].prim != SIZE_MAX && memcmp(&table[i].key, &k, sizeof k))
                    i = (i + 1) & (cap - 1);
                if (pass == 0) {
                    if (table[i].prim == SIZE_MAX)
                        table[i] = (pos_slot){k, owner[x], 0};
                    else if (table[i].prim != owner[x]) {
                        table[i].shared = 1;
                        resurfi_uf_union(set, (uint32_t)table[i].prim, (uint32_t)owner[x]);
                    }
                } else if (table[i].shared && !lock[v]) {
                    lock[v] = 1;
                    locked++;
                }
            }
            if (made && locked)
                locks[p] = made;
            else
                resurfi_free(alloc, made);
        }
    }
    for (size_t x = 0; linked && x < n; ++x)
        for (size_t y = 0; y <= x; ++y)
            if (resurfi_uf_find(set, (uint32_t)owner[y]) == resurfi_uf_find(set, (uint32_t)owner[x])) {
                linked[x] = prims[y];
                break;
            }
    resurfi_free(alloc, table);
    resurfi_free(alloc, set);
    return st;
}

/* An instance's world matrix for comparing (NULL is the identity). */
static const double *world_of(const resurfi_scene_instance *it)
{
    static const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    return it->world ? it->world : identity;
}

static int by_world_then_mesh(const void *a, const void *b)
{
    const resurfi_scene_instance *x = a, *y = b;
    int c = memcmp(world_of(x), world_of(y), 16 * sizeof(double));
    return c ? c : (x->mesh > y->mesh) - (x->mesh < y->mesh);
}

/* The groups of meshes whose primitives may go together: group[m] is the first mesh of m's group. Each mesh is a
 * group alone. Meshes each shown once by nodes of one world matrix (an exporter's parts of one object, side by side
 * under one parent) were tried as one group, at stop 45, and measured worse where it mattered: on the 39 furniture
 * assets the geometric mean of Hausdorff over gltfpack's went 0.307 -> 0.317 at 25% (0.366 -> 0.361 at 10%), and
 * Sweet Home 3D's bus, its body joined with the parts beside it, went from 0.75x to 1.79x gltfpack's at both
 * levels; the truck and the toy cart gained. Those meshes lock what they share (resurfi_scene_shared_between_meshes)
 * until that is understood. */
resurf_status resurfi_scene_mesh_groups(const resurf_scene *scene, const resurfi_scene_instances *list,
                                        const resurf_allocator *alloc, size_t *group)
{
    (void)list, (void)alloc;
    for (size_t m = 0; m < scene->mesh_count; ++m)
        group[m] = m;
    return RESURF_OK;
}

/* The primitives of group g (those with a mesh; with `layout` not NULL, only its triangle primitives of that
 * mesh's attribute layout) into prims, in order; returns how many. */
static size_t group_prims(const resurf_scene *scene, const size_t *group, size_t g, const resurf_mesh *layout,
                          size_t *prims)
{
    size_t k = 0;
    for (size_t m = g; m < scene->mesh_count; ++m)
        for (size_t p = scene->mesh_first[m]; group[m] == g && p < scene->mesh_first[m + 1]; ++p) {
            const resurfi_scene_prim *prim = &scene->prims[p];
            if (prim->mesh && (!layout || (prim->info.kind == RESURF_PRIMITIVE_TRIANGLES &&
                                           resurfi_mesh_same_attributes(layout, prim->mesh))))
                prims[k++] = p;
        }
    return k;
}

resurf_status resurfi_scene_linked(const resurf_scene *scene, const size_t *group, const resurf_allocator *alloc,
                                   size_t *linked)
{
    size_t pc = scene->prim_count;
    size_t *prims = resurfi_alloc(alloc, pc + 1, sizeof *prims);
    size_t *owner = resurfi_alloc(alloc, pc + 1, sizeof *owner);
    size_t *found = resurfi_alloc(alloc, pc + 1, sizeof *found);
    resurf_status st = prims && owner && found ? RESURF_OK : RESURF_ERR_OUT_OF_MEMORY;
    for (size_t p = 0; p < pc; ++p)
        linked[p] = SIZE_MAX;
    /* per group, per attribute layout (the first triangle primitive not yet placed shows the next one) */
    for (size_t p = 0; st == RESURF_OK && p < pc; ++p) {
        const resurfi_scene_prim *prim = &scene->prims[p];
        if (linked[p] != SIZE_MAX || !prim->mesh || prim->info.kind != RESURF_PRIMITIVE_TRIANGLES)
            continue;
        size_t k = group_prims(scene, group, group[prim->info.mesh], prim->mesh, prims);
        for (size_t x = 0; x < k; ++x)
            owner[x] = x, found[x] = prims[x];
        if (k >= 2)
            st = lock_shared(scene, prims, owner, k, alloc, NULL, found);
        for (size_t x = 0; x < k; ++x)
            linked[prims[x]] = found[x];
    }
    for (size_t p = 0; p < pc; ++p)
        linked[p] = linked[p] == SIZE_MAX ? p : linked[p];
    resurfi_free(alloc, prims);
    resurfi_free(alloc, owner);
    resurfi_free(alloc, found);
    return st;
}

resurf_status resurfi_scene_lock_between_units(const resurf_scene *scene, const size_t *group, const size_t *unit,
                                               const resurf_allocator *alloc, uint8_t **locks)
{
    size_t pc = scene->prim_count;
    size_t *prims = resurfi_alloc(alloc, pc + 1, sizeof *prims);
    size_t *owner = resurfi_alloc(alloc, pc + 1, sizeof *owner);
    resurf_status st = prims && owner ? RESURF_OK : RESURF_ERR_OUT_OF_MEMORY;
    for (size_t g = 0; st == RESURF_OK && g < scene->mesh_count; ++g) {
        if (group[g] != g)
            continue;
        size_t k = group_prims(scene, group, g, NULL, prims);
        for (size_t x = 0; x < k; ++x) { /* a unit's primitives are one owner */
            owner[x] = x;
            for (size_t y = 0; unit[prims[x]] != SIZE_MAX && y < x; ++y)
                if (unit[prims[y]] == unit[prims[x]]) {
                    owner[x] = owner[y];
                    break;
                }
        }
        if (k >= 2)
            st = lock_shared(scene, prims, owner, k, alloc, locks, NULL);
    }
    resurfi_free(alloc, prims);
    resurfi_free(alloc, owner);
    return st;
}

resurf_status resurfi_scene_lock_shared(const resurf_scene *scene, const size_t *prims, size_t n,
                                        const resurf_allocator *alloc, uint8_t **locks)
{
    size_t *owner = resurfi_alloc(alloc, n + 1, sizeof *owner);
    if (!owner)
        return RESURF_ERR_OUT_OF_MEMORY;
    for (size_t x = 0; x < n; ++x)
        owner[x] = x;
    resurf_status st = lock_shared(scene, prims, owner, n, alloc, locks, NULL);
    resurfi_free(alloc, owner);
    return st;
}

/* Different meshes shown by nodes of one world matrix (the parts an exporter split an object into, side by side
 * under one parent): the positions they share, bit for bit, are locked in each, so that no level opens a crack
 * between them either. */
resurf_status resurfi_scene_shared_between_meshes(const resurf_scene *scene, const resurfi_scene_instances *list,
                                                  const resurf_allocator *alloc, uint8_t **locks)
{
    if (list->count < 2)
        return RESURF_OK;
    resurfi_scene_instance *sorted = resurfi_alloc(alloc, list->count, sizeof *sorted);
    size_t *prims = resurfi_alloc(alloc, scene->prim_count + 1, sizeof *prims);
    size_t *owner = resurfi_alloc(alloc, scene->prim_count + 1, sizeof *owner);
    resurf_status st = sorted && prims && owner ? RESURF_OK : RESURF_ERR_OUT_OF_MEMORY;
    if (st == RESURF_OK) {
        memcpy(sorted, list->items, list->count * sizeof *sorted);
        qsort(sorted, list->count, sizeof *sorted, by_world_then_mesh);
    }
    for (size_t a = 0, b; st == RESURF_OK && a < list->count; a = b) {
        /* sorted[a .. b) share one world matrix; their distinct meshes are the owners */
        size_t n = 0, owners = 0;
        for (b = a; b < list->count && !memcmp(world_of(&sorted[a]), world_of(&sorted[b]), 16 * sizeof(double));
             ++b) {
            if (b > a && sorted[b].mesh == sorted[b - 1].mesh)
                continue;
            size_t m = sorted[b].mesh;
            for (size_t p = scene->mesh_first[m]; p < scene->mesh_first[m + 1]; ++p)
                if (scene->prims[p].mesh)
                    prims[n] = p, owner[n] = owners, n++;
            owners++;
        }
        if (owners >= 2)
            st = lock_shared(scene, prims, owner, n, alloc, locks, NULL);
    }
    resurfi_free(alloc, sorted);
    resurfi_free(alloc, prims);
    resurfi_free(alloc, owner);
    return st;
}
