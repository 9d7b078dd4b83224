// The page's figures for BENCHMARKS.md: node bench.mjs SITE_DIR [N] [RUNS]
// Loads the page (times since navigation: wasm ready, WebGPU open, first picture of the demo),
// then fixes the demo teapot at N quads a patch side (125: 1,000,000 triangles) RUNS times with
// each tangent method inside the page (one thread: wasm32 without threads) and prints each time.
import { serve, launch, openPage } from "./browser.mjs";

const [dir, n = "125", runs = "3"] = process.argv.slice(2);
const { server, base } = await serve(dir);
const browser = await launch();
try {
  const page = await openPage(browser, base);
  console.log("page times (ms since navigation):", await page.evaluate(() => document.body.dataset.times));
  for (const tangents of ["mikktspace", "seamlit"]) {
    for (let i = 0; i < Number(runs); i++) {
      const [triangles, ms] = await page.evaluate((n, t) => Array.from(window.seamlit.Viewer.timeDemoFix(n, t)), Number(n), tangents);
      console.log(`${triangles} triangles, tangents ${tangents}: ${Math.round(ms)} ms`);
    }
  }
} finally {
  await browser.close();
  server.close();
}
