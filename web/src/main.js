// The editor: panels from the schema, the view, and the store of edits. A moving slider
// sends its value at once and asks for a preview (masters, then a strand subset); when it
// is released the full hair follows. Undo is a list of edits, not of snapshots.
import "./style.css";
import { getJson, postJson, getBinary, decodeStrands, decodeHead } from "./api.js";
import { Panels } from "./panels.js";
import { Painter } from "./paint.js";
import { Viewport } from "./viewport.js";
import { MotionMode } from "./motion.js";
import { Constraints } from "./constraints.js";
import { colorModes, needsAttributes, recolor, fetchAttributes, setInset, renderPicture,
  exportHair } from "./views.js";

const previewStrands = 20000;
const status = document.getElementById("status");
const hud = document.getElementById("hud");
const viewport = new Viewport(document.getElementById("view"));
let values = {};
const undo = [], redo = [];
let generation = 0;

function say(text) {
  status.textContent = text;
}

// The document: autosaved (DOC.autosave.toml beside it) a moment after each edit. An
// autosave that answers after a Save began does not overwrite what the Save reports.
let autosaveTimer = null;
let saves = 0;
function edited() {
  clearTimeout(autosaveTimer);
  autosaveTimer = setTimeout(async () => {
    const before = saves;
    const result = await postJson("/api/autosave", {});
    if (saves !== before) return;
    document.getElementById("saved").textContent = result.ok
      ? `autosaved ${new Date().toTimeString().slice(0, 5)}` : "";
    if (!result.ok) say(result.body.error);
  }, 1500);
}

// The hair as the view shows it: the server's strands, coloured as the colour menu says, then
// the HUD's figures and each constraint group's progress. While a value moves: with
// `mastersFirst` (a value that the masters depend on), the coarse masters first
// (GET /api/masters?preview=1, a solve of every 3rd wisp), then 20,000 strands; when it
// stops, the whole hair.
const colorBy = document.getElementById("color-by");
async function refreshHair(final, { mastersFirst = false } = {}) {
  const mine = ++generation;
  const mastersOnly = document.getElementById("show-masters").checked;
  const t0 = performance.now();
  try {
    let legend = "";
    if (mastersOnly) {
      const buffer = await getBinary(final ? "/api/masters" : "/api/masters?preview=1");
      if (!buffer || mine !== generation) return;
      const masters = decodeStrands(buffer);
      // Master i is wisp i: colour by wisp (or group, length) needs no more.
      const wisps = Int32Array.from({ length: masters.strands }, (_, i) => i);
      const shown = recolor(masters, ["group", "progress"].includes(colorBy.value) ? "color" : colorBy.value, { wisp: wisps });
      viewport.setHair(shown.strands, { masters: true });
      legend = shown.legend;
      hud.dataset.strands = masters.strands;
      hud.dataset.points = masters.points;
      hud.dataset.total = masters.strands;
    } else {
      if (!final && mastersFirst) {
        const buffer = await getBinary("/api/masters?preview=1");
        if (mine !== generation) return;  // overtaken by a newer request
        if (buffer) viewport.setHair(decodeStrands(buffer), { masters: true });
      }
      const limit = final ? 1e7 : previewStrands;
      const buffer = await getBinary(`/api/hair?strands=${limit}`);
      if (!buffer || mine !== generation) return;  // overtaken by a newer request
      const strands = decodeStrands(buffer);
      const attributes = needsAttributes(colorBy.value) ? await fetchAttributes(limit) : null;
      if (mine !== generation) return;
      const shown = recolor(strands, colorBy.value, attributes);
      viewport.setHair(shown.strands);
      legend = shown.legend;
      hud.dataset.strands = strands.strands;
      hud.dataset.points = strands.points;
      hud.dataset.total = strands.total;
    }
    document.getElementById("legend").textContent = legend;
    const [stats, report] = await Promise.all([getJson("/api/stats"), getJson("/api/report")]);
    const stages = Object.entries(stats.stages)
      .map(([name, s]) => `${name} ${s.ms.toFixed(0)}`)
      .join(" · ");
    const n = (v) => Number(v ?? 0).toLocaleString();
    const shown = Number(hud.dataset.strands), total = Number(hud.dataset.total);
    const figures = [
      `${n(shown)}${total > shown ? ` of ${n(total)}` : ""} strands · ${n(hud.dataset.points)} points`,
      `${stages} ms · round trip ${(performance.now() - t0).toFixed(0)} ms`,
    ];
    if (report.points_inside_head !== null) figures.push(`${n(report.points_inside_head)} points inside the head`);
    if (report.unresolved !== null) figures.push(`${n(report.unresolved)} unresolved joints`);
    hud.textContent = figures.join("  ·  ");
    hud.dataset.inside = report.points_inside_head ?? "";
    constraints.setProgress(report.groups);
    say("");
  } catch (e) {
    say(e.message);
  }
}

let timer = null;
async function setField(path, value, { final = true, record = true } = {}) {
  const before = values[path];
  const result = await postJson("/api/set", { path, value });
  if (!result.ok) {
    panels.showError(path, result.body.error);
    return false;
  }
  panels.showError(path, "");
  values[path] = result.body.value;
  if (record && final && JSON.stringify(before) !== JSON.stringify(result.body.value)) {
    undo.push({ path, before, after: result.body.value });
    redo.length = 0;
  }
  if (final) edited();
  if (mapFields.includes(path)) {
    painter.invalidate(path);
    if (final) panels.setValues({ [path]: result.body.value });  // the map control's kind
  }
  // In Motion the view shows the moving hair: a dynamics field goes to the running tree.
  if (motion.active) return path.startsWith("dynamics.") ? motion.setDynamics(path, result.body.value) : true;
  clearTimeout(timer);
  if (final) refreshHair(true);
  else timer = setTimeout(() => refreshHair(false, { mastersFirst: feedsMasters(path) }), 30);
  return true;
}

// Sliders send while they move; the edit recorded for undo is the one from the value
// before the drag to the value at release.
const dragStart = new Map();
const schema = await getJson("/api/schema");
const mapFields = schema.fields.filter((f) => f.type === "map").map((f) => f.path);
// The fields whose change moves the masters: those feeding the roots, masters or solve.
const mastersStages = new Set(["head", "roots", "masters", "solve"]);
const feedsMasters = (path) => mastersStages.has(schema.fields.find((f) => f.path === path)?.stage);
const panels = new Panels(document.getElementById("panels"), schema, (path, value, { final }) => {
  if (!dragStart.has(path)) dragStart.set(path, values[path]);
  setField(path, value, { final, record: false }).then((ok) => {
    if (!final) return;
    const before = dragStart.get(path);
    dragStart.delete(path);
    if (ok && JSON.stringify(before) !== JSON.stringify(values[path])) {
      undo.push({ path, before, after: values[path] });
      redo.length = 0;
    }
  });
});

async function loadStyle() {
  const style = await getJson("/api/style");
  values = style.values;
  panels.setValues(values);
  document.getElementById("document").textContent = style.document;
}

async function step(from, to, key) {
  const edit = from.pop();
  if (!edit) return;
  const ok = edit.kind === "map"
    ? await painter.restore(edit.path, edit[key], (p, v) => setField(p, v, { record: false }))
    : edit.kind === "constraints" ? await constraints.apply(edit[key], { record: false })
    : edit.kind === "selection" ? await constraints.selector.restore(edit.path, edit[key])
    : await setField(edit.path, edit[key], { record: false });
  if (ok) {
    if (!edit.kind) panels.setValues({ [edit.path]: edit[key] });
    to.push(edit);
  } else {
    from.push(edit);
  }
}
document.getElementById("undo").onclick = () => step(undo, redo, "before");
document.getElementById("redo").onclick = () => step(redo, undo, "after");
window.addEventListener("keydown", (e) => {
  if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === "z") {
    e.preventDefault();
    e.shiftKey ? step(redo, undo, "after") : step(undo, redo, "before");
  } else if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === "s") {
    e.preventDefault();
    save();
  } else if (!e.ctrlKey && !e.metaKey && !e.altKey && !(e.target instanceof HTMLInputElement) &&
             !(e.target instanceof HTMLSelectElement)) {
    const k = e.key.toLowerCase();
    if (k === "p") setPainting(!painter.active);
    else if (k === "m") motion.toggle();
    else if (motion.active && k === " ") { e.preventDefault(); motion.play(!motion.state?.playing); }
    else if (k === "t" || k === "c" || k === "b" || k === "u") {
      const tool = { t: "tie", c: "comb", b: "braid", u: "updo" }[k];
      if (constraints.active && constraints.tool === tool) setTying(false);
      else {
        constraints.setTool(tool);
        setTying(true);
      }
    }
    else if (constraints.selector.active && k === "e") brushInput("select-erase", (el) => (el.checked = !el.checked));
    else if (painter.active && k === "e") brushInput("brush-erase", (el) => (el.checked = !el.checked));
    else if (painter.active && (k === "[" || k === "]"))
      brushInput("brush-radius", (el) => (el.value = Number(el.value) * (k === "]" ? 1.2 : 1 / 1.2)));
  }
});

// Painting: the toolbar over the view drives the brush (paint.js).
let previewing = false;
const painter = new Painter(viewport, {
  valueOf: (path) => values[path],
  onSent: (path, value, final) => {
    values[path] = value;
    panels.setValues({ [path]: value });
    panels.showError(path, "");
    // While the stroke runs, one preview at a time: a brush sends maps faster than the
    // hair can come back.
    if (final) refreshHair(true);
    else if (!previewing) {
      previewing = true;
      refreshHair(false).finally(() => (previewing = false));
    }
    if (final) edited();
  },
  onStroke: (path, before, after) => {
    undo.push({ kind: "map", path, before, after });
    redo.length = 0;
  },
  onError: (message) => say(message),
  onLoaded: () => brushChanged(),
});
let constraintTimer = null;
const constraints = new Constraints(viewport, document.getElementById("tie-tools"), {
  // A dragged handle's previews (final false) come as fast as the server answers them: the
  // hair follows a moment after the newest, as it follows a moving slider; the release's
  // edit (final) drops a preview still waiting.
  onChanged: (final) => {
    clearTimeout(constraintTimer);
    if (!final) {
      constraintTimer = setTimeout(() => refreshHair(false), 30);
      return;
    }
    edited();
    refreshHair(true);
  },
  onEdit: (edit) => {
    undo.push(edit);
    redo.length = 0;
  },
  onError: (message) => say(message),
  sectionFields: schema.sections,
});
function selectBrushChanged() {
  const b = constraints.selector.brush;
  b.radius = Number(document.getElementById("select-radius").value);
  b.erase = document.getElementById("select-erase").checked;
}
for (const id of ["select-radius", "select-erase"]) {
  document.getElementById(id).addEventListener("input", selectBrushChanged);
  document.getElementById(id).addEventListener("change", selectBrushChanged);
}
const fieldSelect = document.getElementById("paint-field");
for (const path of mapFields) fieldSelect.append(new Option(path.replace("maps.", ""), path));
fieldSelect.onchange = () => painter.load(fieldSelect.value);
function brushInput(id, change) {
  const el = document.getElementById(id);
  change(el);
  el.dispatchEvent(new Event("input"));
}
function brushChanged() {
  const b = painter.brush;
  b.radius = Number(document.getElementById("brush-radius").value);
  b.strength = Number(document.getElementById("brush-strength").value);
  b.value = Number(document.getElementById("brush-value").value);
  b.falloff = document.getElementById("brush-falloff").value;
  b.mirror = document.getElementById("brush-mirror").checked;
  b.erase = document.getElementById("brush-erase").checked;
  const field = schema.fields.find((f) => f.path === painter.field);
  const unit = field?.unit ? ` ${field.unit}` : "";
  const m = painter.map;
  const scaled = (t) => (m ? m.low + t * (m.high - m.low) : t);
  const fmt = (v) => (Math.abs(v) >= 10 ? v.toFixed(0) : v.toFixed(2));
  document.getElementById("brush-radius-text").textContent = `${b.radius.toFixed(1)} cm`;
  document.getElementById("brush-strength-text").textContent = b.strength.toFixed(2);
  document.getElementById("brush-value-text").textContent = fmt(scaled(b.value)) + unit;
  document.getElementById("ramp-low").textContent = fmt(scaled(0)) + unit;
  document.getElementById("ramp-high").textContent = fmt(scaled(1)) + unit;
}
for (const id of ["brush-radius", "brush-strength", "brush-value", "brush-falloff", "brush-mirror", "brush-erase"]) {
  document.getElementById(id).addEventListener("input", brushChanged);
  document.getElementById(id).addEventListener("change", brushChanged);
}
// One tool at a time; its panel sits at the view's left, and the picture moves right of it.
function toolInset() {
  const panel = ["paint-tools", "tie-tools"].map((id) => document.getElementById(id)).find((el) => !el.hidden);
  setInset(viewport, panel ? panel.offsetWidth + 10 : 0);
}
async function setPainting(on) {
  if (on && constraints.active) await setTying(false);
  document.getElementById("paint").classList.toggle("on", on);
  document.getElementById("paint-tools").hidden = !on;
  document.getElementById("view").classList.toggle("painting", on);
  await painter.setActive(on);
  toolInset();
}
async function setTying(on) {
  if (on && painter.active) await setPainting(false);
  document.getElementById("tie").classList.toggle("on", on);
  document.getElementById("view").classList.toggle("painting", on);
  await constraints.setActive(on);
  toolInset();
}
document.getElementById("tie").onclick = () => setTying(!constraints.active);
for (const button of document.querySelectorAll("#tie-tools [data-tool]"))
  button.onclick = () => constraints.setTool(button.dataset.tool);
document.getElementById("paint").onclick = () => setPainting(!painter.active);

// Save, Save as, Open: files of the style's folder only (the server checks the names).
async function save(name) {
  ++saves;
  const result = await postJson("/api/save", name ? { name } : {});
  if (!result.ok) return say(result.body.error);
  say("");
  document.getElementById("saved").textContent = `saved ${result.body.files.join(", ")}`;
  await loadStyle();
}
document.getElementById("save").onclick = () => save();
document.getElementById("save-as").onclick = () => {
  const name = prompt("Save as (a .toml file in the style's folder)", document.getElementById("document").textContent);
  if (name) save(name);
};
const open = document.getElementById("open");
open.onfocus = open.onmousedown = async () => {
  const { files } = await getJson("/api/files");
  const have = [...open.options].slice(1).map((o) => o.value).join("|");
  if (have === files.join("|")) return;
  open.length = 1;
  for (const f of files) open.append(new Option(f, f));
};
open.onchange = async () => {
  const name = open.value;
  open.value = "";
  if (!name) return;
  const result = await postJson("/api/open", { name });
  if (!result.ok) return say(result.body.error);
  undo.length = redo.length = 0;
  await loadStyle();
  painter.invalidate();
  await constraints.load();
  refreshHair(true);
};

const presets = document.getElementById("preset");
presets.append(new Option("—", ""));
for (const name of await getJson("/api/presets")) presets.append(new Option(name, name));
presets.onchange = async () => {
  if (!presets.value) return;
  await postJson("/api/preset", { name: presets.value });
  undo.length = redo.length = 0;
  await loadStyle();
  painter.invalidate();
  await constraints.load();
  refreshHair(true);
  edited();
};
document.getElementById("show-head").onchange = (e) => viewport.showHead(e.target.checked);
document.getElementById("show-masters").onchange = () => refreshHair(true);
for (const [mode, text] of Object.entries(colorModes)) colorBy.append(new Option(text, mode));
colorBy.onchange = () => refreshHair(true);

// The final picture beside the live view, from wisp's own renderer.
const picture = document.getElementById("picture");
document.getElementById("render").onclick = async () => {
  const t0 = performance.now();
  say("");
  document.getElementById("picture-time").textContent = "rendering…";
  picture.hidden = false;
  try {
    const { clientWidth: w, clientHeight: h } = viewport.element;
    const width = 512, height = Math.max(16, Math.min(1024, Math.round((512 * h) / Math.max(1, w))));
    const url = await renderPicture(viewport, width, height);
    const image = document.getElementById("picture-image");
    if (image.src) URL.revokeObjectURL(image.src);
    image.src = url;
    document.getElementById("picture-time").textContent = `${((performance.now() - t0) / 1000).toFixed(1)} s`;
  } catch (e) {
    document.getElementById("picture-time").textContent = "";
    say(e.message);
  }
};
document.getElementById("picture-close").onclick = () => (picture.hidden = true);

// Export: the full hair in any of wisp's formats, into the style's folder.
const exportMenu = document.getElementById("export");
for (const ext of (await getJson("/api/export")).formats) exportMenu.append(new Option(ext, ext));
exportMenu.onchange = async () => {
  const ext = exportMenu.value;
  exportMenu.value = "";
  if (!ext) return;
  const doc = document.getElementById("document").textContent.replace(/\.toml$/, "");
  const name = prompt(`Export the hair as (a ${ext} file in the style's folder)`, doc + ext);
  if (!name) return;
  say("exporting…");
  const result = await exportHair(name);
  if (!result.ok) return say(result.body.error);
  say("");
  document.getElementById("saved").textContent = `exported ${result.body.file} (${result.body.strands.toLocaleString()} strands)`;
};

// A head OBJ: uploaded with the Head panel's scale and scalp method.
const headFile = document.getElementById("head-file");
document.getElementById("upload-head").onclick = () => headFile.click();
headFile.onchange = async () => {
  const file = headFile.files[0];
  headFile.value = "";
  if (!file) return;
  const method = values["head.scalp.method"] === "hairline" ? "hairline" : "group";
  const scale = values["head.scale"] ?? 1;
  say("loading the head…");
  const token = new URLSearchParams(location.search).get("token") ?? "";
  const response = await fetch(`/api/head?name=${encodeURIComponent(file.name)}&scale=${scale}&method=${method}`, {
    method: "POST", headers: { "X-Wisp-Token": token, "Content-Type": "text/plain" }, body: file,
  });
  const body = await response.json();
  if (!response.ok) return say(`${file.name}: ${body.error}`);
  say("");
  undo.length = redo.length = 0;
  await loadStyle();
  await refreshHair(true);  // the update loads the new head (its stage runs first)
  const head = decodeHead(await getBinary("/api/head"));
  viewport.setHead(head);
  const scalp = await getJson("/api/scalp");
  painter.setScalp(scalp, head);
  constraints.setScalp(scalp, head);
  painter.invalidate();
  edited();
};

// The server's progress on long runs (the full hair, a render, an export), as server-sent
// events (GET /api/events): a bar over the view while one runs. The browser reconnects a
// dropped stream by itself.
// A long stage (the solve, the members) also sends its own fraction done as it runs. A
// preview (20,000 strands while a value moves) shows the bar only once it has run for
// kPreviewBarMs: most are quicker, and the bar would flicker.
const progressBar = document.getElementById("progress");
const kPreviewBarMs = 300;
let progressTimer = null, previewSince = 0;
const events = new EventSource(`/api/events?token=${encodeURIComponent(new URLSearchParams(location.search).get("token") ?? "")}`);
events.addEventListener("progress", (message) => {
  const e = JSON.parse(message.data);
  if (e.task === "preview") {
    const shown = !progressBar.hidden && progressBar.dataset.task === "preview";
    if (e.finished) previewSince = 0;
    else if (!previewSince) previewSince = performance.now();
    if (!shown && (e.finished || performance.now() - previewSince < kPreviewBarMs)) return;
  }
  clearTimeout(progressTimer);
  progressBar.hidden = false;
  progressBar.classList.toggle("failed", Boolean(e.error));
  const fraction = e.total ? Math.min(1, (e.done + (e.finished ? 0 : e.fraction ?? 0)) / e.total) : 1;
  progressBar.querySelector(".fill").style.width = `${(100 * fraction).toFixed(0)}%`;
  progressBar.querySelector("span").textContent = e.finished
    ? `${e.task} ${e.error ? `failed: ${e.error}` : "done"}`
    : `${e.task}: ${e.step}${e.fraction ? ` ${(100 * e.fraction).toFixed(0)}%` : ""} (${e.done + 1} of ${e.total})`;
  progressBar.dataset.task = e.task;
  progressBar.dataset.finished = e.finished ? "1" : "";
  if (e.finished) progressTimer = setTimeout(() => (progressBar.hidden = true), e.error ? 2500 : 600);
});

// Motion (M): the style animated live by the Adaptive Wisp Tree (motion.js).
const motion = new MotionMode(viewport, {
  strands: previewStrands,
  onEnter: () => setPainting(false),
  onExit: () => refreshHair(true),
  say,
});

const head = decodeHead(await getBinary("/api/head"));
viewport.setHead(head);
const scalp = await getJson("/api/scalp");
painter.setScalp(scalp, head);
constraints.setScalp(scalp, head);
await constraints.load();
await loadStyle();
say("generating…");
await refreshHair(true);
window.wispEditor = { viewport, painter, motion, constraints };  // for the browser tests
document.body.dataset.ready = "1";
