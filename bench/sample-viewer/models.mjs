// The models of the comparison, as GLB files with one camera and one KHR_lights_punctual
// light each, so that both viewers see the same scene:
//   spheres.glb    5 x 5 spheres, metallic 0..1 left to right, roughness 0..1 bottom to top,
//                  one constant base colour, one directional light (built here)
//   materials.glb  emissive with KHR_materials_emissive_strength, textured base colour,
//                  occlusion and metallic-roughness, alpha MASK and alpha BLEND (built here)
//   clearcoat.glb, sheen.glb, specular.glb, anisotropy.glb, transforms.glb
//                  the PBR extensions, three or four spheres each, by factors and by textures
//                  (built here)
//   emissive.glb   KHR_materials_emissive_strength at 1, 4 and 2.5 (textured) (built here)
//   variants.glb   KHR_materials_variants: three spheres, two variants (built here)
//   transmission.glb  KHR_materials_transmission and _volume: three glass spheres before a
//                  striped backdrop (built here)
//   dispersion.glb KHR_materials_dispersion: three clear solid spheres before the same panel
//                  (built here)
//   iridescence.glb  KHR_materials_iridescence: two films over a dark dielectric, one over a
//                  metal (built here)
//   transmission_texture.glb, thickness_texture.glb, iridescence_texture.glb,
//   iridescence_thickness_texture.glb, anisotropy_texture.glb, clearcoat_roughness_texture.glb,
//   specular_texture.glb
//                  one extension texture each, on three spheres: as it is, through a
//                  KHR_texture_transform, and from TEXCOORD_1 (built here)
//   and each model file named on the command line (GLB), with a camera framing its bounds
//   and the same directional light added.
// Usage: node models.mjs OUT_DIR [NAME=FILE.glb ...]
// Writes OUT_DIR/NAME.glb, OUT_DIR/NAME.camera.json (the camera for seamlit's scene file, and
// the model's KHR_materials_variants names) and
// OUT_DIR/sky.hdr (128 x 64, the environment of the second mode).

import { readFileSync, writeFileSync, mkdirSync } from 'node:fs';
import { deflateSync, crc32 } from 'node:zlib';
import { join } from 'node:path';

/** The light every model gets: directional, from the upper left front, 3 lux, white. */
const LIGHT = { type: 'directional', color: [1, 1, 1], intensity: 3, name: 'sun' };
const LIGHT_DIRECTION = normalize([0.5, -0.6, -0.62]);
const YFOV_DEG = 30;

function normalize(v) {
  const l = Math.hypot(...v);
  return v.map((x) => x / l);
}

function cross(a, b) {
  return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
}

/** The rotation (quaternion x, y, z, w) whose -Z axis points along `dir` with +Y up. */
function lookRotation(dir, up = [0, 1, 0]) {
  const z = normalize(dir.map((x) => -x));
  const x = normalize(cross(up, z));
  const y = cross(z, x);
  // Rotation matrix columns x, y, z to a quaternion.
  const m = [x, y, z];
  const trace = m[0][0] + m[1][1] + m[2][2];
  let q;
  if (trace > 0) {
    const s = 0.5 / Math.sqrt(trace + 1);
    q = [(m[1][2] - m[2][1]) * s, (m[2][0] - m[0][2]) * s, (m[0][1] - m[1][0]) * s, 0.25 / s];
  } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
    const s = 2 * Math.sqrt(1 + m[0][0] - m[1][1] - m[2][2]);
    q = [0.25 * s, (m[1][0] + m[0][1]) / s, (m[2][0] + m[0][2]) / s, (m[1][2] - m[2][1]) / s];
  } else if (m[1][1] > m[2][2]) {
    const s = 2 * Math.sqrt(1 + m[1][1] - m[0][0] - m[2][2]);
    q = [(m[1][0] + m[0][1]) / s, 0.25 * s, (m[2][1] + m[1][2]) / s, (m[2][0] - m[0][2]) / s];
  } else {
    const s = 2 * Math.sqrt(1 + m[2][2] - m[0][0] - m[1][1]);
    q = [(m[2][0] + m[0][2]) / s, (m[2][1] + m[1][2]) / s, 0.25 * s, (m[0][1] - m[1][0]) / s];
  }
  return normalize(q);
}

/** A glTF document under construction with one binary buffer. */
class Doc {
  constructor() {
    this.json = {
      asset: { version: '2.0', generator: 'seamlit bench/sample-viewer/models.mjs' },
      scene: 0, scenes: [{ nodes: [] }], nodes: [], meshes: [], materials: [],
      accessors: [], bufferViews: [], buffers: [{ byteLength: 0 }],
    };
    this.chunks = [];
    this.length = 0;
  }

  view(bytes, target) {
    const pad = (4 - (this.length % 4)) % 4;
    if (pad) { this.chunks.push(Buffer.alloc(pad)); this.length += pad; }
    const view = { buffer: 0, byteOffset: this.length, byteLength: bytes.byteLength };
    if (target) view.target = target;
    this.chunks.push(Buffer.from(bytes.buffer, bytes.byteOffset, bytes.byteLength));
    this.length += bytes.byteLength;
    this.json.bufferViews.push(view);
    return this.json.bufferViews.length - 1;
  }

  accessor(array, type, componentType, target, minmax) {
    const size = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 }[type];
    const acc = { bufferView: this.view(array, target), componentType, count: array.length / size, type };
    if (minmax) {
      acc.min = []; acc.max = [];
      for (let c = 0; c < size; c++) {
        let lo = Infinity, hi = -Infinity;
        for (let i = c; i < array.length; i += size) { lo = Math.min(lo, array[i]); hi = Math.max(hi, array[i]); }
        acc.min.push(lo); acc.max.push(hi);
      }
    }
    this.json.accessors.push(acc);
    return this.json.accessors.length - 1;
  }

  /** Positions, normals, UVs (and a second set, `uvs1`) and indices as one primitive's
   * attributes. */
  geometry({ positions, normals, tangents, uvs, uvs1, indices }) {
    const attributes = {
      POSITION: this.accessor(new Float32Array(positions), 'VEC3', 5126, 34962, true),
      NORMAL: this.accessor(new Float32Array(normals), 'VEC3', 5126, 34962),
      TANGENT: this.accessor(new Float32Array(tangents), 'VEC4', 5126, 34962),
      TEXCOORD_0: this.accessor(new Float32Array(uvs), 'VEC2', 5126, 34962),
    };
    if (uvs1) attributes.TEXCOORD_1 = this.accessor(new Float32Array(uvs1), 'VEC2', 5126, 34962);
    return { attributes, indices: this.accessor(new Uint16Array(indices), 'SCALAR', 5123, 34963) };
  }

  material(m) { this.json.materials.push(m); return this.json.materials.length - 1; }

  /** A node with a one-primitive mesh at `translation`, in the scene. */
  place(geometry, material, translation, name) {
    this.json.meshes.push({ name, primitives: [{ ...geometry, material }] });
    this.json.nodes.push({ name, mesh: this.json.meshes.length - 1, translation });
    this.json.scenes[0].nodes.push(this.json.nodes.length - 1);
  }

  /** A PNG image as a texture (sampler: linear, mipmaps, repeat). */
  texture(png) {
    this.json.images ??= []; this.json.textures ??= []; this.json.samplers ??= [{ magFilter: 9729, minFilter: 9987 }];
    this.json.images.push({ bufferView: this.view(png), mimeType: 'image/png' });
    this.json.textures.push({ sampler: 0, source: this.json.images.length - 1 });
    return this.json.textures.length - 1;
  }

  glb() {
    this.json.buffers[0].byteLength = this.length;
    return packGlb(this.json, Buffer.concat(this.chunks));
  }
}

function packGlb(json, bin) {
  const pad = (b, fill) => Buffer.concat([b, Buffer.alloc((4 - (b.length % 4)) % 4, fill)]);
  const text = pad(Buffer.from(JSON.stringify(json)), 0x20);
  const data = pad(bin, 0);
  const header = Buffer.alloc(12);
  header.writeUInt32LE(0x46546c67, 0); header.writeUInt32LE(2, 4);
  header.writeUInt32LE(12 + 8 + text.length + (data.length ? 8 + data.length : 0), 8);
  const chunk = (type, body) => {
    const h = Buffer.alloc(8); h.writeUInt32LE(body.length, 0); h.writeUInt32LE(type, 4);
    return Buffer.concat([h, body]);
  };
  return Buffer.concat([header, chunk(0x4e4f534a, text), ...(data.length ? [chunk(0x004e4942, data)] : [])]);
}

/** A .gltf whose buffers are all `data:` URIs as GLB parts: the buffers joined into one BIN
 * chunk (each at a 4-byte boundary), the buffer views pointed into it. */
function embeddedGltf(bytes) {
  const json = JSON.parse(bytes.toString('utf8'));
  const parts = [];
  const starts = [];
  let length = 0;
  for (const buffer of json.buffers ?? []) {
    const uri = buffer.uri ?? '';
    if (!uri.startsWith('data:')) throw new Error(`buffer ${uri}: only data: URIs (or a GLB) are read`);
    const data = Buffer.from(uri.slice(uri.indexOf(',') + 1), 'base64');
    const padded = Buffer.concat([data, Buffer.alloc((4 - (data.length % 4)) % 4)]);
    starts.push(length);
    parts.push(padded);
    length += padded.length;
  }
  for (const view of json.bufferViews ?? []) {
    view.byteOffset = (view.byteOffset ?? 0) + starts[view.buffer];
    view.buffer = 0;
  }
  const bin = Buffer.concat(parts);
  json.buffers = bin.length ? [{ byteLength: bin.length }] : [];
  return { json, bin };
}

function unpackGlb(bytes) {
  if (bytes[0] === 0x7b) return embeddedGltf(bytes); // '{': a .gltf
  if (bytes.readUInt32LE(0) !== 0x46546c67) throw new Error('not a GLB file');
  const jsonLength = bytes.readUInt32LE(12);
  const json = JSON.parse(bytes.subarray(20, 20 + jsonLength).toString('utf8'));
  const rest = 20 + jsonLength;
  const bin = rest < bytes.length ? bytes.subarray(rest + 8, rest + 8 + bytes.readUInt32LE(rest)) : Buffer.alloc(0);
  return { json, bin };
}

/** A UV sphere of `radius`: `rings` x `segments` quads, V running down as glTF's does; the
 * tangents given (the Sample Viewer's MikkTSpace overflows its stack on the poles). */
function sphere(radius, rings = 32, segments = 64) {
  const positions = [], normals = [], tangents = [], uvs = [], indices = [];
  for (let r = 0; r <= rings; r++) {
    const theta = (r / rings) * Math.PI;
    for (let s = 0; s <= segments; s++) {
      const phi = (s / segments) * 2 * Math.PI;
      const n = [Math.sin(theta) * Math.sin(phi), Math.cos(theta), Math.sin(theta) * Math.cos(phi)];
      tangents.push(Math.cos(phi), 0, -Math.sin(phi), 1);
      normals.push(...n); positions.push(...n.map((x) => x * radius)); uvs.push(s / segments, r / rings);
    }
  }
  for (let r = 0; r < rings; r++) {
    for (let s = 0; s < segments; s++) {
      const a = r * (segments + 1) + s, b = a + segments + 1;
      indices.push(a, b, a + 1, a + 1, b, b + 1);
    }
  }
  return { positions, normals, tangents, uvs, indices };
}

/** A square in the XY plane facing +Z, side `size`. */
function quad(size) {
  const h = size / 2;
  return {
    positions: [-h, -h, 0, h, -h, 0, h, h, 0, -h, h, 0],
    normals: [0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1],
    tangents: [1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1],
    uvs: [0, 1, 1, 1, 1, 0, 0, 0],
    indices: [0, 1, 2, 0, 2, 3],
  };
}

/** An RGBA PNG of `size` x `size` pixels, `pixel(x, y)` giving [r, g, b, a] in 0..255. */
function png(size, pixel) {
  const raw = Buffer.alloc(size * (size * 4 + 1));
  for (let y = 0; y < size; y++) {
    for (let x = 0; x < size; x++) raw.set(pixel(x, y), y * (size * 4 + 1) + 1 + x * 4);
  }
  const chunk = (type, body) => {
    const len = Buffer.alloc(4); len.writeUInt32BE(body.length);
    const tb = Buffer.concat([Buffer.from(type, 'latin1'), body]);
    const crc = Buffer.alloc(4); crc.writeUInt32BE(crc32(tb));
    return Buffer.concat([len, tb, crc]);
  };
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(size, 0); ihdr.writeUInt32BE(size, 4); ihdr.set([8, 6, 0, 0, 0], 8);
  return new Uint8Array(Buffer.concat([
    Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]),
    chunk('IHDR', ihdr), chunk('IDAT', deflateSync(raw)), chunk('IEND', Buffer.alloc(0)),
  ]));
}

/** A Radiance .hdr (RGBE, run-length-encoded scanlines of literal runs) of `width` x
 * `height` pixels, `radiance(x, y)` giving linear [r, g, b]. */
function hdr(width, height, radiance) {
  const parts = [Buffer.from(`#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y ${height} +X ${width}\n`, 'latin1')];
  for (let y = 0; y < height; y++) {
    const rgbe = Array.from({ length: width }, (_, x) => {
      const c = radiance(x, y), m = Math.max(...c);
      if (m < 1e-32) return [0, 0, 0, 0];
      const e = Math.ceil(Math.log2(m + 1e-12) + 1e-9);
      const scale = 256 / 2 ** e;
      return [...c.map((v) => Math.min(255, Math.floor(v * scale))), e + 128];
    });
    parts.push(Buffer.from([2, 2, width >> 8, width & 255]));
    for (let ch = 0; ch < 4; ch++) {
      for (let x = 0; x < width; x += 128) {
        const run = rgbe.slice(x, x + 128).map((p) => p[ch]);
        parts.push(Buffer.from([run.length, ...run]));
      }
    }
  }
  return Buffer.concat(parts);
}

/** The environment of the second mode: a sky from blue above to brown below, and a sun. */
function sky() {
  const [w, h] = [128, 64];
  const sun = normalize([-0.5, 0.6, 0.62]);
  return hdr(w, h, (x, y) => {
    const phi = ((x + 0.5) / w) * 2 * Math.PI, theta = ((y + 0.5) / h) * Math.PI;
    const d = [Math.sin(theta) * Math.cos(phi), Math.cos(theta), Math.sin(theta) * Math.sin(phi)];
    const up = d[1];
    const base = up > 0 ? [0.35 + 0.2 * (1 - up), 0.5 + 0.15 * (1 - up), 0.9] : [0.25, 0.2, 0.15];
    const glow = Math.max(0, d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2]) ** 64 * 40;
    return base.map((v) => v + glow);
  });
}

/** Adds the light and a camera at `eye` looking at `target` to a document's JSON (after
 * the cameras and lights it has); returns the camera as seamlit's scene file names it. */
function addCameraAndLight(json, eye, target, aspect) {
  json.extensionsUsed = [...new Set([...(json.extensionsUsed ?? []), 'KHR_lights_punctual'])];
  json.extensions ??= {};
  json.extensions.KHR_lights_punctual ??= { lights: [] };
  const lights = json.extensions.KHR_lights_punctual.lights;
  lights.push(LIGHT);
  json.nodes ??= [];
  json.cameras ??= [];
  const dist = Math.hypot(...eye.map((x, i) => x - target[i]));
  const [near, far] = [dist / 100, dist * 10];
  json.cameras.push({ name: 'compare', type: 'perspective', perspective: {
    yfov: (YFOV_DEG * Math.PI) / 180, aspectRatio: aspect, znear: near, zfar: far } });
  json.nodes.push({ name: 'compare-camera', camera: json.cameras.length - 1, translation: eye,
    rotation: lookRotation(eye.map((x, i) => target[i] - x)) });
  json.nodes.push({ name: 'compare-light', rotation: lookRotation(LIGHT_DIRECTION),
    extensions: { KHR_lights_punctual: { light: lights.length - 1 } } });
  const scene = json.scenes[json.scene ?? 0];
  scene.nodes.push(json.nodes.length - 2, json.nodes.length - 1);
  return { name: 'compare', index: json.cameras.length - 1, position: eye, target, fov_deg: YFOV_DEG, near, far };
}

function spheres() {
  const doc = new Doc();
  const geometry = doc.geometry(sphere(0.4));
  for (let row = 0; row < 5; row++) {
    for (let col = 0; col < 5; col++) {
      const material = doc.material({ name: `m${col}r${row}`, pbrMetallicRoughness: {
        baseColorFactor: [0.9, 0.45, 0.2, 1], metallicFactor: col / 4, roughnessFactor: row / 4 } });
      doc.place(geometry, material, [(col - 2), (row - 2), 0], `sphere m${col} r${row}`);
    }
  }
  return doc;
}

function materials() {
  const doc = new Doc();
  const ball = doc.geometry(sphere(0.45));
  // Emissive: a dark base, an orange glow beyond 1 (strength 4).
  doc.json.extensionsUsed = ['KHR_materials_emissive_strength'];
  doc.place(ball, doc.material({ name: 'emissive', emissiveFactor: [1, 0.4, 0.1],
    pbrMetallicRoughness: { baseColorFactor: [0.1, 0.1, 0.1, 1], metallicFactor: 0, roughnessFactor: 0.5 },
    extensions: { KHR_materials_emissive_strength: { emissiveStrength: 4 } } }), [-1.5, 0.5, 0], 'emissive');
  // Textured: checker base colour (sRGB), occlusion stripes (R), metal/rough quarters (B/G).
  const checker = doc.texture(png(64, (x, y) => (((x >> 3) + (y >> 3)) & 1 ? [230, 200, 60, 255] : [40, 90, 200, 255])));
  const occlusion = doc.texture(png(64, (x) => [(x >> 2) & 1 ? 255 : 90, 0, 0, 255]));
  const metalRough = doc.texture(png(64, (x, y) => [0, y < 32 ? 60 : 200, x < 32 ? 0 : 255, 255]));
  doc.place(ball, doc.material({ name: 'textured',
    pbrMetallicRoughness: { baseColorTexture: { index: checker }, metallicRoughnessTexture: { index: metalRough } },
    occlusionTexture: { index: occlusion, strength: 0.8 } }), [-0.5, 0.5, 0], 'textured');
  // Alpha MASK: a quad whose texture cuts out a disc.
  const disc = doc.texture(png(64, (x, y) => [220, 220, 220, Math.hypot(x - 31.5, y - 31.5) < 24 ? 255 : 40]));
  doc.place(doc.geometry(quad(0.9)), doc.material({ name: 'mask', alphaMode: 'MASK', alphaCutoff: 0.5, doubleSided: true,
    pbrMetallicRoughness: { baseColorTexture: { index: disc }, metallicFactor: 0, roughnessFactor: 0.6 } }),
  [0.5, 0.5, 0], 'mask');
  // Alpha BLEND: a half-transparent green sphere in front of an opaque white one.
  doc.place(ball, doc.material({ name: 'white', pbrMetallicRoughness: { baseColorFactor: [0.9, 0.9, 0.9, 1], metallicFactor: 0, roughnessFactor: 0.4 } }),
    [1.5, 0.5, -0.6], 'behind');
  doc.place(doc.geometry(sphere(0.3)), doc.material({ name: 'blend', alphaMode: 'BLEND',
    pbrMetallicRoughness: { baseColorFactor: [0.1, 0.8, 0.2, 0.5], metallicFactor: 0, roughnessFactor: 0.3 } }),
  [1.5, 0.5, 0.4], 'blend');
  // A grey wall behind them all.
  doc.place(doc.geometry(quad(4)), doc.material({ name: 'wall', pbrMetallicRoughness: {
    baseColorFactor: [0.5, 0.5, 0.5, 1], metallicFactor: 0, roughnessFactor: 0.8 } }), [0, 0.5, -1.2], 'wall');
  return doc;
}

/** A tangent-space normal map of ridges along V (normals tilted in U), as an RGBA PNG. */
function ridges(size, period) {
  return png(size, (x) => {
    const nx = 0.45 * Math.sin((2 * Math.PI * (x + 0.5)) / period);
    const nz = Math.sqrt(1 - nx * nx);
    return [Math.round((nx * 0.5 + 0.5) * 255), 128, Math.round((nz * 0.5 + 0.5) * 255), 255];
  });
}

/** Spheres in a row at x = -1.5 .. 1.5 (step 3 / (n - 1)), each a material of `materials`. */
function row(doc, materials, extensions) {
  doc.json.extensionsUsed = extensions;
  const ball = doc.geometry(sphere(0.45));
  materials.forEach((m, i) => {
    const x = materials.length === 1 ? 0 : -1.5 + (3 * i) / (materials.length - 1);
    doc.place(ball, doc.material(m), [x, 0, 0], m.name);
  });
}

/** KHR_materials_clearcoat: a smooth coat over a rough red dielectric, a half coat of some
 * roughness, and a striped coat (clearcoatTexture, red) with its own ridged normal map over
 * a rough blue metal. */
function clearcoat() {
  const doc = new Doc();
  const stripes = doc.texture(png(64, (x, y) => [(y >> 3) & 1 ? 255 : 0, 0, 0, 255]));
  const normals = doc.texture(ridges(64, 16));
  const red = { baseColorFactor: [0.8, 0.1, 0.05, 1], metallicFactor: 0, roughnessFactor: 0.7 };
  row(doc, [
    { name: 'coat', pbrMetallicRoughness: red,
      extensions: { KHR_materials_clearcoat: { clearcoatFactor: 1, clearcoatRoughnessFactor: 0.05 } } },
    { name: 'half coat', pbrMetallicRoughness: red,
      extensions: { KHR_materials_clearcoat: { clearcoatFactor: 0.5, clearcoatRoughnessFactor: 0.35 } } },
    { name: 'striped coat', pbrMetallicRoughness: { baseColorFactor: [0.2, 0.35, 0.8, 1], metallicFactor: 1, roughnessFactor: 0.55 },
      extensions: { KHR_materials_clearcoat: { clearcoatFactor: 1, clearcoatTexture: { index: stripes },
        clearcoatRoughnessFactor: 0.1, clearcoatNormalTexture: { index: normals, scale: 1 } } } },
  ], ['KHR_materials_clearcoat']);
  return doc;
}

/** KHR_materials_sheen: velvet (a dark base under a pink sheen) at sheen roughness 0.3 and
 * 0.8, and a sheen whose colour (checker) and roughness (alpha) come from textures. */
function sheen() {
  const doc = new Doc();
  const colour = doc.texture(png(64, (x, y) => (((x >> 3) + (y >> 3)) & 1 ? [255, 230, 120, 255] : [90, 200, 255, 255])));
  const rough = doc.texture(png(64, (x) => [255, 255, 255, x < 32 ? 90 : 230]));
  const velvet = { baseColorFactor: [0.05, 0.03, 0.12, 1], metallicFactor: 0, roughnessFactor: 0.9 };
  row(doc, [
    { name: 'sheen 0.3', pbrMetallicRoughness: velvet,
      extensions: { KHR_materials_sheen: { sheenColorFactor: [1, 0.45, 0.7], sheenRoughnessFactor: 0.3 } } },
    { name: 'sheen 0.8', pbrMetallicRoughness: velvet,
      extensions: { KHR_materials_sheen: { sheenColorFactor: [1, 0.45, 0.7], sheenRoughnessFactor: 0.8 } } },
    { name: 'textured sheen', pbrMetallicRoughness: velvet,
      extensions: { KHR_materials_sheen: { sheenColorFactor: [1, 1, 1], sheenColorTexture: { index: colour },
        sheenRoughnessFactor: 1, sheenRoughnessTexture: { index: rough } } } },
  ], ['KHR_materials_sheen']);
  return doc;
}

/** KHR_materials_ior and KHR_materials_specular: a glossy grey dielectric at ior 1.2 and 2.4,
 * at specularFactor 0.3, and with a specular colour from a texture (red and cyan halves)
 * times a factor. */
function specular() {
  const doc = new Doc();
  const tint = doc.texture(png(64, (x) => (x < 32 ? [255, 60, 60, 255] : [60, 255, 255, 255])));
  const grey = { baseColorFactor: [0.25, 0.25, 0.25, 1], metallicFactor: 0, roughnessFactor: 0.3 };
  row(doc, [
    { name: 'ior 1.2', pbrMetallicRoughness: grey, extensions: { KHR_materials_ior: { ior: 1.2 } } },
    { name: 'ior 2.4', pbrMetallicRoughness: grey, extensions: { KHR_materials_ior: { ior: 2.4 } } },
    { name: 'specular 0.3', pbrMetallicRoughness: grey,
      extensions: { KHR_materials_ior: { ior: 2.4 }, KHR_materials_specular: { specularFactor: 0.3 } } },
    { name: 'specular colour', pbrMetallicRoughness: grey,
      extensions: { KHR_materials_ior: { ior: 2.4 }, KHR_materials_specular: { specularColorFactor: [1, 1, 1],
        specularColorTexture: { index: tint } } } },
  ], ['KHR_materials_ior', 'KHR_materials_specular']);
  return doc;
}

/** KHR_materials_anisotropy: brushed copper (a rough metal) without anisotropy, with
 * strength 0.6 along the tangent (around the sphere) and 0.9 turned a quarter turn (along
 * the meridians). */
function anisotropy() {
  const doc = new Doc();
  const copper = { baseColorFactor: [0.95, 0.64, 0.54, 1], metallicFactor: 1, roughnessFactor: 0.35 };
  row(doc, [
    { name: 'isotropic', pbrMetallicRoughness: copper },
    { name: 'along', pbrMetallicRoughness: copper,
      extensions: { KHR_materials_anisotropy: { anisotropyStrength: 0.6 } } },
    { name: 'across', pbrMetallicRoughness: copper,
      extensions: { KHR_materials_anisotropy: { anisotropyStrength: 0.9, anisotropyRotation: Math.PI / 2 } } },
  ], ['KHR_materials_anisotropy']);
  return doc;
}

/** KHR_texture_transform on every core slot, and KHR_materials_unlit: a checker base colour
 * turned, scaled and moved; a rough metal whose metallic-roughness, occlusion, normal and
 * emissive textures each have their own transform; an unlit sphere with a transformed
 * base colour texture. */
function transforms() {
  const doc = new Doc();
  doc.json.extensionsUsed = ['KHR_texture_transform', 'KHR_materials_unlit'];
  const ball = doc.geometry(sphere(0.45));
  const checker = doc.texture(png(64, (x, y) => (((x >> 3) + (y >> 3)) & 1 ? [230, 200, 60, 255] : [40, 90, 200, 255])));
  const stripes = doc.texture(png(64, (x) => [(x >> 3) & 1 ? 255 : 60, (x >> 3) & 1 ? 60 : 220, (x >> 3) & 1 ? 0 : 255, 255]));
  const glow = doc.texture(png(64, (x, y) => (Math.hypot(x - 31.5, y - 31.5) < 10 ? [255, 120, 40, 255] : [0, 0, 0, 255])));
  const normals = doc.texture(ridges(64, 16));
  const t = (offset, rotation, scale) => ({ KHR_texture_transform: { offset, rotation, scale } });
  doc.place(ball, doc.material({ name: 'base transform', pbrMetallicRoughness: {
    baseColorTexture: { index: checker, extensions: t([0.1, 0.2], 0.4, [2, 3]) }, metallicFactor: 0, roughnessFactor: 0.5 } }),
  [-1.5, 0, 0], 'base transform');
  doc.place(ball, doc.material({ name: 'every slot',
    pbrMetallicRoughness: { baseColorFactor: [0.9, 0.6, 0.4, 1],
      metallicRoughnessTexture: { index: stripes, extensions: t([0.25, 0], 0.8, [1.5, 1]) } },
    normalTexture: { index: normals, extensions: t([0, 0], 1.2, [2, 2]) },
    occlusionTexture: { index: stripes, strength: 0.9, extensions: t([0, 0.5], -0.6, [3, 1]) },
    emissiveFactor: [1, 1, 1], emissiveTexture: { index: glow, extensions: t([-0.3, 0.1], 0.2, [2, 1]) } }),
  [0, 0, 0], 'every slot');
  doc.place(ball, doc.material({ name: 'unlit', pbrMetallicRoughness: {
    baseColorTexture: { index: checker, extensions: t([0, 0], -0.7, [1, 4]) } },
    extensions: { KHR_materials_unlit: {} } }), [1.5, 0, 0], 'unlit');
  return doc;
}

/** KHR_materials_emissive_strength: a dark base glowing blue at strength 1 (the core's
 * limit), orange at strength 4, and a striped emissive texture at strength 2.5. */
function emissive() {
  const doc = new Doc();
  const stripes = doc.texture(png(64, (x, y) => ((y >> 3) & 1 ? [255, 200, 120, 255] : [40, 40, 40, 255])));
  const dark = { baseColorFactor: [0.05, 0.05, 0.05, 1], metallicFactor: 0, roughnessFactor: 0.5 };
  const strength = (s) => ({ KHR_materials_emissive_strength: { emissiveStrength: s } });
  row(doc, [
    { name: 'strength 1', pbrMetallicRoughness: dark, emissiveFactor: [0.1, 0.25, 0.5], extensions: strength(1) },
    { name: 'strength 4', pbrMetallicRoughness: dark, emissiveFactor: [0.3, 0.12, 0.03], extensions: strength(4) },
    { name: 'textured 2.5', pbrMetallicRoughness: dark, emissiveFactor: [0.4, 0.4, 0.4],
      emissiveTexture: { index: stripes }, extensions: strength(2.5) },
  ], ['KHR_materials_emissive_strength']);
  return doc;
}

/** KHR_materials_transmission and KHR_materials_volume: three spheres of glass in front of a
 * striped opaque backdrop (pastel colours): thin-walled (no volume), a solid amber one (thickness 0.9, its
 * diameter, absorbing towards orange within 0.5), and a rough, blue-tinted solid one. */
function transmission({ only } = {}) {
  const doc = new Doc();
  doc.json.extensionsUsed = ['KHR_materials_transmission', 'KHR_materials_volume'];
  // Pastel colours (no channel near 0, where the tone mapping's toe magnifies what the two
  // renderers' shading of a lit wall differs by).
  const shift = only === 'panel' ? 1 : 3; // dispersion's panel: finer stripes, more edges
  const stripes = doc.texture(png(64, (x, y) => [[235, 140, 120, 255], [240, 215, 130, 255], [125, 155, 235, 255], [235, 235, 235, 255]][((x >> shift) + (y >> 4)) & 3]));
  doc.place(doc.geometry(quad(4.6)), doc.material({ name: 'backdrop', pbrMetallicRoughness: {
    baseColorTexture: { index: stripes }, metallicFactor: 0, roughnessFactor: 0.9 } }), [0, 0, -1.5], 'backdrop');
  // A panel 4.6 x 1.84 behind the spheres, not the whole frame.
  doc.json.nodes[doc.json.nodes.length - 1].scale = [1, 0.4, 1];
  if (only) return doc; // 'panel' (fine stripes) or 'backdrop': the panel alone
  const glass = (name, extensions, baseColorFactor = [1, 1, 1, 1], roughnessFactor = 0) => ({ name,
    pbrMetallicRoughness: { baseColorFactor, metallicFactor: 0, roughnessFactor }, extensions });
  const ball = doc.geometry(sphere(0.45));
  [
    glass('thin glass', { KHR_materials_transmission: { transmissionFactor: 1 } }),
    glass('amber', { KHR_materials_transmission: { transmissionFactor: 1 },
      KHR_materials_volume: { thicknessFactor: 0.9, attenuationDistance: 0.5, attenuationColor: [0.95, 0.55, 0.2] } }),
    glass('frosted', { KHR_materials_transmission: { transmissionFactor: 0.9 },
      KHR_materials_volume: { thicknessFactor: 0.9 } }, [0.6, 0.85, 1, 1], 0.35),
  ].forEach((m, i) => doc.place(ball, doc.material(m), [-1.5 + 1.5 * i, 0, 0], m.name));
  return doc;
}

/** KHR_materials_dispersion: three clear solid spheres (transmission, thickness 0.9, ior 1.5)
 * before transmission's panel with finer stripes, at dispersion 0, 20 and 60 (colour fringes
 * where the stripes' edges are seen through them). */
function dispersion() {
  const doc = transmission({ only: 'panel' });
  doc.json.extensionsUsed.push('KHR_materials_dispersion');
  const ball = doc.geometry(sphere(0.45));
  [0, 20, 60].forEach((d, i) => {
    const m = { name: `dispersion ${d}`, pbrMetallicRoughness: { baseColorFactor: [1, 1, 1, 1], metallicFactor: 0, roughnessFactor: 0 },
      extensions: { KHR_materials_transmission: { transmissionFactor: 1 }, KHR_materials_volume: { thicknessFactor: 0.9 },
        KHR_materials_dispersion: { dispersion: d } } };
    doc.place(ball, doc.material(m), [-1.5 + 1.5 * i, 0, 0], m.name);
  });
  return doc;
}

/** KHR_materials_iridescence: a dark rough dielectric (broad highlights) under a film of 400 nm (ior 1.3, the
 * defaults) and of 700 nm (ior 1.8), and a rough metal under a film of 300 nm at factor 0.8. */
function iridescence() {
  const doc = new Doc();
  const dark = { baseColorFactor: [0.04, 0.04, 0.05, 1], metallicFactor: 0, roughnessFactor: 0.6 };
  row(doc, [
    { name: 'film 400', pbrMetallicRoughness: dark, extensions: { KHR_materials_iridescence: { iridescenceFactor: 1 } } },
    { name: 'film 700', pbrMetallicRoughness: dark, extensions: { KHR_materials_iridescence: {
      iridescenceFactor: 1, iridescenceIor: 1.8, iridescenceThicknessMaximum: 700 } } },
    { name: 'metal film', pbrMetallicRoughness: { baseColorFactor: [0.9, 0.9, 0.92, 1], metallicFactor: 1, roughnessFactor: 0.6 },
      extensions: { KHR_materials_iridescence: { iridescenceFactor: 0.8, iridescenceThicknessMaximum: 300 } } },
  ], ['KHR_materials_iridescence']);
  return doc;
}

/** A sphere whose second texture coordinate set (TEXCOORD_1) is its first scaled by 3 in U
 * and 2 in V. */
function sphereUv1(radius) {
  const g = sphere(radius);
  return { ...g, uvs1: g.uvs.map((x, i) => x * (i % 2 ? 2 : 3)) };
}

/** Three spheres of `material(textureInfo)`, its texture `png` read three ways: as it is
 * (TEXCOORD_0), through a KHR_texture_transform (turned, scaled, moved), and from TEXCOORD_1
 * (the first set scaled by 3 x 2); before `backdrop`'s panel where given (transmission's). */
function textured(extension, png, material, backdrop) {
  const doc = backdrop ? transmission({ only: 'backdrop' }) : new Doc();
  doc.json.extensionsUsed = [...new Set([...(doc.json.extensionsUsed ?? []), ...extension, 'KHR_texture_transform'])];
  const texture = doc.texture(png);
  const ball = doc.geometry(sphereUv1(0.45));
  const infos = [
    ['texture', { index: texture }],
    ['transformed', { index: texture, extensions: { KHR_texture_transform: { offset: [0.1, 0.3], rotation: 0.6, scale: [2, 1.5] } } }],
    ['texCoord 1', { index: texture, texCoord: 1 }],
  ];
  infos.forEach(([name, info], i) => doc.place(ball, doc.material({ name, ...material(info) }), [-1.5 + 1.5 * i, 0, 0], name));
  return doc;
}

/** Stripes across V (rows of 8 texels), `on` and `off` texels in turn. */
const bands = (on, off) => png(64, (x, y) => ((y >> 3) & 1 ? on : off));
/** A checker of 8-texel squares, `on` and `off`. */
const checks = (on, off) => png(64, (x, y) => (((x >> 3) + (y >> 3)) & 1 ? on : off));

/** KHR_materials_transmission's transmissionTexture (red): thin clear glass where the bands
 * are red, an opaque white dielectric between, before transmission's panel. */
function transmissionTexture() {
  return textured(['KHR_materials_transmission'], bands([255, 0, 0, 255], [0, 0, 0, 255]), (info) => ({
    pbrMetallicRoughness: { baseColorFactor: [1, 1, 1, 1], metallicFactor: 0, roughnessFactor: 0.15 },
    extensions: { KHR_materials_transmission: { transmissionFactor: 1, transmissionTexture: info } } }), true);
}

/** KHR_materials_volume's thicknessTexture (green): solid amber glass (attenuation towards
 * orange within 0.3) of thickness 0.9 where the checker is green, 0.1 between. */
function thicknessTexture() {
  return textured(['KHR_materials_transmission', 'KHR_materials_volume'], checks([0, 255, 0, 255], [0, 28, 0, 255]), (info) => ({
    pbrMetallicRoughness: { baseColorFactor: [1, 1, 1, 1], metallicFactor: 0, roughnessFactor: 0 },
    extensions: { KHR_materials_transmission: { transmissionFactor: 1 },
      KHR_materials_volume: { thicknessFactor: 0.9, thicknessTexture: info, attenuationDistance: 0.3, attenuationColor: [0.95, 0.5, 0.15] } } }), true);
}

/** A dark, rough metal: broad highlights, which the films colour. */
const darkMetal = { baseColorFactor: [0.35, 0.35, 0.38, 1], metallicFactor: 1, roughnessFactor: 0.7 };

/** KHR_materials_iridescence's iridescenceTexture (red): a film of 550 nm (ior 1.8) over a
 * dark rough metal where the checker is red, none between. */
function iridescenceTexture() {
  return textured(['KHR_materials_iridescence'], checks([255, 0, 0, 255], [0, 0, 0, 255]), (info) => ({
    pbrMetallicRoughness: darkMetal,
    extensions: { KHR_materials_iridescence: { iridescenceFactor: 1, iridescenceTexture: info, iridescenceIor: 1.8,
      iridescenceThicknessMaximum: 550 } } }));
}

/** KHR_materials_iridescence's iridescenceThicknessTexture (green): a film (ior 1.8) over a
 * dark rough metal, 200 nm (the minimum) to 800 nm (the maximum) in four bands. */
function iridescenceThicknessTexture() {
  const steps = png(64, (x, y) => [0, [0, 85, 170, 255][(y >> 3) & 3], 0, 255]);
  return textured(['KHR_materials_iridescence'], steps, (info) => ({
    pbrMetallicRoughness: darkMetal,
    extensions: { KHR_materials_iridescence: { iridescenceFactor: 1, iridescenceIor: 1.8, iridescenceThicknessMinimum: 200,
      iridescenceThicknessMaximum: 800, iridescenceThicknessTexture: info } } }));
}

/** KHR_materials_anisotropy's anisotropyTexture (red-green: direction, blue: strength):
 * brushed copper streaked along the tangent in one band, along the bitangent in the next,
 * at strength 1 and 0.5 in turn, under an anisotropyStrength of 0.9 turned by 0.3. */
function anisotropyTexture() {
  const directions = png(64, (x, y) => {
    const [dx, dy] = (y >> 4) & 1 ? [0, 1] : [1, 0];
    return [Math.round((dx * 0.5 + 0.5) * 255), Math.round((dy * 0.5 + 0.5) * 255), (x >> 4) & 1 ? 255 : 128, 255];
  });
  return textured(['KHR_materials_anisotropy'], directions, (info) => ({
    pbrMetallicRoughness: { baseColorFactor: [0.95, 0.64, 0.54, 1], metallicFactor: 1, roughnessFactor: 0.35 },
    extensions: { KHR_materials_anisotropy: { anisotropyStrength: 0.9, anisotropyRotation: 0.3, anisotropyTexture: info } } }));
}

/** KHR_materials_clearcoat's clearcoatRoughnessTexture (green): a full coat over a red
 * dielectric, smooth (0.05) where the bands are dark, rough (0.8) where they are green. */
function clearcoatRoughnessTexture() {
  return textured(['KHR_materials_clearcoat'], bands([0, 255, 0, 255], [0, 16, 0, 255]), (info) => ({
    pbrMetallicRoughness: { baseColorFactor: [0.8, 0.1, 0.05, 1], metallicFactor: 0, roughnessFactor: 0.7 },
    extensions: { KHR_materials_clearcoat: { clearcoatFactor: 1, clearcoatRoughnessFactor: 0.8, clearcoatRoughnessTexture: info } } }));
}

/** KHR_materials_specular's specularTexture (alpha): a glossy grey dielectric of ior 2.4 whose
 * specular strength is 1 in the checker's opaque squares, 0.1 in the others. */
function specularTexture() {
  return textured(['KHR_materials_ior', 'KHR_materials_specular'], checks([255, 255, 255, 255], [255, 255, 255, 26]), (info) => ({
    pbrMetallicRoughness: { baseColorFactor: [0.25, 0.25, 0.25, 1], metallicFactor: 0, roughnessFactor: 0.3 },
    extensions: { KHR_materials_ior: { ior: 2.4 }, KHR_materials_specular: { specularFactor: 1, specularTexture: info } } }));
}

/** KHR_materials_variants: three spheres, two variants. The body (a white dielectric by
 * default) is red in "ruby" and a clear-coated blue in "sapphire"; the trim (gold) is silver
 * in "sapphire" and unmapped in "ruby"; the third sphere (green) is mapped by neither. */
function variants() {
  const doc = new Doc();
  doc.json.extensionsUsed = ['KHR_materials_variants', 'KHR_materials_clearcoat'];
  doc.json.extensions = { KHR_materials_variants: { variants: [{ name: 'ruby' }, { name: 'sapphire' }] } };
  const ball = doc.geometry(sphere(0.45));
  const pbr = (baseColorFactor, metallicFactor, roughnessFactor) => ({ baseColorFactor, metallicFactor, roughnessFactor });
  const white = doc.material({ name: 'white', pbrMetallicRoughness: pbr([0.8, 0.8, 0.8, 1], 0, 0.4) });
  const ruby = doc.material({ name: 'ruby', pbrMetallicRoughness: pbr([0.8, 0.03, 0.05, 1], 0, 0.25) });
  const sapphire = doc.material({ name: 'sapphire', pbrMetallicRoughness: pbr([0.05, 0.15, 0.8, 1], 0, 0.6),
    extensions: { KHR_materials_clearcoat: { clearcoatFactor: 1, clearcoatRoughnessFactor: 0.05 } } });
  const gold = doc.material({ name: 'gold', pbrMetallicRoughness: pbr([1, 0.77, 0.34, 1], 1, 0.3) });
  const silver = doc.material({ name: 'silver', pbrMetallicRoughness: pbr([0.95, 0.95, 0.95, 1], 1, 0.3) });
  const green = doc.material({ name: 'green', pbrMetallicRoughness: pbr([0.1, 0.6, 0.15, 1], 0, 0.5) });
  const mapped = (material, mappings, x, name) => {
    doc.json.meshes.push({ name, primitives: [{ ...ball, material,
      ...(mappings.length ? { extensions: { KHR_materials_variants: { mappings } } } : {}) }] });
    doc.json.nodes.push({ name, mesh: doc.json.meshes.length - 1, translation: [x, 0, 0] });
    doc.json.scenes[0].nodes.push(doc.json.nodes.length - 1);
  };
  mapped(white, [{ material: ruby, variants: [0] }, { material: sapphire, variants: [1] }], -1.5, 'body');
  mapped(gold, [{ material: silver, variants: [1] }], 0, 'trim');
  mapped(green, [], 1.5, 'plain');
  return doc;
}

/** World-space bounds of a document's meshes from the POSITION accessors' min and max (and
 * their morph targets'). */
function bounds(json) {
  const mul = (a, b) => a.map((_, i) => [0, 1, 2, 3].reduce((s, k) => s + a[(i & 12) + k] * b[k * 4 + (i & 3)], 0));
  const trs = (n) => {
    if (n.matrix) return transpose(n.matrix);
    const [x, y, z, w] = n.rotation ?? [0, 0, 0, 1], [sx, sy, sz] = n.scale ?? [1, 1, 1], t = n.translation ?? [0, 0, 0];
    // Row-major 4x4.
    return [
      (1 - 2 * (y * y + z * z)) * sx, 2 * (x * y - z * w) * sy, 2 * (x * z + y * w) * sz, t[0],
      2 * (x * y + z * w) * sx, (1 - 2 * (x * x + z * z)) * sy, 2 * (y * z - x * w) * sz, t[1],
      2 * (x * z - y * w) * sx, 2 * (y * z + x * w) * sy, (1 - 2 * (x * x + y * y)) * sz, t[2],
      0, 0, 0, 1];
  };
  const transpose = (m) => m.map((_, i) => m[(i % 4) * 4 + Math.floor(i / 4)]);
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  const visit = (index, parent) => {
    const node = json.nodes[index];
    const world = mul(parent, trs(node));
    if (node.mesh !== undefined) {
      for (const p of json.meshes[node.mesh].primitives) {
        const a = json.accessors[p.attributes.POSITION];
        // Morph targets at weights 0..1 each widen the box by their deltas' bounds.
        const [min, max] = [[...a.min], [...a.max]];
        for (const t of p.targets ?? []) {
          if (t.POSITION === undefined) continue;
          const d = json.accessors[t.POSITION];
          for (let k = 0; k < 3; k++) { min[k] += Math.min(d.min[k], 0); max[k] += Math.max(d.max[k], 0); }
        }
        for (let c = 0; c < 8; c++) {
          const v = [0, 1, 2].map((k) => ((c >> k) & 1 ? max[k] : min[k]));
          for (let k = 0; k < 3; k++) {
            const w = world[k * 4] * v[0] + world[k * 4 + 1] * v[1] + world[k * 4 + 2] * v[2] + world[k * 4 + 3];
            lo[k] = Math.min(lo[k], w); hi[k] = Math.max(hi[k], w);
          }
        }
      }
    }
    for (const child of node.children ?? []) visit(child, world);
  };
  const identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
  for (const n of json.scenes[json.scene ?? 0].nodes) visit(n, identity);
  return { lo, hi };
}

/** A camera from the front (+Z), a little above, whose view takes in the bounds' sphere. */
function framingEye(json) {
  const { lo, hi } = bounds(json);
  const centre = lo.map((x, i) => (x + hi[i]) / 2);
  const radius = Math.hypot(...hi.map((x, i) => x - lo[i])) / 2;
  const dist = radius / Math.sin(((YFOV_DEG * Math.PI) / 180) / 2) * 0.75;
  const dir = normalize([0.25, 0.3, 1]);
  return { eye: centre.map((x, i) => x + dir[i] * dist), target: centre };
}

/** The names of a document's KHR_materials_variants (none: []). */
function variantNames(json) {
  return (json.extensions?.KHR_materials_variants?.variants ?? []).map((v, i) => v.name ?? `variant${i}`);
}

function main() {
  const [out, ...inputs] = process.argv.slice(2);
  if (!out) { console.error('usage: node models.mjs OUT_DIR [NAME=FILE.glb|FILE.gltf (data: URIs) ...]'); process.exit(2); }
  mkdirSync(out, { recursive: true });
  // ASPECT is W/H (the image size, so that the viewer does not letterbox by a rounding).
  const [w, h] = (process.env.ASPECT ?? '4/3').split('/').map(Number);
  const aspect = w / h;
  const models = [
    ['spheres', spheres(), { eye: [0, 0, 10.5], target: [0, 0, 0] }],
    ['materials', materials(), { eye: [0, 1.6, 6.2], target: [0, 0.5, 0] }],
    ['clearcoat', clearcoat(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['sheen', sheen(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['specular', specular(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['anisotropy', anisotropy(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['transforms', transforms(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['emissive', emissive(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['variants', variants(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['transmission', transmission(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['iridescence', iridescence(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['dispersion', dispersion(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['transmission_texture', transmissionTexture(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['thickness_texture', thicknessTexture(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['iridescence_texture', iridescenceTexture(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['iridescence_thickness_texture', iridescenceThicknessTexture(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['anisotropy_texture', anisotropyTexture(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['clearcoat_roughness_texture', clearcoatRoughnessTexture(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
    ['specular_texture', specularTexture(), { eye: [0, 0.9, 6.6], target: [0, 0, 0] }],
  ];
  for (const [name, doc, { eye, target }] of models) {
    const camera = { ...addCameraAndLight(doc.json, eye, target, aspect), variants: variantNames(doc.json) };
    writeFileSync(join(out, `${name}.glb`), doc.glb());
    writeFileSync(join(out, `${name}.camera.json`), JSON.stringify(camera));
  }
  writeFileSync(join(out, 'sky.hdr'), sky());
  for (const arg of inputs) {
    const [name, file] = arg.split('=');
    let glb;
    try { glb = unpackGlb(readFileSync(file)); } catch (e) { console.error(`${file}: ${e.message}`); process.exit(2); }
    // A primitive without a material gets the glTF default material written out (`{}`: base
    // colour 1, metallic 1, roughness 1), which the viewer draws as it draws none; seamlit
    // gives material-less objects its own grey default instead.
    for (const mesh of glb.json.meshes ?? []) {
      for (const p of mesh.primitives) {
        if (p.material === undefined) {
          glb.json.materials ??= [];
          p.material = glb.json.materials.length;
          glb.json.materials.push({ name: 'glTF default' });
        }
      }
    }
    const { eye, target } = framingEye(glb.json);
    const camera = { ...addCameraAndLight(glb.json, eye, target, aspect), variants: variantNames(glb.json) };
    writeFileSync(join(out, `${name}.glb`), packGlb(glb.json, glb.bin));
    writeFileSync(join(out, `${name}.camera.json`), JSON.stringify(camera));
  }
}

main();
