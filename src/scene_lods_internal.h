/* What resurf_scene_build_lods (scene_lods.c) shares with the files it is split into: the shared borders
 * (scene_borders.c), the chains of a mesh whose primitives are simplified together (scene_joint.c) and the world
 * errors of the levels (scene_lod_errors.c). Not installed, not used elsewhere. */
#ifndef RESURF_SCENE_LODS_INTERNAL_H
#define RESURF_SCENE_LODS_INTERNAL_H

#include <pthread.h>
#include <stdatomic.h>

#include "scene_internal.h"

/* A chain's plain half (resurfi_plain_half) kept by the default pass for the plain pass (scene_nearer.c): made over
 * the primitive, or over its mesh's primitives joined (scene_joint.c; kept at the mesh's first primitive). */
typedef struct resurfi_chain_half {
    resurfi_plain_half half;
    bool joined;
} resurfi_chain_half;

/* Everything a call allocates, freed in one place. */
typedef struct resurfi_lod_work {
    const resurf_allocator *alloc;
    resurfi_scene_instances list;
    resurf_mesh *full;            /* level 0 of the whole scene in world space */
    resurf_mesh ***chains;        /* per primitive: `count` levels, or NULL */
    size_t *kept;                 /* per primitive: the levels that help */
    double *mesh_scale;           /* per mesh: the largest scale of its nodes */
    size_t *mesh_levels;          /* per mesh: 1 + the most levels its primitives kept */
    double *errors;               /* per mesh and level: the mesh's own relative world error */
    double **coverage;            /* per mesh */
    uint8_t **locks;              /* per primitive: its vertices shared with other primitives of its mesh, or NULL */
    size_t *unit;                 /* per primitive simplified with others of its mesh as one surface (a unit:
                                     resurfi_scene_find_units), the unit's first primitive (its leader); else
                                     SIZE_MAX */
    size_t *unit_members;         /* the primitives of each unit, in order, the units in their leaders' order */
    size_t *unit_at, *unit_size;  /* per leader: where its members start in unit_members, and how many */
    size_t *joint_kept;           /* per primitive of such a mesh: 1 + the levels of the mesh that help, 0 = not yet */
    int *joint_why;               /* and why the chain ended there (resurfi_levels_that_help); then every primitive's */
    uint8_t *held;                /* per primitive of a unit: its vertices are held still in the unit's runs (a level
                                     left it without triangles; resurfi_make_joint_chain) */
    resurfi_chain_half *halves;   /* per primitive, in the default pass that a plain pass follows, else NULL */
    size_t budget_units;          /* the units the scene budget spent triangles between (0: no budget) */
    /* The plain pass: its levels that are the default's (every primitive shows the same surface with the same report
       there), left unmeasured by resurfi_level_errors and their figures copied by resurfi_keep_nearer_levels. */
    bool twin_levels[RESURF_SCENE_MAX_LEVELS];
} resurfi_lod_work;

/* The primitives of the unit led by `leader` (resurfi_lod_work.unit), *n of them. */
static inline const size_t *resurfi_unit_members(const resurfi_lod_work *w, size_t leader, size_t *n)
{
    *n = w->unit_size[leader];
    return w->unit_members + w->unit_at[leader];
}

/* What every primitive's chain needs, and where it goes (indexed by primitive). */
typedef struct resurfi_chain_job {
    const resurf_scene *scene;
    const double *ratios;
    size_t count;
    const resurf_simplify_options *sim;
    const resurf_scene_lod_options *o;
    resurfi_lod_work *w;
    double diagonal;
    size_t sample_budget;
    double scene_area;
    resurf_simplify_report *reports; /* count per primitive */
    resurf_status *status;
    resurf_error *errors;
    pthread_mutex_t lock;            /* over done and the caller's progress, side by side */
    double done, total;
    double from, span;               /* this pass's share of the caller's progress */
    atomic_int cancelled;
    const size_t *order;             /* side by side: the triangle primitives in the order they are taken */
    resurfi_chain_half *from_halves; /* the plain pass: the default pass's halves, to start the chains from */
} resurfi_chain_job;

/* ---- the chains (scene_lods.c) ---- */

double resurfi_mesh_area(const resurf_mesh *m);
resurf_status resurfi_make_chain(const resurf_mesh *in, const double *ratios, size_t count, const double *bounds,
                                 const resurf_simplify_options *sim, resurf_mesh **chain,
                                 resurf_simplify_report *reports, resurfi_plain_half *keep, resurfi_plain_half *from,
                                 resurf_error *e);
/* Where chain p (a primitive, or a mesh `joined` at its first primitive) keeps its plain half in this pass, or NULL
 * (*st on failure); and the half the plain pass starts it from, or NULL. */
resurfi_plain_half *resurfi_half_to_keep(resurfi_chain_job *job, size_t p, bool joined, resurf_status *st,
                                         resurf_error *e);
resurfi_plain_half *resurfi_half_to_use(resurfi_chain_job *job, size_t p, bool joined);
size_t resurfi_levels_that_help(const resurf_mesh *in, const resurf_simplify_report *rep, const double *ratios,
                                size_t count, int *why);
void resurfi_run_options(const resurfi_chain_job *job, const resurf_simplify_options *base, size_t m, double scale,
                         double area, const uint8_t *lock, resurf_simplify_options *sim, double *bounds);
resurf_status resurfi_make_primitive_chain(resurfi_chain_job *job, size_t p, const resurf_simplify_options *base);

/* ---- the default's levels against the plain pass's (scene_nearer.c) ---- */

/* What the composition reads: the chains as they will be set, the primitives' reports, and their levels' areas. */
typedef struct resurfi_lod_levels_view {
    resurf_mesh *const *const *chains; /* per primitive: its levels, or NULL */
    const size_t *kept;                /* per primitive: the levels that help */
    const resurf_simplify_report *reports;
    const double *areas;
    size_t count;                      /* levels asked for */
} resurfi_lod_levels_view;

/* One pass of a call's levels: its chains, its primitives' reports (count each), its report. */
typedef struct resurfi_lod_pass {
    resurfi_lod_work *w;
    resurf_simplify_report *reports;
    resurf_scene_lod_report *report;
} resurfi_lod_pass;

/* How the levels' world errors are measured (resurfi_level_errors). */
typedef struct resurfi_level_measure {
    size_t samples;
    int threads;
    bool per_mesh;
} resurfi_level_measure;

/* The plain pass's levels (1 .. levels - 1) that are the default's, whose levels are final (`d`): twin[k]. */
void resurfi_find_twin_levels(const resurf_scene *scene, const resurfi_lod_levels_view *plain,
                              const resurfi_lod_levels_view *d, size_t levels, bool *twin);

/* Level by level, the default pass's level where it is at least as near the input as the plain pass's, else the
 * plain one: into *d (what `plain` then holds is the caller's to free). */
resurf_status resurfi_keep_nearer_levels(const resurf_scene *scene, size_t count, const resurfi_level_measure *how,
                                         resurfi_lod_pass *d, resurfi_lod_pass *plain, resurf_error *error);

/* ---- shared borders (scene_borders.c) ---- */

resurf_status resurfi_scene_mesh_groups(const resurf_scene *scene, const resurfi_scene_instances *list,
                                        const resurf_allocator *alloc, size_t *group);
/* Which triangle primitives of one attribute layout shared positions link within a group of meshes: linked[p]
 * becomes the first primitive of p's linked set (p itself when it is linked to none). */
resurf_status resurfi_scene_linked(const resurf_scene *scene, const size_t *group, const resurf_allocator *alloc,
                                   size_t *linked);
/* Within each group of meshes, the positions that primitives of different units (a primitive alone is its own)
 * use, bit for bit: locked in each, so that no level opens a crack between them. */
resurf_status resurfi_scene_lock_between_units(const resurf_scene *scene, const size_t *group, const size_t *unit,
                                               const resurf_allocator *alloc, uint8_t **locks);
/* The positions that prims[0 .. n) use two or more of, bit for bit: locked in each rewritten one (added to
 * locks[p], allocated when NULL), so that no level opens a crack between them. */
resurf_status resurfi_scene_lock_shared(const resurf_scene *scene, const size_t *prims, size_t n,
                                        const resurf_allocator *alloc, uint8_t **locks);
resurf_status resurfi_scene_shared_between_meshes(const resurf_scene *scene, const resurfi_scene_instances *list,
                                                  const resurf_allocator *alloc, uint8_t **locks);

/* ---- a mesh's primitives simplified together (scene_joint.c) ---- */

bool resurfi_scene_simplified_together(const resurf_scene *scene, const size_t *members, size_t n);
resurf_status resurfi_scene_find_units(const resurf_scene *scene, resurfi_lod_work *w);
double resurfi_joint_input(const resurfi_chain_job *job, size_t leader, const resurf_simplify_options *base,
                           resurf_mesh **joined, uint8_t **lock, resurf_simplify_options *sim, double *bounds,
                           resurf_status *st, resurf_error *e);
resurf_status resurfi_make_joint_chain(resurfi_chain_job *job, size_t leader, const resurf_simplify_options *base);

/* ---- the world errors of the levels (scene_lod_errors.c) ---- */

/* Level k's figures in world units over some instances: one-sided maxima and area-weighted means of each side. */
typedef struct resurfi_world_errors {
    double to_full, from_full;      /* the level's surface to level 0's, and level 0's to the level's: maxima */
    double to_sum, to_area;         /* the level's side: sum of mean × area, and the area */
    double from_sum, from_area;     /* level 0's side */
} resurfi_world_errors;

/* An instance and its own bound on one side of a level, for measuring the largest first. */
typedef struct resurfi_bound_item {
    double bound;
    size_t instance;
} resurfi_bound_item;

double resurfi_matrix_scale(const double *a);
int resurfi_add_instance(const resurf_scene *scene, const resurfi_lod_levels_view *v,
                         const resurfi_scene_instance *item, size_t k, resurfi_world_errors *e);
int resurfi_larger_bound_first(const void *a, const void *b);
resurf_status resurfi_side_over_scene(const resurf_scene *scene, const resurfi_scene_instances *list, size_t shown,
                                      const resurfi_scene_levels *levels, const resurfi_bound_item *order,
                                      double density, uint64_t seed, int facet_points, const resurf_mesh *to,
                                      unsigned threads, const resurf_allocator *alloc, double *out_max,
                                      resurf_error *error);
resurf_status resurfi_measure_level(const resurf_scene *scene, const resurfi_scene_instances *list,
                                    const resurf_mesh *full, size_t level, const resurfi_scene_levels *levels,
                                    const resurf_compare_options *co, resurf_compare_report *out,
                                    resurf_error *error);
/* The world errors of the levels as the chains stand (w->chains, w->kept, reports: count per primitive; levels up to
 * report->levels): the whole scene's into report->level_* and, with per_mesh, each mesh's own into w->errors (as its
 * first node shows it), `samples` a side. */
resurf_status resurfi_level_errors(const resurf_scene *scene, resurfi_lod_work *w,
                                   const resurf_simplify_report *reports, size_t count, size_t samples,
                                   int threads_option, bool per_mesh, resurf_scene_lod_report *report,
                                   resurf_error *error);

#endif
