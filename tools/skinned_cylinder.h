/* A skinned test asset: a capped cylinder of two bones, written as a .glb (tools/skinned_cylinder.c). Shared by
 * tests/test_skin.c, resurf-gen-analytic --skinned-cylinder and the glTF corpus test. */
#ifndef RESURF_SKINNED_CYLINDER_H
#define RESURF_SKINNED_CYLINDER_H

/* Radius 0.2 about the y axis, y from 0 to 2. Joint 0 (node 0, the root, at the origin) holds the lower half,
 * joint 1 (node 1, its child at (0, 1, 0)) the upper half; the weight of joint 1 rises smoothly (3u² − 2u³) from 0
 * at y = 0.7 to 1 at y = 1.3. Each vertex lists its stronger joint first (the joint order differs across the
 * middle), unused slots hold joint 0 with weight 0. Both inverse bind matrices are those of the unposed bones
 * (joint 1's: a translation by (0, −1, 0)). The file poses joint 1 by SKINNED_CYLINDER_BEND_DEG about +z, so the
 * upper half points along −x: a skinned vertex p becomes (1 − w1) p + w1 (c + Rz(90°)(p − c)), c = (0, 1, 0).
 * Node 2 carries the mesh and the skin, beside the skeleton at the scene's root. */
#define SKINNED_CYLINDER_BEND_DEG 90.0
#define SKINNED_CYLINDER_BLEND_LO 0.7
#define SKINNED_CYLINDER_BLEND_HI 1.3

/* segments around, rings along (rings + 1 circles of vertices, plus one centre per cap); flags: SKINNED_CYLINDER_UBYTE
 * for WEIGHTS_0 as normalized unsigned bytes (summing to exactly 255), else float; SKINNED_CYLINDER_NODE_MOVED to
 * give the skinned node a translation (which skinning ignores; the validator warns of it). Returns 0, or -1 when
 * the file cannot be written. */
enum { SKINNED_CYLINDER_UBYTE = 1, SKINNED_CYLINDER_NODE_MOVED = 2 };
int skinned_cylinder_write(const char *path, unsigned segments, unsigned rings, unsigned flags);

#endif
