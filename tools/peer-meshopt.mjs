// npm meshoptimizer's simplifier (wasm) as a peer of bench-simplify (tools/peers.h, tools/peer_meshopt_js.c).
//
//   node tools/peer-meshopt.mjs IN OUT
//
// IN (little-endian, as bench-simplify writes it on x86 and ARM): u32 magic 'RSPI', u32 mode (0 simplify,
// 1 simplifyWithUpdate), u32 repeat, u32 0, u64 vertex count, u64 index count, u64 target index count, then
// float32 positions[3 × vertices] and u32 indices[index count].
// OUT: u32 magic 'RSPO', u32 0, u64 index count, u64 vertex count, f64 seconds (best of the repeats, the call
// alone), f64 the simplifier's error, float32 positions[3 × vertices] (moved by simplifyWithUpdate; the input's
// for simplify), u32 indices[index count].
// Settings as bench-simplify's native meshopt_simplify call: target_error 1 (no bound), no flags.
import { readFileSync, writeFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';
import { MeshoptSimplifier } from './node/node_modules/meshoptimizer/meshopt_simplifier.js';

const [inPath, outPath] = process.argv.slice(2);
const input = readFileSync(inPath);
const view = new DataView(input.buffer, input.byteOffset, input.byteLength);
if (view.getUint32(0, true) !== 0x49505352) throw new Error(`${inPath}: not a bench-simplify request`);
const mode = view.getUint32(4, true);
const repeat = Math.max(1, view.getUint32(8, true));
const vertexCount = Number(view.getBigUint64(16, true));
const indexCount = Number(view.getBigUint64(24, true));
const targetIndexCount = Number(view.getBigUint64(32, true));
const header = 40;
// copies: aligned, and a fresh start for every run of simplifyWithUpdate, which works in place
const slice = (offset, bytes) => input.buffer.slice(input.byteOffset + offset, input.byteOffset + offset + bytes);
const positions0 = new Float32Array(slice(header, 12 * vertexCount));
const indices0 = new Uint32Array(slice(header + 12 * vertexCount, 4 * indexCount));

await MeshoptSimplifier.ready;
let best = Infinity, positions = positions0, indices, error = 0;
for (let run = 0; run < repeat; ++run) {
  if (mode === 1) {
    const p = positions0.slice(), i = indices0.slice(), none = new Float32Array(0);
    const t0 = performance.now();
    const [count, e] = MeshoptSimplifier.simplifyWithUpdate(i, p, 3, none, 0, [], null, targetIndexCount, 1, []);
    best = Math.min(best, (performance.now() - t0) * 1e-3);
    positions = p;
    indices = i.subarray(0, count);
    error = e;
  } else {
    const t0 = performance.now();
    const [i, e] = MeshoptSimplifier.simplify(indices0, positions0, 3, targetIndexCount, 1, []);
    best = Math.min(best, (performance.now() - t0) * 1e-3);
    indices = i;
    error = e;
  }
}

const outHeader = new DataView(new ArrayBuffer(40));
outHeader.setUint32(0, 0x4f505352, true);
outHeader.setBigUint64(8, BigInt(indices.length), true);
outHeader.setBigUint64(16, BigInt(vertexCount), true);
outHeader.setFloat64(24, best, true);
outHeader.setFloat64(32, error, true);
writeFileSync(outPath, Buffer.concat([Buffer.from(outHeader.buffer), Buffer.from(positions.buffer, positions.byteOffset,
  positions.byteLength), Buffer.from(indices.buffer, indices.byteOffset, indices.byteLength)]));
