// The Motion mode (issue 17): the current style becomes the rest shape of an Adaptive Wisp
// Tree that runs on the server (src/edit/motion_routes.hpp); the view shows the moving
// skinned strands (the preview's subset), the head posed as the server poses it, and the
// tree itself (Bertails et al. Fig. 4: active nodes as spheres, segments as cylinders,
// coloured by level; splits and merges flash where they happen) with a live plot of the
// active nodes per level.
//
// Frames are streamed: GET /api/motion/stream sends a message (the frame, the poses, the tree
// when shown, the splits and merges since the last message; src/edit/motion_session.hpp) for
// the newest frame whenever this page has read the last one, so a slow browser skips frames
// and the simulation never waits for it. If the stream breaks, the page polls instead
// (GET /api/motion/frame?after=N&wait=MS, the newest frame past N). Dragging the head
// with the mouse turns it about the neck (Shift: moves it); the server keys the drag at its
// frame boundaries, so a recording replays exactly in `wisp animate`.
import * as THREE from "three";
import { decodeStrands, postBinary, request } from "./api.js";
import "./motion.css";

const levelColors = [0xe8a33d, 0x4fb3e8, 0x8fdc6a, 0xe86a9b];
const presets = ["lean", "shake", "nod", "jump", "run"];

async function post(path, body = {}) {
  const response = await request("POST", path, body);
  const json = await response.json();
  if (!response.ok) throw new Error(json.field ? `${json.field}: ${json.error}` : json.error);
  return json;
}

// "WISPTREE" (src/edit/motion_session.hpp encode_tree).
export function decodeTree(buffer) {
  const magic = new TextDecoder().decode(new Uint8Array(buffer, 0, 8));
  if (magic !== "WISPTREE") throw new Error("not a tree buffer");
  const [, frame, nodes, levels, events] = new Uint32Array(buffer, 8, 5);
  let at = 28;
  const positions = new Float32Array(buffer, at, 3 * nodes);
  at += 12 * nodes;
  const parents = new Float32Array(buffer, at, 3 * nodes);
  at += 12 * nodes;
  const radius = new Float32Array(buffer, at, nodes);
  at += 4 * nodes;
  const level = new Uint32Array(buffer, at, nodes);
  at += 4 * nodes;
  const perLevel = new Uint32Array(buffer, at, levels);
  at += 4 * levels;
  const eventData = new Float32Array(buffer, at, 4 * events);
  return { frame, nodes, levels, positions, parents, radius, level, perLevel, events: eventData };
}

// The tree view: three instanced meshes (spheres, cylinders, event flashes), one draw call each.
class TreeView {
  constructor(scene) {
    this.group = new THREE.Group();
    this.group.visible = false;
    scene.add(this.group);
    this.capacity = 0;
    this.sphereGeometry = new THREE.SphereGeometry(1, 12, 8);
    this.cylinderGeometry = new THREE.CylinderGeometry(1, 1, 1, 8, 1, true);
    this.material = new THREE.MeshStandardMaterial({ roughness: 0.5 });
    this.flashMaterial = new THREE.MeshBasicMaterial({ transparent: true, opacity: 0.9 });
    this.flashes = [];  // { x, y, z, kind, born }
    this.grow(1024);
  }

  grow(n) {
    for (const m of [this.spheres, this.cylinders, this.flash]) if (m) {
      this.group.remove(m);
      m.dispose();
    }
    this.capacity = n;
    this.spheres = new THREE.InstancedMesh(this.sphereGeometry, this.material, n);
    this.cylinders = new THREE.InstancedMesh(this.cylinderGeometry, this.material, n);
    this.flash = new THREE.InstancedMesh(this.sphereGeometry, this.flashMaterial, 512);
    for (const m of [this.spheres, this.cylinders, this.flash]) {
      m.count = 0;
      m.frustumCulled = false;
      this.group.add(m);
    }
  }

  // tree: decodeTree's; events: float32 x, y, z, kind (0 split, 1 merge) to flash, every step's
  // since the last tree drawn (the stream's), or the tree's own (its frame's steps).
  set(tree, events = tree.events) {
    if (tree.nodes > this.capacity) this.grow(Math.max(tree.nodes, 2 * this.capacity));
    const m = new THREE.Matrix4(), q = new THREE.Quaternion(), s = new THREE.Vector3();
    const p = new THREE.Vector3(), a = new THREE.Vector3(), d = new THREE.Vector3();
    const up = new THREE.Vector3(0, 1, 0), color = new THREE.Color();
    for (let i = 0; i < tree.nodes; ++i) {
      p.fromArray(tree.positions, 3 * i);
      a.fromArray(tree.parents, 3 * i);
      const r = tree.radius[i];
      color.setHex(levelColors[tree.level[i] % levelColors.length]);
      const ball = Math.min(1, Math.max(0.15, 0.2 * r));
      m.compose(p, q.identity(), s.setScalar(ball));
      this.spheres.setMatrixAt(i, m);
      this.spheres.setColorAt(i, color);
      // The segment from the parent: a cylinder along it, thinner than the sphere.
      d.subVectors(p, a);
      const length = d.length();
      q.setFromUnitVectors(up, length > 1e-6 ? d.divideScalar(length) : up);
      const thick = Math.min(0.6, Math.max(0.08, 0.12 * r));
      m.compose(a.add(p).multiplyScalar(0.5), q, s.set(thick, length, thick));
      this.cylinders.setMatrixAt(i, m);
      this.cylinders.setColorAt(i, color);
    }
    this.spheres.count = this.cylinders.count = tree.nodes;
    for (const mesh of [this.spheres, this.cylinders]) {
      mesh.instanceMatrix.needsUpdate = true;
      if (mesh.instanceColor) mesh.instanceColor.needsUpdate = true;
    }
    const now = performance.now();
    for (let e = 0; e < events.length / 4; ++e)
      this.flashes.push({ at: new THREE.Vector3().fromArray(events, 4 * e), kind: events[4 * e + 3], born: now });
    this.flashes = this.flashes.filter((f) => now - f.born < 400).slice(-512);
    this.flashes.forEach((f, i) => {
      const t = (now - f.born) / 400;
      m.compose(f.at, q.identity(), s.setScalar(1.2 + 2 * t));
      this.flash.setMatrixAt(i, m);
      this.flash.setColorAt(i, color.setHex(f.kind ? 0x66ffee : 0xffffff));
    });
    this.flash.count = this.flashes.length;
    this.flash.instanceMatrix.needsUpdate = true;
    if (this.flash.instanceColor) this.flash.instanceColor.needsUpdate = true;
  }
}

// The active node count per level, the last `length` frames, one line per level.
class Plot {
  constructor(canvas, length = 240) {
    this.canvas = canvas;
    this.length = length;
    this.rows = [];
  }

  push(perLevel) {
    this.rows.push(perLevel.slice());
    if (this.rows.length > this.length) this.rows.shift();
    const g = this.canvas.getContext("2d");
    const { width: w, height: h } = this.canvas;
    g.clearRect(0, 0, w, h);
    const top = Math.max(1, ...this.rows.flat());
    const levels = Math.max(0, ...this.rows.map((r) => r.length));
    for (let l = 0; l < levels; ++l) {
      g.strokeStyle = `#${levelColors[l % levelColors.length].toString(16).padStart(6, "0")}`;
      g.beginPath();
      this.rows.forEach((r, i) => {
        const x = (i / (this.length - 1)) * w, y = h - 2 - ((r[l] ?? 0) / top) * (h - 14);
        i ? g.lineTo(x, y) : g.moveTo(x, y);
      });
      g.stroke();
    }
    g.fillStyle = "#8b8e97";
    g.fillText(`${top} active`, 4, 10);
  }
}

export class MotionMode {
  // viewport: the Viewport; strands: how many strands to show (the preview count);
  // onEnter(), onExit(): the editor gives the view over and takes it back; say(message).
  constructor(viewport, { strands, onEnter, onExit, say }) {
    this.viewport = viewport;
    this.strands = strands;
    this.onEnter = onEnter;
    this.onExit = onExit;
    this.say = say;
    this.active = false;
    this.state = null;
    this.last = -1;
    this.frames = 0;
    this.pose = { rotate: [0, 0, 0], translate: [0, 0, 0] };
    this.tree = new TreeView(viewport.scene);
    this.show = "strands";
    this.build();
    const canvas = viewport.renderer.domElement;
    this.raycaster = new THREE.Raycaster();
    // Capture phase: a press on the head drags it before the orbit controls see it.
    canvas.addEventListener("pointerdown", (e) => this.down(e), { capture: true });
    window.addEventListener("pointermove", (e) => this.move(e));
    window.addEventListener("pointerup", () => this.up());
  }

  build() {
    const button = document.createElement("button");
    button.id = "motion";
    button.textContent = "Motion";
    button.title = "Animate the style with the Adaptive Wisp Tree; drag the head (M)";
    button.onclick = () => this.toggle();
    document.getElementById("status").before(button);
    this.button = button;

    const tools = document.createElement("div");
    tools.id = "motion-tools";
    tools.hidden = true;
    tools.innerHTML = `
      <div class="row buttons">
        <button id="motion-play" title="Play or pause (Space)">▶</button>
        <button id="motion-step" title="One frame">step</button>
        <button id="motion-reset" title="Back to the rest pose at frame 0">reset</button>
      </div>
      <div class="row buttons" id="motion-presets"></div>
      <div class="row"><label for="motion-wind-dir">wind</label>
        <input type="range" id="motion-wind-dir" min="0" max="360" step="5" value="90" />
        <span id="motion-wind-dir-text">90°</span></div>
      <div class="row"><label for="motion-wind">speed</label>
        <input type="range" id="motion-wind" min="0" max="500" step="5" value="0" />
        <span id="motion-wind-text">0 cm/s</span></div>
      <div class="row"><label for="motion-show">show</label>
        <select id="motion-show"><option value="strands">strands</option><option value="tree">tree</option><option value="both">both</option></select></div>
      <canvas id="motion-plot" width="236" height="70"></canvas>
      <div class="row buttons">
        <input id="motion-name" value="take.usda" title="a .usda (value clips) or .hair/.obj/.ply (a file per frame) in the style's folder" />
        <button id="motion-record" title="Write the recording as a motion file (NAME.motion.json)">record</button>
        <button id="motion-export" title="Write the style, the recording and the animation as wisp animate does">export</button>
      </div>
      <div class="row checks">
        <label title="Also render every frame to NAME_####.png, as wisp animate --png does"><input type="checkbox" id="motion-png" /> PNG frames</label>
        <label title="Also encode the frames to NAME.mp4 with ffmpeg, as wisp animate --mp4 does"><input type="checkbox" id="motion-mp4" /> MP4</label>
      </div>
      <div id="motion-info"></div>
      <div class="hint">drag the head to turn it · Shift-drag to move it · off the head to orbit</div>`;
    document.getElementById("view").append(tools);
    this.tools = tools;
    const $ = (id) => document.getElementById(id);
    for (const name of presets) {
      const b = document.createElement("button");
      b.textContent = name;
      b.dataset.preset = name;
      b.onclick = () => this.run(() => post("/api/motion/preset", { name }).then(() => this.play(true)));
      $("motion-presets").append(b);
    }
    // A motion file (wisp animate --motion's JSON), played like a preset; the server's reader
    // checks it and names what is wrong.
    const file = document.createElement("input");
    file.type = "file";
    file.accept = ".json,application/json";
    file.hidden = true;
    file.id = "motion-file";
    file.onchange = () => this.run(async () => {
      const chosen = file.files[0];
      file.value = "";
      if (!chosen) return;
      const r = await postBinary("/api/motion/file", await chosen.text(), "application/json");
      if (!r.ok) throw new Error(`${chosen.name}: ${r.body.error}`);
      await this.play(true);
    });
    const open = document.createElement("button");
    open.textContent = "file…";
    open.title = "Play a motion file (JSON, as wisp animate --motion reads it)";
    open.onclick = () => file.click();
    $("motion-presets").append(open, file);
    $("motion-play").onclick = () => this.play(!this.state?.playing);
    $("motion-step").onclick = () => this.run(async () => {
      if (this.state?.playing) await this.play(false);
      await post("/api/motion/step");
    });
    $("motion-reset").onclick = () => this.run(async () => {
      this.state = await post("/api/motion/reset");
      this.pose = { rotate: [0, 0, 0], translate: [0, 0, 0] };
      this.last = -1;
      this.plot.rows = [];
      $("motion-play").textContent = "▶";
      await this.wind();
    });
    for (const id of ["motion-wind-dir", "motion-wind"]) $(id).addEventListener("input", () => this.wind());
    $("motion-show").onchange = (e) => this.setShow(e.target.value);
    $("motion-record").onclick = () => this.run(async () => {
      const name = `${$("motion-name").value.replace(/\.[^.]*$/, "")}.motion.json`;
      const r = await post("/api/motion/record", { name });
      this.info(`recorded ${r.file}: wisp animate STYLE --motion ${r.file} ${r.arguments}`);
    });
    $("motion-export").onclick = () => this.run(async () => {
      this.info("exporting…");
      // The server renders the pictures while this request runs: its progress meanwhile.
      let finished = false;
      const progress = setInterval(async () => {
        const p = await request("GET", "/api/motion/export").then((r) => r.json()).catch(() => null);
        if (p?.exporting && !finished) this.info(`exporting: ${p.stage}, frame ${p.done} of ${p.frames}…`);
      }, 300);
      try {
        const r = await post("/api/motion/export", { name: $("motion-name").value, png: $("motion-png").checked, mp4: $("motion-mp4").checked });
        this.exported = r;
        this.info(`${r.files.join(", ")} · ${r.command}${r.warning ? ` · ${r.warning}` : ""}`);
      } catch (e) {
        this.info(`export: ${e.message}`);
        throw e;
      } finally {
        finished = true;
        clearInterval(progress);
      }
    });
    this.plot = new Plot($("motion-plot"));
  }

  // A dynamics field changed in the panels: the running tree takes the ones it reads at every
  // step from the next one (the fields that shape the tree apply when Motion starts again).
  async setDynamics(path, value) {
    const response = await request("POST", "/api/motion/dynamics", { path, value });
    const body = await response.json();
    this.info(response.ok ? `${path} = ${JSON.stringify(value)} from the next step` : `${path}: ${body.error}`);
    return true;
  }

  info(text) {
    document.getElementById("motion-info").textContent = text;
  }

  // Runs an action, showing its error.
  async run(action) {
    try {
      await action();
    } catch (e) {
      this.say(e.message);
    }
  }

  async toggle() {
    return this.active ? this.exit() : this.enter();
  }

  async enter() {
    if (this.active) return;
    this.onEnter?.();
    this.say("building the wisp tree…");
    try {
      this.state = await post("/api/motion/start", { strands: this.strands, fps: 25 });
      const response = await request("GET", "/api/motion/strands");
      this.rest = decodeStrands(await response.arrayBuffer());
      this.viewport.setHair(this.rest);
    } catch (e) {
      this.say(e.message);
      this.onExit?.();
      return;
    }
    this.say("");
    this.active = true;
    this.last = -1;
    this.frames = 0;
    this.pose = { rotate: [0, 0, 0], translate: [0, 0, 0] };
    this.button.classList.add("on");
    this.tools.hidden = false;
    this.setShow(this.show);
    await this.wind();
    this.hudTimer = setInterval(() => this.refresh(), 250);
    this.receive();
  }

  async exit() {
    if (!this.active) return;
    this.active = false;
    clearInterval(this.hudTimer);
    this.abort?.abort();
    this.button.classList.remove("on");
    this.tools.hidden = true;
    this.tree.group.visible = false;
    this.restMesh();
    await post("/api/motion/stop").catch(() => {});
    this.onExit?.();
  }

  async play(on) {
    await this.run(() => post(on ? "/api/motion/play" : "/api/motion/pause"));
    if (this.state) this.state.playing = on;
    document.getElementById("motion-play").textContent = on ? "❚❚" : "▶";
  }

  async wind() {
    const angle = Number(document.getElementById("motion-wind-dir").value);
    const strength = Number(document.getElementById("motion-wind").value);
    document.getElementById("motion-wind-dir-text").textContent = `${angle}°`;
    document.getElementById("motion-wind-text").textContent = `${strength} cm/s`;
    // The direction the air blows toward, about the vertical: 0° toward +Z (the face).
    const a = (angle * Math.PI) / 180;
    if (!this.active && !this.state) return;
    await this.run(() => post("/api/motion/wind", { direction: [Math.sin(a), 0, Math.cos(a)], strength }));
  }

  setShow(show) {
    this.show = show;
    document.getElementById("motion-show").value = show;
    if (this.viewport.hair) this.viewport.hair.visible = show !== "tree";
    this.tree.group.visible = this.active && show !== "strands";
    // A stream without the tree reopens with it.
    if (show !== "strands" && this.transport === "stream" && !this.streamTree) this.abort?.abort();
    this.viewport.render();
  }

  // The frames: streamed, the stream reopened when it ends (a reset replaces the session), or
  // polled from the first time it breaks.
  async receive() {
    while (this.active) {
      try {
        this.transport = "stream";
        await this.stream();
      } catch (e) {
        if (!this.active) return;
        if (e.name === "AbortError") continue;
        console.warn(`motion: the frame stream broke (${e.message}); polling`);
        this.transport = "poll";
        return this.poll();
      }
    }
  }

  // Reads the frame stream until it ends; throws when it breaks.
  async stream() {
    this.abort = new AbortController();
    this.streamTree = this.show !== "strands";
    const response = await request("GET", `/api/motion/stream?tree=${this.streamTree ? 1 : 0}`, undefined, this.abort.signal);
    if (!response.ok) throw new Error((await response.json()).error ?? response.statusText);
    const reader = response.body.getReader();
    // The chunks read, joined only once they hold what the next step needs (a frame of
    // 20,000 strands is megabytes in many chunks: joining at every chunk would copy it often).
    const chunks = [];
    let size = 0, need = 4;
    for (;;) {
      const { done, value } = await reader.read();
      if (done || !this.active) return;
      chunks.push(value);
      size += value.length;
      if (size < need) continue;
      const pending = chunks.length === 1 ? chunks[0] : new Uint8Array(size);
      if (chunks.length > 1) chunks.reduce((at, c) => (pending.set(c, at), at + c.length), 0);
      // Length-prefixed messages; only the newest complete one is drawn.
      let at = 0, newest = null;
      need = 4;
      while (pending.length - at >= 4) {
        const length = new DataView(pending.buffer, pending.byteOffset + at, 4).getUint32(0, true);
        if (pending.length - at - 4 < length) {
          need = 4 + length;
          break;
        }
        const message = pending.slice(at + 4, at + 4 + length).buffer;
        if (newest) this.flashOnly(newest);
        newest = message;
        at += 4 + length;
      }
      chunks.length = 0;
      size = pending.length - at;
      if (size) chunks.push(pending.subarray(at));
      if (newest) this.message(newest);
    }
  }

  // "WISPMOTN" (src/edit/motion_session.hpp): frame, poses, tree, events.
  decodeMessage(buffer) {
    const magic = new TextDecoder().decode(new Uint8Array(buffer, 0, 8));
    if (magic !== "WISPMOTN") throw new Error("not a motion stream message");
    const [, frame, frameBytes, treeBytes, events] = new Uint32Array(buffer, 8, 5);
    const head = Array.from(new Float32Array(buffer, 28, 12)), body = Array.from(new Float32Array(buffer, 76, 12));
    const at = 124;
    return {
      frame, head, body,
      frameBuffer: buffer.slice(at, at + frameBytes),
      tree: treeBytes ? decodeTree(buffer.slice(at + frameBytes, at + frameBytes + treeBytes)) : null,
      events: new Float32Array(buffer, at + frameBytes + treeBytes, 4 * events),
    };
  }

  message(buffer) {
    const m = this.decodeMessage(buffer);
    this.draw(m.head, m.body, m.frameBuffer);
    if (m.tree && this.show !== "strands") {
      this.lastTree = m.tree;
      this.tree.set(m.tree, this.eventsWith(m.events));
      this.viewport.render();
    }
  }

  // A message overtaken in the same read: its events still flash with the next tree.
  flashOnly(buffer) {
    const m = this.decodeMessage(buffer);
    this.heldEvents = this.eventsWith(m.events);
  }

  eventsWith(events) {
    if (!this.heldEvents?.length) return events;
    const all = new Float32Array(this.heldEvents.length + events.length);
    all.set(this.heldEvents);
    all.set(events, this.heldEvents.length);
    this.heldEvents = null;
    return all;
  }

  // The state for the HUD and the plot, four times a second.
  async refresh() {
    if (this.refreshing || !this.active) return;
    this.refreshing = true;
    try {
      const response = await request("GET", "/api/motion");
      if (response.ok) {
        this.state = await response.json();
        this.hud();
      }
    } catch {
      // The next tick tries again.
    } finally {
      this.refreshing = false;
    }
  }

  // Frames as fast as the server makes them and this page takes them: each request asks for
  // the newest frame past the last one drawn.
  async poll() {
    const pose = (text) => text?.trim().split(/\s+/).map(Number);
    while (this.active) {
      try {
        const response = await request("GET", `/api/motion/frame?after=${this.last}&wait=500`);
        if (!this.active) break;
        if (response.status === 200)
          this.draw(pose(response.headers.get("X-Wisp-Head")), pose(response.headers.get("X-Wisp-Body")), await response.arrayBuffer());
        else if (!response.ok) throw new Error((await response.json()).error);
        if (this.show !== "strands") await this.drawTree();
      } catch (e) {
        this.say(e.message);
        await new Promise((r) => setTimeout(r, 500));
      }
    }
  }

  draw(head, body, buffer) {
    const [, frame, points] = new Uint32Array(buffer, 8, 3);
    const positions = new Float32Array(buffer, 20, 3 * points);
    this.last = frame;
    ++this.frames;
    this.lastFrame = { frame, positions };
    const geometry = this.viewport.hair?.geometry;
    const attribute = geometry?.getAttribute("position");
    if (attribute && attribute.array.length === positions.length) {
      attribute.array.set(positions);
      attribute.needsUpdate = true;
      const tangent = geometry.getAttribute("tangent3");
      if (tangent) this.tangents(tangent.array, positions);
      if (tangent) tangent.needsUpdate = true;
    } else {
      this.viewport.setHair({ ...this.rest, positions: positions.slice() });
      this.viewport.hair.visible = this.show !== "tree";
    }
    if (head && body && this.viewport.head) this.poseMesh(head, body);
    this.viewport.render();
  }

  // The head mesh posed as the server's pose_body does: above the chin with the head, below
  // the neck's base with the body, blended linearly between. head, body: 12 numbers each, the
  // rotation row by row and the translation (cm).
  poseMesh(headPose, bodyPose) {
    const matrix = (v) => {
      return new THREE.Matrix4().set(v[0], v[1], v[2], v[9], v[3], v[4], v[5], v[10], v[6], v[7], v[8], v[11], 0, 0, 0, 1);
    };
    const geometry = this.viewport.head.geometry;
    const attribute = geometry.getAttribute("position");
    if (!this.restHead || this.restHead.length !== attribute.array.length) this.restHead = attribute.array.slice();
    const h = matrix(headPose), b = matrix(bodyPose);
    const c = this.state?.head_center ?? [0, 0, 0], r = this.state?.head_radius ?? 10;
    const top = c[1] - 0.8 * r, bottom = c[1] - 1.6 * r;
    const p = new THREE.Vector3(), q = new THREE.Vector3(), rest = this.restHead, out = attribute.array;
    for (let i = 0; i < rest.length; i += 3) {
      p.set(rest[i], rest[i + 1], rest[i + 2]);
      const w = Math.min(1, Math.max(0, (p.y - bottom) / (top - bottom)));
      q.copy(p).applyMatrix4(b);
      p.applyMatrix4(h).multiplyScalar(w).addScaledVector(q, 1 - w);
      out[i] = p.x;
      out[i + 1] = p.y;
      out[i + 2] = p.z;
    }
    attribute.needsUpdate = true;
    geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    geometry.computeBoundingBox();
  }

  // The mesh back at rest (leaving Motion).
  restMesh() {
    if (!this.restHead || !this.viewport.head) return;
    const geometry = this.viewport.head.geometry;
    geometry.getAttribute("position").array.set(this.restHead);
    geometry.getAttribute("position").needsUpdate = true;
    geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    geometry.computeBoundingBox();
  }

  tangents(out, positions) {
    const { offsets, strands } = this.rest;
    for (let s = 0; s < strands; ++s) {
      const a = offsets[s], b = offsets[s + 1];
      for (let i = a; i < b; ++i) {
        const p = Math.max(a, i - 1), n = Math.min(b - 1, i + 1);
        for (let c = 0; c < 3; ++c) out[3 * i + c] = positions[3 * n + c] - positions[3 * p + c];
      }
    }
  }

  async drawTree() {
    const response = await request("GET", "/api/motion/tree");
    if (!response.ok) return;
    this.lastTree = decodeTree(await response.arrayBuffer());
    this.tree.set(this.lastTree);
    this.viewport.render();
  }

  hud() {
    const s = this.state;
    if (!s) return;
    this.plot.push(s.active_per_level ?? []);
    const hud = document.getElementById("hud");
    hud.textContent = `Motion · frame ${s.frame} · ${s.shown.toLocaleString()} strands shown · ` +
      `active ${s.active_per_level.join(" / ")} of ${s.finest_nodes.toLocaleString()} finest · ` +
      `${s.splits} splits ${s.merges} merges · step ${s.step_ms.toFixed(1)} ms · skin ${s.skin_ms.toFixed(1)} ms` +
      (s.error ? ` · ${s.error}` : "");
    if (s.error) this.say(s.error);
  }

  // Dragging the head: horizontal turns it (yaw), vertical nods it (pitch); Shift moves it in
  // the view's plane. One request in flight; the newest pose goes next.
  down(e) {
    if (!this.active || e.button !== 0 || !this.viewport.head) return;
    const rect = e.target.getBoundingClientRect();
    const ndc = new THREE.Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1,
      -((e.clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.viewport.camera);
    this.viewport.head.updateMatrixWorld();
    if (!this.raycaster.intersectObject(this.viewport.head).length) return;
    e.preventDefault();
    e.stopImmediatePropagation();
    this.viewport.controls.enabled = false;
    this.dragging = { x: e.clientX, y: e.clientY, start: structuredClone(this.pose) };
    if (!this.state?.playing) this.play(true);  // the hair follows while the head moves
  }

  move(e) {
    const d = this.dragging;
    if (!d) return;
    const dx = e.clientX - d.x, dy = e.clientY - d.y;
    const pose = structuredClone(d.start);
    if (e.shiftKey) {
      const camera = this.viewport.camera;
      const right = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 0);
      const up = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 1);
      const move = right.multiplyScalar(dx * 0.06).addScaledVector(up, -dy * 0.06);
      for (let c = 0; c < 3; ++c) pose.translate[c] += move.getComponent(c);
    } else {
      pose.rotate[1] = Math.max(-80, Math.min(80, pose.rotate[1] + dx * 0.4));
      pose.rotate[0] = Math.max(-60, Math.min(60, pose.rotate[0] + dy * 0.4));
    }
    this.pose = pose;
    this.sendPose();
  }

  up() {
    if (!this.dragging) return;
    this.dragging = null;
    this.viewport.controls.enabled = true;
    this.sendPose();
  }

  async sendPose() {
    if (this.sending) {
      this.pending = true;
      return;
    }
    this.sending = true;
    do {
      this.pending = false;
      await this.run(() => post("/api/motion/drag", this.pose));
    } while (this.pending);
    this.sending = false;
  }
}
