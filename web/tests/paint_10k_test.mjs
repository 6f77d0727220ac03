// Browser test of painting at 10,000 strands in `wisp edit` (registered in ctest as editor.*):
// headless Chromium on software GL (SwiftShader) used to crash while a brush ran at 10k+
// strands, each preview of the stroke allocating new GPU buffers for the whole hair. Here a
// long stroke (40 pointer moves, with a preview after each map that reaches the server) runs
// on a 10,000-strand style; the page must stay alive (no crash, no lost WebGL context),
// draw the full hair after the stroke, and have reused its buffers (allocations counted by
// the viewport stay a handful, not one per preview). Screenshots go to OUT_DIR.
//   node web/tests/paint_10k_test.mjs WISP_EXE OUT_DIR
import { failWith, launchChromium, openEditor, settler, startEditor, tempFolder, testArguments } from "./harness.mjs";
import { rmSync } from "node:fs";
import path from "node:path";

const { wisp, outDir } = testArguments();
const fail = failWith("paint 10k test");

const folder = tempFolder("paint10k", { "style.toml": "[roots]\nstrands = 10000\nwisps = 400\npoints_per_strand = 16\n" });
const { server, url, token } = await startEditor(wisp, ["style.toml"], folder);

let browser;
let crashed = false;
try {
  browser = await launchChromium();
  const page = await openEditor(browser, url);
  page.on("crash", () => { crashed = true; console.error("the page crashed"); });
  await page.waitForSelector("body[data-ready='1']", { timeout: 180000 });
  await page.evaluate(() => {
    window.contextLost = 0;
    window.wispEditor.viewport.renderer.domElement.addEventListener("webglcontextlost", () => ++window.contextLost);
  });
  const drawn = () => page.evaluate(() => window.wispEditor.viewport.stats());
  const start = await drawn();
  console.log(`before the stroke: ${JSON.stringify(start)}`);
  if (start.strands !== 10000) fail(`the page draws ${start.strands} strands, not 10,000`);

  await page.click("#paint");
  await page.waitForFunction(() => window.wispEditor?.painter.map !== null);
  await page.locator("#brush-radius").evaluate((e) => { e.value = 4; e.dispatchEvent(new Event("input")); });
  await page.check("#brush-erase");

  // A stroke back and forth over the top of the head, as seen from the default camera.
  const path2 = await page.evaluate(() => {
    const { viewport, painter } = window.wispEditor;
    const rect = viewport.renderer.domElement.getBoundingClientRect();
    const c = painter.center;
    const r = Math.hypot(...painter.scalp.crown.map((v, i) => v - [c.x, c.y, c.z][i]));
    const points = [];
    for (let i = 0; i <= 40; ++i) {
      const a = ((25 + 30 * Math.abs(Math.sin(i / 6))) * Math.PI) / 180, b = (i / 40) * Math.PI * 0.8 - 0.4;
      const p = c.clone().set(c.x + r * Math.sin(a) * Math.sin(b), c.y + r * Math.cos(a), c.z + r * Math.sin(a) * Math.cos(b))
        .project(viewport.camera);
      points.push([rect.left + ((p.x + 1) / 2) * rect.width, rect.top + ((1 - p.y) / 2) * rect.height]);
    }
    return points;
  });
  await page.mouse.move(...path2[0]);
  await page.mouse.down();
  for (const p of path2.slice(1)) {
    await page.mouse.move(...p);
    await page.waitForTimeout(40);
  }
  await page.mouse.up();
  // The full hair after the stroke: the server up to date and the page drawing all of it.
  await settler(page, token, { timeoutMs: 180000, polling: 500, drawMs: 0 })();
  await page.waitForFunction(() => window.wispEditor.viewport.stats().final, null, { timeout: 60000, polling: 300 });
  const end = await drawn();
  console.log(`after the stroke: ${JSON.stringify(end)}`);
  await page.screenshot({ path: path.join(outDir, "paint-10k.png") });
  if (crashed) fail("the page crashed while painting");
  if (await page.evaluate(() => window.contextLost)) fail("the WebGL context was lost while painting");
  // The density map moves the roots, not their count (N_s): all 10,000 are drawn.
  if (end.strands !== 10000 || !end.final) fail(`after the stroke the page draws ${end.strands} strands`);
  if (end.updates - start.updates < 3) fail(`only ${end.updates - start.updates} hair updates while the stroke ran: the preview did not follow it`);
  // Buffers grow geometrically and are reused: far fewer allocations than updates.
  if (end.allocations > 4) fail(`${end.allocations} buffer allocations for ${end.updates} hair updates`);
  // The view still draws: pixels that are neither background nor flat.
  const lit = await page.evaluate(() => {
    const gl = window.wispEditor.viewport.renderer.getContext();
    window.wispEditor.viewport.renderNow();
    const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight, px = new Uint8Array(4 * w * h);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let n = 0;
    for (let i = 0; i < px.length; i += 4) if (Math.abs(px[i] - 0x24) + Math.abs(px[i + 1] - 0x26) + Math.abs(px[i + 2] - 0x2b) > 30) ++n;
    return n / (w * h);
  });
  console.log(`coverage after the stroke: ${(100 * lit).toFixed(1)}%`);
  if (lit < 0.02) fail(`the view is empty after the stroke (${(100 * lit).toFixed(1)}% covered)`);
} finally {
  if (browser) await browser.close().catch(() => {});
  server.kill("SIGINT");
  if (!process.exitCode) rmSync(folder, { recursive: true, force: true });
}
