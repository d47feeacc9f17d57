/* What the two halves of a scene save share (scene_save.c: the options, the document's plan and the files;
 * scene_pack.c: each primitive at each level packed into accessors or a checked Draco payload): the save
 * context, an arena of allocations freed together, with the plan's growing arrays. */
#ifndef RESURF_SCENE_SAVE_INTERNAL_H
#define RESURF_SCENE_SAVE_INTERNAL_H

#include "scene_internal.h"

/* One primitive at one level, packed (cached: a level shown by several output meshes is packed once). */
typedef struct packed {
    int done, empty;
    size_t attribute_count;
    resurfi_gltf_named *attributes; /* name → plan accessor */
    long long indices;
    unsigned char *draco;
    size_t draco_size;
    resurfi_gltf_named *draco_ids;
    size_t target_count;    /* morph targets: target t has target_attributes[target_begin[t] .. target_begin[t+1]) */
    size_t *target_begin;
    resurfi_gltf_named *target_attributes;
    size_t bytes;
    int quantized;          /* an attribute in a format only KHR_mesh_quantization allows (as its source) */
} packed;

/* A block freed at the end, with the allocator it came from (Draco's encoded bytes come from the C heap). */
typedef struct owned_block {
    void *block;
    const resurf_allocator *alloc;
} owned_block;

/* One Draco payload: its input, set by pack on the saving thread, and what encoding it, decoding it again and
 * checking what came back gave (draco_make, which touches only its job: payloads are made side by side). */
typedef struct draco_job {
    int prepared, made;
    const resurf_mesh *mesh;
    size_t attr_count;
    resurfi_draco_input_attribute in_attrs[32];
    char names[32][64];
    int components[32], integer[32];
    resurfi_draco_input in;
    int position_bits;
    /* made: */
    resurf_status status;   /* RESURF_OK, the encoder's failure, or RESURF_ERR_INTERNAL: it does not decode as meant */
    char message[256];      /* the failure, after "PRIMITIVE level K: " */
    resurfi_draco_output enc;
    size_t points, faces;
    double lo[3], hi[3];    /* the decoded positions' box */
} draco_job;

typedef struct save_ctx {
    const resurf_scene *s;
    const resurf_scene_save_options *o;
    const resurf_allocator *alloc; /* the call's: options, else the scene's */
    const char *path;
    resurf_error *error;
    owned_block *owned;
    size_t owned_count, owned_cap;
    resurfi_gltf_out_accessor *acc;
    size_t acc_count, acc_cap;
    packed *cache;          /* prim_count × RESURF_SCENE_MAX_LEVELS */
    draco_job *jobs;        /* the payloads made ahead (encode_ahead) */
    size_t *job_of;         /* prim_count × RESURF_SCENE_MAX_LEVELS: index into jobs + 1, or 0 */
    int preparing;          /* pack only fills the Draco job of what it packs */
    int draco_used, verbatim_any, quantized_any;
    size_t level_bytes[RESURF_SCENE_MAX_LEVELS];
} save_ctx;


/* scene_save.c */
resurf_status save_oom(save_ctx *c);
/* Remembers p (a block of allocator a) for freeing at the end; NULL stays NULL (and frees p when the list cannot
 * grow). save_own: the same for a block of the call's allocator. */
void *save_own_from(save_ctx *c, void *p, const resurf_allocator *a);
void *save_own(save_ctx *c, void *p);
char *save_own_string(save_ctx *c, const char *s);
long long save_add_accessor(save_ctx *c, const resurfi_gltf_out_accessor *a); /* its index, or -1 */

/* scene_pack.c */
/* The level of primitive p that level `level` of the scene shows (its last one beyond its chain). */
size_t save_effective_level(const resurfi_scene_prim *p, size_t level);
/* Primitive prim at level `level`, packed once (cached in c->cache); with c->preparing only its Draco job is
 * prepared. */
resurf_status save_pack(save_ctx *c, size_t prim, size_t level, packed **out);
/* Every Draco payload the plan will take, encoded and checked side by side on the save's threads. */
resurf_status save_encode_ahead(save_ctx *c);

#endif
