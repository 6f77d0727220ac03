// Browser test of painting and saving in `wisp edit` (registered in ctest as editor.*): a
// 3,000-strand style in a temporary folder; a stroke of the erase brush on the head (mirror
// X) empties the density where it went, on both sides; undo and redo bring it back and take
// it away again; Save writes the TOML and the map PNG, and `wisp generate` of the saved TOML
// gives byte for byte the hair the editor exports. Screenshots go to OUT_DIR.
//   node web/tests/paint_test.mjs WISP_EXE OUT_DIR
import { exportAndGenerate, failWith, testArguments, withEditor } from "./harness.mjs";
import { readFileSync, existsSync } from "node:fs";
import path from "node:path";

const { wisp, outDir } = testArguments();
const fail = failWith("paint test");

const style = "[roots]\nstrands = 3000\nwisps = 150\npoints_per_strand = 16\n";
await withEditor(wisp, { prefix: "paint", files: { "style.toml": style }, viewport: { width: 900, height: 600 } }, async ({ page, token, folder, settle }) => {

  // Roots of the full hair (GET /api/hair) within `radius` cm of each point.
  const rootsNear = (points, radius) => page.evaluate(async ([points, radius, token]) => {
    const r = await fetch("/api/hair", { headers: { "X-Wisp-Token": token } });
    const buffer = await r.arrayBuffer();
    const [, strands] = new Uint32Array(buffer, 8, 4);
    const offsets = new Uint32Array(buffer, 24, strands + 1);
    const positions = new Float32Array(buffer, 24 + 4 * (strands + 1));
    return points.map((p) => {
      let n = 0;
      for (let s = 0; s < strands; ++s) {
        const k = 3 * offsets[s];
        if (Math.hypot(positions[k] - p[0], positions[k + 1] - p[1], positions[k + 2] - p[2]) < radius) ++n;
      }
      return n;
    });
  }, [points, radius, token]);
  // Waits until the server has nothing stale and the page has drawn the full hair.

  // Paint mode: the map on the scalp, the brush: erase, constant falloff, radius 3 cm.
  await page.click("#paint");
  await page.waitForFunction(() => window.wispEditor?.painter.map !== null);
  await page.selectOption("#brush-falloff", "constant");
  await page.locator("#brush-radius").evaluate((e) => { e.value = 3; e.dispatchEvent(new Event("input")); });
  await page.locator("#brush-strength").evaluate((e) => { e.value = 1; e.dispatchEvent(new Event("input")); });
  await page.check("#brush-erase");
  await page.screenshot({ path: path.join(outDir, "paint-before.png") });

  // A point on the head's upper left side as seen: where the pointer presses, and its hit.
  const stroke = await page.evaluate(() => {
    const { viewport, painter } = window.wispEditor;
    const rect = viewport.renderer.domElement.getBoundingClientRect();
    const c = painter.center;
    const r = Math.hypot(...painter.scalp.crown.map((v, i) => v - [c.x, c.y, c.z][i]));
    // 50° from the top, toward the character's left (+X) and the camera (+Z).
    const a = (50 * Math.PI) / 180;
    const aim = (dx, dz) => {
      const p = c.clone().set(c.x + r * Math.sin(a) * dx, c.y + r * Math.cos(a), c.z + r * Math.sin(a) * dz)
        .project(viewport.camera);
      return [rect.left + ((p.x + 1) / 2) * rect.width, rect.top + ((1 - p.y) / 2) * rect.height];
    };
    return { from: aim(0.8, 0.6), to: aim(0.6, 0.8) };
  });
  const hit = await page.evaluate(([x, y]) => {
    const { painter, viewport } = window.wispEditor;
    const h = painter.hit({ target: viewport.renderer.domElement, clientX: x, clientY: y });
    return h ? [h.point.x, h.point.y, h.point.z] : null;
  }, stroke.from);
  if (!hit) fail("the stroke's start is not on the head");
  const mirror = [-hit[0], hit[1], hit[2]];
  const before = await rootsNear([hit, mirror], 2.5);
  console.log(`roots within 2.5 cm of ${hit.map((v) => v.toFixed(1))} and its mirror: ${before}`);
  if (Math.min(...before) < 8) fail(`too few roots where the stroke goes to measure: ${before}`);

  await page.mouse.move(...stroke.from);
  await page.mouse.down();
  for (let i = 1; i <= 6; ++i)
    await page.mouse.move(stroke.from[0] + ((stroke.to[0] - stroke.from[0]) * i) / 6,
      stroke.from[1] + ((stroke.to[1] - stroke.from[1]) * i) / 6);
  await page.mouse.up();
  await settle();
  const after = await rootsNear([hit, mirror], 2.5);
  console.log(`after an erase stroke: ${after}`);
  if (after[0] > 0.15 * before[0] || after[1] > 0.15 * before[1])
    fail(`the erased density still grows ${after} roots (was ${before})`);
  const value = await page.locator("[data-path='maps.density']").textContent();
  if (!value.includes("style.density.png")) fail(`maps.density shows ${value}, not the painted image`);
  await page.screenshot({ path: path.join(outDir, "paint-after.png") });

  // Undo brings the hair back exactly (the constant map), redo takes it away again.
  await page.keyboard.press("Control+z");
  await settle();
  const undone = await rootsNear([hit, mirror], 2.5);
  if (undone.join() !== before.join()) fail(`undo gave ${undone} roots, not ${before}`);
  await page.keyboard.press("Control+Shift+z");
  await settle();
  const redone = await rootsNear([hit, mirror], 2.5);
  if (redone.join() !== after.join()) fail(`redo gave ${redone} roots, not ${after}`);
  console.log(`undo: ${undone}, redo: ${redone}`);

  // Save: the TOML and its map in the folder; `wisp generate` of it is the editor's hair.
  await page.click("#save");
  await page.waitForFunction(() => document.getElementById("saved").textContent.startsWith("saved"));
  for (const f of ["style.toml", "style.density.png"])
    if (!existsSync(path.join(folder, f))) fail(`Save did not write ${f}`);
  const toml = readFileSync(path.join(folder, "style.toml"), "utf8");
  if (!toml.includes('image = "style.density.png"')) fail(`the saved TOML does not name its map:\n${toml}`);
  const { editor: a, cli: b } = await exportAndGenerate(page, token, wisp, folder);
  if (!a.equals(b)) fail(`wisp generate of the saved style differs from the editor's hair (${a.length} vs ${b.length} bytes)`);
  console.log(`save: style.toml + style.density.png; wisp generate gives the editor's hair (${a.length} bytes, identical)`);

  // The autosave sidecar follows the edits (1.5 s after the last one).
  for (let i = 0; i < 50 && !existsSync(path.join(folder, "style.autosave.toml")); ++i) await page.waitForTimeout(200);
  if (!existsSync(path.join(folder, "style.autosave.toml"))) fail("no autosave after the edits");
});
