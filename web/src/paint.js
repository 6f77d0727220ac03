// Painting the scalp maps (Choe & Ko §2.3, Fig. 8) on the head in 3D, as Blender's weight
// paint does: the map is shown on the scalp in a blue → red ramp, a brush ring follows the
// pointer, and a stroke paints the map's image in scalp UV space (geometry/scalp.hpp), which
// goes to the server as a PNG (POST /api/map) while the stroke runs and when it ends.
//
// The brush works in 3D, not in UV: every texel of the map has the direction from the
// scalp's centre that the polar map gives it, and a dab reaches the texels whose point on the
// sphere through the hit point lies within the brush radius (cm). Mirror-X paints the same
// dab at (−x, y, z).
import * as THREE from "three";
import { decodeMap, encodeGrayPng, postBinary } from "./api.js";

// Blender's weight ramp: blue (0), cyan, green (0.5), yellow, red (1).
const overlayVertex = /* glsl */ `
  attribute vec2 mapUv;
  varying vec2 vUv;
  varying vec3 vNormal;
  void main() {
    vUv = mapUv;
    vNormal = normalize(normalMatrix * normal);
    gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
  }
`;
const overlayFragment = /* glsl */ `
  uniform sampler2D map;
  uniform float opacity;
  varying vec2 vUv;
  varying vec3 vNormal;
  vec3 ramp(float t) {
    return clamp(vec3(1.5 - abs(4.0 * t - 3.0), 1.5 - abs(4.0 * t - 2.0), 1.5 - abs(4.0 * t - 1.0)), 0.0, 1.0);
  }
  void main() {
    float t = texture2D(map, vUv).r;
    float shade = 0.55 + 0.45 * max(0.0, normalize(vNormal).z);
    gl_FragColor = vec4(ramp(t) * shade, opacity);
    #include <colorspace_fragment>
  }
`;

const falloffs = {
  smooth: (x) => (1 - x * x) * (1 - x * x),
  linear: (x) => 1 - x,
  constant: () => 1,
};

export class Painter {
  // viewport: the Viewport; valueOf(field): the field's JSON value; onSent(field, value,
  // final): a map reached the server (value: the field's new JSON value); onStroke(field,
  // before, after): a finished stroke, for undo; onError(message); onLoaded(): a map came.
  constructor(viewport, { valueOf, onSent, onStroke, onError, onLoaded }) {
    this.viewport = viewport;
    this.onLoaded = onLoaded;
    this.valueOf = valueOf;
    this.onSent = onSent;
    this.onStroke = onStroke;
    this.onError = onError;
    this.active = false;
    this.field = "maps.density";
    this.brush = { radius: 3, strength: 0.5, value: 1, falloff: "smooth", mirror: true, erase: false };
    this.map = null;  // { width, height, kind, low, high, values: Float32Array }
    this.dirty = false;
    this.sending = false;
    this.stroking = false;
    this.raycaster = new THREE.Raycaster();
    this.cursors = [0, 1].map(() => {
      const points = [];
      for (let i = 0; i < 64; ++i) {
        const a = (i / 64) * Math.PI * 2;
        points.push(new THREE.Vector3(Math.cos(a), Math.sin(a), 0));
      }
      const ring = new THREE.LineLoop(
        new THREE.BufferGeometry().setFromPoints(points),
        new THREE.LineBasicMaterial({ color: 0xffffff, transparent: true, opacity: 0.9 }));
      ring.renderOrder = 10;
      ring.visible = false;
      viewport.scene.add(ring);
      return ring;
    });
    const canvas = viewport.renderer.domElement;
    // Capture phase: a press on the head paints before the orbit controls see it.
    canvas.addEventListener("pointerdown", (e) => this.down(e), { capture: true });
    canvas.addEventListener("pointermove", (e) => this.move(e));
    window.addEventListener("pointerup", (e) => this.up(e));
  }

  // scalp: GET /api/scalp; head: decodeHead's arrays. Builds the overlay: the scalp faces
  // with each vertex's scalp UV (Scalp::uv_of).
  setScalp(scalp, head) {
    this.scalp = scalp;
    this.center = new THREE.Vector3(...scalp.center);
    this.head = head;
    const tris = [];
    for (let f = 0; f < head.scalp.length; ++f)
      if (head.scalp[f]) tris.push(head.triangles[3 * f], head.triangles[3 * f + 1], head.triangles[3 * f + 2]);
    const n = head.positions.length / 3;
    this.uv = new Float32Array(2 * n);
    const tmax = scalp.max_polar_angle;
    for (let i = 0; i < n; ++i) {
      const dx = head.positions[3 * i] - this.center.x, dy = head.positions[3 * i + 1] - this.center.y,
        dz = head.positions[3 * i + 2] - this.center.z;
      const h = Math.hypot(dx, dz);
      if (h < 1e-9) { this.uv[2 * i] = 0.5; this.uv[2 * i + 1] = dy >= 0 ? 0.5 : 1; continue; }
      const r = 0.5 * Math.min(Math.atan2(h, dy) / tmax, 1);
      this.uv[2 * i] = 0.5 - (r * dx) / h;
      this.uv[2 * i + 1] = 0.5 + (r * dz) / h;
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", this.viewport.head.geometry.getAttribute("position"));
    geometry.setAttribute("normal", this.viewport.head.geometry.getAttribute("normal"));
    geometry.setAttribute("mapUv", new THREE.BufferAttribute(new Float32Array(2 * n), 2));
    geometry.setIndex(tris);
    this.texture = new THREE.DataTexture(new Uint8Array(4), 1, 1, THREE.RedFormat, THREE.UnsignedByteType);
    this.texture.magFilter = this.texture.minFilter = THREE.LinearFilter;
    const material = new THREE.ShaderMaterial({
      vertexShader: overlayVertex,
      fragmentShader: overlayFragment,
      uniforms: { map: { value: this.texture }, opacity: { value: 0.92 } },
      transparent: true,
      polygonOffset: true,
      polygonOffsetFactor: -1,
      polygonOffsetUnits: -4,
    });
    if (this.overlay) this.viewport.scene.remove(this.overlay);
    this.overlay = new THREE.Mesh(geometry, material);
    this.overlay.visible = this.active;
    this.viewport.scene.add(this.overlay);
  }

  // Turns painting on or off: the map on the head, the hair faded so the map shows.
  async setActive(active) {
    this.active = active;
    if (active && !this.map) await this.load(this.field);
    if (this.overlay) this.overlay.visible = active;
    this.viewport.setHairOpacity(active ? 0.35 : 1);
    if (!active) for (const c of this.cursors) c.visible = false;
    this.viewport.render();
  }

  // Loads the field's map from the server (after an undo, a preset, Open, a typed value).
  async load(field = this.field) {
    this.field = field;
    const response = await fetch(`/api/map?field=${encodeURIComponent(field)}`, {
      headers: { "X-Wisp-Token": this.token() },
    });
    if (!response.ok) {
      this.onError((await response.json()).error);
      return;
    }
    this.setMap(decodeMap(await response.arrayBuffer()));
  }

  // The field's map changed elsewhere (a typed value, undo of a value, a preset, Open).
  invalidate(field) {
    if (field && field !== this.field) return;
    this.map = null;
    if (this.active) this.load(this.field);
  }

  token() {
    return new URLSearchParams(location.search).get("token") ?? "";
  }

  setMap(map) {
    this.map = map;
    const { width: w, height: h } = map;
    // Each texel's unit direction from the scalp's centre (the inverse of the polar map).
    if (!this.dirs || this.dirs.length !== 3 * w * h) {
      this.dirs = new Float32Array(3 * w * h);
      const tmax = this.scalp.max_polar_angle;
      for (let j = 0; j < h; ++j)
        for (let i = 0; i < w; ++i) {
          const du = i / (w - 1) - 0.5, dv = 1 - j / (h - 1) - 0.5;
          const len = Math.hypot(du, dv), theta = 2 * len * tmax, k = 3 * (j * w + i);
          const s = len > 1e-9 ? Math.sin(theta) / len : 0;
          this.dirs[k] = -s * du;
          this.dirs[k + 1] = Math.cos(theta);
          this.dirs[k + 2] = s * dv;
        }
    }
    // Texel (i, j) lies at UV (i/(w−1), 1 − j/(h−1)): the overlay's coordinates put each
    // vertex's UV on those texel centres (row 0 of the data is the image's top).
    const uvs = this.overlay.geometry.getAttribute("mapUv");
    for (let i = 0; i < uvs.count; ++i) {
      uvs.array[2 * i] = (this.uv[2 * i] * (w - 1) + 0.5) / w;
      uvs.array[2 * i + 1] = ((1 - this.uv[2 * i + 1]) * (h - 1) + 0.5) / h;
    }
    uvs.needsUpdate = true;
    this.texture.dispose();
    this.texture = new THREE.DataTexture(new Uint8Array(w * h), w, h, THREE.RedFormat, THREE.UnsignedByteType);
    this.texture.magFilter = this.texture.minFilter = THREE.LinearFilter;
    this.texture.unpackAlignment = 1;  // rows of any width
    this.overlay.material.uniforms.map.value = this.texture;
    this.upload();
    this.onLoaded?.();
  }

  upload() {
    this.texture.image.data.set(this.bytesOf(this.map));
    this.texture.needsUpdate = true;
    this.viewport.render();
  }

  hit(e) {
    const rect = e.target.getBoundingClientRect();
    const ndc = new THREE.Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1,
      -((e.clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.viewport.camera);
    const hits = this.viewport.head ? this.raycaster.intersectObject(this.viewport.head) : [];
    return hits[0] ?? null;
  }

  showCursor(hit) {
    const points = [hit.point.clone()];
    const normals = [hit.face.normal.clone()];
    if (this.brush.mirror) {
      points.push(new THREE.Vector3(-hit.point.x, hit.point.y, hit.point.z));
      normals.push(new THREE.Vector3(-hit.face.normal.x, hit.face.normal.y, hit.face.normal.z));
    }
    this.cursors.forEach((ring, k) => {
      ring.visible = k < points.length;
      if (!ring.visible) return;
      // Just off the surface, depth-tested: the head hides the far side's mirror ring.
      ring.position.copy(points[k]).addScaledVector(normals[k], 0.15);
      ring.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), normals[k]);
      ring.scale.setScalar(this.brush.radius);
      ring.material.color.set(this.brush.erase ? 0x7fb2ff : 0xffffff);
    });
  }

  // One dab at head-space point p (and its mirror).
  dab(p) {
    const centres = [p];
    if (this.brush.mirror) centres.push(new THREE.Vector3(-p.x, p.y, p.z));
    const { values } = this.map;
    const target = this.brush.erase ? 0 : this.brush.value;
    const fall = falloffs[this.brush.falloff] ?? falloffs.smooth;
    for (const q of centres) {
      const d = q.clone().sub(this.center);
      const r = d.length();
      if (r < 1e-6) continue;
      d.divideScalar(r);
      const reach = this.brush.radius / r, reach2 = reach * reach;
      for (let k = 0, n = values.length; k < n; ++k) {
        const ex = this.dirs[3 * k] - d.x, ey = this.dirs[3 * k + 1] - d.y, ez = this.dirs[3 * k + 2] - d.z;
        const e2 = ex * ex + ey * ey + ez * ez;
        if (e2 >= reach2) continue;
        const w = Math.min(1, this.brush.strength * fall(Math.sqrt(e2) / reach));
        values[k] += (target - values[k]) * w;
      }
    }
    this.dirty = true;
  }

  snapshot() {
    return { value: this.valueOf(this.field), map: { ...this.map, values: this.map.values.slice() } };
  }

  down(e) {
    if (!this.active || e.button !== 0 || !this.map) return;
    const hit = this.hit(e);
    if (!hit) return;  // off the head: the orbit controls take it
    e.preventDefault();
    e.stopImmediatePropagation();
    this.viewport.controls.enabled = false;
    this.stroking = true;
    this.before = this.snapshot();
    this.last = hit.point.clone();
    this.dab(hit.point);
    this.upload();
    this.send(false);
  }

  move(e) {
    if (!this.active) return;
    const hit = this.hit(e);
    if (!hit) {
      for (const c of this.cursors) c.visible = false;
      this.viewport.render();
      return;
    }
    this.showCursor(hit);
    if (this.stroking) {
      // Dabs a quarter of the radius apart along the pointer's path.
      const spacing = Math.max(0.05, this.brush.radius / 4);
      const step = hit.point.clone().sub(this.last);
      const n = Math.floor(step.length() / spacing);
      for (let i = 1; i <= n; ++i) this.dab(this.last.clone().addScaledVector(step, (i * spacing) / step.length()));
      if (n > 0) this.last.addScaledVector(step, (n * spacing) / step.length());
      this.upload();
      this.send(false);
    }
    this.viewport.render();
  }

  up() {
    if (!this.stroking) return;
    this.stroking = false;
    this.viewport.controls.enabled = true;
    const before = this.before;
    this.send(true).then((ok) => {
      if (ok) this.onStroke(this.field, before, this.snapshot());
    });
  }

  // Sends the map while it changes, one request at a time; `final` asks for the full hair
  // once the last change is in. Resolves to whether the server took the last map sent.
  send(final) {
    if (final) this.wantFinal = true;
    if (!this.sending) this.sending = this.pump();
    return this.sending;
  }

  async pump() {
    let ok = true;
    for (;;) {
      if (this.dirty) {
        this.dirty = false;
        const final = !this.stroking && this.wantFinal;
        if (final) this.wantFinal = false;
        ok = await this.post(this.field, this.map, final);
      } else if (this.stroking) {
        await new Promise((r) => setTimeout(r, 30));
      } else {
        if (this.wantFinal) {
          this.wantFinal = false;
          this.onSent(this.field, this.valueOf(this.field), true);
        }
        break;
      }
    }
    this.sending = null;
    return ok;
  }

  async post(field, map, final) {
    const png = await encodeGrayPng(this.bytesOf(map), map.width, map.height);
    const result = await postBinary(`/api/map?field=${encodeURIComponent(field)}&low=${map.low}&high=${map.high}`, png, "image/png");
    if (!result.ok) {
      this.onError(result.body.error);
      return false;
    }
    if (field === this.field) this.map.kind = 3;  // painted: held by the server
    this.onSent(field, result.body.value, final);
    return true;
  }

  bytesOf(map) {
    const out = new Uint8Array(map.values.length);
    for (let i = 0; i < out.length; ++i) out[i] = Math.round(Math.min(1, Math.max(0, map.values[i])) * 255);
    return out;
  }

  // Undo and redo of a stroke: a painted map goes back as its pixels, any other map as its
  // value (a constant, a procedural name, an image file).
  async restore(field, snapshot, setField) {
    const ok = snapshot.map.kind === 3
      ? await this.post(field, snapshot.map, true)
      : await setField(field, snapshot.value);
    if (ok && field === this.field) this.setMap({ ...snapshot.map, values: snapshot.map.values.slice() });
    return ok;
  }
}
