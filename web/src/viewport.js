// The 3D view: the head mesh and the hair as one LineSegments draw call with a tangent-based
// (Kajiya–Kay) hair shader, under an orbit camera.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

const hairVertex = /* glsl */ `
  attribute vec3 tangent3;
  attribute vec3 color;
  varying vec3 vTangent;
  varying vec3 vColor;
  varying vec3 vView;
  void main() {
    vec4 world = modelMatrix * vec4(position, 1.0);
    vTangent = normalize(mat3(modelMatrix) * tangent3);
    vColor = color;
    vView = normalize(cameraPosition - world.xyz);
    gl_Position = projectionMatrix * viewMatrix * world;
  }
`;

// Kajiya–Kay: diffuse sin(T, L), specular sin(T, H)^p, with a tinted secondary highlight.
const hairFragment = /* glsl */ `
  uniform vec3 lightDir;
  uniform float opacity;
  varying vec3 vTangent;
  varying vec3 vColor;
  varying vec3 vView;
  void main() {
    vec3 t = normalize(vTangent);
    vec3 l = normalize(lightDir);
    vec3 h = normalize(l + normalize(vView));
    float tl = dot(t, l);
    float th = dot(t, h);
    float diffuse = sqrt(max(0.0, 1.0 - tl * tl));
    float sinth = sqrt(max(0.0, 1.0 - th * th));
    float spec = pow(sinth, 80.0) * 0.12;
    float spec2 = pow(sinth, 20.0) * 0.3;
    vec3 c = vColor * (0.25 + 0.85 * diffuse) + vec3(spec) + vColor * spec2;
    gl_FragColor = vec4(c, opacity);
    #include <colorspace_fragment>
  }
`;

export class Viewport {
  constructor(element) {
    this.element = element;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.renderer.setClearColor(0x24262b);
    element.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(30, 1, 1, 2000);
    this.camera.position.set(45, 20, 80);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.set(0, 0, 0);
    this.controls.addEventListener("change", () => this.render());
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x404048, 2.2));
    const key = new THREE.DirectionalLight(0xffffff, 1.6);
    key.position.set(30, 60, 50);
    this.scene.add(key);
    this.lightDir = key.position.clone().normalize();
    this.hairMaterial = new THREE.ShaderMaterial({
      vertexShader: hairVertex,
      fragmentShader: hairFragment,
      uniforms: { lightDir: { value: this.lightDir }, opacity: { value: 1 } },
    });
    this.hair = null;
    this.capacity = { points: 0, index: 0 };
    this.counts = { updates: 0, allocations: 0, mastersDrawn: 0 };
    this.shown = null;
    this.frame = 0;
    this.head = null;
    new ResizeObserver(() => this.resize()).observe(element);
    this.resize();
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.element;
    if (!w || !h) return;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  // Draws on the next animation frame, once: the pointer, the brush and each answer ask for
  // many renders a frame, and software GL draws every one of them in full.
  render() {
    if (this.frame) return;
    this.frame = requestAnimationFrame(() => this.renderNow());
  }

  // Draws at once (the browser tests read the pixels back).
  renderNow() {
    if (this.frame) cancelAnimationFrame(this.frame);
    this.frame = 0;
    this.renderer.render(this.scene, this.camera);
  }

  setHead(head) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(head.positions, 3));
    geometry.setIndex(new THREE.BufferAttribute(head.triangles, 1));
    // The renderer's skin normals (smooth across a bust's seam with its body proxy), not
    // three.js's, which would show the seam as a line.
    geometry.setAttribute("normal", new THREE.BufferAttribute(head.normals, 3));
    geometry.computeBoundingBox();
    const material = new THREE.MeshStandardMaterial({ color: 0xc9a58c, roughness: 0.7 });
    if (this.head) this.scene.remove(this.head);
    this.head = new THREE.Mesh(geometry, material);
    this.scene.add(this.head);
    const box = geometry.boundingBox;
    // Frame the head and its hair: the top of the mesh holds the head.
    this.controls.target.set(0, box.max.y - 14, 0);
    this.controls.update();
    this.render();
  }

  // Fades the hair (painting shows the map on the scalp through it).
  setHairOpacity(opacity) {
    const m = this.hairMaterial;
    m.uniforms.opacity.value = opacity;
    m.transparent = opacity < 1;
    m.depthWrite = opacity >= 1;
    m.needsUpdate = true;
    this.render();
  }

  showHead(visible) {
    if (this.head) this.head.visible = visible;
    this.render();
  }

  // strands: decodeStrands()'s arrays; masters: they are the masters (a first answer while a
  // value moves), not strands of the hair. One vertex per control point, one index pair per
  // segment: a single LineSegments, a single draw call. The buffers are kept and rewritten
  // in place (only the range in use is uploaded, and drawn with setDrawRange); they grow by
  // a quarter more than asked when an answer outgrows them. Software GL (SwiftShader)
  // crashed when every preview of a brush stroke made new buffers of the whole hair.
  setHair(strands, { masters = false } = {}) {
    const { offsets, positions, colors, strands: count } = strands;
    const points = positions.length / 3;
    const segments = Math.max(0, points - count);
    if (!this.hair || points > this.capacity.points || 2 * segments > this.capacity.index) {
      const capacity = { points: Math.ceil(1.25 * points) + 64, index: 2 * Math.ceil(1.25 * segments) + 64 };
      const geometry = new THREE.BufferGeometry();
      for (const name of ["position", "tangent3", "color"]) {
        const attribute = new THREE.BufferAttribute(new Float32Array(3 * capacity.points), 3);
        attribute.setUsage(THREE.DynamicDrawUsage);
        geometry.setAttribute(name, attribute);
      }
      const index = new THREE.BufferAttribute(new Uint32Array(capacity.index), 1);
      index.setUsage(THREE.DynamicDrawUsage);
      geometry.setIndex(index);
      if (this.hair) {
        this.scene.remove(this.hair);
        this.hair.geometry.dispose();
      }
      this.hair = new THREE.LineSegments(geometry, this.hairMaterial);
      this.hair.frustumCulled = false;
      this.scene.add(this.hair);
      this.capacity = capacity;
      ++this.counts.allocations;
    }
    const geometry = this.hair.geometry;
    const position = geometry.getAttribute("position");
    const tangent = geometry.getAttribute("tangent3");
    const color = geometry.getAttribute("color");
    const index = geometry.getIndex();
    position.array.set(positions);
    const tangents = tangent.array, vertexColors = color.array, pairs = index.array;
    let k = 0;
    for (let s = 0; s < count; ++s) {
      const a = offsets[s], b = offsets[s + 1];
      for (let i = a; i < b; ++i) {
        const p = Math.max(a, i - 1), n = Math.min(b - 1, i + 1);
        for (let c = 0; c < 3; ++c) {
          tangents[3 * i + c] = positions[3 * n + c] - positions[3 * p + c];
          vertexColors[3 * i + c] = colors[3 * s + c];
        }
        if (i + 1 < b) {
          pairs[k++] = i;
          pairs[k++] = i + 1;
        }
      }
    }
    for (const attribute of [position, tangent, color]) {
      attribute.clearUpdateRanges();
      attribute.addUpdateRange(0, 3 * points);
      attribute.needsUpdate = true;
    }
    index.clearUpdateRanges();
    index.addUpdateRange(0, k);
    index.needsUpdate = true;
    geometry.setDrawRange(0, k);
    this.counts.updates += 1;
    if (masters) this.counts.mastersDrawn += 1;
    this.shown = { strands: count, total: strands.total, points, masters };
    this.render();
  }

  // What the hair view holds, for the HUD and the browser tests: strands and points drawn,
  // strands in all, whether it is the whole hair, and how many updates (of them masters) and
  // buffer allocations it took so far.
  stats() {
    const { strands = 0, total = 0, points = 0, masters = false } = this.shown ?? {};
    return { strands, total, points, masters, final: !masters && strands > 0 && strands === total,
      ...this.counts };
  }
}
