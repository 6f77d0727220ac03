// Browser test of placing a tie in `wisp edit` (registered in ctest as editor_tie_gathers): a
// 3,000-strand style in a temporary folder, seen from behind; a click on the back of the head
// places a tie just off it, a stroke of the selection brush picks its wisps on the scalp, and
// the strands of that group then pass near the tie point (where before far fewer did), the
// group's progress says so, and the hair outside the selection is left out of it. Save
// writes [[tie]] with its mask, which `wisp generate` turns into the editor's hair byte for
// byte; undo takes the tie away again. Screenshots go to OUT_DIR.
//   node web/tests/tie_test.mjs WISP_EXE OUT_DIR
import { dragThrough, exportAndGenerate, failWith, measureHair, onScreen, testArguments, viewFromBehind, withEditor } from "./harness.mjs";
import { readFileSync, existsSync } from "node:fs";
import path from "node:path";

const { wisp, outDir } = testArguments();
const fail = failWith("tie test");

const style = "[roots]\nstrands = 3000\nwisps = 150\npoints_per_strand = 16\n";
await withEditor(wisp, { prefix: "tie", files: { "style.toml": style } }, async ({ page, token, folder, settle }) => {

  // Of the strands (of group `group`, or all when null) of the full hair, how many and what
  // fraction pass within `reach` cm of point p (a control point or a segment between two).
  const near = (p, reach, group) => measureHair(page, token, ({ strands, offsets, x, groups }, [p, reach, group]) => {
    let count = 0, passing = 0;
    for (let s = 0; s < strands; ++s) {
      if (group !== null && groups[s] !== group) continue;
      ++count;
      let best = Infinity;
      for (let i = offsets[s]; i + 1 < offsets[s + 1]; ++i) {
        const a = [x[3 * i], x[3 * i + 1], x[3 * i + 2]], b = [x[3 * i + 3], x[3 * i + 4], x[3 * i + 5]];
        const e = b.map((v, k) => v - a[k]), w = p.map((v, k) => v - a[k]);
        const t = Math.max(0, Math.min(1, (w[0] * e[0] + w[1] * e[1] + w[2] * e[2]) / Math.max(1e-12, e[0] ** 2 + e[1] ** 2 + e[2] ** 2)));
        best = Math.min(best, Math.hypot(...w.map((v, k) => v - t * e[k])));
      }
      if (best <= reach) ++passing;
    }
    return { count, passing, fraction: count ? passing / count : 0, strands };
  }, [p, reach, group]);

  // The view from behind and a little above; the tie tool.
  await page.click("#tie");
  await viewFromBehind(page, [15, 22, -85]);
  // A point on the back of the head at about ear level, as the pointer sees it.
  const [at] = await onScreen(page, [[0, 0.1, -1.2]]);
  const aim = await page.evaluate((at) => {
    const tie = window.wispEditor.constraints.tiePoint({ clientX: at[0], clientY: at[1] });
    return { at, tie: tie && tie.toArray() };
  }, at);
  if (!aim.tie) fail("the click's point is not on or near the head");
  const radius = 1.2, reach = radius + 1.0;
  const baseline = await near(aim.tie, reach, null);
  console.log(`before the tie: ${baseline.passing} of ${baseline.count} strands pass within ${reach} cm of ` +
    `${aim.tie.map((v) => v.toFixed(1))} (${(100 * baseline.fraction).toFixed(0)}%)`);

  await page.mouse.click(...aim.at);
  await page.waitForFunction(() => window.wispEditor.constraints.sections.length === 1);
  await settle();
  const sections = await page.evaluate(() => window.wispEditor.constraints.sections);
  if (sections[0].section !== "tie" || Math.hypot(...sections[0].point.map((v, k) => v - aim.tie[k])) > 0.05)
    fail(`the tie is ${JSON.stringify(sections[0])}, not at ${aim.tie}`);
  const all = await near(aim.tie, reach, 1);
  console.log(`a tie of every wisp: ${all.passing} of ${all.count} strands pass near it`);
  if (all.count !== all.strands || all.fraction < 0.8) fail(`a tie of every wisp gathered ${all.passing} of ${all.count}`);

  // Its selection: a stroke of the brush over the lower back of the scalp.
  await page.click("#tie-tools .section button:text('select')");
  await page.waitForFunction(() => window.wispEditor.constraints.selector.map !== null);
  await page.locator("#select-radius").evaluate((e) => { e.value = 5; e.dispatchEvent(new Event("input")); });
  await dragThrough(page, await onScreen(page, [[-0.45, 0.35, -0.9], [0, 0.3, -0.97], [0.45, 0.35, -0.9]]), 5);
  await page.waitForFunction(() => window.wispEditor.constraints.sections[0]?.selection !== undefined);
  await settle();
  await page.screenshot({ path: path.join(outDir, "tie-select.png") });
  await page.click("#tie-tools .section button:text('done')");
  await settle();

  const picked = await near(aim.tie, reach, 1);
  const others = await near(aim.tie, reach, 0);
  console.log(`the painted selection: ${picked.passing} of ${picked.count} strands of the tie's group pass within ` +
    `${reach} cm (${(100 * picked.fraction).toFixed(0)}%); of the ${others.count} others, ${others.passing}`);
  if (picked.count < 100 || others.count < 100) fail(`the selection took ${picked.count} strands of ${picked.strands}`);
  if (picked.fraction < 0.8) fail(`the tie gathered only ${(100 * picked.fraction).toFixed(0)}% of its group`);
  if (picked.fraction < baseline.fraction + 0.4) fail("the tie's group passes near the point no more than before");

  // Its progress, from the solver and on the panel.
  const report = await page.evaluate(async (token) =>
    (await fetch("/api/report", { headers: { "X-Wisp-Token": token } })).json(), token);
  const g = report.groups[0];
  console.log(`progress: ${g.name}: ${g.wisps} wisps, met ${g.met.map((m) => m.toFixed(2))}`);
  if (report.groups.length !== 1 || g.met[0] < 0.8) fail(`the report says ${JSON.stringify(report.groups)}`);
  const row = await page.locator("#tie-tools .section").first().textContent();
  if (!row.includes(`${g.wisps} wisps`) || !row.includes("met")) fail(`the panel shows '${row}'`);
  await page.screenshot({ path: path.join(outDir, "tie.png") });

  // Save: [[tie]] with its mask; `wisp generate` of it is the editor's hair.
  await page.click("#save");
  await page.waitForFunction(() => document.getElementById("saved").textContent.startsWith("saved"));
  const toml = readFileSync(path.join(folder, "style.toml"), "utf8");
  const mask = `style.${sections[0].name.replace(/ /g, "-")}.mask.png`;
  if (!toml.includes("[[tie]]") || !toml.includes(`mask = "${mask}"`) || !existsSync(path.join(folder, mask)))
    fail(`the saved style does not hold the tie and its mask ${mask}:\n${toml}`);
  const { editor: a, cli: b } = await exportAndGenerate(page, token, wisp, folder);
  if (!a.equals(b)) fail(`wisp generate of the saved tie differs from the editor's hair (${a.length} vs ${b.length} bytes)`);
  console.log(`save: [[tie]] with ${mask}; wisp generate gives the editor's hair (${a.length} bytes, identical)`);

  // Undo: the selection, the stroke, then the tie itself.
  for (let i = 0; i < 3; ++i) {
    await page.keyboard.press("Control+z");
    await page.waitForTimeout(400);
  }
  await settle();
  const left = await page.evaluate(() => window.wispEditor.constraints.sections.length);
  const undone = await near(aim.tie, reach, null);
  console.log(`undo ×3: ${left} sections; ${undone.passing} strands pass near the point`);
  if (left !== 0 || undone.passing !== baseline.passing) fail("undo did not take the tie away");
});
