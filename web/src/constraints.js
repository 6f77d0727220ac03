// Placing constraints (Choe & Ko §4, §6.2): ties put with a click on or near the head and
// dragged by their handle, each tie's wisps picked by painting a selection on the scalp with
// the map painter's brush, and each group's progress (the wisps that met each constraint).
//
// The sections are kept by the server as the TOML reader reads them (GET/POST
// /api/constraints: [[tie]], [[comb]], [[group]] tables as JSON); a tie placed here is
// `{section: "tie", name, point: [x, y, z] cm, radius cm, head_relative: false,
// selection: KEY}`, where KEY names a selection painted here (POST /api/selection), which
// Save writes as DOC.KEY.mask.png and the TOML as `mask = "DOC.KEY.mask.png"`.
import * as THREE from "three";
import { getJson, postJson, postBinary, decodeMap, encodeGrayPng } from "./api.js";
import { Painter } from "./paint.js";
import { groupColor } from "./views.js";

// How far off the scalp a tie clicked on the head sits (cm): ties hold hair just off it.
const tieLift = 1.5;
const defaultTieRadius = 1.2;  // cm: the reader's 0.12 head units on the built-in head

// The map painter's brush and overlay on a group's selection: 1 where the group takes the
// wisps whose master root lies there, 0 elsewhere.
class SelectionPainter extends Painter {
  constructor(viewport, { onSent, onStroke, onError }) {
    super(viewport, { valueOf: () => null, onSent, onStroke, onError, onLoaded: () => {} });
    this.brush = { radius: 2.5, strength: 1, value: 1, falloff: "constant", mirror: false, erase: false };
    this.field = null;  // the selection's key
  }

  async load(key = this.field) {
    this.field = key;
    const response = await fetch(`/api/selection?key=${encodeURIComponent(key)}`, {
      headers: { "X-Wisp-Token": this.token() },
    });
    if (!response.ok) return this.onError((await response.json()).error);
    this.setMap(decodeMap(await response.arrayBuffer()));
  }

  async post(key, map, final) {
    const png = await encodeGrayPng(this.bytesOf(map), map.width, map.height);
    const result = await postBinary(`/api/selection?key=${encodeURIComponent(key)}`, png, "image/png");
    if (!result.ok) {
      this.onError(result.body.error);
      return false;
    }
    if (key === this.field) this.map.kind = 3;
    this.onSent(key, null, final);
    return true;
  }

  async restore(key, snapshot) {
    const ok = await this.post(key, snapshot.map, true);
    if (ok && key === this.field) this.setMap({ ...snapshot.map, values: snapshot.map.values.slice() });
    return ok;
  }
}

export class Constraints {
  // viewport: the Viewport. onChanged(final): the groups changed on the server (refresh the
  // hair); onEdit(edit): an edit for the undo list ({kind: "constraints", before, after} or
  // {kind: "selection", path, before, after}); onError(message).
  constructor(viewport, panel, { onChanged, onEdit, onError }) {
    this.viewport = viewport;
    this.panel = panel;
    this.list = panel.querySelector(".sections");
    this.onChanged = onChanged;
    this.onEdit = onEdit;
    this.onError = onError;
    this.sections = [];
    this.progress = [];  // GET /api/report's groups
    this.active = false;
    this.selecting = null;  // the index of the section whose selection is being painted
    this.raycaster = new THREE.Raycaster();
    this.handles = new THREE.Group();
    this.handles.renderOrder = 20;
    viewport.scene.add(this.handles);
    this.selector = new SelectionPainter(viewport, {
      onSent: (key, value, final) => {
        if (final) this.onChanged(true);
      },
      onStroke: (key, before, after) => {
        this.onEdit({ kind: "selection", path: key, before, after });
        this.useSelection(key);
      },
      onError,
    });
    const canvas = viewport.renderer.domElement;
    canvas.addEventListener("pointerdown", (e) => this.down(e), { capture: true });
    canvas.addEventListener("pointermove", (e) => this.move(e));
    window.addEventListener("pointerup", (e) => this.up(e));
  }

  setScalp(scalp, head) {
    this.center = new THREE.Vector3(...scalp.center);
    this.radius = this.center.distanceTo(new THREE.Vector3(...scalp.crown));
    this.selector.setScalp(scalp, head);
  }

  async load() {
    const { sections } = await getJson("/api/constraints");
    this.sections = sections;
    this.draw();
  }

  // Sends the sections; with `record`, the change goes on the undo list. Resolves to
  // whether the server took them (its message is shown otherwise).
  async apply(sections, { record = true } = {}) {
    const before = this.sections;
    const result = await postJson("/api/constraints", { sections });
    if (!result.ok) {
      this.onError(`${result.body.field ?? ""}: ${result.body.error}`);
      return false;
    }
    this.sections = result.body.sections;
    if (record) this.onEdit({ kind: "constraints", before, after: this.sections });
    this.draw();
    this.onChanged(true);
    return true;
  }

  async setActive(on) {
    this.active = on;
    this.panel.hidden = !on;
    if (!on) await this.select(null);
    this.draw();
  }

  // Paints the selection of section i (null: stops painting).
  async select(i) {
    this.selecting = i;
    const on = i !== null && i !== undefined;
    if (on) {
      const s = this.sections[i];
      this.selector.map = null;
      this.selector.field = s.selection ?? this.freeKey(s);
    }
    await this.selector.setActive(on);
    this.draw();
  }

  // A selection key not yet used: the section's name made plain.
  freeKey(section) {
    const used = new Set(this.sections.map((s) => s.selection).filter(Boolean));
    const base = (section.name ?? section.section).toLowerCase().replace(/[^a-z0-9]+/g, "-").replace(/^-|-$/g, "") || "group";
    let key = base.slice(0, 24), n = 2;
    while (used.has(key)) key = `${base.slice(0, 24)}-${n++}`;
    return key;
  }

  // After the first stroke of a selection, the section takes it.
  useSelection(key) {
    const i = this.selecting;
    if (i === null || this.sections[i]?.selection === key) return;
    const next = structuredClone(this.sections);
    next[i].selection = key;
    this.apply(next);
  }

  // The report's groups for section i: a tie, comb or group is one, a braid one per strand.
  groupsOf(i) {
    const s = this.sections[i];
    const kindIndex = this.sections.slice(0, i).filter((t) => t.section === s.section).length;
    const name = s.name ?? `${s.section}[${kindIndex}]`;
    return this.progress.filter((g) => g.name === name || g.name.startsWith(`${name} strand `));
  }

  setProgress(groups) {
    this.progress = groups;
    this.drawList();
  }

  draw() {
    this.drawHandles();
    this.drawList();
  }

  drawHandles() {
    this.handles.clear();
    this.sections.forEach((s, i) => {
      if (s.section !== "tie" || s.head_relative !== false || !s.point) return;
      const [r, g, b] = groupColor(this.groupIndex(i));
      const color = new THREE.Color(r, g, b);
      const handle = new THREE.Mesh(new THREE.SphereGeometry(0.55, 20, 12),
        new THREE.MeshBasicMaterial({ color, depthTest: false, transparent: true, opacity: 0.95 }));
      handle.position.set(...s.point);
      handle.userData.section = i;
      handle.renderOrder = 20;
      const ring = new THREE.Mesh(new THREE.SphereGeometry(s.radius ?? defaultTieRadius, 20, 12),
        new THREE.MeshBasicMaterial({ color, wireframe: true, transparent: true, opacity: 0.35, depthTest: false }));
      ring.position.copy(handle.position);
      ring.renderOrder = 19;
      handle.userData.ring = ring;
      this.handles.add(handle, ring);
    });
    this.viewport.render();
  }

  // 1 + the index of section i's first group in the style (Hair::group's numbering).
  groupIndex(i) {
    let g = 1;
    for (let k = 0; k < i; ++k) g += this.sections[k].section === "braid" ? (this.sections[k].strands ?? 3) : 1;
    return g;
  }

  drawList() {
    this.list.textContent = "";
    if (!this.sections.length) {
      const empty = document.createElement("div");
      empty.className = "hint";
      empty.textContent = "no constraints yet";
      this.list.append(empty);
    }
    this.sections.forEach((s, i) => {
      const row = document.createElement("div");
      row.className = "section" + (this.selecting === i ? " selecting" : "");
      const swatch = document.createElement("span");
      swatch.className = "swatch";
      const [r, g, b] = groupColor(this.groupIndex(i));
      swatch.style.background = `rgb(${r * 255}, ${g * 255}, ${b * 255})`;
      const name = document.createElement("span");
      name.className = "name";
      name.textContent = s.name ?? `${s.section} ${i + 1}`;
      name.title = `[[${s.section}]]` + (s.selection ? ` · selection ${s.selection}` : s.mask ? ` · mask ${s.mask}` : s.region ? ` · region ${s.region}` : " · every wisp");
      const select = document.createElement("button");
      select.textContent = this.selecting === i ? "done" : "select";
      select.title = "paint the wisps this constraint takes on the scalp";
      select.onclick = () => this.select(this.selecting === i ? null : i);
      const remove = document.createElement("button");
      remove.textContent = "×";
      remove.title = "remove";
      remove.onclick = async () => {
        if (this.selecting !== null) await this.select(null);
        this.apply(this.sections.filter((_, k) => k !== i));
      };
      row.append(swatch, name, select, remove);
      // Progress: the fraction of the group's wisps that met each constraint.
      const groups = this.groupsOf(i);
      const bar = document.createElement("div");
      bar.className = "progress";
      if (groups.length) {
        const wisps = groups.reduce((n, g) => n + g.wisps, 0);
        const met = groups.map((g) => g.met.map((m) => `${Math.round(100 * m)}%`).join(" → ")).join(", ");
        const worst = Math.min(...groups.flatMap((g) => g.met.length ? g.met : [0]));
        bar.innerHTML = `<div class="fill" style="width:${(100 * worst).toFixed(0)}%"></div>`;
        const text = document.createElement("span");
        text.textContent = `${wisps} wisps · met ${met}`;
        bar.append(text);
        row.dataset.wisps = wisps;
        row.dataset.met = worst;
      } else {
        bar.textContent = "…";
      }
      row.append(bar);
      if (s.section === "tie") {
        const radius = document.createElement("input");
        radius.type = "range";
        radius.min = 0.3;
        radius.max = 5;
        radius.step = 0.1;
        radius.value = s.radius ?? defaultTieRadius;
        radius.title = "the tie's tolerance radius (cm): how tight it gathers the hair";
        radius.onchange = () => {
          const next = structuredClone(this.sections);
          next[i].radius = Number(radius.value);
          this.apply(next);
        };
        const label = document.createElement("label");
        label.textContent = "radius";
        row.append(label, radius);
      }
      this.list.append(row);
    });
  }

  ray(e) {
    const rect = this.viewport.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1,
      -((e.clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.viewport.camera);
    return this.raycaster.ray;
  }

  // Where a click puts a tie: just off the head where it hits it, else the point of the ray
  // nearest the head's centre if that is near the head (within 1.8 head radii); else null.
  tiePoint(e) {
    const ray = this.ray(e);
    const hits = this.viewport.head ? this.raycaster.intersectObject(this.viewport.head) : [];
    if (hits[0]) return hits[0].point.clone().addScaledVector(hits[0].face.normal, tieLift);
    const p = ray.closestPointToPoint(this.center, new THREE.Vector3());
    return p.distanceTo(this.center) < 1.8 * this.radius ? p : null;
  }

  down(e) {
    if (!this.active || e.button !== 0 || this.selector.active) return;
    this.ray(e);
    const hit = this.raycaster.intersectObjects(this.handles.children.filter((h) => h.userData.section !== undefined))[0];
    if (hit) {
      // Drag a tie's handle in the plane facing the camera.
      e.preventDefault();
      e.stopImmediatePropagation();
      this.viewport.controls.enabled = false;
      const normal = this.viewport.camera.getWorldDirection(new THREE.Vector3());
      this.drag = { handle: hit.object, plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, hit.object.position) };
      return;
    }
    this.press = { x: e.clientX, y: e.clientY };
  }

  move(e) {
    if (!this.drag) return;
    const p = this.ray(e).intersectPlane(this.drag.plane, new THREE.Vector3());
    if (!p) return;
    this.drag.handle.position.copy(p);
    this.drag.handle.userData.ring.position.copy(p);
    this.drag.moved = true;
    this.viewport.render();
  }

  up(e) {
    if (this.drag) {
      const { handle, moved } = this.drag;
      this.drag = null;
      this.viewport.controls.enabled = true;
      if (!moved) return;
      const next = structuredClone(this.sections);
      next[handle.userData.section].point = handle.position.toArray().map((v) => Math.round(v * 100) / 100);
      this.apply(next);
      return;
    }
    const press = this.press;
    this.press = null;
    if (!press || !this.active || Math.hypot(e.clientX - press.x, e.clientY - press.y) > 4) return;
    const p = this.tiePoint(e);
    if (!p) return this.onError("click on or near the head to place a tie");
    const n = this.sections.filter((s) => s.section === "tie").length + 1;
    let name = `tie ${n}`;
    for (let k = n + 1; this.sections.some((s) => s.name === name); ++k) name = `tie ${k}`;
    this.apply([...this.sections, {
      section: "tie", name, point: p.toArray().map((v) => Math.round(v * 100) / 100),
      radius: defaultTieRadius, head_relative: false,
    }]);
  }
}
