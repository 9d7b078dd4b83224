// The page's glue: the wasm module (crates/seamlit-web) does the work, this file wires the
// canvas, the file input, drag and drop and the controls to it.
import init, { Viewer } from "./pkg/seamlit_web.js";

const $ = (id) => document.getElementById(id);
const error = (line) => { $("error").textContent = line; };
const status = (line) => { $("status").textContent = line; };

let viewer = null;
let pending = false;
// Draws on the next animation frame, once however many changes ask for it.
function redraw() {
  if (!viewer || pending) return;
  pending = true;
  requestAnimationFrame(() => {
    pending = false;
    try { viewer.draw(); } catch (e) { error(String(e.message ?? e)); }
  });
}

// Times since navigation started (performance.now()'s origin), for BENCHMARKS.md: the wasm
// module compiled and instantiated, WebGPU opened, the demo's first picture on the canvas.
const times = {};
async function start() {
  await init();
  times.wasmMs = performance.now();
  // For measurements from the console or puppeteer (web/test/bench.mjs, check.mjs).
  window.seamlit = { Viewer, report: () => (viewer ? viewer.report : ""), fixed: () => (viewer ? viewer.fixed : "") };
  try {
    viewer = await Viewer.create($("view"));
    times.webgpuMs = performance.now();
  } catch (e) {
    error(String(e.message ?? e));
    document.body.dataset.state = "no-webgpu";
    return;
  }
  status(`WebGPU: ${viewer.adapter()}`);
  try {
    // `seamlit demo`'s teapot: 8 quads a patch side.
    viewer.showDemo(8);
    times.demoMs = performance.now();
    viewer.draw();
    times.drawnMs = performance.now();
  } catch (e) {
    error(String(e.message ?? e));
    document.body.dataset.state = "error";
    return;
  }
  // The picture is on the canvas once the GPU has finished the frame.
  await new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve)));
  status(`WebGPU: ${viewer.adapter()}. The demo teapot: ${viewer.marked} shared positions whose normals differ are marked on it as loaded.`);
  document.body.dataset.marked = String(viewer.marked);
  times.firstPictureMs = performance.now();
  document.body.dataset.times = JSON.stringify(times);
  document.body.dataset.state = "ready";
}

// Orbit camera: drag to turn, wheel to zoom.
const canvas = $("view");
let drag = null;
canvas.addEventListener("pointerdown", (e) => { drag = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
canvas.addEventListener("pointerup", () => { drag = null; });
canvas.addEventListener("pointermove", (e) => {
  if (!drag || !viewer) return;
  viewer.rotate(e.clientX - drag[0], e.clientY - drag[1]);
  drag = [e.clientX, e.clientY];
  redraw();
});
canvas.addEventListener("wheel", (e) => {
  if (!viewer) return;
  e.preventDefault();
  viewer.zoom(-Math.sign(e.deltaY));
  redraw();
}, { passive: false });

for (const radio of document.querySelectorAll("input[name=view]")) {
  radio.addEventListener("change", () => { viewer?.setView(radio.value); redraw(); });
}
for (const radio of document.querySelectorAll("input[name=state]")) {
  radio.addEventListener("change", () => { viewer?.setFixed(radio.value === "fixed"); redraw(); });
}

// Files: the picker and drag and drop. Each file is named by its path below what was
// dropped (a folder keeps its tree), so that a glTF finds its buffers and images and an OBJ
// its material libraries and textures; the wasm side picks the model among them.
async function takeFiles(files) {
  error("");
  if (!files.length || !viewer) return;
  document.body.dataset.state = "loading";
  try {
    const names = files.map((f) => f.path ?? (f.webkitRelativePath || f.name));
    const contents = await Promise.all(files.map(async (f) => new Uint8Array(await f.arrayBuffer())));
    offer(null);
    const summary = viewer.loadFiles(names, contents);
    status(summary);
    offer(viewer);
    redraw();
    document.body.dataset.state = "ready";
  } catch (e) {
    error(String(e.message ?? e).split("\n")[0]);
    document.body.dataset.state = "ready";
  }
  document.body.dataset.loads = String(Number(document.body.dataset.loads ?? 0) + 1);
}

// The files of a drop, folders walked (FileSystemEntry): each with `path`, its path below
// what was dropped.
async function droppedFiles(items) {
  const entries = [...items].map((i) => i.webkitGetAsEntry?.()).filter(Boolean);
  const files = [];
  const walk = async (entry, prefix) => {
    if (entry.isFile) {
      const file = await new Promise((ok, fail) => entry.file(ok, fail));
      file.path = prefix + file.name;
      files.push(file);
    } else if (entry.isDirectory) {
      const reader = entry.createReader();
      for (;;) {
        const batch = await new Promise((ok, fail) => reader.readEntries(ok, fail));
        if (!batch.length) break;
        for (const child of batch) await walk(child, `${prefix}${entry.name}/`);
      }
    }
  };
  for (const entry of entries) await walk(entry, "");
  return files;
}
// The fix options: the command line's flags --crease, --normals and --tangents. A change fixes
// the model shown again, and its download and report follow.
function fixOptions() {
  const fix = { crease_angle_deg: Number($("crease").value), normals: $("normals").value };
  const tangents = $("tangents").value;
  if (tangents) fix.tangents = tangents;
  return JSON.stringify({ fix, tangents_asked: tangents !== "" });
}
for (const id of ["crease", "normals", "tangents"]) {
  $(id).addEventListener("change", () => {
    if (!viewer) return;
    error("");
    try {
      viewer.setOptions(fixOptions());
      offer(viewer.outputName ? viewer : null);
      redraw();
    } catch (e) {
      error(String(e.message ?? e).split("\n")[0]);
    }
    document.body.dataset.fixes = String(Number(document.body.dataset.fixes ?? 0) + 1);
  });
}

// The fixed file as a download, the seam report and what the fix did, for the model just
// loaded (or nothing).
let downloadUrl = null;
function offer(loaded) {
  const link = $("download");
  if (downloadUrl) URL.revokeObjectURL(downloadUrl);
  downloadUrl = null;
  link.hidden = true;
  $("report").textContent = "";
  $("summary").textContent = "";
  if (!loaded) return;
  const fixed = JSON.parse(loaded.fixed);
  const type = loaded.outputName.endsWith(".zip") ? "application/zip" : "model/gltf-binary";
  downloadUrl = URL.createObjectURL(new Blob([loaded.outputBytes], { type }));
  link.href = downloadUrl;
  link.download = loaded.outputName;
  link.textContent = `download the fixed file (${loaded.outputName})`;
  link.hidden = false;
  const warnings = fixed.warnings.map((w) => `warning: ${w}`);
  $("summary").textContent = [fixed.summary, ...warnings].join("\n");
  $("report").textContent = loaded.report;
}
$("file").addEventListener("change", (e) => takeFiles([...e.target.files]));
const drop = $("drop");
drop.addEventListener("dragover", (e) => { e.preventDefault(); drop.classList.add("over"); });
drop.addEventListener("dragleave", () => drop.classList.remove("over"));
drop.addEventListener("drop", (e) => {
  e.preventDefault();
  drop.classList.remove("over");
  droppedFiles(e.dataTransfer.items).then((files) => takeFiles(files.length ? files : [...e.dataTransfer.files]));
});

start();
