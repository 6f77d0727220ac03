// The braid and updo tools of the Constraints panel (Choe & Ko §6.2, Fig. 15): a braid is
// placed with a press on the back of the head (its `start`, just off the scalp as a tie is)
// and a drag along the way it hangs (its axis and length); an updo with a click where the
// bun sits (its `point`, facing away from the head). Each is then reshaped by its handles
// (the braid's start and the end of its axis; the bun's centre and the tip of its facing)
// and by sliders whose ranges, defaults and documentation are the schema's (GET
// /api/schema "sections"; the reader checks the same ranges and its message names the key).
//
// They are kept as the TOML reader reads them: `{section: "braid", name, start: [x, y, z],
// axis, side, length, strands, width, period, radius, weight}`, `{section: "updo", name,
// point, facing, bun_radius, turns, radius, weight}`; keys left out take the reader's
// defaults. Those placed here are in head units (the sections' default, so a saved braid
// fits any head); one opened from a file may be in cm (`head_relative = false`), and each
// keeps the units it has: the server says which (the "frames" of /api/constraints, cm =
// origin + scale·value), and its handles are placed and dragged in them. What is drawn —
// each braid strand's figure-eight and the bun's spiral — is the server's expansion of the
// sections (groom/hairdressing.cpp, the "paths" of /api/constraints), in cm, not a copy of
// its formulas.
import * as THREE from "three";
import { groupColor } from "./views.js";

// A press moved less than this (cm) is a click: the braid takes the reader's axis and length.
const minDrag = 2;
// The tubes drawn along a braid's strands (cm): thin enough to see the crossings.
const strandTube = 0.2;

const round3 = (v) => Math.round(v * 1000) / 1000;

// The arrows that turn a braid (its end) and a bun (its facing), in CSS pixels: the head's
// radius and length, the updo's shaft's radius, the dark outline round them and the sign
// shown where the arrow points at or away from the camera. Sized on the screen, not in cm,
// they read the same at any zoom. Seen across, an arrow is a shaded cone on a shaft; seen
// along its length it shrinks to a disc, so it wears the draughtsman's sign instead: ⊙
// (a ring round a dot) pointing at the viewer, ⊗ (a ring round a cross) pointing away,
// fading in from `signFrom` to `signFull` (the cosine of the angle to the line of sight).
const arrowPx = { radius: 8, length: 22, shaft: 1.7, outline: 1.5, sign: 32 };
const signFrom = 0.75, signFull = 0.92;
const outlineColor = 0x0c0d0f;

// The ⊙ or ⊗ sign in `color` with a dark outline, as a texture (one per colour and kind).
const signs = new Map();
function signTexture(color, toward) {
  const key = `${color.getHexString()}${toward ? "+" : "x"}`;
  if (signs.has(key)) return signs.get(key);
  const n = 128, c = n / 2;
  const canvas = document.createElement("canvas");
  canvas.width = canvas.height = n;
  const g = canvas.getContext("2d");
  g.lineCap = "round";
  const stroke = (draw, width, style) => {
    g.beginPath();
    draw();
    g.lineWidth = width;
    g.strokeStyle = style;
    g.stroke();
  };
  // The outline wide enough to stay dark when the texture is drawn at 32 px.
  const ring = () => g.arc(c, c, 0.34 * n, 0, 2 * Math.PI);
  const mark = toward ? () => g.arc(c, c, 0.06 * n, 0, 2 * Math.PI)
    : () => {
      const a = 0.17 * n;
      g.moveTo(c - a, c - a);
      g.lineTo(c + a, c + a);
      g.moveTo(c + a, c - a);
      g.lineTo(c - a, c + a);
    };
  const dark = `#${new THREE.Color(outlineColor).getHexString()}`, fill = `#${color.getHexString()}`;
  for (const [width, style] of [[0.26 * n, dark], [0.08 * n, fill]]) {
    stroke(ring, width, style);
    stroke(mark, toward ? width + 0.06 * n : width, style);
  }
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  signs.set(key, texture);
  return texture;
}

// cm per CSS pixel at p, seen by the perspective `camera` on `renderer`'s canvas.
function cmPerPixel(renderer, camera, p) {
  const depth = Math.max(camera.near, -p.clone().applyMatrix4(camera.matrixWorldInverse).z);
  return (2 * depth * Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2)) / Math.max(1, renderer.domElement.clientHeight);
}

// A mesh that clears the depth buffer when its turn in `order` comes: what is drawn after
// it lies over the hair and the head, yet hides itself where it should. With `late`, its
// turn is among the see-through overlays (three.js draws them after every opaque mesh).
function depthClear(order, late = false) {
  const clear = new THREE.Mesh(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3(), new THREE.Vector3()]),
    new THREE.MeshBasicMaterial({ colorWrite: false, depthWrite: false, transparent: late }));
  clear.frustumCulled = false;
  clear.renderOrder = order;
  clear.onBeforeRender = (renderer) => renderer.clearDepth();
  return clear;
}

// A slider of a section's number (here and in constraints.js): its label, the name and value
// on one line, and the range beside it.
export function sliderRow(label, input) {
  const row = document.createElement("div");
  row.className = "slider";
  row.append(label, input);
  return row;
}

export class Hairdressing {
  // constraints: the Constraints it serves (its viewport, sections, paths, apply());
  // fields: the schema's section numbers ([{section, key, type, unit, min, max, min_open,
  // soft_min, soft_max, doc, default}]).
  constructor(constraints, fields) {
    this.c = constraints;
    this.fields = fields ?? [];
    this.placing = null;  // a braid being dragged out: { start (cm), plane, line }
  }

  // The units section i is in, as the server read it: {origin, scale, units}, cm = origin
  // + scale·value (head units: the scalp sphere's centre and the distance to its crown, as
  // solve/pipeline.cpp head_frame maps them; cm: origin 0, scale 1).
  frame(i) {
    return this.c.frames[i] ?? this.c.headFrame;
  }
  headFrame() {
    return this.c.headFrame;
  }

  // cm ⇄ a frame's units.
  toSection(p, frame) {
    return p.clone().sub(new THREE.Vector3(...frame.origin)).divideScalar(frame.scale);
  }
  toSpace(a, frame) {
    return new THREE.Vector3(...a).multiplyScalar(frame.scale).add(new THREE.Vector3(...frame.origin));
  }

  numbers(kind) {
    return this.fields.filter((f) => f.section === kind);
  }

  valueOf(s, key) {
    return s[key] ?? this.fields.find((f) => f.section === s.section && f.key === key)?.default;
  }

  // The braid's or bun's handles and paths, for section i.
  draw(i) {
    const s = this.c.sections[i];
    const paths = this.c.paths[i] ?? [];
    const frame = this.frame(i);
    const first = this.c.groupIndex(i);
    const overlay = (m) => Object.assign(m, { depthTest: false, transparent: true });
    // The strands are drawn over the hair and the head but hide each other where they
    // cross (over and under): the depth is cleared after the hair, before them.
    if (s.section === "braid" && paths.length) this.c.handles.add(depthClear(17));
    paths.forEach((path, k) => {
      const [r, g, b] = groupColor(first + (s.section === "braid" ? k : 0));
      const color = new THREE.Color(r, g, b);
      const points = path.points.map((q) => new THREE.Vector3(...q));
      if (points.length < 2) return;
      const curve = path.smooth ? new THREE.CatmullRomCurve3(points, false, "catmullrom", 0.5)
        : new THREE.CatmullRomCurve3(points, false, "chordal", 0);
      const samples = Math.min(2000, 8 * points.length);
      if (s.section === "braid") {
        // The strands as shaded tubes.
        const tube = new THREE.Mesh(new THREE.TubeGeometry(curve, samples, strandTube, 8, false),
          new THREE.MeshStandardMaterial({ color, roughness: 0.55 }));
        tube.renderOrder = 18;
        this.c.handles.add(tube);
      } else {
        const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints(curve.getSpacedPoints(samples)),
          overlay(new THREE.LineBasicMaterial({ color, opacity: 0.95 })));
        line.renderOrder = 19;
        const tube = new THREE.Mesh(new THREE.TubeGeometry(curve, samples, path.radius, 8, false),
          overlay(new THREE.MeshBasicMaterial({ color, opacity: 0.12, depthWrite: false })));
        tube.renderOrder = 18;
        this.c.handles.add(tube, line);
      }
    });
    const [r, g, b] = groupColor(first);
    const color = new THREE.Color(r, g, b);
    // The handles and arrows lie over the hair, the head and the paths (the depth cleared
    // after those) and hide each other as they lie in depth: an arrow pointing at the camera
    // covers the handle it starts from, one pointing away is partly behind it. They are
    // drawn with the overlays, after the paths, so as to lie over them.
    this.c.handles.add(depthClear(20.5, true));
    const solid = (m) => Object.assign(m, { transparent: true, depthTest: true, depthWrite: true });
    const handle = (p, role, size, tint = color) => {
      const h = new THREE.Mesh(new THREE.SphereGeometry(size, 20, 12), solid(new THREE.MeshBasicMaterial({ color: tint })));
      h.position.copy(p);
      h.userData = { section: i, role };
      h.renderOrder = 21;
      this.c.handles.add(h);
      return h;
    };
    // An arrow from `from` to `to` whose head (centred on `to`) is the handle `role`: a
    // shaded cone with a dark base, on a shaft when `shaft` (else a dashed line shows the
    // way), each with a dark outline (its back faces, a little larger), sized in pixels.
    const arrow = (from, to, role, shaft) => {
      const line = shaft ? null : new THREE.Line(new THREE.BufferGeometry().setFromPoints([from, to]),
        overlay(new THREE.LineDashedMaterial({ color: 0xffffff, opacity: 0.8, dashSize: 0.6, gapSize: 0.4 })));
      if (line) {
        line.computeLineDistances();
        line.renderOrder = 20;
        this.c.handles.add(line);
      }
      const lit = solid(new THREE.MeshStandardMaterial({ color, roughness: 0.4, emissive: color, emissiveIntensity: 0.35 }));
      const dark = solid(new THREE.MeshBasicMaterial({ color: outlineColor, side: THREE.BackSide }));
      const base = solid(new THREE.MeshBasicMaterial({ color: color.clone().multiplyScalar(0.3) }));
      // ConeGeometry's groups: 0 its side, 2 its base.
      const head = new THREE.Mesh(new THREE.ConeGeometry(1, 1, 28), [lit, lit, base]);
      head.position.copy(to);
      const rim = new THREE.Mesh(head.geometry, dark);
      const parts = [rim, head];
      const stick = shaft ? new THREE.Mesh(new THREE.CylinderGeometry(1, 1, 1, 12), lit) : null;
      const stickRim = shaft ? new THREE.Mesh(stick.geometry, dark) : null;
      if (shaft) parts.push(stickRim, stick);
      // The signs, over everything, on the head.
      const sign = (toward) => {
        const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: signTexture(color, toward), depthTest: false,
          depthWrite: false, transparent: true, opacity: 0 }));
        sprite.renderOrder = 22;
        sprite.userData = { sign: toward ? "toward" : "away", of: role };
        return sprite;
      };
      const [toward, away] = [sign(true), sign(false)];
      const up = new THREE.Vector3(0, 1, 0);
      // Each frame, before it is drawn: the way from `from` to the head (a drag moves the
      // head) and the sizes for the camera's distance.
      const fit = (renderer, scene, camera) => {
        const d = head.position.clone().sub(from);
        const length = d.length();
        if (length < 1e-6) return;
        d.divideScalar(length);
        const q = new THREE.Quaternion().setFromUnitVectors(up, d);
        const px = cmPerPixel(renderer, camera, head.position);
        const [r, h, o] = [arrowPx.radius * px, arrowPx.length * px, arrowPx.outline * px];
        head.quaternion.copy(q);
        head.scale.set(r, h, r);
        rim.position.copy(head.position).addScaledVector(d, 0.2 * o);
        rim.quaternion.copy(q);
        rim.scale.set(r + 2 * o, h + 3 * o, r + 2 * o);
        if (shaft) {
          // From the handle it starts at to the head's base.
          const reach = Math.max(1e-3, length - h / 2);
          const w = arrowPx.shaft * px;
          for (const [m, radius] of [[stick, w], [stickRim, w + o]]) {
            m.position.copy(from).addScaledVector(d, reach / 2);
            m.quaternion.copy(q);
            m.scale.set(radius, reach, radius);
          }
        }
        // The sign for how nearly the arrow points along the line of sight, the cone and
        // shaft fading as it comes in.
        const along = d.dot(camera.position.clone().sub(head.position).normalize());
        const t = THREE.MathUtils.smoothstep(Math.abs(along), signFrom, signFull);
        for (const m of [lit, dark, base]) m.opacity = 1 - t;
        const size = arrowPx.sign * px;
        for (const [m, shown] of [[toward, along > 0], [away, along < 0]]) {
          m.material.opacity = shown ? t : 0;
          m.position.copy(head.position);
          m.scale.set(size, size, 1);
        }
        for (const m of [...parts, toward, away]) m.updateMatrixWorld();
      };
      for (const m of [toward, away]) {
        m.frustumCulled = false;
        m.onBeforeRender = fit;
      }
      for (const m of parts) {
        m.renderOrder = 21;
        m.frustumCulled = false;
        m.onBeforeRender = fit;
      }
      // While dragged, the dashed line follows the head (the rest follows in fit).
      const follow = (p) => {
        if (!line) return;
        line.geometry.setFromPoints([from, p]);
        line.computeLineDistances();
      };
      head.userData = { section: i, role, follow };
      this.c.handles.add(...parts, toward, away);
    };
    if (s.section === "braid") {
      // The start, and the axis's end: the strands' phases cancel, so the mean of their
      // ends is start + length·axis as the server expanded it.
      const start = s.start ? this.toSpace(s.start, frame) : null;
      const end = new THREE.Vector3();
      for (const p of paths) end.add(new THREE.Vector3(...p.points[p.points.length - 1]));
      if (start) handle(start, "start", 0.6, 0xffffff);
      if (paths.length && start) arrow(start, end.divideScalar(paths.length), "end", false);
    } else if (s.section === "updo" && s.point) {
      const centre = this.toSpace(s.point, frame);
      handle(centre, "point", 0.6, 0xffffff);
      if (Array.isArray(s.facing)) {
        const facing = new THREE.Vector3(...s.facing).normalize();
        const reach = this.valueOf(s, "bun_radius") * frame.scale + 3;
        arrow(centre, centre.clone().addScaledVector(facing, reach), "facing", true);
      }
    }
  }

  // A handle dragged to p (cm): the sections with the braid or bun reshaped, in the units
  // the section is in.
  moved(sections, handle, p) {
    const { section: i, role } = handle.userData;
    const s = sections[i];
    const frame = this.frame(i);
    const at = this.toSection(p, frame);
    if (role === "start" || role === "point") {
      s[role] = at.toArray().map(round3);
    } else if (role === "end") {
      const d = at.sub(new THREE.Vector3(...s.start));
      if (d.length() < minDrag / frame.scale) return null;
      Object.assign(s, this.orientation(d, s.side));
    } else if (role === "facing") {
      const d = p.clone().sub(this.toSpace(s.point, frame));
      if (d.length() < 0.5) return null;
      s.facing = d.normalize().toArray().map(round3);
    }
    return sections;
  }

  // A braid's axis, length and side for an axis vector d (in the section's units): side is `previous`
  // (or across the view) made perpendicular to the axis, pointing to +x where it can.
  orientation(d, previous) {
    const axis = d.clone().normalize();
    const view = this.c.viewport.camera.getWorldDirection(new THREE.Vector3());
    let side = previous ? new THREE.Vector3(...previous) : axis.clone().cross(view);
    side.addScaledVector(axis, -side.dot(axis));
    if (side.length() < 0.2) side = axis.clone().cross(view);
    if (side.length() < 0.2) side = axis.clone().cross(new THREE.Vector3(0, 0, 1));
    side.normalize();
    if (side.x < -1e-3) side.negate();
    return { axis: axis.toArray().map(round3), side: side.toArray().map(round3), length: round3(d.length()) };
  }

  // A free name: "braid 1", "updo 2", …
  nameFor(kind) {
    const n = this.c.sections.filter((s) => s.section === kind).length + 1;
    let name = `${kind} ${n}`;
    for (let k = n + 1; this.c.sections.some((s) => s.name === name); ++k) name = `${kind} ${k}`;
    return name;
  }

  // Where a press or click puts a braid's start or a bun's centre (cm), or null: just off
  // the head, as a tie is put.
  anchor(e) {
    return this.c.tiePoint(e);
  }

  // The braid tool's press: starts dragging out a braid. True when it took the event.
  down(e) {
    if (this.c.tool !== "braid") return false;
    const start = this.anchor(e);
    if (!start) return false;
    const normal = this.c.viewport.camera.getWorldDirection(new THREE.Vector3());
    const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints([start, start]),
      new THREE.LineBasicMaterial({ color: 0xd7a05b, depthTest: false, transparent: true }));
    line.renderOrder = 22;
    this.c.handles.add(line);
    this.placing = { start, end: start.clone(), plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, start), line };
    return true;
  }

  move(e) {
    if (!this.placing) return false;
    const p = this.c.ray(e).intersectPlane(this.placing.plane, new THREE.Vector3());
    if (p) {
      this.placing.end.copy(p);
      this.placing.line.geometry.setFromPoints([this.placing.start, p]);
      this.c.viewport.render();
    }
    return true;
  }

  // The braid dragged out: start where the press was, the axis along the drag (a click:
  // the reader's axis, side and length).
  finish() {
    const { start, end, line } = this.placing;
    this.placing = null;
    this.c.handles.remove(line);
    const head = this.headFrame();
    const section = { section: "braid", name: this.nameFor("braid"), start: this.toSection(start, head).toArray().map(round3) };
    if (end.distanceTo(start) >= minDrag)
      Object.assign(section, this.orientation(this.toSection(end, head).sub(this.toSection(start, head))));
    this.c.apply([...this.c.sections, section]);
  }

  // The updo tool's click: a bun at p, facing away from the head's centre.
  placeUpdo(e) {
    const p = this.anchor(e);
    if (!p) return this.c.onError("click on or near the head to place a bun");
    const point = this.toSection(p, this.headFrame());
    this.c.apply([...this.c.sections, {
      section: "updo", name: this.nameFor("updo"), point: point.toArray().map(round3),
      facing: point.clone().normalize().toArray().map(round3),
    }]);
  }

  // The sliders of section i's numbers, from the schema: its range where a useful value
  // lies, its unit and its documentation as the title. Sizes are kept in the section's units
  // (head units, or cm in a section with head_relative = false) and shown in cm; the
  // schema's ranges, in head units, are taken to the section's units through cm.
  sliders(row, i) {
    const s = this.c.sections[i];
    const frame = this.frame(i);
    for (const f of this.numbers(s.section)) {
      const input = document.createElement("input");
      input.type = "range";
      const integer = f.type === "integer";
      const size = f.unit === "head units";
      const toUnits = size ? this.headFrame().scale / frame.scale : 1;
      const step = integer ? 1 : Math.pow(10, Math.floor(Math.log10((f.soft_max - f.soft_min) * toUnits)) - 2);
      // The ends on the step's grid, so the value written (a round number) is one of the
      // slider's values.
      const snap = (v, round) => Number((round(v / step) * step).toFixed(Math.max(0, -Math.log10(step))));
      const [min, max] = [snap(f.soft_min * toUnits, Math.floor), snap(f.soft_max * toUnits, Math.ceil)];
      Object.assign(input, { min, max, step });
      input.value = this.valueOf(s, f.key);
      input.dataset.key = f.key;
      const unit = size ? frame.units : f.unit;
      input.title = `${f.doc} (${s.section}.${f.key}${unit ? `, ${unit}` : ""}; default ${f.default})`;
      const label = document.createElement("label");
      // Sizes shown in cm, kept in the section's units (the tooltip gives both).
      const show = () => {
        const v = Number(input.value);
        const text = integer ? `${v}` : v.toFixed(step < 0.01 ? 3 : 2);
        label.textContent = size ? `${f.key} ${(v * frame.scale).toFixed(1)} cm` : `${f.key} ${text}`;
        label.title = unit ? `${text} ${unit}` : text;
      };
      show();
      input.oninput = show;
      input.onchange = () => {
        const next = structuredClone(this.c.sections);
        next[i][f.key] = integer ? parseInt(input.value, 10) : Number(input.value);
        this.c.apply(next);
      };
      row.append(sliderRow(label, input));
    }
  }
}
