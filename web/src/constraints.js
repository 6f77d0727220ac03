// Placing constraints (Choe & Ko §4, §6.2): ties put with a click on or near the head and
// dragged by their handle; combs and trajectories drawn as a stroke over the head (its
// points lifted onto a surface just off the scalp) and reshaped by dragging their control
// points; each constraint's wisps picked by painting a selection on the scalp with the map
// painter's brush, and each group's progress (the wisps that met each constraint).
//
// The sections are kept by the server as the TOML reader reads them (GET/POST
// /api/constraints: [[tie]], [[comb]], [[group]] tables as JSON); a tie placed here is
// `{section: "tie", name, point: [x, y, z] cm, radius cm, head_relative: false,
// selection: KEY}`, where KEY names a selection painted here (POST /api/selection), which
// Save writes as DOC.KEY.mask.png and the TOML as `mask = "DOC.KEY.mask.png"`. A comb is
// `{section: "comb", name, trajectory: [[x, y, z], …] cm, smooth: true, radius, weight,
// head_relative: false}`; a trajectory is a [[group]] whose queue is one trajectory
// constraint, `{section: "group", name, head_relative: false, constraint: [{kind:
// "trajectory", trajectory, smooth: true, radius, weight}]}`. Braids and updos are
// hairdressing.js's.
import * as THREE from "three";
import { getJson, postJson, postBinary, decodeMap, encodeGrayPng } from "./api.js";
import { Painter } from "./paint.js";
import { groupColor } from "./views.js";
import { Hairdressing, sliderRow } from "./hairdressing.js";

// How far off the scalp a tie clicked on the head sits (cm): ties hold hair just off it.
const tieLift = 1.5;
const defaultTieRadius = 1.2;  // cm: the reader's 0.12 head units on the built-in head
// A drawn stroke: its points sit this far off the scalp (cm), where the hair's outer layer
// lies; a point is kept every `strokeStep` cm, and the stroke becomes one control point per
// `controlSpacing` cm of its length (3 to 8 of them).
const strokeLift = 1.5;
const strokeStep = 0.4;
const controlSpacing = 4;
// A drawn comb reaches 5 cm with weight 0.95, wider and firmer than the reader's defaults
// (0.4 head units, 3 cm on the built-in head; 0.6), so a stroke shows to the eye: its
// direction constraint turns only the wisps whose joints are within its reach from the
// root on, and lets a wisp go for good once it leaves (docs/style.md), so a narrow reach
// catches a thin band of roots and a weight of 0.8 leaves gravity enough to pull them out
// before they turn (over long straight hair, 30,000 strands: mean alignment with the stroke
// 0.34 at 3 cm and 0.8, 0.73 at 5 cm and 0.95; 0.99 and up would let hair pass through
// hair, as a tie's w = 1 does). A trajectory's tube is 1.5 cm wide and followed exactly.
const defaultComb = { radius: 5, weight: 0.95 };
const defaultTrajectory = { radius: 1.5, weight: 1 };
// What each tool does, for the panel's hint.
const toolHints = {
  tie: "click on or near the head: a tie · drag its handle to move it",
  comb: "drag over the head: a comb stroke, in the direction to comb · drag a control point to reshape it",
  trajectory: "drag from the roots outward: a path the hair follows · drag a control point to reshape it",
  braid: "press on the back of the head and drag down the way it hangs: a braid · drag its start or its end to move it",
  updo: "click where the bun sits: an updo · drag its centre, or the tip of its arrow to turn it",
};

// The points of a stroke resampled to `n` points evenly spaced along it.
function resample(points, n) {
  const lengths = [0];
  for (let i = 1; i < points.length; ++i) lengths.push(lengths[i - 1] + points[i].distanceTo(points[i - 1]));
  const total = lengths[lengths.length - 1];
  const out = [];
  let i = 1;
  for (let k = 0; k < n; ++k) {
    const at = (total * k) / (n - 1);
    while (i < points.length - 1 && lengths[i] < at) ++i;
    const span = lengths[i] - lengths[i - 1];
    const t = span > 0 ? Math.min(1, Math.max(0, (at - lengths[i - 1]) / span)) : 0;
    out.push(points[i - 1].clone().lerp(points[i], t));
  }
  return out;
}

// [x, y, z] rounded to 0.01 cm, as the sections keep positions.
const rounded = (p) => p.toArray().map((v) => Math.round(v * 100) / 100);

// The control points a section draws and lets drag: a comb's path, a group's trajectory
// and direction constraints (in cm only: head-relative ones are left as the file has them).
// [{ path: -1 (the comb's own) or the constraint's index, points: [[x, y, z], …] }]
function pathsOf(s) {
  if (s.head_relative !== false) return [];
  if (s.section === "comb" && Array.isArray(s.trajectory)) return [{ path: -1, points: s.trajectory }];
  if (s.section !== "group" || !Array.isArray(s.constraint)) return [];
  return s.constraint.flatMap((c, k) => (c.kind === "trajectory" || c.kind === "direction") &&
    Array.isArray(c.trajectory) && c.head_relative !== true ? [{ path: k, points: c.trajectory }] : []);
}

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
  // {kind: "selection", path, before, after}); onError(message). sectionFields: the
  // schema's numbers of [[braid]] and [[updo]] (GET /api/schema "sections").
  constructor(viewport, panel, { onChanged, onEdit, onError, sectionFields }) {
    this.viewport = viewport;
    this.panel = panel;
    this.list = panel.querySelector(".sections");
    this.onChanged = onChanged;
    this.onEdit = onEdit;
    this.onError = onError;
    this.sections = [];
    this.paths = [];  // per section, the server's expansion of its paths (cm)
    // Per section, the units the server read it in ({origin, scale, units}: cm = origin +
    // scale·value), and head units' (what a new braid or updo is written in).
    this.frames = [];
    this.headFrame = null;
    this.hairdressing = new Hairdressing(this, sectionFields);
    this.progress = [];  // GET /api/report's groups
    this.active = false;
    this.tool = "tie";  // what a click or a drag on the head makes: tie, comb or trajectory
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
    const reply = await getJson("/api/constraints");
    this.take(reply);
    this.draw();
  }

  // Sends the sections; with `record`, the change goes on the undo list (as from `before`,
  // the sections a drag started from). Resolves to whether the server took them (its
  // message is shown otherwise).
  async apply(sections, { record = true, before = this.sections } = {}) {
    const result = await postJson("/api/constraints", { sections });
    if (!result.ok) {
      this.onError(`${result.body.field ?? ""}: ${result.body.error}`);
      return false;
    }
    this.take(result.body);
    if (record) this.onEdit({ kind: "constraints", before, after: this.sections });
    this.draw();
    this.onChanged(true);
    return true;
  }

  // The server's sections, their paths and their units (GET or POST /api/constraints).
  take({ sections, paths, frames, head }) {
    this.sections = sections;
    this.paths = paths ?? [];
    this.frames = frames ?? [];
    if (head) this.headFrame = head;
  }

  async setActive(on) {
    this.active = on;
    this.panel.hidden = !on;
    this.setTool(this.tool);
    if (!on) await this.select(null);
    this.draw();
  }

  // tie, comb or trajectory: what a click or a drag on the head makes.
  setTool(tool) {
    this.tool = tool;
    for (const b of this.panel.querySelectorAll("[data-tool]")) b.classList.toggle("on", b.dataset.tool === tool);
    const hint = this.panel.querySelector(".tool-hint");
    if (hint) hint.textContent = toolHints[tool];
    this.viewport.element.classList.toggle("stroking", this.active && tool !== "tie" && tool !== "updo");
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
    this.sections.forEach((s, i) => {
      for (const { path, points } of pathsOf(s)) this.drawPath(i, path, points);
      if (s.section === "braid" || s.section === "updo") this.hairdressing.draw(i);
    });
    this.viewport.render();
  }

  // A comb's or trajectory's path: the curve through its control points (a Catmull-Rom
  // curve, as the solver draws it when `smooth`), a faint tube of its radius (the comb's
  // reach, the trajectory's tolerance), an arrowhead at its end (the direction it combs)
  // and a handle on each control point.
  drawPath(i, path, points) {
    const s = this.sections[i];
    const spec = path < 0 ? s : s.constraint[path];
    const [r, g, b] = groupColor(this.groupIndex(i));
    const color = new THREE.Color(r, g, b);
    const p = points.map((q) => new THREE.Vector3(...q));
    if (p.length < 2) return;
    const curve = spec.smooth === false ? new THREE.CurvePath() : new THREE.CatmullRomCurve3(p, false, "catmullrom", 0.5);
    if (spec.smooth === false) for (let k = 1; k < p.length; ++k) curve.add(new THREE.LineCurve3(p[k - 1], p[k]));
    const samples = curve.getSpacedPoints(Math.max(8, 12 * (p.length - 1)));
    const overlay = (material) => Object.assign(material, { depthTest: false, transparent: true });
    const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints(samples),
      overlay(new THREE.LineBasicMaterial({ color, opacity: 0.95 })));
    line.renderOrder = 19;
    const radius = spec.radius ?? (path < 0 ? defaultComb.radius : defaultTrajectory.radius);
    const tube = new THREE.Mesh(new THREE.TubeGeometry(curve, samples.length, radius, 10, false),
      overlay(new THREE.MeshBasicMaterial({ color, opacity: 0.1, depthWrite: false })));
    tube.renderOrder = 18;
    const end = samples[samples.length - 1], before = samples[samples.length - 2];
    const arrow = new THREE.Mesh(new THREE.ConeGeometry(0.5, 1.4, 14),
      overlay(new THREE.MeshBasicMaterial({ color, opacity: 0.95 })));
    arrow.position.copy(end);
    arrow.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), end.clone().sub(before).normalize());
    arrow.renderOrder = 20;
    this.handles.add(tube, line, arrow);
    p.forEach((q, k) => {
      const handle = new THREE.Mesh(new THREE.SphereGeometry(k === 0 ? 0.45 : 0.38, 16, 10),
        overlay(new THREE.MeshBasicMaterial({ color: k === 0 ? 0xffffff : color, opacity: 0.95 })));
      handle.position.copy(q);
      handle.userData = { section: i, path, point: k };
      handle.renderOrder = 21;
      this.handles.add(handle);
    });
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
        // A braid's strands: each strand's least share, the whole queue in the tooltip.
        text.textContent = groups.length > 1
          ? `${wisps} wisps · met ${groups.map((g) => Math.round(100 * Math.min(...g.met.length ? g.met : [0]))).join("/")}%`
          : `${wisps} wisps · met ${met}`;
        bar.title = `met ${met}`;
        bar.append(text);
        row.dataset.wisps = wisps;
        row.dataset.met = worst;
      } else {
        bar.textContent = "…";
      }
      row.append(bar);
      // A slider of one of the section's numbers (of its constraint `path`, -1: its own).
      const slider = (key, path, min, max, step, fallback, title, unit = "") => {
        const input = document.createElement("input");
        input.type = "range";
        Object.assign(input, { min, max, step, title });
        const spec = path < 0 ? s : s.constraint[path];
        input.value = spec[key] ?? fallback;
        input.dataset.key = key;
        const label = document.createElement("label");
        const show = () => (label.textContent = `${key} ${Number(input.value).toFixed(step < 0.1 ? 2 : 1)}${unit}`);
        show();
        input.oninput = show;
        input.onchange = () => {
          const next = structuredClone(this.sections);
          (path < 0 ? next[i] : next[i].constraint[path])[key] = Number(input.value);
          this.apply(next);
        };
        row.append(sliderRow(label, input));
      };
      if (s.section === "tie" && s.head_relative === false)
        slider("radius", -1, 0.3, 5, 0.1, defaultTieRadius, "the tie's tolerance radius (cm): how tight it gathers the hair", " cm");
      if (s.section === "comb" && s.head_relative === false) {
        slider("radius", -1, 0.5, 10, 0.1, defaultComb.radius, "the comb's reach (cm): hair this close to its path turns along it", " cm");
        slider("weight", -1, 0.05, 1, 0.05, defaultComb.weight, "how firmly the comb overrides gravity (w of eq. 7)");
      }
      if (s.section === "braid" || s.section === "updo") this.hairdressing.sliders(row, i);
      for (const { path } of s.section === "group" ? pathsOf(s) : [])
        slider("radius", path, 0.3, 6, 0.1, defaultTrajectory.radius, "the path's tolerance radius (cm): how tightly the hair keeps to it", " cm");
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

  // Where a stroke or a dragged control point goes: `strokeLift` off the head where the
  // pointer is over it; off it, the pointer's ray's point nearest the head's centre, put
  // as far from the centre as the head's surface plus the lift (the stroke runs on round
  // the silhouette); null when the pointer is far from the head.
  surfacePoint(e) {
    const ray = this.ray(e);
    const hits = this.viewport.head ? this.raycaster.intersectObject(this.viewport.head) : [];
    if (hits[0]) return hits[0].point.clone().addScaledVector(hits[0].face.normal, strokeLift);
    const p = ray.closestPointToPoint(this.center, new THREE.Vector3());
    const d = p.distanceTo(this.center);
    if (d > 1.6 * this.radius) return null;
    return this.center.clone().addScaledVector(p.sub(this.center).normalize(), Math.max(d, this.radius + strokeLift));
  }

  down(e) {
    if (!this.active || e.button !== 0 || this.selector.active) return;
    this.ray(e);
    const hit = this.raycaster.intersectObjects(this.handles.children.filter((h) => h.userData.section !== undefined))[0];
    if (hit) {
      // Drag a tie's handle in the plane facing the camera; a control point over the head.
      e.preventDefault();
      e.stopImmediatePropagation();
      this.viewport.controls.enabled = false;
      const normal = this.viewport.camera.getWorldDirection(new THREE.Vector3());
      this.drag = { handle: hit.object, plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, hit.object.position),
        before: this.sections };
      return;
    }
    if (this.hairdressing.down(e)) {
      e.preventDefault();
      e.stopImmediatePropagation();
      this.viewport.controls.enabled = false;
      return;
    }
    if (this.tool === "comb" || this.tool === "trajectory") {
      const p = this.surfacePoint(e);
      if (!p) return;
      e.preventDefault();
      e.stopImmediatePropagation();
      this.viewport.controls.enabled = false;
      this.stroke = { points: [p], line: new THREE.Line(new THREE.BufferGeometry(),
        new THREE.LineBasicMaterial({ color: 0xd7a05b, depthTest: false, transparent: true })) };
      this.stroke.line.renderOrder = 22;
      this.handles.add(this.stroke.line);
      return;
    }
    this.press = { x: e.clientX, y: e.clientY };
  }

  move(e) {
    if (this.hairdressing.move(e)) return;
    if (this.stroke) {
      const p = this.surfacePoint(e);
      const last = this.stroke.points[this.stroke.points.length - 1];
      if (!p || p.distanceTo(last) < strokeStep) return;
      this.stroke.points.push(p);
      this.stroke.line.geometry.setFromPoints(this.stroke.points);
      this.viewport.render();
      return;
    }
    if (!this.drag) return;
    const { handle } = this.drag;
    const p = handle.userData.path !== undefined
      ? this.surfacePoint(e) ?? this.ray(e).intersectPlane(this.drag.plane, new THREE.Vector3())
      : this.ray(e).intersectPlane(this.drag.plane, new THREE.Vector3());
    if (!p) return;
    this.place(handle, p);
    this.drag.at = p.clone();
    this.drag.moved = true;
    this.viewport.render();
    this.preview();
  }

  place(handle, p) {
    handle.position.copy(p);
    handle.userData.ring?.position.copy(p);
    handle.userData.follow?.(p);
  }

  // `sections` (a copy) with the dragged handle's section as the handle leaves it, or null
  // when it leaves none (a braid's end dragged onto its start).
  reshaped(sections, handle) {
    const { section, path, point, role } = handle.userData;
    if (role) return this.hairdressing.moved(sections, handle, handle.position);
    if (path === undefined) sections[section].point = rounded(handle.position);
    else (path < 0 ? sections[section] : sections[section].constraint[path]).trajectory[point] = rounded(handle.position);
    return sections;
  }

  // While a handle is dragged the hair follows it, as it follows a moving slider: the
  // sections as the handle would leave them go to the server off the undo list, one request
  // at a time (the positions that come meanwhile fold into the next one: the newest wins),
  // and each answer redraws the paths and asks for a preview of the hair (main.js debounces
  // it; the server cancels an update a newer request made stale). The release sends the
  // last position as one edit from where the drag started.
  preview() {
    const drag = this.drag;
    if (drag.sending) {
      drag.pending = true;
      return;
    }
    drag.pending = false;
    const next = this.reshaped(structuredClone(this.sections), drag.handle);
    if (!next) return;
    drag.previewed = true;
    drag.sending = postJson("/api/constraints", { sections: next }).then((result) => {
      if (!result.ok) return;  // the release says why
      this.take(result.body);
      if (this.drag === drag) {
        this.drawHandles();
        this.rebind(drag);
      }
      this.onChanged(false);
    }).finally(() => {
      drag.sending = null;
      if (drag.pending && this.drag === drag) this.preview();
    });
  }

  // After a redraw, the drag holds the new handle of its section, role and point, at the
  // pointer (which may have moved on since the positions drawn were sent).
  rebind(drag) {
    const u = drag.handle.userData;
    const same = this.handles.children.find((h) => h.userData.section === u.section && h.userData.role === u.role &&
      h.userData.path === u.path && h.userData.point === u.point);
    if (!same) return;
    drag.handle = same;
    this.place(same, drag.at);
    this.viewport.render();
  }

  // The stroke drawn becomes a comb or a trajectory through its resampled control points.
  finishStroke() {
    const { points, line } = this.stroke;
    this.stroke = null;
    this.viewport.controls.enabled = true;
    this.handles.remove(line);
    let length = 0;
    for (let k = 1; k < points.length; ++k) length += points[k].distanceTo(points[k - 1]);
    if (length < 2) {
      this.viewport.render();
      return this.onError("drag further over the head to draw a stroke");
    }
    const n = Math.max(3, Math.min(8, Math.round(length / controlSpacing) + 1));
    const trajectory = resample(points, n).map(rounded);
    const kind = this.tool;
    const count = this.sections.filter((s) => (kind === "comb" ? s.section === "comb" : pathsOf(s).length && s.section === "group")).length + 1;
    let name = `${kind} ${count}`;
    for (let k = count + 1; this.sections.some((s) => s.name === name); ++k) name = `${kind} ${k}`;
    const section = kind === "comb"
      ? { section: "comb", name, trajectory, smooth: true, ...defaultComb, head_relative: false }
      : { section: "group", name, head_relative: false,
        constraint: [{ kind: "trajectory", trajectory, smooth: true, ...defaultTrajectory }] };
    this.apply([...this.sections, section]);
  }

  async up(e) {
    if (this.stroke) return this.finishStroke();
    if (this.hairdressing.placing) {
      this.viewport.controls.enabled = true;
      return this.hairdressing.finish();
    }
    if (this.drag) {
      const drag = this.drag;
      this.drag = null;
      this.viewport.controls.enabled = true;
      if (!drag.moved) return;
      await drag.sending;  // the last preview lands before the edit, not over it
      const next = this.reshaped(structuredClone(this.sections), drag.handle);
      // Nothing to keep, or the server refused it: back to where the drag started.
      const back = () => drag.previewed ? this.apply(drag.before, { record: false }) : this.draw();
      if (!next) return back();
      if (!(await this.apply(next, { before: drag.before }))) back();
      return;
    }
    const press = this.press;
    this.press = null;
    if (!press || !this.active || Math.hypot(e.clientX - press.x, e.clientY - press.y) > 4) return;
    if (this.tool === "updo") return this.hairdressing.placeUpdo(e);
    if (this.tool !== "tie") return;
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
