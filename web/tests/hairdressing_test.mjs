// Browser tests of the braid and updo tools in `wisp edit` (registered in ctest as
// editor_braid_* and editor_updo_*, WISP_HAIRDRESSING_CASE=braid or updo): a 3,000-strand
// long-haired style in a temporary folder, seen from behind.
//   braid: a press on the back of the head dragged down places a [[braid]] (its start just
//     off the scalp, its axis along the drag, in head units); the hair beside its axis below
//     the start then lies within the braid's width of it (where before it hung as a sheet),
//     the panel shows each strand's progress, the strands drawn are the server's expansion;
//     a slider changes the width, a bad width shows the reader's message naming it; dragging
//     the axis's end handle turns the braid and undo restores it.
//   updo: a click on the upper back places an [[updo]] facing away from the head; the hair
//     then passes within bun_radius of its centre (where before little did); dragging the
//     facing handle turns the bun and undo restores it.
// Both: Save writes the section as the CLI reads it, and `wisp generate` of the saved style
// is the editor's hair byte for byte. Screenshots go to OUT_DIR.
//   WISP_HAIRDRESSING_CASE=braid node web/tests/hairdressing_test.mjs WISP_EXE OUT_DIR
import { dragThrough, exportAndGenerate, failWith, measureHair, onScreen, pageConstraints, testArguments, toScreen, viewFromBehind, withEditor } from "./harness.mjs";
import { readFileSync } from "node:fs";
import path from "node:path";

const { wisp, outDir } = testArguments();
const kind = process.env.WISP_HAIRDRESSING_CASE ?? "braid";
if (kind !== "braid" && kind !== "updo") throw new Error(`WISP_HAIRDRESSING_CASE=${kind}: braid or updo`);
const fail = failWith(`${kind} test`);

// Long hair brushed back, as the braid and updo presets have it, at 3,000 strands.
const style = `[roots]
strands = 3000
wisps = 150
points_per_strand = 32

[maps]
length = { procedural = "front", low = ${kind === "braid" ? "58, high = 72" : "34, high = 44"} }

[growth]
part = "none"
front = "back"

[prototype]
shape = "straight"
length = 70.0

[solve]
stiffness = 0.5
threshold = 0.6
`;
await withEditor(wisp, { prefix: kind, files: { "style.toml": style } }, async ({ page, token, folder, settle }) => {
  const editor = () => pageConstraints(page);
  const measure = (f, arg) => measureHair(page, token, f, arg);

  await page.click("#tie");
  await page.click(`#tie-tools [data-tool='${kind}']`);
  if (kind === "braid") {
    await viewFromBehind(page, [25, 5, -110]);
    // The share of the hair's points beside the braid's axis (cm), between 15% and 85% of
    // its length below the start, that lie within the braid's width of the axis.
    const beside = ({ offsets, x, strands }, { start, end, width }) => {
      const axis = end.map((v, k) => v - start[k]);
      const length = Math.hypot(...axis);
      const u = axis.map((v) => v / length);
      let inSlab = 0, inside = 0;
      for (let i = 0; i < offsets[strands]; ++i) {
        const d = [x[3 * i] - start[0], x[3 * i + 1] - start[1], x[3 * i + 2] - start[2]];
        const t = d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
        if (t < 0.15 * length || t > 0.85 * length) continue;
        const r = Math.hypot(d[0] - t * u[0], d[1] - t * u[1], d[2] - t * u[2]);
        if (r > 12) continue;  // the hair round the braid, not the shoulders' far side
        ++inSlab;
        if (r <= width) ++inside;
      }
      return { inSlab, inside, fraction: inSlab ? inside / inSlab : 0 };
    };
    const [from, to] = await onScreen(page, [[0, -0.45, -1.2], [0, -2.3, -1.35]]);
    const planned = await page.evaluate(([from, to]) => {
      const { constraints } = window.wispEditor;
      const start = constraints.tiePoint({ clientX: from[0], clientY: from[1] });
      return start && start.toArray();
    }, [from, to]);
    if (!planned) fail("the press is not on or near the head");
    await dragThrough(page, [from, to], 10);
    await page.waitForFunction(() => window.wispEditor.constraints.sections.length === 1);
    await settle();
    let { sections, paths } = await editor();
    const braid = sections[0];
    console.log(`the braid: ${JSON.stringify(braid)}`);
    const { center, radius } = await page.evaluate(() => {
      const { constraints } = window.wispEditor;
      return { center: constraints.center.toArray(), radius: constraints.radius };
    });
    const cm = (a) => a.map((v, k) => center[k] + radius * v);
    if (braid.section !== "braid" || braid.head_relative !== undefined || !braid.axis || !(braid.axis[1] < -0.8) ||
        !(braid.length > 1.2 && braid.length < 3))
      fail(`the drag made ${JSON.stringify(braid)}`);
    if (Math.hypot(...cm(braid.start).map((v, k) => v - planned[k])) > 0.05)
      fail(`the braid starts at ${cm(braid.start)}, not where the press was (${planned})`);
    // What is drawn: the server's expansion, one path per strand from the start.
    if (paths.length !== 1 || paths[0].length !== 3 || paths[0].some((p) => p.points.length < 17))
      fail(`the paths drawn are ${JSON.stringify(paths).slice(0, 200)}`);
    const geometry = (b, p) => {
      const end = [0, 1, 2].map((k) => p.reduce((sum, q) => sum + q.points.at(-1)[k], 0) / p.length);
      return { start: cm(b.start), end, width: (b.width ?? 0.35) * radius };
    };
    const g = geometry(braid, paths[0]);
    const expectEnd = cm(braid.start.map((v, k) => v + braid.length * braid.axis[k] / Math.hypot(...braid.axis)));
    if (Math.hypot(...g.end.map((v, k) => v - expectEnd[k])) > 0.05) fail(`the strands end at ${g.end}, not ${expectEnd}`);

    // The hair beside the axis, before (the braid taken away without recording) and after.
    const after = await measure(beside, g);
    await page.evaluate(() => window.wispEditor.constraints.apply([], { record: false }));
    await settle();
    const before = await measure(beside, g);
    await page.evaluate((s) => window.wispEditor.constraints.apply(s, { record: false }), sections);
    await settle();
    console.log(`hair beside the braid's axis within its width (${g.width.toFixed(1)} cm): before ` +
      `${before.inside} of ${before.inSlab} points (${(100 * before.fraction).toFixed(0)}%), after ${after.inside} of ` +
      `${after.inSlab} (${(100 * after.fraction).toFixed(0)}%)`);
    if (after.inSlab < 300) fail(`only ${after.inSlab} points beside the braid`);
    if (!(after.fraction > 0.6) || !(after.fraction > before.fraction + 0.3))
      fail(`the braid did not gather the hair: ${(100 * before.fraction).toFixed(0)}% → ${(100 * after.fraction).toFixed(0)}%`);

    // Progress per strand: three groups, on the panel.
    const report = await page.evaluate(async (token) =>
      (await fetch("/api/report", { headers: { "X-Wisp-Token": token } })).json(), token);
    console.log(`progress: ${report.groups.map((q) => `${q.name}: ${q.wisps} wisps, met ${q.met.map((m) => m.toFixed(2))}`).join("; ")}`);
    if (report.groups.length !== 3 || report.groups.some((q, k) => q.name !== `${braid.name} strand ${k}` || !(q.met[0] > 0.8)))
      fail(`the report says ${JSON.stringify(report.groups)}`);
    const row = await page.locator("#tie-tools .section").first().textContent();
    const wisps = report.groups.reduce((n, q) => n + q.wisps, 0);
    if (!row.includes(`${wisps} wisps`) || !/met \d+\/\d+\/\d+%/.test(row))
      fail(`the panel shows '${row}'`);
    await page.screenshot({ path: path.join(outDir, "braid.png") });

    // A slider: the width, from the schema's range; a bad width shows the reader's message.
    const slider = page.locator("#tie-tools .section input[data-key='width']");
    const range = await slider.evaluate((e) => [Number(e.min), Number(e.max), Number(e.value)]);
    if (range[0] !== 0.1 || range[1] !== 1 || Math.abs(range[2] - 0.35) > 1e-9) fail(`the width slider is ${range}`);
    await slider.evaluate((e) => { e.value = 0.5; e.dispatchEvent(new Event("change")); });
    await page.waitForFunction(() => window.wispEditor.constraints.sections[0].width === 0.5);
    await settle();  // the hair's refresh clears the status line
    await page.evaluate((s) => { s[0].width = -1; return window.wispEditor.constraints.apply(s); }, structuredClone(sections));
    const message = await page.locator("#status").textContent();
    console.log(`a width of -1: '${message}'`);
    if (!message.includes("braid[0].width") || !message.includes("> 0")) fail(`a bad width says '${message}'`);
    await page.keyboard.press("Control+z");
    await page.waitForFunction(() => window.wispEditor.constraints.sections[0].width === undefined);
    await settle();

    // Drag the axis's end sideways: the braid turns; undo puts it back.
    const endAt = await toScreen(page, g.end);
    await dragThrough(page, [endAt, [endAt[0] + 80, endAt[1] - 10]], 8);
    await page.waitForFunction((before) => JSON.stringify(window.wispEditor.constraints.sections[0].axis) !== before,
      JSON.stringify(braid.axis));
    await settle();
    ({ sections, paths } = await editor());
    const turned = geometry(sections[0], paths[0]);
    console.log(`the end dragged: axis ${braid.axis} → ${sections[0].axis}, side ${sections[0].side}, the end moved ` +
      `${Math.hypot(...turned.end.map((v, k) => v - g.end[k])).toFixed(1)} cm`);
    if (Math.hypot(...turned.end.map((v, k) => v - g.end[k])) < 3) fail("dragging the end did not move the braid's end");
    if (JSON.stringify(sections[0].start) !== JSON.stringify(braid.start)) fail("dragging the end moved the start");
    await page.screenshot({ path: path.join(outDir, "braid-drag.png") });
    await page.keyboard.press("Control+z");
    await page.waitForFunction((before) => JSON.stringify(window.wispEditor.constraints.sections[0].axis) === before,
      JSON.stringify(braid.axis));
    await settle();
    ({ sections, paths } = await editor());
    if (JSON.stringify(sections[0]) !== JSON.stringify(braid) || Math.hypot(...geometry(sections[0], paths[0]).end.map((v, k) => v - g.end[k])) > 1e-3)
      fail(`undo left ${JSON.stringify(sections[0])}`);
  } else {
    await viewFromBehind(page, [20, 35, -95]);
    // Of the strands, how many pass within `reach` cm of p.
    const near = ({ offsets, x, strands }, { p, reach }) => {
      let passing = 0;
      for (let s = 0; s < strands; ++s) {
        for (let i = offsets[s]; i < offsets[s + 1]; ++i) {
          if (Math.hypot(x[3 * i] - p[0], x[3 * i + 1] - p[1], x[3 * i + 2] - p[2]) <= reach) {
            ++passing;
            break;
          }
        }
      }
      return { passing, strands, fraction: passing / strands };
    };
    const [at] = await onScreen(page, [[0, 0.55, -1.05]]);
    const planned = await page.evaluate((at) => window.wispEditor.constraints.tiePoint({ clientX: at[0], clientY: at[1] })?.toArray(), at);
    if (!planned) fail("the click is not on or near the head");
    await page.mouse.click(...at);
    await page.waitForFunction(() => window.wispEditor.constraints.sections.length === 1);
    await settle();
    let { sections, paths } = await editor();
    const updo = sections[0];
    console.log(`the updo: ${JSON.stringify(updo)}`);
    const { center, radius } = await page.evaluate(() => {
      const { constraints } = window.wispEditor;
      return { center: constraints.center.toArray(), radius: constraints.radius };
    });
    const cm = (a) => a.map((v, k) => center[k] + radius * v);
    const point = cm(updo.point);
    if (updo.section !== "updo" || Math.hypot(...point.map((v, k) => v - planned[k])) > 0.05)
      fail(`the click made ${JSON.stringify(updo)}, not at ${planned}`);
    const out = Math.hypot(...updo.point);
    if (updo.facing.some((v, k) => Math.abs(v - updo.point[k] / out) > 0.01)) fail(`the bun faces ${updo.facing}, not away from the head`);
    if (paths.length !== 1 || paths[0].length !== 1 || Math.hypot(...paths[0][0].points[0].map((v, k) => v - point[k])) > 1e-3)
      fail(`the spiral drawn is ${JSON.stringify(paths).slice(0, 200)}`);
    const reach = (0.3 + 0.12) * radius;  // bun_radius and the tolerance radius
    const after = await measure(near, { p: point, reach });
    await page.evaluate(() => window.wispEditor.constraints.apply([], { record: false }));
    await settle();
    const before = await measure(near, { p: point, reach });
    await page.evaluate((s) => window.wispEditor.constraints.apply(s, { record: false }), sections);
    await settle();
    console.log(`strands within ${reach.toFixed(1)} cm of the bun's centre: before ${before.passing} of ${before.strands} ` +
      `(${(100 * before.fraction).toFixed(0)}%), after ${after.passing} (${(100 * after.fraction).toFixed(0)}%)`);
    if (!(after.fraction > 0.8) || !(after.fraction > before.fraction + 0.4))
      fail(`the updo did not gather the hair: ${(100 * before.fraction).toFixed(0)}% → ${(100 * after.fraction).toFixed(0)}%`);
    const report = await page.evaluate(async (token) =>
      (await fetch("/api/report", { headers: { "X-Wisp-Token": token } })).json(), token);
    console.log(`progress: ${report.groups.map((q) => `${q.name}: ${q.wisps} wisps, met ${q.met.map((m) => m.toFixed(2))}`).join("; ")}`);
    if (report.groups.length !== 1 || !(report.groups[0].met[0] > 0.8)) fail(`the report says ${JSON.stringify(report.groups)}`);
    await page.screenshot({ path: path.join(outDir, "updo.png") });

    // Drag the facing handle: the bun turns; undo puts it back.
    const reachOut = 0.3 * radius + 3;
    const tip = point.map((v, k) => v + reachOut * updo.facing[k] / Math.hypot(...updo.facing));
    const tipAt = await toScreen(page, tip);
    await dragThrough(page, [tipAt, [tipAt[0] + 70, tipAt[1] + 20]], 8);
    await page.waitForFunction((before) => JSON.stringify(window.wispEditor.constraints.sections[0].facing) !== before,
      JSON.stringify(updo.facing));
    await settle();
    ({ sections, paths } = await editor());
    console.log(`the facing handle dragged: facing ${updo.facing} → ${sections[0].facing}`);
    if (JSON.stringify(sections[0].point) !== JSON.stringify(updo.point)) fail("turning the bun moved it");
    await page.screenshot({ path: path.join(outDir, "updo-drag.png") });
    await page.keyboard.press("Control+z");
    await page.waitForFunction((before) => JSON.stringify(window.wispEditor.constraints.sections[0].facing) === before,
      JSON.stringify(updo.facing));
    await settle();
  }

  // Save: the section as the CLI reads it; `wisp generate` of it is the editor's hair.
  await page.click("#save");
  await page.waitForFunction(() => document.getElementById("saved").textContent.startsWith("saved"));
  const toml = readFileSync(path.join(folder, "style.toml"), "utf8");
  const keys = kind === "braid" ? ["start = [", "axis = [", "side = [", "length = "] : ["point = [", "facing = ["];
  if (!toml.includes(`[[${kind}]]`) || keys.some((k) => !toml.includes(k)) || toml.includes("head_relative"))
    fail(`the saved style does not hold the ${kind} in head units:\n${toml}`);
  const { editor: a, cli: b } = await exportAndGenerate(page, token, wisp, folder);
  if (!a.equals(b)) fail(`wisp generate of the saved ${kind} differs from the editor's hair (${a.length} vs ${b.length} bytes)`);
  console.log(`save: [[${kind}]]; wisp generate gives the editor's hair (${a.length} bytes, identical)`);
});
