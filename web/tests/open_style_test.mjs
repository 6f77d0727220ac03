// Browser tests of a braid or an updo read from a style file in `wisp edit` (registered in
// ctest as editor_open_braid_* and editor_open_updo_*, WISP_OPEN_CASE=braid or updo): the
// braid or updo preset (presets/KIND.toml) at 3,000 strands, saved as style.toml in a
// temporary folder and opened with `wisp edit style.toml`, seen from behind.
//   - The panel lists it as a [[braid]] / [[updo]] (not as the [[group]] tables it expands
//     into) with the file's values, its sliders from the schema, each label on one line,
//     and its handles on the view, as one made with the tool.
//   - A handle dragged (the braid's end, the bun's centre): while the button is still held,
//     the section on the server, its drawn paths and the hair drawn change (the preview
//     follows the drag); none of it goes on the undo list until the release, which puts one
//     edit there; undo restores the file's section exactly.
//   - Save writes it back as [[KIND]] with the file's keys and values; Open of the saved
//     file and Save again give the same bytes.
// Screenshots go to OUT_DIR.
//   WISP_OPEN_CASE=braid node web/tests/open_style_test.mjs WISP_EXE OUT_DIR
import { failWith, pageConstraints, smallPreset, testArguments, toScreen, viewFromBehind, withEditor } from "./harness.mjs";
import { readFileSync } from "node:fs";
import path from "node:path";

const { wisp, outDir } = testArguments();
const kind = process.env.WISP_OPEN_CASE ?? "braid";
if (kind !== "braid" && kind !== "updo") throw new Error(`WISP_OPEN_CASE=${kind}: braid or updo`);
const fail = failWith(`open ${kind} test`);

// The preset with few strands (software GL), its sections as written.
const style = smallPreset(kind);
// The section as the file has it (its keys and values, comments left out).
const written = {};
for (const line of style.slice(style.indexOf(`[[${kind}]]`)).split("\n").slice(1)) {
  const m = line.match(/^(\w+)\s*=\s*([^#]*?)\s*(#.*)?$/);
  if (!m) break;
  written[m[1]] = JSON.parse(m[2]);
}
await withEditor(wisp, { prefix: `open-${kind}`, files: { "style.toml": style } }, async ({ page, token, folder, settle }) => {
  await settle();
  const editor = () => pageConstraints(page);

  // Listed as the file has it.
  let { sections, paths } = await editor();
  console.log(`opened: ${JSON.stringify(sections)}`);
  if (sections.length !== 1 || sections[0].section !== kind) fail(`the file's ${kind} shows as ${JSON.stringify(sections)}`);
  const opened = sections[0];
  for (const [key, value] of Object.entries(written))
    if (JSON.stringify(opened[key]) !== JSON.stringify(value))
      fail(`${kind}.${key} is ${JSON.stringify(opened[key])}, the file says ${JSON.stringify(value)}`);
  if (Object.keys(opened).length !== Object.keys(written).length + 1)
    fail(`the ${kind} has keys ${Object.keys(opened)}, the file ${Object.keys(written)}`);
  const openedPaths = JSON.stringify(paths);
  if (paths[0]?.length !== (kind === "braid" ? 3 : 1)) fail(`the paths drawn are ${JSON.stringify(paths).slice(0, 200)}`);

  await page.click("#tie");
  await viewFromBehind(page, kind === "braid" ? [25, 5, -110] : [20, 35, -95]);
  const row = page.locator("#tie-tools .section").first();
  const title = await row.locator(".name").getAttribute("title");
  if (!title.startsWith(`[[${kind}]]`)) fail(`the panel lists it as '${title}'`);
  const fields = kind === "braid" ? ["strands", "length", "width", "period", "radius", "weight"]
    : ["radius", "bun_radius", "turns", "weight"];
  for (const key of fields) {
    const input = row.locator(`input[data-key='${key}']`);
    if (!(await input.count())) fail(`no ${key} slider`);
    else if (written[key] !== undefined && Number(await input.inputValue()) !== written[key])
      fail(`the ${key} slider shows ${await input.inputValue()}, the file says ${written[key]}`);
  }
  // Each slider's label on one line: no taller than the range beside it.
  const labels = await row.locator(".slider label").evaluateAll((ls) => ls.map((l) => {
    const r = l.getBoundingClientRect();
    return { text: l.textContent, height: r.height, clipped: l.scrollWidth > l.clientWidth };
  }));
  const wrapped = labels.filter((l) => l.height > 20 || l.clipped);
  if (labels.length !== fields.length || wrapped.length) fail(`labels that wrap or are cut: ${JSON.stringify(wrapped)} of ${JSON.stringify(labels)}`);
  console.log(`the panel: ${title}; sliders ${labels.map((l) => l.text).join(", ")}`);

  // The handles, as a tool's: the braid's start and end, the bun's centre and facing.
  const roles = await page.evaluate(() => window.wispEditor.constraints.handles.children
    .map((h) => h.userData.role).filter(Boolean));
  const want = kind === "braid" ? ["start", "end"] : ["point", "facing"];
  if (want.some((r) => !roles.includes(r))) fail(`the handles are ${roles}`);
  await page.screenshot({ path: path.join(outDir, `open-${kind}.png`) });

  // Drag a handle and hold it: the preview follows before the release.
  const grabbed = kind === "braid" ? "end" : "point";
  const from = await toScreen(page, (await editor()).handles[grabbed]);
  // A fingerprint of the hair drawn (its first points), and the page's hair requests.
  const hairPrint = () => page.evaluate(() => {
    const { viewport } = window.wispEditor;
    const p = viewport.hair.geometry.getAttribute("position").array;
    let sum = 0;
    for (let i = 0; i < Math.min(p.length, 300000); ++i) sum += p[i] * ((i % 7) + 1);
    return sum;
  });
  const printBefore = await hairPrint();
  await page.evaluate(() => {
    window.hairRequests = 0;
    const original = window.fetch;
    window.fetch = (url, ...rest) => {
      if (String(url).startsWith("/api/hair?strands=20000")) ++window.hairRequests;
      return original(url, ...rest);
    };
  });
  await page.mouse.move(...from);
  await page.mouse.down();
  const t0 = Date.now();
  const [dx, dy] = kind === "braid" ? [90, -15] : [40, 25];
  for (let i = 1; i <= 8; ++i) await page.mouse.move(from[0] + (dx * i) / 8, from[1] + (dy * i) / 8);
  // Still held: the server has the moved section, the paths and the hair follow.
  const key = kind === "braid" ? "axis" : "point";
  await page.waitForFunction(([key, before]) => JSON.stringify(window.wispEditor.constraints.sections[0][key]) !== before,
    [key, JSON.stringify(opened[key])], { timeout: 60000 });
  const served = await page.evaluate(async (token) =>
    (await (await fetch("/api/constraints", { headers: { "X-Wisp-Token": token } })).json()).sections, token);
  if (JSON.stringify(served[0][key]) === JSON.stringify(opened[key])) fail(`the server still has ${kind}.${key} ${opened[key]} mid-drag`);
  await page.waitForFunction(() => window.hairRequests > 0, null, { timeout: 60000 });
  await page.waitForFunction(async (before) => {
    const p = window.wispEditor.viewport.hair.geometry.getAttribute("position").array;
    let sum = 0;
    for (let i = 0; i < Math.min(p.length, 300000); ++i) sum += p[i] * ((i % 7) + 1);
    return sum !== before;
  }, printBefore, { timeout: 120000, polling: 250 });
  const followedMs = Date.now() - t0;
  ({ sections, paths } = await editor());
  if (JSON.stringify(paths) === openedPaths) fail("the paths drawn did not follow the drag");
  if (!(await page.evaluate(() => Boolean(window.wispEditor.constraints.drag)))) fail("the drag ended before the release");
  console.log(`mid-drag: ${kind}.${key} ${JSON.stringify(opened[key])} → ${JSON.stringify(sections[0][key])}; ` +
    `${await page.evaluate(() => window.hairRequests)} hair preview(s) asked for, the hair drawn changed ` +
    `${followedMs} ms after the press, before the release`);
  await page.screenshot({ path: path.join(outDir, `open-${kind}-drag.png`) });
  await page.mouse.up();
  await page.waitForFunction(() => window.wispEditor.constraints.drag === null);
  await settle();
  ({ sections, paths } = await editor());
  if (JSON.stringify(sections[0][key]) === JSON.stringify(opened[key])) fail(`the release left ${kind}.${key} as it was`);

  // One edit for the whole drag: one undo restores the file's section exactly.
  await page.keyboard.press("Control+z");
  await page.waitForFunction((before) => JSON.stringify(window.wispEditor.constraints.sections[0]) === before,
    JSON.stringify(opened), { timeout: 60000 });
  await settle();
  await page.keyboard.press("Control+z");  // nothing more to undo: the section stays
  await page.waitForTimeout(500);
  ({ sections } = await editor());
  if (JSON.stringify(sections) !== JSON.stringify([opened])) fail(`a second undo left ${JSON.stringify(sections)}`);

  // Save writes it back as written; Open and Save again: the same bytes.
  await page.click("#save");
  await page.waitForFunction(() => document.getElementById("saved").textContent.startsWith("saved"));
  const saved = readFileSync(path.join(folder, "style.toml"), "utf8");
  const section = saved.slice(saved.indexOf(`[[${kind}]]`));
  if (saved.includes("[[group]]") || !section.startsWith(`[[${kind}]]`)) fail(`the saved style:\n${saved}`);
  // The file's values as written (2.0 and 2 alike: JSON does not tell them apart).
  const plain = (l) => l.replace(/\b(\d+)\.0\b/g, "$1");
  for (const [key, value] of Object.entries(written)) {
    const line = `${key} = ${JSON.stringify(value).replaceAll(",", ", ")}`;
    if (!section.split("\n").some((l) => plain(l) === plain(line)))
      fail(`the saved [[${kind}]] has no '${line}':\n${section}`);
  }
  const opened2 = await page.evaluate(async (token) => (await fetch("/api/open", {
    method: "POST", headers: { "X-Wisp-Token": token, "Content-Type": "application/json" },
    body: JSON.stringify({ name: "style.toml" }),
  })).status, token);
  if (opened2 !== 200) fail(`open answered ${opened2}`);
  await page.click("#save");
  await page.waitForFunction(() => document.getElementById("saved").textContent.startsWith("saved"));
  const again = readFileSync(path.join(folder, "style.toml"), "utf8");
  if (again !== saved) fail(`Open and Save again changed the file:\n${saved}\n---\n${again}`);
  console.log(`save: [[${kind}]] as written (${section.trim().split("\n").length - 1} keys); Open + Save: the same ${again.length} bytes`);
});
