// The editor: panels from the schema, the view, and the store of edits. A moving slider
// sends its value at once and asks for a preview (masters, then a strand subset); when it
// is released the full hair follows. Undo is a list of edits, not of snapshots.
import "./style.css";
import { getJson, postJson, getBinary, decodeStrands, decodeHead } from "./api.js";
import { Panels } from "./panels.js";
import { Viewport } from "./viewport.js";

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

async function refreshHair(final) {
  const mine = ++generation;
  const mastersOnly = document.getElementById("show-masters").checked;
  const t0 = performance.now();
  try {
    if (mastersOnly) {
      const buffer = await getBinary("/api/masters");
      if (buffer && mine === generation) viewport.setHair(decodeStrands(buffer));
    } else {
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
  clearTimeout(timer);
  if (final) refreshHair(true);
  else timer = setTimeout(() => refreshHair(false), 30);
  return true;
}

// Sliders send while they move; the edit recorded for undo is the one from the value
// before the drag to the value at release.
const dragStart = new Map();
const panels = new Panels(document.getElementById("panels"), await getJson("/api/schema"), (path, value, { final }) => {
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
  values = (await getJson("/api/style")).values;
  panels.setValues(values);
}

async function step(from, to, key) {
  const edit = from.pop();
  if (!edit) return;
  if (await setField(edit.path, edit[key], { record: false })) {
    panels.setValues({ [edit.path]: edit[key] });
    to.push(edit);
  }
}
document.getElementById("undo").onclick = () => step(undo, redo, "before");
document.getElementById("redo").onclick = () => step(redo, undo, "after");
window.addEventListener("keydown", (e) => {
  if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === "z") {
    e.preventDefault();
    e.shiftKey ? step(redo, undo, "after") : step(undo, redo, "before");
  }
});

const presets = document.getElementById("preset");
presets.append(new Option("—", ""));
for (const name of await getJson("/api/presets")) presets.append(new Option(name, name));
presets.onchange = async () => {
  if (!presets.value) return;
  await postJson("/api/preset", { name: presets.value });
  undo.length = redo.length = 0;
  await loadStyle();
  refreshHair(true);
};
document.getElementById("show-head").onchange = (e) => viewport.showHead(e.target.checked);
document.getElementById("show-masters").onchange = () => refreshHair(true);

viewport.setHead(decodeHead(await getBinary("/api/head")));
await loadStyle();
say("generating…");
await refreshHair(true);
document.body.dataset.ready = "1";  // for the browser tests
