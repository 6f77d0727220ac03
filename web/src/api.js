// The server's API (src/edit/server.hpp): JSON requests carrying the launch token, and the
// binary strand and head arrays (src/edit/wire.hpp), all little-endian.
const token = new URLSearchParams(location.search).get("token") ?? "";

async function request(method, path, body) {
  const response = await fetch(path, {
    method,
    headers: { "X-Wisp-Token": token, ...(body ? { "Content-Type": "application/json" } : {}) },
    body: body ? JSON.stringify(body) : undefined,
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

// "WISPHEAD": positions (cm), triangles, a scalp flag per face.
export function decodeHead(buffer) {
  const header = new Uint32Array(buffer, 8, 3);
  const [, vertices, faces] = header;
  let at = 20;
  const positions = new Float32Array(buffer.slice(at, at + 12 * vertices));
  at += 12 * vertices;
  const triangles = new Uint32Array(buffer.slice(at, at + 12 * faces));
  at += 12 * faces;
  const scalp = new Uint8Array(buffer, at, faces);
  return { positions, triangles, scalp };
}
