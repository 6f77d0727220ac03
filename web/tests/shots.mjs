// The pictures of docs/edit.md: the editor with wisp's render beside the live view, painting
// the density map, a tie with its painted selection coloured by group, a comb stroke
// (then coloured by constraint progress), a braid and an updo. Not a test: run
// by hand after a change to the editor's look, then look at the pictures.
//   node web/tests/shots.mjs WISP_EXE OUT_DIR
// WISP_SHOTS=braid,updo makes only those (editor, paint, tie, comb, braid, updo,
// braid-preset, updo-preset; updo-views adds the updo seen from three more sides).
import { dragThrough, launchChromium, onScreen, openEditor, settler, startEditor, tempFolder, testArguments, viewFromBehind } from "./harness.mjs";
import { rmSync } from "node:fs";
import path from "node:path";

const { wisp, outDir } = testArguments();
const wanted = (name) => !process.env.WISP_SHOTS || process.env.WISP_SHOTS.split(",").includes(name);
const folder = tempFolder("shots");
const browser = await launchChromium();
const servers = [];
try {
  const open = async (preset, strands) => {
    const e = await startEditor(wisp, ["--preset", preset], folder, { timeoutMs: 300000 });
    servers.push(e.server);
    const page = await openEditor(browser, e.url, { width: 1100, height: 660 });
    await page.waitForSelector("body[data-ready='1']", { timeout: 300000 });
    await page.evaluate(async ([token, strands]) => {
      await fetch("/api/set", { method: "POST", headers: { "X-Wisp-Token": token, "Content-Type": "application/json" },
        body: JSON.stringify({ path: "roots.strands", value: strands }) });
    }, [e.token, strands]);
    await page.reload();
    await page.waitForSelector("body[data-ready='1']", { timeout: 300000 });
    const settle = settler(page, e.token, { timeoutMs: 300000, polling: 500, drawMs: 2500 });
    return { page, settle };
  };

  // The editor with wisp's own render beside the live view.
  if (wanted("editor")) {
    const { page, settle } = await open("wavy-bob", 30000);
    await page.click("#render");
    await page.waitForFunction(() => document.getElementById("picture-time").textContent.endsWith(" s"), null,
      { timeout: 300000 });
    await settle();
    await page.screenshot({ path: path.join(outDir, "editor.png") });
  }
  // Painting the density map.
  if (wanted("paint")) {
    const { page, settle } = await open("long-straight", 30000);
    await page.click("#paint");
    await page.waitForFunction(() => window.wispEditor?.painter.map !== null, null, { timeout: 300000 });
    const aim = await page.evaluate(() => {
      const { viewport, painter } = window.wispEditor;
      const rect = viewport.renderer.domElement.getBoundingClientRect();
      const c = painter.center;
      const r = Math.hypot(...painter.scalp.crown.map((v, i) => v - [c.x, c.y, c.z][i]));
      const at = (a, dx, dz) => {
        const p = c.clone().set(c.x + r * Math.sin(a) * dx, c.y + r * Math.cos(a), c.z + r * Math.sin(a) * dz).project(viewport.camera);
        return [rect.left + ((p.x + 1) / 2) * rect.width, rect.top + ((1 - p.y) / 2) * rect.height];
      };
      return [at(0.6, 0.9, 0.4), at(0.7, 0.5, 0.85)];
    });
    await page.check("#brush-erase");
    await page.mouse.move(...aim[0]);
    await page.mouse.down();
    for (let i = 1; i <= 8; ++i)
      await page.mouse.move(aim[0][0] + ((aim[1][0] - aim[0][0]) * i) / 8, aim[0][1] + ((aim[1][1] - aim[0][1]) * i) / 8);
    await page.mouse.up();
    await settle();
    await page.mouse.move(aim[1][0] + 30, aim[1][1] + 10);
    await page.waitForTimeout(500);
    await page.screenshot({ path: path.join(outDir, "paint.png") });
  }
  // A tie with its painted selection, coloured by group.
  if (wanted("tie")) {
    const { page, settle } = await open("long-straight", 30000);
    await page.selectOption("#color-by", "group");
    await page.click("#tie");
    await viewFromBehind(page, [15, 22, -85]);
    // The geometry of web/tests/tie_test.mjs: a tie on the back of the head at ear level.
    const [tie, ...selection] = await onScreen(page, [[0, 0.1, -1.2], [-0.45, 0.35, -0.9], [0, 0.3, -0.97], [0.45, 0.35, -0.9]]);
    await page.mouse.click(...tie);
    await page.waitForFunction(() => window.wispEditor.constraints.sections.length === 1, null, { timeout: 300000 });
    await settle();
    // The row re-renders with each report: select through the editor rather than the button.
    await page.evaluate(() => window.wispEditor.constraints.select(0));
    await page.waitForFunction(() => window.wispEditor.constraints.selector.map !== null, null, { timeout: 300000 });
    await page.locator("#select-radius").evaluate((e) => { e.value = 6; e.dispatchEvent(new Event("input")); });
    await dragThrough(page, selection);
    await page.waitForFunction(() => window.wispEditor.constraints.sections[0]?.selection !== undefined, null, { timeout: 300000 });
    await settle();
    await page.screenshot({ path: path.join(outDir, "tie-select.png") });
    await page.evaluate(() => window.wispEditor.constraints.select(null));
    await settle();
    await page.screenshot({ path: path.join(outDir, "tie.png") });
  }
  // A comb stroke across the back of the head, left to right; then coloured by progress.
  if (wanted("comb")) {
    const { page, settle } = await open("long-straight", 30000);
    await page.click("#tie");
    await page.click("#tie-tools [data-tool='comb']");
    await viewFromBehind(page, [10, 20, -85]);
    // The geometry of web/tests/comb_test.mjs.
    await dragThrough(page, await onScreen(page, [[0.7, 0.1, -0.75], [0.35, 0.15, -0.95], [0, 0.15, -1.0], [-0.35, 0.15, -0.95], [-0.7, 0.1, -0.75]]));
    await page.waitForFunction(() => window.wispEditor.constraints.sections.length === 1, null, { timeout: 300000 });
    await settle();
    await page.screenshot({ path: path.join(outDir, "comb.png") });
    await page.selectOption("#color-by", "progress");
    await page.waitForFunction(() => document.getElementById("legend").textContent.includes("constraints met"), null,
      { timeout: 300000 });
    await page.waitForTimeout(1500);
    await page.screenshot({ path: path.join(outDir, "comb-progress.png") });
  }
  // A braid dragged down the back of the head, on the braid preset's hair (long enough to
  // reach the nape and be braided) with the preset's own braid taken away.
  if (wanted("braid")) {
    const { page, settle } = await open("braid", 30000);
    await page.click("#tie");
    await page.evaluate(() => window.wispEditor.constraints.apply([], { record: false }));
    await page.click("#tie-tools [data-tool='braid']");
    await viewFromBehind(page, [25, 5, -110]);
    // The geometry of web/tests/hairdressing_test.mjs.
    await dragThrough(page, await onScreen(page, [[0, -0.45, -1.2], [0, -2.3, -1.35]]), 10);
    await page.waitForFunction(() => window.wispEditor.constraints.sections.length === 1, null, { timeout: 300000 });
    await settle();
    await page.screenshot({ path: path.join(outDir, "braid.png") });
  }
  // An updo clicked on the upper back of the head.
  if (wanted("updo") || wanted("updo-views")) {
    const { page, settle } = await open("long-straight", 30000);
    await page.click("#tie");
    await page.click("#tie-tools [data-tool='updo']");
    await viewFromBehind(page, [20, 35, -95]);
    const [at] = await onScreen(page, [[0, 0.55, -1.05]]);
    await page.mouse.click(...at);
    await page.waitForFunction(() => window.wispEditor.constraints.sections.length === 1, null, { timeout: 300000 });
    await settle();
    await page.screenshot({ path: path.join(outDir, "updo.png") });
    // Its facing arrow from where it points at the camera (behind and close), away from it
    // (the front) and across (the side): readable from each.
    for (const [name, offset] of [["updo-toward", [4, 30, -60]], ["updo-front", [15, 30, 95]], ["updo-side", [100, 25, -15]]]) {
      if (!wanted("updo-views")) continue;
      await viewFromBehind(page, offset);
      await page.waitForTimeout(500);
      await page.screenshot({ path: path.join(outDir, `${name}.png`) });
    }
  }
  // The braid and updo presets as opened: their sections with handles and sliders.
  for (const [kind, behind] of [["braid", [25, 5, -110]], ["updo", [20, 35, -95]]]) {
    if (!wanted(`${kind}-preset`)) continue;
    const { page, settle } = await open(kind, 30000);
    await page.click("#tie");
    await viewFromBehind(page, behind);
    await settle();
    await page.screenshot({ path: path.join(outDir, `${kind}-preset.png`) });
  }
} finally {
  await browser.close();
  for (const s of servers) s.kill("SIGINT");
  rmSync(folder, { recursive: true, force: true });
}
