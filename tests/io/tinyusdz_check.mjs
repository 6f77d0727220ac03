// Every kind of .usda that wisp writes, read by a USD library that is not wisp's: TinyUSDZ
// (npm `tinyusdz`, its C++ parser compiled to WebAssembly). Debian has no OpenUSD; TinyUSDZ
// is the USD reader three.js's loader and many web viewers use.
//
// For the hair (with guides and the head), a value-clip animation and a time-sampled one, it
// checks what TinyUSDZ read back: the prims and their types, the curve and mesh counts, every
// array's length against the counts it must match, the `groom_*` primvars that Unreal's groom
// translator reads, and the points' bounds against `wisp info` (wisp's own reader).
//
// Usage: node tests/io/tinyusdz_check.mjs WISP_EXE WORK_DIR
// Exits 77 (skipped) when web/node_modules has no tinyusdz (scripts/setup installs it).
import {execFileSync} from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import {fileURLToPath} from 'node:url';

const [wisp, workArg] = process.argv.slice(2);
const here = path.dirname(fileURLToPath(import.meta.url));
const pkg = path.join(here, '../../web/node_modules/tinyusdz');
if (!fs.existsSync(path.join(pkg, 'tinyusdz.js'))) {
  console.log('tinyusdz-check: SKIPPED: web/node_modules/tinyusdz is missing (scripts/setup)');
  process.exit(77);
}

// The npm build of TinyUSDZ is made for browsers and refuses to start when it sees Node: it
// is shown no Node version while it starts, and given its WebAssembly bytes directly (a
// browser would fetch them).
async function loadTinyUsdz() {
  const versions = process.versions;
  Object.defineProperty(process, 'versions', {value: {}, configurable: true});
  globalThis.window ??= globalThis;
  try {
    const {default: init} = await import(path.join(pkg, 'tinyusdz.js'));
    return await init({wasmBinary: fs.readFileSync(path.join(pkg, 'tinyusdz.wasm'))});
  } finally {
    Object.defineProperty(process, 'versions', {value: versions, configurable: true});
  }
}
const tinyusdz = await loadTinyUsdz();

let failures = 0;
function check(ok, what) {
  if (!ok) {
    console.error(`tinyusdz-check: FAILED: ${what}`);
    failures++;
  }
}

// The layer TinyUSDZ parsed from `file`, as the prims it printed back: path → {type,
// specifier, attrs: name → {type, values: [...] | samples: {time: [...]}, text}, meta}.
function readLayer(file) {
  const usd = new tinyusdz.TinyUSDZLoaderNative();
  const ok = usd.loadAsLayerFromBinary(new Uint8Array(fs.readFileSync(file)), file);
  if (!ok) throw new Error(`TinyUSDZ could not read ${file}: ${usd.error()}`);
  const text = usd.layerToString();
  const prims = new Map();
  const stack = [];  // [{path, depth}]
  let depth = 0;
  let current = null;
  let samplesOf = null;
  let lastAttr = null;
  let dictDepth = 0;  // inside a metadata dictionary (clips = { ... })
  const lines = text.split('\n');
  for (const line of lines) {
    const t = line.trim();
    if (dictDepth > 0 || (!samplesOf && t.endsWith('{') && t !== '{' && !t.includes('.timeSamples'))) {
      if (current) current.meta += t + '\n';
      if (t.endsWith('{')) dictDepth++;
      else if (t.startsWith('}')) dictDepth--;
      continue;
    }
    const prim = t.match(/^(def|over|class)\s+(?:(\w+)\s+)?"([^"]+)"/);
    if (prim) {
      while (stack.length && stack[stack.length - 1].depth >= depth) stack.pop();
      const parent = stack.length ? stack[stack.length - 1].path : '';
      current = {path: `${parent}/${prim[3]}`, specifier: prim[1], type: prim[2] ?? '',
                 attrs: new Map(), meta: ''};
      prims.set(current.path, current);
      stack.push({path: current.path, depth});
      continue;
    }
    if (t === '{') { depth++; continue; }
    if (t === '}' || t === '},') {
      if (samplesOf) { samplesOf = null; continue; }
      depth--;
      continue;
    }
    if (!current) continue;
    if (samplesOf) {
      const sample = t.match(/^([-\d.e+]+):\s*(\[.*\]),?$/);
      if (sample) samplesOf.samples[sample[1]] = parseArray(sample[2]);
      continue;
    }
    const interpolation = t.match(/^interpolation = "(\w+)"/);
    if (interpolation && lastAttr) {
      lastAttr.interpolation = interpolation[1];
      continue;
    }
    const attr = t.match(/^(?:uniform\s+)?([\w\[\]]+)\s+([\w:]+)(\.timeSamples)?\s*=\s*(.*)$/);
    if (attr) {
      const a = {type: attr[1], text: attr[4]};
      if (attr[3]) {
        a.samples = {};
        samplesOf = a;
      } else if (attr[4].startsWith('[')) {
        a.values = parseArray(attr[4]);
      }
      current.attrs.set(attr[2], a);
      lastAttr = a;
    } else {
      current.meta += t + '\n';
    }
  }
  return prims;
}

// "[1, 2]" → [1, 2]; "[(1, 2, 3), (4, 5, 6)]" → [[1, 2, 3], [4, 5, 6]]; strings and assets as
// they are written.
function parseArray(s) {
  const body = s.trim().replace(/\s*\($/, '').replace(/^\[/, '').replace(/\]\s*\)?,?$/, '');
  if (!body.trim()) return [];
  if (body.trim().startsWith('(')) {
    return [...body.matchAll(/\(([^)]*)\)/g)].map(m => m[1].split(',').map(Number));
  }
  return body.split(',').map(v => v.trim()).map(v => (/^[-\d.e+]+$/.test(v) ? Number(v) : v));
}

function run(...args) { return execFileSync(wisp, args, {encoding: 'utf8'}); }
function sum(values) { return values.reduce((a, b) => a + b, 0); }

// Points' bounds (TinyUSDZ's) against `wisp info`'s, to a float's rounding.
function checkBounds(points, file) {
  const info = JSON.parse(run('info', '--json', file));
  for (let c = 0; c < 3; c++) {
    const lo = Math.min(...points.map(p => p[c]));
    const hi = Math.max(...points.map(p => p[c]));
    check(Math.abs(lo - info.bbox.min[c]) <= 1e-5 * Math.max(1, Math.abs(lo)) &&
              Math.abs(hi - info.bbox.max[c]) <= 1e-5 * Math.max(1, Math.abs(hi)),
          `${file}: axis ${c}: TinyUSDZ's points span [${lo}, ${hi}], wisp info's ` +
              `[${info.bbox.min[c]}, ${info.bbox.max[c]}]`);
  }
}

// A BasisCurves prim's counts, arrays and groom primvars; returns its point count.
function checkCurves(prims, primPath, curves, file, {animated = false} = {}) {
  const p = prims.get(primPath);
  check(p && p.type === 'BasisCurves', `${file}: no BasisCurves ${primPath}`);
  if (!p) return 0;
  const get = name => p.attrs.get(name);
  for (const [name, value] of [['type', '"cubic"'], ['basis', '"catmullRom"'],
                               ['wrap', '"pinned"']])
    check(get(name)?.text === value, `${file}: ${primPath}.${name} is ${get(name)?.text}`);
  const counts = get('curveVertexCounts')?.values ?? [];
  check(counts.length === curves, `${file}: ${primPath} has ${counts.length} curves, not ${curves}`);
  const n = sum(counts);
  check(counts.every(c => c >= 2), `${file}: ${primPath}: a pinned curve with under 2 points`);
  if (!animated) {
    const points = get('points');
    check(points?.type === 'point3f[]' && points.values.length === n,
          `${file}: ${primPath}.points holds ${points?.values.length}, not ${n}`);
  }
  const widths = get('widths');
  check(widths?.type === 'float[]' && widths.values.length === n &&
            widths.values.every(w => w > 0),
        `${file}: ${primPath}.widths: ${widths?.values.length} of ${n}, or not positive`);
  for (const [name, type] of [['primvars:displayColor', 'color3f[]'],
                              ['primvars:groom_color', 'float3[]'],
                              ['primvars:groom_root_uv', 'float2[]'],
                              ['primvars:groom_group_id', 'int[]']]) {
    const a = get(name);
    const expected = a?.interpolation === 'constant' ? 1 : curves;
    check(a?.type === type && a.values.length === expected &&
              ['uniform', 'constant'].includes(a.interpolation),
          `${file}: ${primPath}.${name} is ${a?.type} of ${a?.values?.length} ` +
              `(${a?.interpolation}), not ${type}, one per curve or one in all`);
  }
  const uv = get('primvars:groom_root_uv')?.values ?? [];
  check(uv.every(([u, v]) => u >= 0 && u <= 1 && v >= 0 && v <= 1),
        `${file}: ${primPath}: a groom_root_uv outside [0, 1]`);
  return n;
}

const work = fs.mkdtempSync(path.join(workArg ?? fs.realpathSync('/tmp'), 'tinyusdz-'));
try {
  const style = path.join(work, 'small.toml');
  fs.writeFileSync(style, 'name = "small"\n[roots]\nwisps = 30\nstrands = 300\n');

  // The hair, its guides and the head in one stage.
  const hair = path.join(work, 'hair.usda');
  run('generate', style, '-q', '--guides', '--with-head', '-o', hair);
  let prims = readLayer(hair);
  check(prims.get('/hair')?.type === 'Xform', `${hair}: no Xform /hair`);
  const n = checkCurves(prims, '/hair/strands', 300, hair);
  checkBounds(prims.get('/hair/strands').attrs.get('points').values, hair);
  const closest = prims.get('/hair/strands').attrs.get('primvars:groom_closest_guides');
  check(closest?.type === 'int[]' && closest.values.length === 300,
        `${hair}: groom_closest_guides is ${closest?.type} of ${closest?.values?.length}`);
  checkCurves(prims, '/hair/guides', 30, hair);
  check(prims.get('/hair/guides')?.attrs.get('primvars:groom_guide')?.values?.[0] === 1,
        `${hair}: /hair/guides has no groom_guide = 1`);
  check(prims.get('/hair/strands')?.attrs.get('primvars:groom_guide')?.values?.[0] === 0,
        `${hair}: /hair/strands has no groom_guide = 0`);
  const head = prims.get('/head');
  check(head?.type === 'Mesh', `${hair}: no Mesh /head`);
  if (head) {
    const counts = head.attrs.get('faceVertexCounts')?.values ?? [];
    const indices = head.attrs.get('faceVertexIndices')?.values ?? [];
    const vertices = head.attrs.get('points')?.values.length ?? 0;
    check(counts.length > 1000 && indices.length === sum(counts),
          `${hair}: /head has ${counts.length} faces and ${indices.length} indices`);
    check(indices.every(i => i >= 0 && i < vertices), `${hair}: a /head index out of range`);
    const scalp = prims.get('/head/scalp');
    const faces = scalp?.attrs.get('indices')?.values ?? [];
    check(scalp?.type === 'GeomSubset' && faces.length > 0 &&
              faces.every(f => f >= 0 && f < counts.length),
          `${hair}: /head/scalp is not a subset of the head's faces`);
  }

  // An animation as value clips: the top layer, the manifest, a layer per frame.
  const frames = 3;
  const take = path.join(work, 'anim', 'take.usda');
  run('animate', style, '-q', '--frames', String(frames), '-o', take);
  prims = readLayer(take);
  const m = checkCurves(prims, '/hair/strands', 300, take, {animated: true});
  const clips = prims.get('/hair')?.meta ?? '';
  const assets = [...clips.matchAll(/@([^@]+)@/g)].map(a => a[1]);
  check(assets.length === frames + 1, `${take}: clips name ${assets.length} layers, not ` +
                                          `${frames} and the manifest`);
  for (const asset of assets) {
    const layer = readLayer(path.join(work, 'anim', asset));
    if (asset.includes('manifest')) {
      check(layer.has('/hair/strands'), `${asset}: no /hair/strands`);
      continue;
    }
    const points = layer.get('/hair/strands')?.attrs.get('points');
    const samples = Object.values(points?.samples ?? {});
    check(samples.length === 1 && samples[0].length === m,
          `${asset}: points holds ${samples.map(s => s.length)} samples, not one of ${m}`);
  }

  // One time-sampled layer.
  const single = path.join(work, 'single.usda');
  run('animate', style, '-q', '--frames', String(frames), '--usda', 'single', '-o', single);
  prims = readLayer(single);
  const k = checkCurves(prims, '/hair/strands', 300, single, {animated: true});
  const samples = prims.get('/hair/strands')?.attrs.get('points')?.samples ?? {};
  check(Object.keys(samples).length === frames &&
            Object.values(samples).every(s => s.length === k),
        `${single}: ${Object.keys(samples).length} samples of points, not ${frames} of ${k}`);
  console.log(`tinyusdz-check: ${failures ? 'FAILED' : 'passed'}: hair (${n} points, guides, ` +
              `head), value clips (${frames} frames), time samples`);
} finally {
  fs.rmSync(work, {recursive: true, force: true});
}
process.exit(failures ? 1 : 0);
