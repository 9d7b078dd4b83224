// The page's browser checks (web/test/run.sh runs them): headless chromium, WebGPU on
// SwiftShader. Usage: node check.mjs SITE_DIR OUT_DIR
// - the page starts, draws seamlit demo's teapot and writes the canvas to OUT/canvas-demo.png
//   (run.sh compares it with `seamlit demo`'s picture by FLIP);
// - files through #file: Fox.glb shows, its download is the file `seamlit fix` writes (OUT/cli,
//   written by run.sh) and its report the lines it prints, and with the page's options set
//   (normals recompute, crease 30) the file `seamlit fix` writes with those flags; a corrupted GLB gets one line naming it, and the next
//   model loads;
// - a browser without WebGPU gets one line in #error and nothing else breaks.
// Prints one JSON line of measurements; exits 1 on the first failed check.
import { writeFile, readFile, mkdir } from "node:fs/promises";
import { createHash } from "node:crypto";
import { serve, launch, openPage } from "./browser.mjs";

const [dir, out] = process.argv.slice(2);
await mkdir(out, { recursive: true });
const { server, base } = await serve(dir);
const fail = (what) => { console.error(`web check failed: ${what}`); process.exitCode = 1; };
const result = {};
try {
  const browser = await launch();
  try {
    const page = await openPage(browser, base);
    const state = await page.evaluate(() => document.body.dataset.state);
    const error = await page.$eval("#error", (e) => e.textContent);
    result.adapter = await page.$eval("#status", (e) => e.textContent);
    result.times = JSON.parse(await page.evaluate(() => document.body.dataset.times ?? "{}"));
    if (state !== "ready" || error) fail(`the page did not draw the demo: state ${state}, error ${JSON.stringify(error)}`);
    await writeFile(`${out}/canvas-demo.png`, await (await page.$("#view")).screenshot());

    // Files through #file: a model, a corrupted one (one line naming it), then the next.
    const input = await page.$("#file");
    let loads = 0;
    const load = async (path) => {
      await input.uploadFile(path);
      loads += 1;
      await page.waitForFunction((n) => Number(document.body.dataset.loads ?? 0) >= n, { timeout: 120000 }, loads);
      return {
        error: await page.$eval("#error", (e) => e.textContent),
        status: await page.$eval("#status", (e) => e.textContent),
      };
    };
    const models = new URL("../../assets/models/", import.meta.url).pathname;
    const fox = await load(`${models}fox/Fox.glb`);
    if (fox.error || !/^Fox\.glb: 1 objects, 576 triangles/.test(fox.status)) fail(`Fox.glb: ${JSON.stringify(fox)}`);
    // The download is the file `seamlit fix` writes (run.sh wrote it to OUT/cli/Fox.glb, and
    // what it printed to OUT/cli/Fox.txt), and the report says what the command line says.
    const offered = await page.evaluate(async () => {
      const link = document.getElementById("download");
      const bytes = await (await fetch(link.href)).arrayBuffer();
      const digest = new Uint8Array(await crypto.subtle.digest("SHA-256", bytes));
      return {
        hidden: link.hidden,
        name: link.download,
        bytes: bytes.byteLength,
        sha256: [...digest].map((b) => b.toString(16).padStart(2, "0")).join(""),
        report: document.getElementById("report").textContent,
      };
    });
    const cliBytes = await readFile(`${out}/cli/Fox.glb`);
    const cliSha = createHash("sha256").update(cliBytes).digest("hex");
    const cliText = (await readFile(`${out}/cli/Fox.txt`, "utf8")).trim().replace(`${out}/cli/Fox.glb`, "Fox.glb");
    result.download = { name: offered.name, bytes: offered.bytes, sameAsCli: offered.sha256 === cliSha };
    if (offered.hidden || offered.name !== "Fox.glb") fail(`the download of Fox.glb: ${JSON.stringify(offered)}`);
    if (offered.sha256 !== cliSha) fail(`the page's Fox.glb (${offered.bytes} bytes) is not seamlit fix's (${cliBytes.length} bytes)`);
    if (offered.report.split("\n")[0] !== cliText.split("\n")[0] || !offered.report.startsWith(cliText)) {
      fail(`the page's report is not seamlit fix's: ${JSON.stringify(offered.report)} vs ${JSON.stringify(cliText)}`);
    }
    // The page's options are the command line's flags: recompute the normals with a crease
    // of 30 degrees, and the download is `seamlit fix --normals recompute --crease 30`'s file.
    await page.select("#normals", "recompute");
    await page.waitForFunction(() => Number(document.body.dataset.fixes ?? 0) >= 1, { timeout: 120000 });
    await page.$eval("#crease", (e) => { e.value = "30"; e.dispatchEvent(new Event("change")); });
    await page.waitForFunction(() => Number(document.body.dataset.fixes ?? 0) >= 2, { timeout: 120000 });
    const refixed = await page.evaluate(async () => {
      const link = document.getElementById("download");
      const bytes = await (await fetch(link.href)).arrayBuffer();
      const digest = new Uint8Array(await crypto.subtle.digest("SHA-256", bytes));
      return {
        error: document.getElementById("error").textContent,
        sha256: [...digest].map((b) => b.toString(16).padStart(2, "0")).join(""),
        options: JSON.parse(window.seamlit.report()).options,
      };
    });
    const recomputed = createHash("sha256").update(await readFile(`${out}/cli/Fox-recompute.glb`)).digest("hex");
    result.options = { ...refixed.options, sameAsCli: refixed.sha256 === recomputed };
    if (refixed.error || refixed.options.crease_angle_deg !== 30 || refixed.options.normals !== "recompute") {
      fail(`the page's options: ${JSON.stringify(refixed)}`);
    }
    if (refixed.sha256 !== recomputed || refixed.sha256 === cliSha) {
      fail(`the page's Fox.glb with --normals recompute --crease 30 is not seamlit fix's`);
    }
    // Back to the defaults for the checks below.
    await page.select("#normals", "auto");
    await page.$eval("#crease", (e) => { e.value = "60"; e.dispatchEvent(new Event("change")); });
    // An OBJ, read from memory: the download is the GLB `seamlit fix groups.obj` writes.
    const obj = await load(`${models}groups.obj`);
    if (obj.error) throw new Error(`groups.obj: ${obj.error}`);
    const objOffered = await page.evaluate(async () => {
      const link = document.getElementById("download");
      const bytes = await (await fetch(link.href)).arrayBuffer();
      const digest = new Uint8Array(await crypto.subtle.digest("SHA-256", bytes));
      return { name: link.download, sha256: [...digest].map((b) => b.toString(16).padStart(2, "0")).join("") };
    });
    const objCli = createHash("sha256").update(await readFile(`${out}/cli/groups.glb`)).digest("hex");
    result.obj = { status: obj.status, name: objOffered.name, sameAsCli: objOffered.sha256 === objCli };
    if (obj.error || !/^groups\.obj: \d+ objects/.test(obj.status) || objOffered.name !== "groups.glb" || objOffered.sha256 !== objCli) {
      fail(`groups.obj: ${JSON.stringify({ obj, objOffered })}`);
    }
    await writeFile(`${out}/canvas-fox.png`, await (await page.$("#view")).screenshot());
    const good = await readFile(`${models}lowpoly/kenney-platformer-blockLevel.glb`);
    await writeFile(`${out}/broken.glb`, good.subarray(0, good.length >> 1));
    const broken = await load(`${out}/broken.glb`);
    if (!/^broken\.glb/.test(broken.error) || broken.error.includes("\n")) fail(`broken.glb: ${JSON.stringify(broken)}`);
    result.corrupted = broken.error;
    const next = await load(`${models}lowpoly/kenney-platformer-blockLevel.glb`);
    if (next.error || !/^kenney-platformer-blockLevel\.glb: \d+ objects/.test(next.status)) {
      fail(`after the corrupted file: ${JSON.stringify(next)}`);
    }
    result.loaded = [fox.status, next.status];
    await writeFile(`${out}/canvas-blocklevel.png`, await (await page.$("#view")).screenshot());
  } finally {
    await browser.close();
  }
  // Without WebGPU: one line, no exception.
  const plain = await launch({ webgpu: false });
  try {
    const page = await openPage(plain, base, () => {});
    const state = await page.evaluate(() => document.body.dataset.state);
    const error = await page.$eval("#error", (e) => e.textContent);
    result.noWebGpu = error;
    if (state !== "no-webgpu" || !/WebGPU/.test(error) || error.includes("\n")) {
      fail(`without WebGPU: state ${state}, error ${JSON.stringify(error)}`);
    }
  } finally {
    await plain.close();
  }
} finally {
  server.close();
}
console.log(JSON.stringify(result));
