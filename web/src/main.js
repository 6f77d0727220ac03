// The editor: panels from the schema, the view, and the store of edits. A moving slider
// sends its value at once and asks for a preview (masters, then a strand subset); when it
// is released the full hair follows. Undo is a list of edits, not of snapshots.
import "./style.css";
import { getJson, postJson, getBinary, decodeStrands, decodeHead } from "./api.js";
import { Panels } from "./panels.js";
import { Painter } from "./paint.js";
import { Viewport } from "./viewport.js";
import { MotionMode } from "./motion.js";

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

// The document: autosaved (DOC.autosave.toml beside it) a moment after each edit.
let autosaveTimer = null;
function edited() {
  clearTimeout(autosaveTimer);
  autosaveTimer = setTimeout(async () => {
    const result = await postJson("/api/autosave", {});
    document.getElementById("saved").textContent = result.ok
      ? `autosaved ${new Date().toTimeString().slice(0, 5)}` : "";
    if (!result.ok) say(result.body.error);
  }, 1500);
}

// While a value moves: with `mastersFirst` (a value that the masters depend on), the coarse
// masters first (GET /api/masters?preview=1, a solve of every 3rd wisp), then 20,000 strands;
// when it stops, the whole hair.
async function refreshHair(final, { mastersFirst = false } = {}) {
  const mine = ++generation;
  const mastersOnly = document.getElementById("show-masters").checked;
  const t0 = performance.now();
  try {
    if (mastersOnly) {
      const buffer = await getBinary(final ? "/api/masters" : "/api/masters?preview=1");
      if (buffer && mine === generation) viewport.setHair(decodeStrands(buffer), { masters: true });
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
      viewport.setHair(strands);
      hud.dataset.strands = strands.strands;
      hud.dataset.points = strands.points;
    }
    const stats = await getJson("/api/stats");
    const stages = Object.entries(stats.stages)
      .map(([name, s]) => `${name} ${s.ms.toFixed(0)} ms`)
      .join(" · ");
    hud.textContent = `${Number(hud.dataset.strands ?? 0).toLocaleString()} strands · ` +
      `${Number(hud.dataset.points ?? 0).toLocaleString()} points · ${stages} · ` +
      `round trip ${(performance.now() - t0).toFixed(0)} ms`;
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
  if (mapFields.includes(path)) painter.invalidate(path);
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
    : await setField(edit.path, edit[key], { record: false });
  if (ok) {
    if (edit.kind !== "map") panels.setValues({ [edit.path]: edit[key] });
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
async function setPainting(on) {
  document.getElementById("paint").classList.toggle("on", on);
  document.getElementById("paint-tools").hidden = !on;
  document.getElementById("view").classList.toggle("painting", on);
  await painter.setActive(on);
}
document.getElementById("paint").onclick = () => setPainting(!painter.active);

// Save, Save as, Open: files of the style's folder only (the server checks the names).
async function save(name) {
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
  refreshHair(true);
  edited();
};
document.getElementById("show-head").onchange = (e) => viewport.showHead(e.target.checked);
document.getElementById("show-masters").onchange = () => refreshHair(true);

// Motion (M): the style animated live by the Adaptive Wisp Tree (motion.js).
const motion = new MotionMode(viewport, {
  strands: previewStrands,
  onEnter: () => setPainting(false),
  onExit: () => refreshHair(true),
  say,
});

const head = decodeHead(await getBinary("/api/head"));
viewport.setHead(head);
painter.setScalp(await getJson("/api/scalp"), head);
await loadStyle();
say("generating…");
await refreshHair(true);
window.wispEditor = { viewport, painter, motion };  // for the browser tests
document.body.dataset.ready = "1";
