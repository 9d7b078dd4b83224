// Writes crates/seamlit-render/src/sheen_table.rs: the Khronos glTF Sample Viewer's sheen
// albedo table (lut_sheen_E.png, 1024 x 1024, 16 bits, E in red: x is n.v, y the sheen
// roughness, row 0 roughness 0, read as the viewer reads it, without flipping) sampled
// bilinearly at the centres of seamlit's 32 x 32 grid.
//
//   node bench/sample-viewer/sheen-table.mjs   (after npm ci --prefix bench/sample-viewer)
import { readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { decode } from 'fast-png';

const here = dirname(fileURLToPath(import.meta.url));
const source = join(here, 'node_modules/gltf-viewer-1.0.10/dist/assets/lut_sheen_E.png');
const target = join(here, '../../crates/seamlit-render/src/sheen_table.rs');
const SIZE = 32;

const png = decode(readFileSync(source));
if (png.depth !== 16) throw new Error(`${source}: expected 16 bits a channel, found ${png.depth}`);
const red = (x, y) => png.data[(y * png.width + x) * png.channels] / 65535;
// What a linear-filtered texture returns at (u, v) in 0..1, clamped to the edge.
const sample = (u, v) => {
  const fx = Math.min(Math.max(u * png.width - 0.5, 0), png.width - 1);
  const fy = Math.min(Math.max(v * png.height - 0.5, 0), png.height - 1);
  const x0 = Math.floor(fx), y0 = Math.floor(fy);
  const x1 = Math.min(x0 + 1, png.width - 1), y1 = Math.min(y0 + 1, png.height - 1);
  const tx = fx - x0, ty = fy - y0;
  const row = (y) => red(x0, y) * (1 - tx) + red(x1, y) * tx;
  return row(y0) * (1 - ty) + row(y1) * ty;
};

const entries = [];
for (let y = 0; y < SIZE; y++) {
  for (let x = 0; x < SIZE; x++) {
    entries.push(Math.round(sample((x + 0.5) / SIZE, (y + 0.5) / SIZE) * 65535));
  }
}
const lines = [];
for (let i = 0; i < entries.length; i += 16) lines.push(`    ${entries.slice(i, i + 16).join(', ')},`);
writeFileSync(target, `//! The Khronos glTF Sample Viewer's sheen albedo table, E(n.v, sheen roughness), as 16-bit
//! fractions of 1: its \`lut_sheen_E.png\` (1024 x 1024) sampled bilinearly at the centres of a
//! ${SIZE} x ${SIZE} grid, row by row (x the cosine, y the roughness). Written by
//! bench/sample-viewer/sheen-table.mjs; do not edit. The table is the Sample Viewer's
//! (KhronosGroup/glTF-Sample-Viewer, Apache 2.0: assets/models/licenses/glTF-Sample-Viewer-Apache-2.0.txt).

pub(crate) const SIZE: u32 = ${SIZE};

#[rustfmt::skip]
pub(crate) const SHEEN_E: [u16; ${SIZE * SIZE}] = [
${lines.join('\n')}
];
`);
console.log(`wrote ${target}`);
