/* What scene.c (loading, checking, decoding, the public scene calls) shares with scene_save.c (writing). Not
 * installed, not used elsewhere. */
#ifndef RESURF_SCENE_INTERNAL_H
#define RESURF_SCENE_INTERNAL_H

#include "internal.h"
#include "io/gltf_shim.h"

/* The component type an attribute had in the source, so that extras (JOINTS_n as bytes, WEIGHTS_n normalized
 * shorts, ...) are written back as they came. */
typedef struct resurfi_scene_format {
    char name[64];
    int component_type;     /* RESURFI_GLTF_* */
    int normalized;
    int components;
} resurfi_scene_format;

typedef struct resurfi_scene_prim {
    resurf_scene_primitive info;
    resurf_mesh *mesh;      /* decoded; NULL for RESURF_PRIMITIVE_OTHER */
    size_t format_count;
    resurfi_scene_format *formats;
    size_t lod_count;
    resurf_mesh **lods;     /* lods[k - 1] is level k */
} resurfi_scene_prim;

struct resurf_scene {
    resurfi_gltf_doc *doc;  /* the loaded document, or NULL for a scene made from a mesh */
    const resurfi_gltf_view *view;
    size_t mesh_count;
    size_t *mesh_first;     /* mesh_count + 1: the primitives of mesh m are prims[mesh_first[m] .. mesh_first[m+1]) */
    double **coverage;      /* per mesh, NULL when unset */
    size_t *coverage_count;
    size_t prim_count;
    resurfi_scene_prim *prims;
    double (*world)[16];    /* per node: its world matrix (column-major) in the scene that first reaches it */
    int quantized;          /* the source declared KHR_mesh_quantization */
    int unknown_extensions; /* the source uses an extension that may refer to accessors or bufferViews */
    size_t warning_count;
    char **warnings;
    resurf_allocator alloc; /* the scene's C blocks and meshes come from it (all zero: the C heap); the document
                               (doc, view) lives on the C++ heap */
};

/* The effective mesh of primitive p at level k (its last level when it has fewer). */
static inline const resurf_mesh *resurfi_scene_level_mesh(const resurfi_scene_prim *p, size_t level)
{
    if (level == 0 || p->lod_count == 0)
        return p->mesh;
    return p->lods[(level < p->lod_count ? level : p->lod_count) - 1];
}

/* Does s end with suffix (given in lower case), ignoring ASCII case? */
int resurfi_ends_with_nocase(const char *s, const char *suffix);

/* Bytes of one component of a glTF component type, 0 for an unknown type. */
size_t resurfi_gltf_component_size(int component_type);

#endif
