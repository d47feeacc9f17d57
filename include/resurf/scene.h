/*
 * resurf — scenes: glTF documents, their levels of detail, saving.
 *
 * Part of the manual that include/resurf/resurf.h begins (its conventions hold here); resurf.h includes this
 * header, so `#include <resurf/resurf.h>` is all a caller needs.
 */
#ifndef RESURF_RESURF_H
#include "resurf.h" /* which includes this header at its end, in the manual's order */
#elif !defined(RESURF_SCENE_H)
#define RESURF_SCENE_H

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------------------------------------------- */
/* Scenes (glTF)                                                                                                 */
/* ------------------------------------------------------------------------------------------------------------- */

/* A resurf_scene is a whole glTF 2.0 document (.gltf, .glb), a raw Draco mesh (.drc) or a mesh file (OBJ, PLY, OFF,
 * STL: a scene of one mesh). Its triangle primitives are decoded into resurf_meshes that the caller reads,
 * simplifies and hands back as levels of detail; everything else (node hierarchy, transforms, materials, textures,
 * images, samplers, skins, animations, morph targets, cameras, extras, extensions) is kept and written again.
 * A mesh instanced by several nodes is one set of primitives: it is decoded, simplified and written once.
 * A scene is used by one thread at a time; different scenes are independent.
 *
 * Attributes: POSITION → positions, NORMAL → normals, TEXCOORD_0..3 → texcoords, COLOR_0 → colors; every other
 * attribute (TANGENT, JOINTS_n, WEIGHTS_n, COLOR_n with n > 0, TEXCOORD_n with n > 3, _CUSTOM) becomes an extra
 * named exactly like the glTF attribute, carried untouched and written back in its original component type, so
 * joints stay integers. Each morph target attribute becomes a float extra "targets[t].NAME" (see
 * RESURF_MORPH_TARGET_PREFIX below). A JOINTS_n / WEIGHTS_n pair (VEC4 both, the same n) is a skin's influences: a
 * simplified level combines them as influences, never as numbers (the corners' (joint, barycentric × weight) over
 * all sets, equal joints merged, the strongest 4 per set, renormalized), and the writer stores weights that sum to
 * exactly 1 in their component type, with joint 0 in unused slots (see resurf_scene_save_options.generic_bits for
 * Draco). Integer and normalized component types are decoded as glTF defines them (a normalized ubyte 255 is 1.0),
 * sparse accessors are applied, triangle strips and fans become lists (the joining triangles that repeat an index
 * are dropped), KHR_draco_mesh_compression, KHR_mesh_quantization, EXT_meshopt_compression and
 * KHR_meshopt_compression inputs are decoded (the last two from their fallback buffers when the document does not
 * require them), EXT_mesh_gpu_instancing is read.
 * The JSON is checked against the glTF 2.0 schema first (github.com/KhronosGroup/glTF, specification/2.0/schema):
 * the JSON type of every property of the core objects, required properties, array lengths and unique items, enum
 * values (componentType, accessor type, primitive mode, bufferView target, sampler filters and wraps, camera type,
 * animated path, interpolation, alphaMode: the values the specification lists, plus "pointer" when the document
 * uses KHR_animation_pointer) and numeric ranges (byteLength and count >= 1, byteStride a multiple of 4 in 4..252,
 * indices >= 0, factors in 0..1, ...). Unknown properties, extras and the content of extensions (each an object)
 * are free. The first problem fails with RESURF_ERR_PARSE and a message naming the JSON path and the cause
 * ("meshes[0].primitives[0].mode: 9 is not a glTF primitive mode (0..6)"); with resurf_load_options.lenient each
 * problem is a warning of the scene instead (the first 100, then one that counts the rest) and the document is
 * read as tinygltf reads it (a property of the wrong type is ignored), the checks below still applying. A number
 * such as 2.0 where the schema wants an integer is read as that integer.
 * Every index, accessor, buffer range, node graph and Draco reference is checked before it is used: a malformed
 * or hostile file fails with RESURF_ERR_PARSE and a one-line message naming the glTF object ("accessors[3]: ...").
 * JSON nested deeper than 128 levels, numbers that overflow to infinity and node graphs with cycles or nodes with
 * two parents are refused; so is a document that requires an extension resurf does not know.
 * Draco payloads: their header's counts are checked against the payload size before decoding (more than 2^20 + 256
 * faces or points per payload byte is RESURF_ERR_LIMIT); edgebreaker meshes that carry Draco metadata, whose counts
 * cannot be located ahead, and Draco point clouds are refused (a glTF points primitive with Draco is copied
 * undecoded). Known limit of the Draco library itself (Debian's 1.5.5): a corrupt texture-coordinate count inside a
 * payload can cost it seconds and some hundred MB before it fails cleanly.
 *
 * Images: external image files are read when the scene loads, their uri resolved relative to the document's
 * folder (percent-encoding, "./", ".." and Windows '\' separators understood); one that cannot be read fails the
 * load with RESURF_ERR_IO naming images[i], the path tried and the uri, and one that names no file of the folder
 * (a scheme such as http:, a drive letter, an encoded NUL, or any file of a document loaded from memory) with
 * RESURF_ERR_UNSUPPORTED (either is a warning with resurf_load_options.allow_missing_images). Outputs are whole
 * by themselves: see resurf_scene_save(). */

typedef struct resurf_scene resurf_scene;

/* Loads a scene: .gltf, .glb and .drc by extension (or, failing that, content); anything else goes through
 * resurf_mesh_load() into a one-mesh scene. options: max_triangles counts the triangles of all primitives; format
 * forces a mesh format (AUTO = by name); NULL = defaults. External .bin files are read relative to the .gltf file.
 * On success *out_scene owns everything; free it with resurf_scene_free(). */
RESURF_API resurf_status resurf_scene_load(const char *path, const resurf_load_options *options,
                                           resurf_scene **out_scene, resurf_error *error);

/* What resurf_scene_load_memory() reads. */
typedef enum resurf_scene_format {
    RESURF_SCENE_FORMAT_AUTO = 0, /* by content: "glTF" → GLB, "DRACO" → DRC, '{' → GLTF, else MESH; a mesh format
                                     in options->format means MESH */
    RESURF_SCENE_FORMAT_GLTF,     /* glTF JSON */
    RESURF_SCENE_FORMAT_GLB,      /* binary glTF */
    RESURF_SCENE_FORMAT_DRC,      /* raw Draco */
    RESURF_SCENE_FORMAT_MESH,     /* OBJ, PLY, OFF or STL as resurf_mesh_load_memory() reads it (options->format, else
                                     by content): a one-mesh scene */
    RESURF_SCENE_FORMAT_COUNT
} resurf_scene_format;

/* Loads a scene from size bytes at data, checked as resurf_scene_load() checks a file. No file is read: a glTF
 * buffer whose uri is not a data: URI fails with RESURF_ERR_PARSE and a message naming it ("buffers[0]: the uri
 * 'a.bin' names an external file ..."); external images are referenced as by resurf_scene_load() (a warning).
 * Messages name no file. data is not kept: the caller may free it when the call returns. */
RESURF_API resurf_status resurf_scene_load_memory(const void *data, size_t size, resurf_scene_format format,
                                                  const resurf_load_options *options, resurf_scene **out_scene,
                                                  resurf_error *error);

/* A one-mesh scene holding a copy of mesh (one node, one mesh, one triangle primitive, no material). */
RESURF_API resurf_status resurf_scene_from_mesh(const resurf_mesh *mesh, resurf_scene **out_scene,
                                                resurf_error *error);

/* Frees a scene and everything it owns (its meshes, levels and document). NULL is allowed. */
RESURF_API void resurf_scene_free(resurf_scene *scene);

/* Morph targets. A primitive's targets are extras of its mesh, one per target attribute, named
 * "targets[t].NAME" (t from 0, NAME the glTF attribute: "targets[0].POSITION", "targets[1].NORMAL"), in float,
 * each a delta per vertex. Being extras, they follow the vertices through every call: resurf_simplify interpolates
 * them at each output vertex's closest point of the input like any extra (at a restored vertex: the input's delta
 * at the closest point of its surface, so the level's morph at any weight is the input's morph sampled where the
 * level's vertex lies; docs/restoring.md §12), and prices the position deltas in the collapse cost
 * (resurf_simplify_options.morph_weight). resurf_scene_save writes them back as the primitive's targets (float
 * accessors; POSITION with min/max), beside Draco-compressed base attributes when Draco is on (Draco's sequential
 * encoding without merging points, so that the decoded vertex order is the order of the targets' accessors, as
 * KHR_draco_mesh_compression requires; checked by decoding). A mesh saved as OBJ/PLY keeps them as extras. */
#define RESURF_MORPH_TARGET_PREFIX "targets["

typedef enum resurf_primitive_kind {
    RESURF_PRIMITIVE_TRIANGLES = 0, /* triangle list, strip or fan: has a mesh and can take levels of detail */
    RESURF_PRIMITIVE_MORPHED,       /* triangles with morph targets: has a mesh whose extras carry the targets (see
                                       RESURF_MORPH_TARGET_PREFIX) and takes levels of detail like TRIANGLES; each
                                       level is written with its own targets, the mesh's weights and animations
                                       kept. (Before 0.3.0 it stayed at full detail.) A mesh-file scene whose mesh
                                       has such extras is MORPHED too */
    RESURF_PRIMITIVE_OTHER,         /* points or lines: no mesh, written untouched */
} resurf_primitive_kind;

/* What resurf_scene_primitive_info() tells about one primitive. */
typedef struct resurf_scene_primitive {
    size_t mesh;              /* the glTF mesh index (0 in a mesh-file scene) */
    size_t primitive;         /* the primitive's index in that mesh */
    char name[64];            /* "meshes[2].primitives[0]", for messages and tables */
    char mesh_name[64];       /* the glTF mesh's name (shortened to fit), or "" */
    int mode;                 /* glTF mode as in the file: 0 points, 1 lines, 2 loop, 3 strip, 4 triangles, 5 strip, 6 fan */
    resurf_primitive_kind kind;
    bool draco;               /* the input was Draco-compressed */
    size_t instances;         /* nodes that show its mesh, each EXT_mesh_gpu_instancing instance counted (several:
                                 the mesh is still handled once) */
    size_t lod_count;         /* levels of detail set with resurf_scene_set_lods() */
} resurf_scene_primitive;

/* Number of glTF meshes (1 for a mesh-file scene) and of primitives over all meshes, in file order. */
RESURF_API size_t resurf_scene_mesh_count(const resurf_scene *scene);
RESURF_API size_t resurf_scene_primitive_count(const resurf_scene *scene);

/* Describes primitive `index` (0 .. resurf_scene_primitive_count() - 1). */
RESURF_API resurf_status resurf_scene_primitive_info(const resurf_scene *scene, size_t index,
                                                     resurf_scene_primitive *out, resurf_error *error);

/* The decoded mesh of primitive `index` (attributes as described above), or NULL for a RESURF_PRIMITIVE_OTHER
 * primitive or an index out of range. Borrowed: valid until the scene is freed; do not modify it. */
RESURF_API const resurf_mesh *resurf_scene_primitive_mesh(const resurf_scene *scene, size_t index);

/* The whole scene at `level` as one mesh in world space: every triangle primitive with a mesh (morphed ones in
 * their rest pose, weights 0) at that level (0 = full detail; a primitive with fewer levels uses its last), once
 * for each node that shows its mesh (once per instance of its EXT_mesh_gpu_instancing, at the node's world matrix
 * times the instance's T · R · S), with the node's world matrix applied (through the node hierarchy of the
 * default scene, else scene 0, else of every root node; a scene made from a mesh file or without nodes: each mesh
 * once, untransformed). Normals go through the matrix's inverse transpose and are renormalised. A node whose
 * MSFT_lod extension (in a loaded file) names level nodes shows their meshes at level 1, 2, ... (as
 * resurf_preview_render() draws them). The mesh has normals and TEXCOORD_0 when every included primitive has them,
 * no other attribute; vertices are not welded (each primitive instance keeps its own). level: 0 ..
 * RESURF_SCENE_MAX_LEVELS - 1. alloc: NULL = the scene's. *out is freed with resurf_mesh_free(). RESURF_ERR_LIMIT
 * above 2^32 vertices or triangles. */
RESURF_API resurf_status resurf_scene_world_mesh(const resurf_scene *scene, int level, const resurf_allocator *alloc,
                                                 resurf_mesh **out, resurf_error *error);

/* Sets the levels of detail of primitive `index`: lods[0] is level 1 (the first reduced level), lods[k-1] level k.
 * The meshes are copied (the caller keeps its own). Each must have finite positions and indices in range, and
 * carry the attributes the primitive's mesh has, by name (extras the source lacks are written as float custom
 * attributes "_NAME"). lod_count 0 removes the levels; at most RESURF_SCENE_MAX_LEVELS - 1.
 * A morphed primitive's levels carry its target extras like any other (RESURF_MORPH_TARGET_PREFIX), numbered from
 * 0 without a gap. Fails with RESURF_ERR_UNSUPPORTED for a point/line primitive (it stays as it is),
 * RESURF_ERR_INVALID_MESH for a bad level (the message says which). On failure the previous levels stay. */
#define RESURF_SCENE_MAX_LEVELS 16
RESURF_API resurf_status resurf_scene_set_lods(resurf_scene *scene, size_t index, const resurf_mesh *const *lods,
                                               size_t lod_count, resurf_error *error);

/* MSFT_lod screen coverage of glTF mesh `mesh` (extras.MSFT_screencoverage): coverage[k] is the smallest share of
 * the screen at which level k is shown (k = 0 full detail); below the last value nothing is drawn. count must be
 * the mesh's level count (1 + the most levels of detail of any of its primitives) when the scene is saved, which
 * is one more value than MSFT_lod's ids. Values in [0, 1], non-increasing. Unset: 0.5, 0.25, ... halving per
 * level, and 0 for the coarsest level (never culled). */
RESURF_API resurf_status resurf_scene_set_screen_coverage(resurf_scene *scene, size_t mesh, const double *coverage,
                                                          size_t count, resurf_error *error);

/* How resurf_scene_build_lods() works besides the simplification itself. */
typedef struct resurf_scene_lod_options {
    size_t struct_size;
    bool set_screen_coverage; /* true (default): set each mesh's MSFT_screencoverage from the measured errors (see
                                 below); false: leave the coverage as it is (values whose count no longer matches
                                 the mesh's levels are removed: the defaults are written) */
    double pixels;            /* a level is shown once its error covers at most this many pixels; > 0, default 1 */
    double screen_height;     /* ... on a screen this many pixels high; > 0, default 1080 */
    const double *level_max_error_rel; /* NULL (default), or `count` values >= 0: level k + 1 also stops where a
                                 collapse's estimated error (resurf_simplify_options.max_error) would exceed
                                 level_max_error_rel[k] × the whole scene's world bounding-box diagonal, in world
                                 units (converted to each mesh's units by the largest scale of its nodes'
                                 matrices); 0 = no error bound for that level */
    const double *level_max_error; /* the same in world units; NULL (default) or `count` values >= 0. With both,
                                 the smaller bound of a level counts */
    bool keep_shared_borders; /* true (default): no level opens a crack between the primitives of one mesh, or of
                                 meshes side by side. Each set of a mesh's triangle primitives of one attribute
                                 layout that shared positions link (a unit; ones that share nothing cannot crack
                                 and keep their own ratios, so a mesh may hold several units and primitives alone)
                                 is simplified together as one surface, each primitive a triangle group whose
                                 border is a crease
                                 that slides along itself (resurf_simplify_options.feature_angle_deg), and each
                                 level is split back into them: each primitive's report then has its own
                                 triangles and vertices and the unit's distances and stop, and one level that does
                                 not help, or that leaves one of them without triangles (level_emptied), ends the
                                 chain of all of them. A position that primitives of different units use (bit for
                                 bit: a morphed primitive's, another layout's) is locked in each of them
                                 (resurf_simplify_options.vertex_lock), as are a unit's shared positions when its
                                 first level leaves a primitive empty. Meshes shown by nodes of one world matrix
                                 (an exporter's parts of one object side by side) lock the positions they share
                                 with each other.
                                 tools/bench-borders measured both on the dragon-48k cut into 4 parts, at equal
                                 triangles: together is 1.00x locked's Hausdorff and 0.90x its mean at 10%, 0.21x
                                 and 0.24x at 2%, where locked stops at twice its target; on real assets the
                                 scene's Hausdorff is 1.09x / 1.00x locked's at 25% / 10% (2CylinderEngine) and
                                 1.14x / 0.65x (an assimp export of HUMAN.blend): the joined cost moves triangles
                                 between the primitives. false: each primitive is simplified alone */
    resurf_progress progress; /* the stages of resurf_simplify (RESURF_STAGE_PREPARE, _SIMPLIFY, _FINISH) with a
                                 fraction of the whole scene's work that never decreases (primitives weighted by
                                 their triangles) and ends at 1; a cancel returns RESURF_ERR_CANCELLED and leaves
                                 the scene as it was */
    bool share_triangles;     /* true (default): with ratios, the scene's triangles go where the error is: per
                                 level, the primitive of the largest measured world error is made again with more
                                 triangles (down to the next largest error), taken back from the largest others
                                 whose error stays under that, within the level's ratio of the scene's triangles
                                 (or its count before, when that is more); see docs/reference.md. false: every
                                 primitive keeps its own ratio */
} resurf_scene_lod_options;

RESURF_API resurf_scene_lod_options resurf_scene_lod_options_default(void);

/* What resurf_scene_build_lods() made. Levels count from 0 (full detail) to `levels` - 1. */
typedef struct resurf_scene_lod_report {
    size_t levels;                                    /* 1 + the most levels any primitive kept (at most 1 + count:
                                                         levels that do not help are not kept, see below) */
    size_t primitives;                                /* triangle primitives that were simplified (morphed ones
                                                         included) */
    size_t morphed;                                   /* of those, primitives with morph targets (before 0.3.0
                                                         they were kept at full detail) */
    size_t other;                                     /* point and line primitives, kept as they are */
    size_t level_triangles[RESURF_SCENE_MAX_LEVELS];  /* triangles of each level over every primitive with a mesh
                                                         (a primitive with fewer levels at its last; each mesh
                                                         once, whatever its instances): what resurf_scene_save()
                                                         reports */
    /* Measured in world space (resurf_scene_world_mesh(): every instance, node transforms applied) between the
     * level and level 0, each side's points (resurf_compare()'s: area-uniform samples, measure_samples over the
     * whole surface, and the vertices; on the level's side also its facet points, as in resurf_simplify_report)
     * measured to the whole other surface: 0 for level 0 and when nothing was
     * measured (measure_samples 0). When every instance's transform is a similarity (rotation, uniform scale,
     * translation), each instance's own bound, its primitives' reports scaled to world units, decides which
     * instances are measured: largest first, until the next bound is no more than the largest distance found (no
     * other instance can raise the maximum, as a point's distance to the whole scene is at most its distance to its
     * own primitive); the mean is then the area-weighted mean of the primitives' own two-sided means (an upper
     * bound of the scene's). Otherwise resurf_compare() between the two world meshes gives all five figures. */
    double level_error_rel[RESURF_SCENE_MAX_LEVELS];  /* two-sided Hausdorff distance over `diagonal` */
    double level_error[RESURF_SCENE_MAX_LEVELS];      /* the same in world units */
    double level_mean_rel[RESURF_SCENE_MAX_LEVELS];   /* two-sided mean distance over `diagonal` */
    double level_to_full_rel[RESURF_SCENE_MAX_LEVELS];   /* one-sided max: the level's surface to level 0's */
    double level_from_full_rel[RESURF_SCENE_MAX_LEVELS]; /* one-sided max: level 0's surface to the level's (what
                                                         the level lost) */
    double diagonal;                                  /* of the whole scene's world bounding box at level 0 */
    size_t level_unreduced[RESURF_SCENE_MAX_LEVELS];  /* primitives whose chain ended at this level because it
                                                         had no fewer triangles than the one before */
    size_t level_missed[RESURF_SCENE_MAX_LEVELS];     /* primitives whose chain ended at this level because it
                                                         missed its ratio (see resurf_scene_build_lods) */
    size_t level_emptied[RESURF_SCENE_MAX_LEVELS];    /* primitives whose chain ended at this level because their
                                                         mesh's level (its primitives simplified together) left
                                                         one of them without triangles */
    bool level_plain[RESURF_SCENE_MAX_LEVELS];        /* with RESURF_RESTORE_MEASURED: this level is the one
                                                         restore none makes, which lay nearer the input in the
                                                         two-sided maximum or the mean (see below) */
    double chains_seconds;                            /* wall-clock time spent making the primitives' chains */
    double errors_seconds;                            /* ... measuring the world errors (scene and each mesh) */
} resurf_scene_lod_report;

/* Builds levels of detail for every triangle primitive of the scene in one call: each primitive's chain comes from
 * resurf_simplify_lods() (ratios, count and simplify as documented there: level k has at most ratios[k-1] × the
 * primitive's triangles and lies on the smooth surface of the ORIGINAL primitive) and is set as with
 * resurf_scene_set_lods(), replacing levels set before. With per-level error bounds (options->level_max_error_rel,
 * level_max_error) that differ between levels, or without ratios, each level is simplified from the ORIGINAL by
 * its own resurf_simplify() call instead. Primitives with morph targets get levels like the others, their targets
 * carried through (RESURF_MORPH_TARGET_PREFIX); point and line primitives keep full detail (counted in the
 * report).
 * Levels that help: a primitive's chain ends before the first level that has no fewer triangles than the level
 * before it (a level where nothing could be collapsed is never kept as a moved copy; level_unreduced), or that
 * missed its ratio by more than the slack, with more than 1.5 × ratio × the primitive's triangles + 2 (level_missed;
 * a level stopped by its error bound, RESURF_STOP_ERROR, has reached its target), or, for a mesh whose primitives
 * are simplified together, that left one of them without triangles (level_emptied; when that is the first level,
 * the mesh's primitives are simplified apart instead, their shared positions locked). A primitive with fewer levels
 * shows its last one in the levels above; a mesh has 1 + the most levels of its primitives, so MSFT_lod's ids are
 * shorter where levels did not help, and a mesh none of whose primitives could be reduced gets none.
 * Errors: the report's are measured in world space over the whole scene (see resurf_scene_lod_report); each
 * primitive's own, in its own units against its own diagonal, are in out_primitive_reports.
 * With options->set_screen_coverage, each mesh that has levels gets its MSFT_screencoverage from its own measured
 * errors in world space: e_k is the two-sided Hausdorff distance between the mesh's level k and its level 0 as its
 * first node shows them (world transform applied), over that mesh's own world bounding-box diagonal (when that
 * node's transform is a similarity, the largest of its primitives' own two-sided maxima scaled to world units, an
 * upper bound of the mesh's; else measured with resurf_compare()). A level of
 * relative error e on an object whose bounding-box diagonal spans d pixels is off by e·d pixels; with d ≈ √c·H for
 * a screen share c on a screen H pixels high, level k is good enough below c_k = (pixels / (e_k·H))², clamped to 1
 * and made non-increasing; coverage[k-1] = c_k is where level k-1 hands over to level k, and the coarsest level is
 * never culled (0). An unmeasured error counts as 0, so c_k = 1. (Before 0.3.0 e_k was the largest error of the
 * mesh's primitives each against its own diagonal: a mesh of many small primitives reported several times its
 * true error, 14% against 3.1% measured on 2CylinderEngine.)
 * The default restoring, RESURF_RESTORE_MEASURED, makes each primitive's level the nearer of its restored and plain
 * ones by the primitive's own measure; the scene as a whole could still end farther from its input than the scene
 * RESURF_RESTORE_NONE makes (the budget spends triangles by errors that differ between the modes, and the world
 * measure sees more than a primitive's own). So, with measure_samples, the levels are also made as RESTORE_NONE makes
 * them, on a thread of their own beside the budget (the plain halves of the chains made already are reused: the
 * budget's runs are the new work), and each scene level is the default's only where it is as near the input as the
 * plain one in both the two-sided maximum and the mean, or nearer by more than the sampling's noise (5% in the
 * maximum, 1% in the mean); else the plain level (level_plain[k]). A primitive whose levels from the two would not
 * form a chain takes its plain level in place of the default's before the break, and the levels are then measured
 * again; where one is still farther than the plain one, the plain levels are taken whole. The plain pass is skipped
 * where it cannot change a level: with no budget between units (whose runs come after), every kept level is the
 * plain one, or every restored level is over 10% nearer than its plain one by the primitive's own measure.
 * - scene: modified only when the call succeeds; on error or cancel it is exactly as it was.
 * - simplify: NULL = resurf_simplify_options_default(); target_triangles and target_ratio are ignored, its
 *   progress and vertex_lock are not used (options->progress and keep_shared_borders are); its max_error / max_error_rel, in each primitive's own units,
 *   apply to every level beside options' bounds; measure_samples is the budget of the whole scene: each
 *   primitive's own report measures its share of it, by world area (at least 250 samples, at most the budget),
 *   and it is also the world measurement's sample count.
 * - ratios: count values in (0, 1], non-increasing; or NULL when every level has an error bound (a chain by
 *   errors alone: each level as far as its bound allows); 1 <= count <= RESURF_SCENE_MAX_LEVELS - 1.
 * - options: NULL = resurf_scene_lod_options_default().
 * - out_report: may be NULL.
 * - out_primitive_reports: NULL, or room for resurf_scene_primitive_count(scene) × count reports:
 *   [p × count + k] is level k + 1 of primitive p as it was made (zeroed for primitives that got no levels and
 *   after the level that ended its chain; that level's report is kept: its stop and blocked_* say why it missed,
 *   and its distances are NaN, since a level that ends the chain is neither built nor measured).
 * Errors name the primitive ("meshes[1].primitives[0]: ..."; with several failures, the first in primitive
 * order). With at least 2 × simplify->threads triangle primitives (0 = all cores, at least 2), none of which holds
 * more than half the triangles, and no thread_pool, the primitives are simplified side by side, each on one
 * thread, and options->progress is then called from those threads (one call at a time) after each primitive;
 * else one after the other, each with simplify->threads worker threads. The result is the same either way, for
 * every thread count. */
RESURF_API resurf_status resurf_scene_build_lods(resurf_scene *scene, const double *ratios, size_t count,
                                                 const resurf_simplify_options *simplify,
                                                 const resurf_scene_lod_options *options,
                                                 resurf_scene_lod_report *out_report,
                                                 resurf_simplify_report *out_primitive_reports, resurf_error *error);

/* How resurf_scene_save() writes the levels of detail (when any primitive has some). */
typedef enum resurf_lod_layout {
    RESURF_LOD_MSFT_LOD = 0,  /* one file: each node showing a mesh with levels gets the MSFT_lod extension, whose
                                 `ids` name new level nodes that are in no scene's node list, and
                                 extras.MSFT_screencoverage (one more value than ids). A node that has children or
                                 an animated transform gets a new child node that carries its mesh instead */
    RESURF_LOD_FILES,         /* one complete file per level, named by resurf_scene_level_path() (NAME_lod0 also
                                 when the scene has no levels) */
    RESURF_LOD_SIDE_BY_SIDE,  /* one file: every level as visible copies of each scene's nodes, level k moved by
                                 k × (scene width × (1 + spacing_rel)) along +x; for looking at in any viewer */
    RESURF_LOD_LAYOUT_COUNT
} resurf_lod_layout;

typedef struct resurf_scene_save_options {
    size_t struct_size;
    bool draco;                /* true: KHR_draco_mesh_compression on every triangle primitive (a morphed one's
                                  payload keeps its vertex order, its targets beside it uncompressed); default
                                  false. A .drc file is always Draco (a morphed mesh's targets are not in it) */
    int position_bits, normal_bits, texcoord_bits, color_bits; /* Draco quantization bits, 1..30; defaults 14, 10,
                                                                   12, 8 */
    int generic_bits;          /* other float attributes (TANGENT, custom): default 12; integer attributes
                                  (JOINTS_n) are stored exactly. Float WEIGHTS_n are written as normalized unsigned
                                  shorts when this is > 0 (Draco keeps integers exactly; quantized floats would not
                                  sum to 1), as floats when it is 0 */
    int compression_level;     /* Draco: 0 fastest .. 10 smallest; default 7 */
    unsigned threads;          /* Draco: payloads encoded side by side on this many threads, 0 (default) = all
                                  cores; the file is the same for any count */
    bool embed_buffers;        /* .gltf: true puts the binary data in a data: URI; default false writes NAME.bin
                                  beside it */
    resurf_lod_layout layout;  /* default RESURF_LOD_MSFT_LOD */
    double spacing_rel;        /* RESURF_LOD_SIDE_BY_SIDE: the gap between levels as a fraction of the scene's width
                                  along x; >= 0; default 0.25 */
    int level;                 /* -1 (default): all levels as `layout` says; k >= 0: level k alone as a plain scene
                                  (0 = full detail; a primitive with fewer levels uses its last one) */
    resurf_progress progress;
    const resurf_allocator *allocator; /* NULL (default): the input mesh's (or the C heap); see resurf_allocator */
} resurf_scene_save_options;

RESURF_API resurf_scene_save_options resurf_scene_save_options_default(void);

/* What resurf_scene_save() wrote. Levels are counted over all primitives (each mesh once, whatever its instances). */
typedef struct resurf_scene_save_report {
    size_t levels;                                   /* 1 + the most levels of detail any primitive has */
    size_t level_triangles[RESURF_SCENE_MAX_LEVELS]; /* triangles of each level (point/line primitives excluded) */
    size_t level_bytes[RESURF_SCENE_MAX_LEVELS];     /* geometry bytes of each level: the Draco payloads, or the
                                                        index and vertex data, of its triangle primitives (morph
                                                        targets' data included; point and line primitives, copied
                                                        untouched, not counted) */
    size_t files;                                    /* files written, .bin files and image copies included */
    size_t total_bytes;                              /* their total size */
    size_t dropped_extensions;                       /* primitive extensions left off rewritten triangle
                                                        primitives (FB_ngon_encoding, unknown ones; counted per
                                                        primitive; the load warnings name them) */
} resurf_scene_save_report;

/* Writes the scene by path's extension: .gltf (JSON; NAME.bin beside it unless embed_buffers), .glb (binary) or
 * .drc (raw Draco of the one triangle primitive the scene must have; with levels, use level or the FILES layout).
 * Triangle primitives are written from their meshes (float positions, normals, texcoords and colors; extras in
 * their original types), everything else from the loaded document. Every Draco payload is decoded again and
 * checked against what was meant (counts, attributes, positions within the quantization step) before it is
 * written; its accessors carry the decoded count and POSITION min/max. Each file goes to a temporary file in its
 * folder and is renamed into place only when every file of the call is complete: a failure leaves no new file and
 * no partial file. out_report may be NULL.
 * Images: a .glb (and a .gltf with embed_buffers) holds every image in a bufferView, with the mimeType its bytes
 * show; a .gltf otherwise gets a copy of each external image beside itself under its relative name (one that was
 * outside the input's folder under its file name: nothing is written outside the output's folder). Extensions of
 * triangle primitives that may describe the source's triangulation or vertex order (FB_ngon_encoding, unknown
 * ones) are left off the rewritten primitives (report.dropped_extensions); KHR_materials_variants stays. A node's
 * EXT_mesh_gpu_instancing goes wherever its mesh goes (its level nodes, a child holding its mesh). Source
 * accessors, bufferViews and buffers that nothing written refers to are not copied (all are kept, at their
 * indices, when an unknown extension elsewhere may refer to them). */
RESURF_API resurf_status resurf_scene_save(const resurf_scene *scene, const char *path,
                                           const resurf_scene_save_options *options,
                                           resurf_scene_save_report *out_report, resurf_error *error);

/* The file name RESURF_LOD_FILES gives to `level` of `path`: "dir/name.glb" → "dir/name_lod0.glb",
 * "dir/name_lod1.glb", ... (level 0 is full detail). Writes into dst (always NUL-terminated when dst_size > 0) and
 * returns the length the full name needs, like snprintf. */
RESURF_API size_t resurf_scene_level_path(char *dst, size_t dst_size, const char *path, unsigned level);

/* A description of the scene, as text lines for people (as_json 0) or as one JSON object: its scenes, nodes (mesh,
 * the instances of its EXT_mesh_gpu_instancing, skin, camera, children, extensions), meshes and their primitives
 * (triangles and vertices as decoded, mode, material, attribute names, morph targets and their attributes, Draco,
 * extensions), materials (textures, extensions), textures, images (uri, bufferView or embedded; mimeType; bytes;
 * missing), skins, animations (channels, samplers, animated paths), cameras and the extensions used and required
 * (as the file gives them: EXT_ and KHR_meshopt_compression too, which the load decodes). A scene made from a mesh
 * (a .drc, a mesh file) is one mesh with one primitive. Written into dst like snprintf (NUL-terminated when
 * dst_size > 0; dst may be NULL with dst_size 0); *out_length gets the length of the whole description. */
RESURF_API resurf_status resurf_scene_describe(const resurf_scene *scene, bool as_json, char *dst, size_t dst_size,
                                               size_t *out_length, resurf_error *error);

/* Problems that did not stop the load (a missing image allowed by allow_missing_images, a schema problem allowed by
 * lenient, primitive extensions that saving drops, a tinygltf warning), one line each. resurf_scene_warning
 * returns NULL for an index out of range; the strings live as long as the scene. */
RESURF_API size_t resurf_scene_warning_count(const resurf_scene *scene);
RESURF_API const char *resurf_scene_warning(const resurf_scene *scene, size_t index);

#ifdef __cplusplus
}
#endif

#endif /* RESURF_SCENE_H */
