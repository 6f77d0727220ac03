// The server's API (src/edit/server.hpp): JSON requests carrying the launch token, and the
// binary strand and head arrays (src/edit/wire.hpp), all little-endian.
const token = new URLSearchParams(location.search).get("token") ?? "";

export async function request(method, path, body, signal) {
  const response = await fetch(path, {
    method,
    headers: { "X-Wisp-Token": token, ...(body ? { "Content-Type": "application/json" } : {}) },
    body: body ? JSON.stringify(body) : undefined,
    signal,
  });
  return response;
}

export async function getJson(path) {
  const response = await request("GET", path);
  if (!response.ok) throw new Error((await response.json()).error ?? response.statusText);
  return response.json();
}

// POST a JSON body; resolves to { ok, status, body } so callers can show a 400's message.
export async function postJson(path, body) {
  const response = await request("POST", path, body);
  return { ok: response.ok, status: response.status, body: await response.json() };
}

// GET binary; null when the server answered 409 (a newer request overtook this one).
export async function getBinary(path) {
  const response = await request("GET", path);
  if (response.status === 409) return null;
  if (!response.ok) throw new Error((await response.json()).error ?? response.statusText);
  return response.arrayBuffer();
}

// "WISPHAIR": strands, points, offsets, positions (cm), colors (linear RGB).
export function decodeStrands(buffer) {
  const magic = new TextDecoder().decode(new Uint8Array(buffer, 0, 8));
  if (magic !== "WISPHAIR") throw new Error("not a strand buffer");
  const header = new Uint32Array(buffer, 8, 4);
  const [, strands, points, total] = header;
  let at = 24;
  const offsets = new Uint32Array(buffer, at, strands + 1);
  at += 4 * (strands + 1);
  const positions = new Float32Array(buffer, at, 3 * points);
  at += 12 * points;
  const colors = new Float32Array(buffer, at, 3 * strands);
  return { strands, points, total, offsets, positions, colors };
}

// "WISPHEAD": positions (cm), the renderer's skin normals, triangles, a scalp flag per face.
export function decodeHead(buffer) {
  const header = new Uint32Array(buffer, 8, 3);
  const [, vertices, faces] = header;
  let at = 20;
  const positions = new Float32Array(buffer.slice(at, at + 12 * vertices));
  at += 12 * vertices;
  const normals = new Float32Array(buffer.slice(at, at + 12 * vertices));
  at += 12 * vertices;
  const triangles = new Uint32Array(buffer.slice(at, at + 12 * faces));
  at += 12 * faces;
  const scalp = new Uint8Array(buffer, at, faces);
  return { positions, normals, triangles, scalp };
}

// POST a binary body (a map's PNG); resolves to { ok, status, body } as postJson does.
export async function postBinary(path, bytes, type) {
  const response = await fetch(path, {
    method: "POST",
    headers: { "X-Wisp-Token": token, "Content-Type": type },
    body: bytes,
  });
  return { ok: response.ok, status: response.status, body: await response.json() };
}

// "WISPMAP\0": a scalp map as the painter edits it, t in [0, 1] per pixel (row 0 the top).
export function decodeMap(buffer) {
  const magic = new TextDecoder().decode(new Uint8Array(buffer, 0, 7));
  if (magic !== "WISPMAP") throw new Error("not a map buffer");
  const [, width, height, kind] = new Uint32Array(buffer, 8, 4);
  const [low, high] = new Float32Array(buffer, 24, 2);
  const bytes = new Uint8Array(buffer, 32, width * height);
  const values = new Float32Array(width * height);
  for (let i = 0; i < values.length; ++i) values[i] = bytes[i] / 255;
  return { width, height, kind, low, high, values };
}

// An 8-bit grayscale PNG of `gray` (#width·height, top row first): filter 0 on every row,
// zlib through the browser's CompressionStream.
const crcTable = Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});
function crc32(bytes) {
  let c = 0xffffffff;
  for (const b of bytes) c = crcTable[(c ^ b) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}
function chunk(type, data) {
  const out = new Uint8Array(12 + data.length);
  const view = new DataView(out.buffer);
  view.setUint32(0, data.length);
  out.set(new TextEncoder().encode(type), 4);
  out.set(data, 8);
  view.setUint32(8 + data.length, crc32(out.subarray(4, 8 + data.length)));
  return out;
}
export async function encodeGrayPng(gray, width, height) {
  const raw = new Uint8Array((width + 1) * height);
  for (let j = 0; j < height; ++j) raw.set(gray.subarray(j * width, (j + 1) * width), j * (width + 1) + 1);
  const zlib = new Uint8Array(await new Response(
    new Blob([raw]).stream().pipeThrough(new CompressionStream("deflate"))).arrayBuffer());
  const header = new Uint8Array(13);
  const view = new DataView(header.buffer);
  view.setUint32(0, width);
  view.setUint32(4, height);
  header.set([8, 0, 0, 0, 0], 8);  // 8 bits, grayscale, deflate, filter 0, no interlace
  return new Blob([new Uint8Array([137, 80, 78, 71, 13, 10, 26, 10]), chunk("IHDR", header),
    chunk("IDAT", zlib), chunk("IEND", new Uint8Array(0))]);
}
