// Where the bytes of a .glb or .gltf go, for bench-draco: prints one JSON line
//   {"file":F,"json":J,"draco":D,"images":I,"other":O,"primitives":P,"draco_primitives":Q}
// F the whole file (a .gltf: plus its external buffers), J the JSON text (a .glb: its JSON chunk, padding included),
// D the bufferViews that KHR_draco_mesh_compression extensions refer to (each counted once), I the bufferViews of
// images, O every other byte of the buffers (accessor data, padding between views, unreferenced bytes), P the
// triangle primitives and Q those with Draco.
//
// usage: node gltf-sizes.mjs FILE
import { readFileSync, statSync } from 'node:fs';
import { dirname, join } from 'node:path';

const path = process.argv[2];
const bytes = readFileSync(path);
let doc, fileSize = bytes.length, jsonSize, binSize = 0;
if (bytes.readUInt32LE(0) === 0x46546c67) { // "glTF"
    jsonSize = bytes.readUInt32LE(12);
    doc = JSON.parse(bytes.subarray(20, 20 + jsonSize).toString('utf8'));
    const at = 20 + jsonSize;
    if (at + 8 <= bytes.length)
        binSize = bytes.readUInt32LE(at);
} else {
    jsonSize = bytes.length;
    doc = JSON.parse(bytes.toString('utf8'));
    for (const b of doc.buffers ?? []) {
        if (b.uri && !b.uri.startsWith('data:')) {
            const size = statSync(join(dirname(path), decodeURIComponent(b.uri))).size;
            fileSize += size;
            binSize += size;
        } else if (b.uri) {
            binSize += b.byteLength; // embedded: already inside the JSON text
        }
    }
}
const views = doc.bufferViews ?? [];
const dracoViews = new Set(), imageViews = new Set();
let primitives = 0, dracoPrimitives = 0;
for (const mesh of doc.meshes ?? [])
    for (const p of mesh.primitives ?? []) {
        if ((p.mode ?? 4) !== 4)
            continue;
        ++primitives;
        const d = p.extensions?.KHR_draco_mesh_compression;
        if (d) {
            ++dracoPrimitives;
            dracoViews.add(d.bufferView);
        }
    }
for (const image of doc.images ?? [])
    if (image.bufferView !== undefined)
        imageViews.add(image.bufferView);
const sum = (set) => [...set].reduce((s, v) => s + (views[v]?.byteLength ?? 0), 0);
const draco = sum(dracoViews), images = sum(imageViews);
console.log(JSON.stringify({
    file: fileSize, json: jsonSize, draco, images, other: Math.max(0, binSize - draco - images), primitives,
    draco_primitives: dracoPrimitives,
}));
