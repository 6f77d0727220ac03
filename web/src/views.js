// Views of the hair: colour by the strands' own colour, their wisp, their constraint group,
// their length or their constraint progress (how much of its group's queue each strand's
// wisp met, from the solver's count that the groups' progress is made of); the view's inset beside a tool panel; and the final picture from wisp's own
// renderer of the live view's camera (POST /api/render).
import { getBinary, postJson } from "./api.js";

export const colorModes = {
  color: "strand colour",
  wisp: "wisp",
  group: "group",
  length: "length",
  progress: "constraint progress",
};

// The modes that need each strand's wisp, group or progress (GET /api/attributes).
export const needsAttributes = (mode) => mode === "wisp" || mode === "group" || mode === "progress";

// Constraint progress t in [0, 1] (the fraction of the queue met): red for none, amber
// half way, green for all of it; linear RGB.
export function progressColor(t) {
  if (t < 0) return [0.06, 0.06, 0.065];
  const stops = [[0.8, 0.06, 0.04], [0.9, 0.45, 0.03], [0.12, 0.75, 0.16]];
  const x = Math.min(1, t) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(x)), f = x - i;
  return stops[i].map((c, k) => c + (stops[i + 1][k] - c) * f);
}

// Linear RGB of a hue (degrees) at full saturation, a little darkened.
function hue(h, value = 0.75) {
  const f = (n) => {
    const k = (n + h / 60) % 6;
    return value * (1 - Math.max(0, Math.min(k, 4 - k, 1)));
  };
  return [f(5), f(3), f(1)].map((c) => c * c);  // sRGB-ish to linear
}

// Group g's colour (0: in no group, a neutral grey): hues a golden angle apart.
export function groupColor(g) {
  return g <= 0 ? [0.09, 0.085, 0.08] : hue((g * 137.508 + 25) % 360, 0.95);
}

// Wisp w's colour: many hues, told apart from their neighbours.
function wispColor(w) {
  if (w < 0) return [0.2, 0.2, 0.2];
  const h = (w * 137.508) % 360;
  return hue(h, 0.55 + 0.4 * (((w * 0.618034) % 1)));
}

// A dark-blue → teal → yellow ramp (viridis-like) for t in [0, 1], linear RGB.
function ramp(t) {
  const stops = [[0.07, 0.01, 0.17], [0.02, 0.16, 0.33], [0.01, 0.38, 0.32], [0.22, 0.63, 0.07], [0.97, 0.84, 0.02]];
  const x = Math.min(0.9999, Math.max(0, t)) * (stops.length - 1);
  const i = Math.floor(x), f = x - i;
  return stops[i].map((c, k) => c + (stops[i + 1][k] - c) * f);
}

// Each strand's length (cm) along its control points.
export function strandLengths(strands) {
  const { offsets, positions, strands: n } = strands;
  const out = new Float32Array(n);
  for (let s = 0; s < n; ++s) {
    let l = 0;
    for (let i = offsets[s] + 1; i < offsets[s + 1]; ++i)
      l += Math.hypot(positions[3 * i] - positions[3 * i - 3], positions[3 * i + 1] - positions[3 * i - 2],
        positions[3 * i + 2] - positions[3 * i - 1]);
    out[s] = l;
  }
  return out;
}

// The strands with their colours replaced for `mode` (attributes: { wisp, group } per strand,
// in the same order). Returns { strands, legend }.
export function recolor(strands, mode, attributes) {
  if (mode === "color") return { strands, legend: "" };
  const n = strands.strands;
  const colors = new Float32Array(3 * n);
  let legend = "";
  if (mode === "length") {
    const lengths = strandLengths(strands);
    let lo = Infinity, hi = 0;
    for (const l of lengths) {
      lo = Math.min(lo, l);
      hi = Math.max(hi, l);
    }
    for (let s = 0; s < n; ++s) colors.set(ramp(hi > lo ? (lengths[s] - lo) / (hi - lo) : 1), 3 * s);
    legend = n ? `length ${lo.toFixed(1)} cm (dark) … ${hi.toFixed(1)} cm (yellow)` : "";
  } else if (mode === "progress") {
    const progress = attributes?.progress;
    let grouped = 0, done = 0;
    for (let s = 0; s < n; ++s) {
      const t = progress && s < progress.length ? progress[s] : -1;
      colors.set(progressColor(t), 3 * s);
      if (t >= 0) ++grouped;
      if (t >= 1) ++done;
    }
    legend = grouped
      ? `constraints met: none (red) … all (green), ${Math.round((100 * done) / grouped)}% met all · no group: dark`
      : "no constraint groups: place a tie or a comb";
  } else {
    const ids = attributes?.[mode];
    for (let s = 0; s < n; ++s) {
      const id = ids && s < ids.length ? ids[s] : -1;
      colors.set(mode === "group" ? groupColor(id) : wispColor(id), 3 * s);
    }
    if (mode === "group") {
      const groups = new Set(ids ?? []);
      groups.delete(0);
      legend = `${groups.size} group${groups.size === 1 ? "" : "s"} in colour, hair in none dark`;
    } else {
      legend = "each wisp its own colour";
    }
  }
  return { strands: { ...strands, colors }, legend };
}

// "WISPATTR": each strand's wisp, group and constraint progress, in /api/hair's order.
export async function fetchAttributes(limit) {
  const buffer = await getBinary(`/api/attributes?strands=${limit}`);
  if (!buffer) return null;
  const [version, count] = new Uint32Array(buffer, 8, 2);
  return {
    wisp: new Int32Array(buffer, 16, count),
    group: new Int32Array(buffer, 16 + 4 * count, count),
    progress: version >= 2 ? new Float32Array(buffer, 16 + 8 * count, count) : null,
  };
}

// Shifts the picture so that the head sits in the middle of the part of the view a tool
// panel of `inset` pixels at its left leaves free (the camera's view offset: picking and
// orbiting stay right).
export function setInset(viewport, inset) {
  viewport.inset = inset;
  const apply = () => {
    const { clientWidth: w, clientHeight: h } = viewport.element;
    if (!w || !h) return;
    if (viewport.inset > 0) viewport.camera.setViewOffset(w, h, -viewport.inset / 2, 0, w, h);
    else viewport.camera.clearViewOffset();
    viewport.camera.updateProjectionMatrix();
    viewport.render();
  };
  if (!viewport.insetObserver) {
    viewport.insetObserver = new ResizeObserver(apply);
    viewport.insetObserver.observe(viewport.element);
  }
  apply();
}

// The final picture of the live view's camera from wisp's renderer, as an object URL.
export async function renderPicture(viewport, width, height) {
  const camera = viewport.camera;
  const result = await fetch("/api/render", {
    method: "POST",
    headers: {
      "X-Wisp-Token": new URLSearchParams(location.search).get("token") ?? "",
      "Content-Type": "application/json",
    },
    body: JSON.stringify({
      eye: camera.position.toArray(),
      target: viewport.controls.target.toArray(),
      up: camera.up.toArray(),
      fov: camera.fov,
      width,
      height,
    }),
  });
  if (!result.ok) throw new Error((await result.json()).error);
  return URL.createObjectURL(await result.blob());
}

// Export: the full hair in one of wisp's formats, into the style's folder.
export async function exportHair(name) {
  return postJson("/api/export", { name });
}
