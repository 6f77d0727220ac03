// Browser tests of the editor's Motion mode (issue 17; ctest editor_motion_*): starts `wisp
// edit` on a small long-haired style in a temporary folder, loads the page in Debian's
// Chromium (headless, software GL) with playwright-core, and runs one case
// ($WISP_MOTION_CASE):
//   plays   a preset plays: the frame index advances and the drawn positions change, the
//           frames coming by the stream (GET /api/motion/stream)
//   drag    dragging the head with the mouse turns it, and the roots go with it
//   file    a motion file chosen with file… turns the head; a malformed one shows its message
//   tree    the tree view draws spheres and cylinders coloured by level, and the plot
//   export  a session (mouse drag, preset) exported from the page, re-run by `wisp animate`
//           from the exported style and motion files: the same frame files, byte for byte
//   node web/tests/motion_test.mjs WISP_EXE OUT_DIR
import { failWith, launchChromium, openEditor, startEditor, styleSetter, tempFolder, testArguments } from "./harness.mjs";
import { spawnSync } from "node:child_process";
import { readFileSync, readdirSync, rmSync } from "node:fs";
import path from "node:path";

const { wisp, outDir } = testArguments();
const which = process.env.WISP_MOTION_CASE ?? "plays";
const fail = failWith(`motion test (${which})`);

const folder = tempFolder("motion");
const { server, url, token } = await startEditor(wisp, ["--preset", "long-straight"], folder);

// The roots (first point of every shown strand) of the newest frame the page drew.
const rootsOf = (page) => page.evaluate(() => {
  const m = window.wispEditor.motion;
  const { offsets, strands } = m.rest;
  const p = m.lastFrame.positions, out = [];
  for (let s = 0; s < strands; ++s) out.push([p[3 * offsets[s]], p[3 * offsets[s] + 1], p[3 * offsets[s] + 2]]);
  return { frame: m.lastFrame.frame, roots: out };
});
const meanDistance = (a, b) => a.reduce((sum, p, i) => sum + Math.hypot(p[0] - b[i][0], p[1] - b[i][1], p[2] - b[i][2]), 0) / a.length;

// Drags the head with the mouse: from its centre on the screen, `dx` pixels across.
async function dragHead(page, dx, dy = 0) {
  const at = await page.evaluate(() => {
    const v = window.wispEditor.viewport;
    v.head.geometry.computeBoundingBox();
    const box = v.head.geometry.boundingBox;
    // The face's front, a little below the top: on the head, not the shoulders.
    const p = box.getCenter(new (box.min.constructor)());
    p.y = box.max.y - 0.35 * 26;
    p.z = box.max.z - 2;
    p.applyMatrix4(v.head.matrixWorld).project(v.camera);
    const r = v.renderer.domElement.getBoundingClientRect();
    return { x: r.left + (p.x + 1) / 2 * r.width, y: r.top + (1 - p.y) / 2 * r.height };
  });
  await page.mouse.move(at.x, at.y);
  await page.mouse.down();
  for (let i = 1; i <= 10; ++i) {
    await page.mouse.move(at.x + (dx * i) / 10, at.y + (dy * i) / 10);
    await page.waitForTimeout(40);
  }
  await page.mouse.up();
}

async function waitFrame(page, past) {
  await page.waitForFunction((past) => (window.wispEditor.motion.lastFrame?.frame ?? -1) > past, past, { timeout: 60000 });
}

let browser;
try {
  browser = await launchChromium();
  const page = await openEditor(browser, url);
  await page.waitForSelector("[data-path='roots.strands']");
  const set = styleSetter(page, token);
  // A small style keeps the simulation and software GL quick.
  if (await set("roots.wisps", 60) !== 200) fail("could not set roots.wisps");
  if (await set("roots.strands", 1500) !== 200) fail("could not set roots.strands");
  await page.reload();
  await page.waitForSelector("body[data-ready='1']", { timeout: 120000 });

  await page.click("#motion");
  await page.waitForSelector("#motion-tools:not([hidden])", { timeout: 120000 });
  await waitFrame(page, -1);
  const rest = await rootsOf(page);
  console.log(`motion: ${rest.roots.length} strands shown, frame ${rest.frame}`);

  if (which === "plays") {
    const before = await page.evaluate(() => Array.from(window.wispEditor.motion.lastFrame.positions));
    await page.click("[data-preset='shake']");
    await waitFrame(page, 5);
    const a = await page.evaluate(() => ({ frame: window.wispEditor.motion.lastFrame.frame, p: Array.from(window.wispEditor.motion.lastFrame.positions) }));
    await waitFrame(page, a.frame + 2);
    const b = await page.evaluate(() => ({ frame: window.wispEditor.motion.lastFrame.frame, p: Array.from(window.wispEditor.motion.lastFrame.positions) }));
    const moved = (x, y) => x.reduce((m, v, i) => Math.max(m, Math.abs(v - y[i])), 0);
    console.log(`frames ${a.frame} → ${b.frame}: positions moved up to ${moved(a.p, b.p).toFixed(2)} cm (${moved(before, a.p).toFixed(2)} cm from rest)`);
    if (!(b.frame > a.frame)) fail("the frame index did not advance");
    if (moved(a.p, b.p) < 0.05) fail("the positions did not change between frames");
    if (a.p.some((v) => !Number.isFinite(v))) fail("a position is not finite");
    const transport = await page.evaluate(() => window.wispEditor.motion.transport);
    console.log(`frames came by ${transport}`);
    if (transport !== "stream") fail(`the frames came by ${transport}, not the stream`);
    await page.screenshot({ path: path.join(outDir, "motion-shake.png") });
    const hud = await page.locator("#hud").textContent();
    console.log(hud);
    if (!hud.includes("Motion · frame")) fail("the HUD shows no motion state");
  } else if (which === "file") {
    // A motion file chosen with "file…" turns the head; a malformed one shows the reader's
    // message with the file's name.
    const turn = JSON.stringify({
      format: "wisp-motion", version: 1, units: "head",
      head: { pivot: [0, -1.2, 0], keys: [{ t: 0 }, { t: 0.4, rotate: [0, 40, 0] }] },
      body: { keys: [] }, duration: 2,
    });
    await page.setInputFiles("#motion-file", { name: "turn.json", mimeType: "application/json", buffer: Buffer.from(turn) });
    await waitFrame(page, rest.frame + 15);
    const after = await rootsOf(page);
    const d = meanDistance(rest.roots, after.roots);
    console.log(`file: roots moved ${d.toFixed(2)} cm on average (frame ${after.frame})`);
    if (d < 1) fail(`the motion file moved the roots only ${d.toFixed(3)} cm`);
    await page.setInputFiles("#motion-file", { name: "bad.json", mimeType: "application/json", buffer: Buffer.from('{"format": "wisp-motion", "version": 1, "head": {"keys": [{"t": 1}, {"t": 0.5}]}}') });
    await page.waitForFunction(() => document.getElementById("status").textContent.includes("bad.json"), null, { timeout: 20000 })
      .catch(() => fail("a malformed motion file showed no message naming it"));
    console.log(`bad file: ${await page.locator("#status").textContent()}`);
  } else if (which === "drag") {
    await dragHead(page, 160);
    await page.waitForTimeout(1500);  // the hair follows two frames late; let it settle a little
    const after = await rootsOf(page);
    const d = meanDistance(rest.roots, after.roots);
    const pose = await page.evaluate(() => window.wispEditor.motion.pose);
    console.log(`drag: head yaw ${pose.rotate[1].toFixed(1)}°, roots moved ${d.toFixed(2)} cm on average (frame ${after.frame})`);
    if (Math.abs(pose.rotate[1]) < 20) fail("the mouse drag did not turn the head");
    if (d < 1) fail(`the roots moved only ${d.toFixed(3)} cm with the head`);
    await page.screenshot({ path: path.join(outDir, "motion-drag.png") });
  } else if (which === "tree") {
    await page.selectOption("#motion-show", "tree");
    await page.evaluate(() => document.getElementById("show-head").click());  // the tree alone
    await page.click("[data-preset='nod']");
    await waitFrame(page, 10);
    await page.waitForFunction(() => window.wispEditor.motion.lastTree?.nodes > 0, null, { timeout: 30000 });
    await page.waitForTimeout(500);
    const tree = await page.evaluate(() => {
      const m = window.wispEditor.motion;
      const canvas = m.viewport.renderer.domElement;
      const gl = canvas.getContext("webgl2");
      const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
      const pixels = new Uint8Array(w * h * 4);
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
      let hit = 0;
      for (let i = 0; i < pixels.length; i += 4)
        if (Math.abs(pixels[i] - 0x24) + Math.abs(pixels[i + 1] - 0x26) + Math.abs(pixels[i + 2] - 0x2b) > 30) ++hit;
      const plot = document.getElementById("motion-plot").getContext("2d").getImageData(0, 0, 236, 70).data;
      let ink = 0;
      for (let i = 3; i < plot.length; i += 4) if (plot[i] > 0) ++ink;
      return { spheres: m.tree.spheres.count, cylinders: m.tree.cylinders.count, levels: m.lastTree.levels,
        perLevel: Array.from(m.lastTree.perLevel), strandsVisible: m.viewport.hair.visible,
        coverage: hit / (w * h), plotInk: ink };
    });
    console.log(`tree: ${tree.spheres} spheres, ${tree.cylinders} cylinders, active per level ${tree.perLevel.join("/")}, ` +
      `coverage ${(100 * tree.coverage).toFixed(1)}%, plot ${tree.plotInk} px`);
    if (tree.spheres === 0 || tree.cylinders !== tree.spheres) fail("the tree view drew no spheres and cylinders");
    if (tree.strandsVisible) fail("the strands still show in the tree-only view");
    if (tree.coverage < 0.005) fail("the tree covers nothing of the view");
    if (tree.plotInk < 50) fail("the active-node plot is empty");
    await page.screenshot({ path: path.join(outDir, "motion-tree.png") });
  } else if (which === "export") {
    await dragHead(page, 120, 40);
    await page.waitForTimeout(600);
    await page.click("[data-preset='nod']");
    await page.waitForTimeout(1500);
    await page.fill("#motion-name", "take.hair");
    await page.click("#motion-export");
    await page.waitForFunction(() => window.wispEditor.motion.exported, null, { timeout: 180000 });
    const exported = await page.evaluate(() => window.wispEditor.motion.exported);
    console.log(`export: ${exported.frames} frames; ${exported.command}`);
    // The command the page gives, with its own output name.
    const args = exported.command.replace(/^wisp /, "").match(/'[^']*'|\S+/g).map((a) => a.replace(/^'|'$/g, ""));
    args[args.indexOf("-o") + 1] = "cli.hair";
    const run = spawnSync(path.resolve(wisp), [...args, "-q"], { cwd: folder, encoding: "utf8" });
    if (run.status !== 0) fail(`wisp animate failed: ${run.stderr}`);
    const frames = readdirSync(folder).filter((f) => /^take_\d+\.hair$/.test(f)).sort();
    const cliFrames = readdirSync(folder).filter((f) => /^cli_\d+\.hair$/.test(f));
    if (frames.length !== exported.frames || cliFrames.length !== exported.frames)
      fail(`${frames.length} exported and ${cliFrames.length} replayed frame files for ${exported.frames} frames`);
    for (const f of frames) {
      const cli = f.replace("take_", "cli_");
      if (!readFileSync(path.join(folder, f)).equals(readFileSync(path.join(folder, cli))))
        fail(`${f} and ${cli} differ`);
    }
    console.log(`wisp animate gave the same ${frames.length} frames byte for byte`);
  } else {
    fail(`unknown case '${which}'`);
  }
} finally {
  if (browser) await browser.close();
  server.kill("SIGINT");
  rmSync(folder, { recursive: true, force: true });
}
