// Renders models in the Khronos glTF Sample Viewer in headless Chromium (WebGL2 through
// SwiftShader), driven by puppeteer-core: page.html does the rendering, this serves it and
// the files and saves the pictures.
// Usage: node render.mjs JOBS.json
// JOBS.json: [{ "model": "FILE.glb", "camera": N, "width": W, "height": H,
//               "clearColor": [r, g, b] (0..255), "out": "OUT.png",
//               "environment": "FILE.hdr", "useIBL": true|false, "environmentIntensity": X,
//               "environmentRotation": DEGREES, "animation": N (optional), "time": SECONDS,
//               "variant": NAME (optional: a KHR_materials_variants variant) }, ...]
// With useIBL false the environment lights nothing (the viewer needs one loaded all the same).
// CHROMIUM names the browser (default /usr/bin/chromium).

import { createServer } from 'node:http';
import { readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const here = dirname(fileURLToPath(import.meta.url));
const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript',
  '.wasm': 'application/wasm', '.png': 'image/png' };

/** The viewer's environment prefilter settings and the cheap ones page.html?punctual uses. */
const FULL_IBL = ['this.textureSize = 256;', 'this.ggxSampleCount = 1024;', 'this.lambertianSampleCount = 2048;', 'this.lutResolution = 1024;'];
const CHEAP_IBL = ['this.textureSize = 16;', 'this.ggxSampleCount = 4;', 'this.lambertianSampleCount = 4;', 'this.lutResolution = 16;'];

/** Serves this folder, and each job's model and environment as /job/N/model.glb, env.hdr. */
function serve(jobs) {
  return createServer((req, res) => {
    const url = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    const job = url.match(/^\/job\/(\d+)\/(model\.glb|env\.hdr)$/);
    let file;
    if (job) file = job[2] === 'model.glb' ? jobs[job[1]].model : jobs[job[1]].environment;
    else if (!url.includes('..')) file = join(here, url);
    try {
      let body = readFileSync(file);
      if (file.endsWith('gltf-viewer.module.js') && req.url.endsWith('?punctual')) {
        let text = body.toString('utf8');
        FULL_IBL.forEach((line, k) => { text = text.replace(line, CHEAP_IBL[k]); });
        body = Buffer.from(text);
      }
      const ext = file.slice(file.lastIndexOf('.'));
      res.writeHead(200, { 'content-type': TYPES[ext] ?? 'application/octet-stream' });
      res.end(body);
    } catch {
      res.writeHead(404);
      res.end();
    }
  });
}

async function main() {
  const jobsFile = process.argv[2];
  if (!jobsFile) { console.error('usage: node render.mjs JOBS.json'); process.exit(2); }
  const jobs = JSON.parse(readFileSync(jobsFile, 'utf8'));
  const server = serve(jobs);
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  const base = `http://127.0.0.1:${server.address().port}`;
  const browser = await puppeteer.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    protocolTimeout: 0,
    args: ['--no-sandbox', '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      '--ignore-gpu-blocklist', '--enable-webgl', '--disable-dev-shm-usage'],
  });
  let failed = false;
  try {
    for (const [i, job] of jobs.entries()) {
      const page = await browser.newPage();
      page.on('console', (m) => { if (m.type() === 'error') console.error(`  viewer: ${m.text()}`); });
      page.on('pageerror', (e) => console.error(`  viewer: ${e.message}`));
      page.on('requestfailed', (r) => console.error(`  viewer: ${r.url()} failed`));
      page.on('response', (r) => { if (r.status() >= 400) console.error(`  viewer: ${r.url()}: ${r.status()}`); });
      await page.setViewport({ width: job.width, height: job.height });
      await page.goto(`${base}/page.html${job.useIBL ? '' : '?punctual'}`);
      await page.waitForFunction('window.viewerReady === true', { timeout: 60000 });
      const png = await page.evaluate((opts) => window.renderModel(opts), {
        model: `${base}/job/${i}/model.glb`, camera: job.camera, width: job.width, height: job.height,
        clearColor: job.clearColor, environment: `${base}/job/${i}/env.hdr`, useIBL: job.useIBL,
        environmentIntensity: job.environmentIntensity ?? 1, environmentRotation: job.environmentRotation ?? 90,
        animation: job.animation ?? null, time: job.time ?? 0, variant: job.variant ?? null,
      }).catch((e) => { console.error(`${job.model}: ${e.stack ?? e.message}`); failed = true; return null; });
      if (png) writeFileSync(job.out, Buffer.from(png.split(',')[1], 'base64'));
      await page.close();
    }
  } finally {
    await browser.close();
    server.close();
  }
  process.exit(failed ? 1 : 0);
}

main();
