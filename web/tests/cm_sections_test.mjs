// Browser tests of a braid or an updo whose positions and sizes are in cm (`head_relative =
// false`) opened in `wisp edit` (registered in ctest as editor_cm_braid_* and
// editor_cm_updo_*, WISP_CM_CASE=braid or updo): the braid or updo preset at 3,000 strands,
// its section written in cm (the preset's head-unit values on the built-in head, rounded to
// 0.1 cm), opened with `wisp edit style.toml` and seen from behind.
//   - The handles are where the file says, in cm: the braid's start at `start` and its end
//     at start + length·axis; the bun's centre at `point` and its arrow's tip bun_radius +
//     3 cm along `facing`. The drawn paths begin at the start or the centre, and the hair
//     of the section's groups is solved where they are drawn: each drawn point has hair of
//     its group near it.
//   - The size sliders show the file's values (not clamped to the head-unit ranges) and
//     their labels give them in cm as written.
//   - A handle dragged (the braid's end, the bun's centre) stays under the pointer: the
//     section takes the new position in cm (still head_relative = false, the rest as it
//     was), and the handle redrawn from the server's answer is where it was let go.
//   - Undo restores the file's section; Save writes it back in cm.
// Screenshots go to OUT_DIR.
//   WISP_CM_CASE=braid node web/tests/cm_sections_test.mjs WISP_EXE OUT_DIR
import { failWith, measureHair, pageConstraints, smallPreset, testArguments, toScreen, viewFromBehind, withEditor } from "./harness.mjs";
import { readFileSync } from "node:fs";
import path from "node:path";

const { wisp, outDir } = testArguments();
const kind = process.env.WISP_CM_CASE ?? "braid";
if (kind !== "braid" && kind !== "updo") throw new Error(`WISP_CM_CASE=${kind}: braid or updo`);
const fail = failWith(`cm ${kind} test`);

// The preset with few strands (software GL) and its section in cm: the built-in head's
// frame (the scalp sphere's centre and the distance to its crown) maps the preset's head
// units to cm. The test checks the editor against the file's cm values, not this frame.
const head = { center: [-0.008, 3.035, -0.724], radius: 9.463 };
const r1 = (v) => Math.round(v * 10) / 10;
const section = kind === "braid"
  ? { name: "braid", strands: 3, start: [0, -0.45, -1.15].map((v, k) => r1(head.center[k] + head.radius * v)),
    axis: [0, -1, -0.12], side: [1, 0, 0], length: r1(2 * head.radius), width: r1(0.32 * head.radius),
    period: r1(0.55 * head.radius), radius: r1(0.06 * head.radius), weight: 1, head_relative: false }
  : { name: "bun", point: [0, 0.55, -1.05].map((v, k) => r1(head.center[k] + head.radius * v)),
    facing: [0, 0.3, -1], radius: r1(0.18 * head.radius), bun_radius: r1(0.38 * head.radius), turns: 2,
    weight: 1, head_relative: false };
const toml = (s) => Object.entries(s).map(([k, v]) => `${k} = ${JSON.stringify(v).replaceAll(",", ", ")}`).join("\n");
const preset = smallPreset(kind);
const style = `${preset.slice(0, preset.indexOf(`[[${kind}]]`))}[[${kind}]]\n${toml(section)}\n`;

const distance = (a, b) => Math.hypot(...a.map((v, k) => v - b[k]));
const unit = (a) => a.map((v) => v / Math.hypot(...a));

await withEditor(wisp, { prefix: `cm-${kind}`, files: { "style.toml": style } }, async ({ page, token, folder, settle }) => {
  await settle();
  const editor = () => pageConstraints(page);

  let { sections, paths, handles } = await editor();
  const opened = sections[0];
  if (sections.length !== 1 || opened.section !== kind || opened.head_relative !== false)
    fail(`the file's ${kind} shows as ${JSON.stringify(sections)}`);
  await page.click("#tie");
  await viewFromBehind(page, kind === "braid" ? [25, 5, -110] : [20, 35, -95]);
  await settle();
  ({ sections, paths, handles } = await editor());

  // The handles where the file puts them, in cm; the drawn paths begin there.
  const anchor = kind === "braid" ? section.start : section.point;
  const anchorRole = kind === "braid" ? "start" : "point";
  const tipRole = kind === "braid" ? "end" : "facing";
  const tip = kind === "braid"
    ? anchor.map((v, k) => v + section.length * unit(section.axis)[k])
    : anchor.map((v, k) => v + (section.bun_radius + 3) * unit(section.facing)[k]);
  console.log(`the ${anchorRole} handle at ${handles[anchorRole]?.map((v) => v.toFixed(2))} (the file: ${anchor}); ` +
    `the ${tipRole} handle at ${handles[tipRole]?.map((v) => v.toFixed(2))} (the file's: ${tip.map((v) => v.toFixed(2))})`);
  if (!handles[anchorRole] || distance(handles[anchorRole], anchor) > 1e-3)
    fail(`the ${anchorRole} handle is at ${handles[anchorRole]}, the file says ${anchor} cm`);
  if (!handles[tipRole] || distance(handles[tipRole], tip) > 0.05)
    fail(`the ${tipRole} handle is at ${handles[tipRole]}, the file's is ${tip} cm`);
  if (paths[0].length !== (kind === "braid" ? 3 : 1) || distance(paths[0][0].points[0], anchor) > 1e-3)
    fail(`the paths drawn do not begin at the ${anchorRole}: ${JSON.stringify(paths[0]).slice(0, 200)}`);

  // The hair of each path's group (the braid's strand k is group k + 1; the updo's, 1) is
  // where the path is drawn: the distance from each drawn point to the nearest point of its
  // group's hair, at most and at the 90th percentile.
  const near = await measureHair(page, token, ({ strands, offsets, x, groups }, paths) => {
    const gaps = [];
    paths.forEach((path, k) => {
      for (const p of path.points) {
        let best = Infinity;
        for (let s = 0; s < strands; ++s) {
          if (groups[s] !== k + 1) continue;
          for (let i = offsets[s]; i < offsets[s + 1]; ++i)
            best = Math.min(best, Math.hypot(x[3 * i] - p[0], x[3 * i + 1] - p[1], x[3 * i + 2] - p[2]));
        }
        gaps.push(best);
      }
    });
    gaps.sort((a, b) => a - b);
    return { count: gaps.length, p90: gaps[Math.floor(0.9 * (gaps.length - 1))], max: gaps[gaps.length - 1] };
  }, paths[0]);
  console.log(`drawn path points: ${near.count}; the nearest hair of their group: ${near.p90.toFixed(2)} cm at the 90th ` +
    `percentile, ${near.max.toFixed(2)} cm at most`);
  if (!(near.p90 < 1.5)) fail(`the hair is not where the paths are drawn (90th percentile ${near.p90.toFixed(2)} cm)`);

  // The size sliders: the file's values, shown in cm as written.
  const row = page.locator("#tie-tools .section").first();
  for (const key of kind === "braid" ? ["length", "width", "period", "radius"] : ["radius", "bun_radius"]) {
    const input = row.locator(`input[data-key='${key}']`);
    const value = Number(await input.inputValue());
    const label = await input.evaluate((e) => e.previousElementSibling.textContent);
    if (value !== section[key] || label !== `${key} ${section[key].toFixed(1)} cm`)
      fail(`the ${key} slider shows ${value} ('${label}'), the file says ${section[key]} cm`);
  }
  await page.screenshot({ path: path.join(outDir, `cm-${kind}.png`) });

  // Drag a handle: it stays under the pointer, the section takes its position in cm.
  const grabbed = kind === "braid" ? "end" : "point";
  const from = await toScreen(page, handles[grabbed]);
  const to = [from[0] + (kind === "braid" ? 70 : 40), from[1] + (kind === "braid" ? -10 : 20)];
  await page.mouse.move(...from);
  await page.mouse.down();
  for (let i = 1; i <= 8; ++i) await page.mouse.move(from[0] + ((to[0] - from[0]) * i) / 8, from[1] + ((to[1] - from[1]) * i) / 8);
  await page.mouse.up();
  await page.waitForFunction(() => window.wispEditor.constraints.drag === null);
  await settle();
  ({ sections, handles } = await editor());
  const moved = sections[0];
  const at = await toScreen(page, handles[grabbed]);
  console.log(`dragged the ${grabbed} handle from ${from.map(Math.round)} to ${to.map(Math.round)}: redrawn at ` +
    `${at.map(Math.round)}; the ${kind}: ${JSON.stringify(moved)}`);
  if (moved.head_relative !== false) fail(`the drag changed the units: ${JSON.stringify(moved)}`);
  if (distance(at, to) > 3) fail(`the ${grabbed} handle was let go at ${to}, it is redrawn at ${at}`);
  const kept = kind === "braid" ? "start" : "facing";
  if (JSON.stringify(moved[kept]) !== JSON.stringify(opened[kept])) fail(`dragging the ${grabbed} moved the ${kept}`);
  if (kind === "braid") {
    const end = moved.start.map((v, k) => v + moved.length * unit(moved.axis)[k]);
    if (distance(end, handles.end) > 0.05) fail(`the braid ends at ${end}, its handle is at ${handles.end}`);
  } else if (distance(moved.point, handles.point) > 0.01) {
    fail(`the bun is at ${moved.point} cm, its handle at ${handles.point}`);
  }
  await page.screenshot({ path: path.join(outDir, `cm-${kind}-drag.png`) });

  // Undo: the file's section; Save: in cm, as written.
  await page.keyboard.press("Control+z");
  await page.waitForFunction((before) => JSON.stringify(window.wispEditor.constraints.sections[0]) === before,
    JSON.stringify(opened), { timeout: 60000 });
  await settle();
  await page.click("#save");
  await page.waitForFunction(() => document.getElementById("saved").textContent.startsWith("saved"));
  const saved = readFileSync(path.join(folder, "style.toml"), "utf8");
  const written = saved.slice(saved.indexOf(`[[${kind}]]`));
  if (!written.includes("head_relative = false") || !written.includes(`${anchorRole} = [${anchor.join(", ")}]`))
    fail(`the saved [[${kind}]] is not in cm as written:\n${written}`);
  console.log(`undo: the file's [[${kind}]]; save: in cm (${anchorRole} ${anchor})`);
});
