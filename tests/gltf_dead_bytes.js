#!/usr/bin/env node
// Byte accounting of a written .gltf/.glb, independent of resurf's writer: which bytes of each buffer something
// refers to (the elements of an accessor that a primitive, a morph target, a skin, an animation or
// EXT_mesh_gpu_instancing uses; a sparse accessor's indices and values; a KHR_draco_mesh_compression payload; an
// image). Bytes that only align the next bufferView to 4 (at most 3 after the end of one) and the final
// padding of a buffer to 4 are allowed; every other byte that nothing refers to is dead.
// Prints "FILE: bytes B dead D" per file, then each dead range as "  buffers[i] [from, to)". Exit 1 when D > 0.
'use strict';
const fs = require('fs');
const path = require('path');

const componentSize = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4};
const typeCount = {SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4, MAT2: 4, MAT3: 9, MAT4: 16};

function load(file) {
  const b = fs.readFileSync(file);
  if (b.slice(0, 4).toString() === 'glTF') {
    const jsonLength = b.readUInt32LE(12);
    const doc = JSON.parse(b.slice(20, 20 + jsonLength).toString());
    const at = 20 + jsonLength;
    const bin = at + 8 <= b.length ? b.slice(at + 8, at + 8 + b.readUInt32LE(at)) : Buffer.alloc(0);
    return {doc, sizes: (doc.buffers || []).map((x, i) => (i === 0 && x.uri === undefined ? bin.length : x.byteLength))};
  }
  const doc = JSON.parse(b.toString());
  return {doc, sizes: (doc.buffers || []).map((x) => x.byteLength)};
}

function account(file) {
  const {doc, sizes} = load(file);
  const used = sizes.map((n) => new Uint8Array(n));
  const views = doc.bufferViews || [];
  const mark = (v, from, length) => {
    const view = views[v];
    const start = (view.byteOffset || 0) + from;
    for (let i = start; i < start + length && i < used[view.buffer].length; ++i)
      used[view.buffer][i] = 1;
  };
  const whole = (v) => mark(v, 0, views[v].byteLength);
  const accessors = doc.accessors || [];
  const usedAccessors = new Set();
  for (const m of doc.meshes || [])
    for (const p of m.primitives || []) {
      Object.values(p.attributes || {}).forEach((i) => usedAccessors.add(i));
      (p.targets || []).forEach((t) => Object.values(t).forEach((i) => usedAccessors.add(i)));
      if (p.indices !== undefined) usedAccessors.add(p.indices);
    }
  for (const s of doc.skins || [])
    if (s.inverseBindMatrices !== undefined) usedAccessors.add(s.inverseBindMatrices);
  for (const a of doc.animations || [])
    for (const s of a.samplers || []) usedAccessors.add(s.input), usedAccessors.add(s.output);
  for (const n of doc.nodes || [])
    if (n.extensions && n.extensions.EXT_mesh_gpu_instancing)
      Object.values(n.extensions.EXT_mesh_gpu_instancing.attributes || {}).forEach((i) => usedAccessors.add(i));
  for (const a of [...usedAccessors].map((i) => accessors[i])) {
    const element = componentSize[a.componentType] * typeCount[a.type];
    if (a.bufferView !== undefined) {
      const stride = views[a.bufferView].byteStride || element;
      if (a.count > 0)
        mark(a.bufferView, a.byteOffset || 0, (a.count - 1) * stride + element);
    }
    if (a.sparse) {
      const i = a.sparse.indices, v = a.sparse.values;
      mark(i.bufferView, i.byteOffset || 0, a.sparse.count * componentSize[i.componentType]);
      mark(v.bufferView, v.byteOffset || 0, a.sparse.count * element);
    }
  }
  for (const m of doc.meshes || [])
    for (const p of m.primitives || [])
      if (p.extensions && p.extensions.KHR_draco_mesh_compression)
        whole(p.extensions.KHR_draco_mesh_compression.bufferView);
  for (const img of doc.images || [])
    if (img.bufferView !== undefined)
      whole(img.bufferView);
  let total = 0, dead = 0;
  const ranges = [];
  used.forEach((u, b) => {
    total += u.length;
    // Allowed padding: up to 3 bytes after a used byte, before the next used byte or the end (aligning to 4).
    for (let i = 0; i < u.length;) {
      if (u[i]) { ++i; continue; }
      let j = i;
      while (j < u.length && !u[j]) ++j;
      if (!(i > 0 && j - i <= 3 && j % 4 === 0)) {
        dead += j - i;
        ranges.push(`  buffers[${b}] [${i}, ${j})`);
      }
      i = j;
    }
  });
  console.log(`${file}: bytes ${total} dead ${dead}`);
  for (const r of ranges.slice(0, 20)) console.log(r);
  return dead;
}

let dead = 0;
for (const f of process.argv.slice(2)) dead += account(path.resolve(f));
process.exit(dead > 0 ? 1 : 0);
