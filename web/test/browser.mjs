// Shared by the page's browser checks: a static server for target/web on 127.0.0.1 and
// Debian's chromium, headless, with WebGPU on SwiftShader (Vulkan in software).
import { createServer } from "node:http";
import { readFile } from "node:fs/promises";
import { join, extname, normalize } from "node:path";
import { createRequire } from "node:module";

// puppeteer-core lives in .ci/node (installed by .ci/run), or PUPPETEER_DIR.
const require = createRequire(import.meta.url);
const root = new URL("../..", import.meta.url).pathname;
const puppeteer = require(join(process.env.PUPPETEER_DIR ?? join(root, ".ci/node/node_modules"), "puppeteer-core"));

const TYPES = { ".html": "text/html", ".js": "text/javascript", ".css": "text/css", ".wasm": "application/wasm" };

/** Serves `dir` on 127.0.0.1 (WebGPU needs a secure context: localhost is one); resolves to its base URL. */
export async function serve(dir) {
  const server = createServer(async (req, res) => {
    const path = normalize(decodeURIComponent(new URL(req.url, "http://x").pathname)).replace(/^\/+/, "");
    try {
      const body = await readFile(join(dir, path || "index.html"));
      res.writeHead(200, { "content-type": TYPES[extname(path || "index.html")] ?? "application/octet-stream" });
      res.end(body);
    } catch {
      res.writeHead(404);
      res.end();
    }
  });
  await new Promise((r) => server.listen(0, "127.0.0.1", r));
  return { server, base: `http://127.0.0.1:${server.address().port}` };
}

/** Chromium with WebGPU on SwiftShader; with `{ webgpu: false }`, with WebGPU turned off. */
export function launch({ webgpu = true } = {}) {
  const gpu = webgpu
    ? ["--enable-unsafe-webgpu", "--enable-features=Vulkan", "--use-webgpu-adapter=swiftshader",
      "--use-vulkan=swiftshader", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
      "--ignore-gpu-blocklist"]
    : ["--disable-features=WebGPU"];
  return puppeteer.launch({
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
    headless: true,
    protocolTimeout: 0,
    // A loaded machine (CI's builds beside it) can take more than puppeteer's 30 s to start it.
    timeout: 180000,
    args: ["--no-sandbox", "--disable-dev-shm-usage", ...gpu],
  });
}

/** Opens the page, forwarding its console errors; waits until it is ready or has failed. */
export async function openPage(browser, base, log = console.error) {
  const page = await browser.newPage();
  page.on("console", (m) => { if (m.type() === "error" || m.type() === "warn") log(`  page: ${m.text()}`); });
  page.on("pageerror", (e) => log(`  page: ${e.message}`));
  await page.setViewport({ width: 1200, height: 900 });
  await page.goto(`${base}/index.html`);
  await page.waitForFunction("document.body.dataset.state !== undefined", { timeout: 120000 });
  return page;
}
