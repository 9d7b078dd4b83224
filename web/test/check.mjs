// The page's browser checks (web/test/run.sh runs them): headless chromium, WebGPU on
// SwiftShader. Usage: node check.mjs SITE_DIR OUT_DIR
// - the page starts, draws seamlit demo's teapot and writes the canvas to OUT/canvas-demo.png
//   (run.sh compares it with `seamlit demo`'s picture by FLIP);
// - files through #file: Fox.glb shows, its download is the file `seamlit fix` writes (OUT/cli,
//   written by run.sh), #summary the lines it prints and #report exactly what `seamlit inspect
//   --json` prints, and with the page's options set (normals recompute, crease 30) the file
//   `seamlit fix` writes with those flags; a glTF picked with its .bin and images, and an OBJ
//   with its MTL and texture, a VRM 0.x avatar and a USDZ come out as `seamlit fix` writes
//   them (the OBJ's files as one zip); a corrupted GLB gets one line naming it, and the next model loads;
// - all of it offline (the network cut once the page is loaded) and without one request;
// - a browser without WebGPU gets one line in #error and nothing else breaks.
// Prints one JSON line of measurements; exits 1 on the first failed check.
import { writeFile, readFile, mkdir, readdir } from "node:fs/promises";
import { createHash } from "node:crypto";
import { execFileSync } from "node:child_process";
import { serve, launch, openPage } from "./browser.mjs";

const [dir, out] = process.argv.slice(2);
await mkdir(out, { recursive: true });
const { server, base } = await serve(dir);
const fail = (what) => { console.error(`web check failed: ${what}`); process.exitCode = 1; };
const result = {};
const sha256 = (bytes) => createHash("sha256").update(bytes).digest("hex");
// The page's download: its name and bytes (written to OUT/page/NAME).
async function download(page) {
  const got = await page.evaluate(async () => {
    const link = document.getElementById("download");
    const bytes = new Uint8Array(await (await fetch(link.href)).arrayBuffer());
    let text = "";
    for (let i = 0; i < bytes.length; i += 0x8000) text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
    return { hidden: link.hidden, name: link.download, base64: btoa(text) };
  });
  const bytes = Buffer.from(got.base64, "base64");
  await mkdir(`${out}/page`, { recursive: true });
  await writeFile(`${out}/page/${got.name}`, bytes);
  return { hidden: got.hidden, name: got.name, bytes };
}
// The files of a zip, by name: their SHA-256 (Python's zipfile reads it).
function zipDigests(path) {
  const script = "import hashlib, json, sys, zipfile\n" +
    "z = zipfile.ZipFile(sys.argv[1])\n" +
    "print(json.dumps({n: hashlib.sha256(z.read(n)).hexdigest() for n in sorted(z.namelist())}))";
  return JSON.parse(execFileSync("python3", ["-c", script, path], { encoding: "utf8" }));
}
// The page's #report against what `seamlit inspect --json` printed (run.sh, OUT/cli/NAME.json).
async function sameReport(page, cliJson, what) {
  const report = await page.$eval("#report", (e) => e.textContent);
  const cli = await readFile(cliJson, "utf8");
  if (report !== cli) fail(`${what}: #report is not what seamlit inspect --json prints (${report.length} against ${cli.length} characters)`);
  return report === cli;
}
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

    // Nothing leaves the page once it is loaded: every request from here on is counted
    // (the downloads' blob: URLs are the page's own memory), and the network is cut.
    const requests = [];
    page.on("request", (r) => { if (!r.url().startsWith("blob:") && !r.url().startsWith("data:")) requests.push(r.url()); });
    await page.setOfflineMode(true);

    // Files through #file: a model, a corrupted one (one line naming it), then the next.
    const input = await page.$("#file");
    let loads = 0;
    const load = async (...paths) => {
      await input.uploadFile(...paths);
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
    // The canvas, for run.sh to compare with `seamlit render` of the same look (FLIP).
    const shoot = async (name) => {
      await new Promise((r) => setTimeout(r, 500));
      await writeFile(`${out}/canvas-${name}.png`, await (await page.$("#view")).screenshot());
    };
    await shoot("Fox.glb");
    // The download is the file `seamlit fix` writes (run.sh wrote it to OUT/cli/Fox.glb, and
    // what it printed to OUT/cli/Fox.txt), #summary says what the command line says, and
    // #report is what `seamlit inspect --json Fox.glb` prints.
    const offered = await download(page);
    const summary = await page.$eval("#summary", (e) => e.textContent);
    const cliBytes = await readFile(`${out}/cli/Fox.glb`);
    const cliSha = sha256(cliBytes);
    const cliText = (await readFile(`${out}/cli/Fox.txt`, "utf8")).trim().replace(`${out}/cli/Fox.glb`, "Fox.glb");
    result.download = { name: offered.name, bytes: offered.bytes.length, sameAsCli: sha256(offered.bytes) === cliSha };
    if (offered.hidden || offered.name !== "Fox.glb") fail(`the download of Fox.glb: ${JSON.stringify(result.download)}`);
    if (sha256(offered.bytes) !== cliSha) fail(`the page's Fox.glb (${offered.bytes.length} bytes) is not seamlit fix's (${cliBytes.length} bytes)`);
    if (summary.split("\n")[0] !== cliText.split("\n")[0] || !summary.startsWith(cliText)) {
      fail(`the page's summary is not seamlit fix's: ${JSON.stringify(summary)} vs ${JSON.stringify(cliText)}`);
    }
    result.download.reportAsInspect = await sameReport(page, `${out}/cli/Fox.json`, "Fox.glb");
    // The page's options are the command line's flags: recompute the normals with a crease
    // of 30 degrees, and the download is `seamlit fix --normals recompute --crease 30`'s file.
    await page.select("#normals", "recompute");
    await page.waitForFunction(() => Number(document.body.dataset.fixes ?? 0) >= 1, { timeout: 120000 });
    await page.$eval("#crease", (e) => { e.value = "30"; e.dispatchEvent(new Event("change")); });
    await page.waitForFunction(() => Number(document.body.dataset.fixes ?? 0) >= 2, { timeout: 120000 });
    const refixed = {
      error: await page.$eval("#error", (e) => e.textContent),
      sha256: sha256((await download(page)).bytes),
      options: JSON.parse(await page.evaluate(() => window.seamlit.report())).options,
    };
    const recomputed = sha256(await readFile(`${out}/cli/Fox-recompute.glb`));
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
    // A glTF picked with its buffer and images (no folders): the download is the GLB
    // `seamlit fix ClearCoatTest.gltf -o ClearCoatTest.glb` writes, #report its inspect.
    const coat = `${models}clearcoat_test/`;
    const coatFiles = (await readdir(coat)).map((f) => coat + f);
    const gltf = await load(...coatFiles);
    await shoot("ClearCoatTest.gltf");
    const gltfOffered = await download(page);
    const gltfCli = await readFile(`${out}/cli/ClearCoatTest.glb`);
    result.gltf = { status: gltf.status, files: coatFiles.length, name: gltfOffered.name, sameAsCli: gltfOffered.bytes.equals(gltfCli) };
    if (gltf.error || gltfOffered.name !== "ClearCoatTest.glb" || !gltfOffered.bytes.equals(gltfCli)) {
      fail(`ClearCoatTest.gltf with its files: ${JSON.stringify(result.gltf)} ${gltf.error}`);
    }
    result.gltf.reportAsInspect = await sameReport(page, `${out}/cli/ClearCoatTest.json`, "ClearCoatTest.gltf");
    // An OBJ with its MTL and texture (run.sh made it in OUT/spot): the download is a zip of
    // the files `seamlit fix spot.obj -o cli/spot/spot.obj` writes.
    const spot = `${out}/spot/`;
    const obj = await load(`${spot}spot.obj`, `${spot}spot.mtl`, `${spot}textures/spot_texture.png`);
    const objOffered = await download(page);
    const objZip = zipDigests(`${out}/page/${objOffered.name}`);
    const objCli = {};
    for (const name of ["spot.mtl", "spot.obj", "textures/spot_texture.png"]) objCli[name] = sha256(await readFile(`${out}/cli/spot/${name}`));
    result.obj = { status: obj.status, name: objOffered.name, files: Object.keys(objZip), sameAsCli: JSON.stringify(objZip) === JSON.stringify(objCli) };
    if (obj.error || objOffered.name !== "spot.zip" || !result.obj.sameAsCli) {
      fail(`spot.obj with its MTL and texture: ${JSON.stringify({ ...result.obj, objZip, objCli })} ${obj.error}`);
    }
    result.obj.reportAsInspect = await sameReport(page, `${out}/cli/spot.json`, "spot.obj");
    // A VRM 0.x avatar and a USDZ: the download is the .vrm and the package `seamlit fix`
    // writes, #report its inspect.
    for (const [path, name, json] of [[`${out}/fox.vrm`, "fox.vrm", "fox.json"], [`${models}usd/head_body.usdz`, "head_body.usdz", "head_body.json"]]) {
      const loaded = await load(path);
      const offered = await download(page);
      const cli = await readFile(`${out}/cli/${name}`);
      const checked = { status: loaded.status, name: offered.name, sameAsCli: offered.bytes.equals(cli) };
      if (loaded.error || offered.name !== name || !checked.sameAsCli) fail(`${name}: ${JSON.stringify(checked)} ${loaded.error}`);
      checked.reportAsInspect = await sameReport(page, `${out}/cli/${json}`, name);
      result[name] = checked;
      await shoot(name);
    }
    // A glTF without its buffer: one line naming the file it needs.
    const nobin = await load(`${coat}ClearCoatTest.gltf`);
    result.missing = nobin.error;
    if (!/^ClearCoatTest\.gltf.*ClearCoatTest\.bin/.test(nobin.error) || nobin.error.includes("\n")) fail(`a glTF without its .bin: ${JSON.stringify(nobin)}`);
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
    // Offline all along, and no request made: every model was read, fixed and offered here.
    result.requestsAfterLoad = requests.length;
    if (requests.length) fail(`the page made requests after it loaded: ${requests.slice(0, 3).join(", ")}`);
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
