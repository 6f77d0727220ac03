// What the editor's browser tests (and shots.mjs) share: their arguments (WISP_EXE OUT_DIR),
// a failure that names the test, a temporary folder of their own (the editor autosaves into
// the style's folder), `wisp edit` started there with its URL and token, Debian's Chromium
// launched headless on software GL (SwiftShader), and a page opened on the editor; or all of
// that at once, cleaned up however the test ends (withEditor).
import { chromium } from "playwright-core";
import { execFileSync, spawn } from "node:child_process";
import { mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";

// { wisp, outDir } from `node TEST.mjs WISP_EXE OUT_DIR`; OUT_DIR (the screenshots) is made.
export function testArguments() {
  const [wispArg, outDir = "."] = process.argv.slice(2);
  if (!wispArg) throw new Error("usage: node TEST.mjs WISP_EXE [OUT_DIR]");
  mkdirSync(outDir, { recursive: true });
  return { wisp: path.resolve(wispArg), outDir };
}

// fail(message): says "NAME: message" on stderr, marks the run failed and throws.
export function failWith(name) {
  return (message) => {
    console.error(`${name}: ${message}`);
    process.exitCode = 1;
    throw new Error(message);
  };
}

// presets/NAME.toml with few strands for software GL (150 wisps, 3,000 strands of 32
// points), the rest as written; throws if it has no [roots] counts to shrink.
export function smallPreset(name) {
  const file = path.join(path.dirname(fileURLToPath(import.meta.url)), "../../presets", `${name}.toml`);
  const preset = readFileSync(file, "utf8");
  const small = preset.replace(/^wisps = \d+/m, "wisps = 150").replace(/^strands = \d+/m, "strands = 3000")
    .replace(/^points_per_strand = \d+/m, "points_per_strand = 32");
  if (small === preset) throw new Error(`${file}: no [roots] to shrink`);
  return small;
}

// A new folder under the system's temporary one, with `files` ({ name: text }) written in it.
export function tempFolder(prefix, files = {}) {
  const folder = mkdtempSync(path.join(os.tmpdir(), `wisp-${prefix}-`));
  for (const [name, text] of Object.entries(files)) writeFileSync(path.join(folder, name), text);
  return folder;
}

// `wisp edit ARGS` in `folder`; resolves to { server, url, token } once it prints its URL.
export async function startEditor(wisp, args, folder, { timeoutMs = 30000 } = {}) {
  const server = spawn(wisp, ["edit", ...args], { cwd: folder, stdio: ["ignore", "pipe", "inherit"] });
  const url = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`wisp edit printed no URL within ${timeoutMs / 1000} s`)), timeoutMs);
    let out = "";
    server.stdout.on("data", (d) => {
      out += d;
      const m = out.match(/http:\/\/\S+/);
      if (m) {
        clearTimeout(timer);
        resolve(m[0]);
      }
    });
    server.on("exit", (code) => {
      clearTimeout(timer);
      reject(new Error(`wisp edit exited with ${code}`));
    });
  });
  return { server, url, token: new URL(url).searchParams.get("token") };
}

// Chromium ($WISP_CHROMIUM, else Debian's), headless, on software GL.
export function launchChromium() {
  return chromium.launch({
    executablePath: process.env.WISP_CHROMIUM ?? "/usr/bin/chromium",
    args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
      "--use-gl=swiftshader", "--enable-unsafe-swiftshader", "--disable-dev-shm-usage"],
  });
}

// A page of `viewport` size on the editor at `url`, its script errors reported.
export async function openEditor(browser, url, viewport = { width: 900, height: 600 }) {
  const page = await browser.newPage({ viewport });
  page.on("pageerror", (e) => console.error("page error:", e.message));
  await page.goto(url);
  return page;
}

// Runs `test({ page, token, folder, settle, server, browser })` on the editor: `wisp edit ARGS` started in a
// new temporary folder (`prefix`, with `files` written in it), Chromium launched, a page of
// `viewport` size opened on it and waited for until it has drawn its first hair; `settle`
// is settler(page, token). However the test ends — done, a failed check, any other error —
// the browser is closed and the server stopped (SIGINT, then SIGKILL if it has not exited
// within 10 s); the folder is removed unless the run failed (it is kept to look into). An
// error marks the run failed and is thrown on. Resolves to what `test` resolves to.
export async function withEditor(wisp, { prefix, files = {}, args = ["style.toml"],
  viewport = { width: 1000, height: 640 }, readyMs = 120000 }, test) {
  const folder = tempFolder(prefix, files);
  let editor = null, browser = null;
  try {
    editor = await startEditor(wisp, args, folder);
    browser = await launchChromium();
    const page = await openEditor(browser, editor.url, viewport);
    await page.waitForSelector("body[data-ready='1']", { timeout: readyMs });
    return await test({ page, token: editor.token, folder, settle: settler(page, editor.token), server: editor.server, browser });
  } catch (e) {
    process.exitCode = 1;
    throw e;
  } finally {
    if (browser) await browser.close().catch((e) => console.error("closing the browser:", e.message));
    if (editor) await stopServer(editor.server);
    if (!process.exitCode) rmSync(folder, { recursive: true, force: true });
  }
}

// Stops `wisp edit` as Ctrl-C does, and for good if it has not exited within `graceMs`.
function stopServer(server, graceMs = 10000) {
  if (server.exitCode !== null || server.signalCode !== null) return Promise.resolve();
  return new Promise((resolve) => {
    const timer = setTimeout(() => server.kill("SIGKILL"), graceMs);
    server.once("exit", () => {
      clearTimeout(timer);
      resolve();
    });
    server.kill("SIGINT");
  });
}

// set(path, value): POST /api/set from the page, as the panels do; resolves to the status.
export function styleSetter(page, token) {
  return (p, v) => page.evaluate(async ([p, v, token]) => {
    const r = await fetch("/api/set", {
      method: "POST",
      headers: { "X-Wisp-Token": token, "Content-Type": "application/json" },
      body: JSON.stringify({ path: p, value: v }),
    });
    return r.status;
  }, [p, v, token]);
}

// settle(): waits until the server has nothing stale (GET /api/stats from the page), then
// `drawMs` for the page to draw what it fetched.
export function settler(page, token, { timeoutMs = 120000, polling = 300, drawMs = 1500 } = {}) {
  return async () => {
    await page.waitForFunction(async (token) => {
      const r = await fetch("/api/stats", { headers: { "X-Wisp-Token": token } });
      return (await r.json()).stale === "none";
    }, token, { timeout: timeoutMs, polling });
    if (drawMs > 0) await page.waitForTimeout(drawMs);
  };
}

// The camera behind the head at `offset` (cm from its centre, looking at a point 6 cm below
// it), drawn at once: the view draws on the next animation frame, and the camera's matrices,
// which onScreen() projects with, are brought up to date by drawing.
export function viewFromBehind(page, offset) {
  return page.evaluate(([dx, dy, dz]) => {
    const { viewport, constraints } = window.wispEditor;
    const c = constraints.center;
    viewport.camera.position.set(c.x + dx, c.y + dy, c.z + dz);
    viewport.controls.target.set(c.x, c.y - 6, c.z);
    viewport.controls.update();
    viewport.renderNow();
  }, offset);
}

// Where points given in head radii from the head's centre ([x, y, z]) are on the page, as the
// pointer sees them ([clientX, clientY] each).
export function onScreen(page, points) {
  return page.evaluate((points) => {
    const { viewport, constraints } = window.wispEditor;
    const rect = viewport.renderer.domElement.getBoundingClientRect();
    const c = constraints.center, r = constraints.radius;
    viewport.camera.updateMatrixWorld();
    return points.map(([x, y, z]) => {
      const p = c.clone().set(c.x + x * r, c.y + y * r, c.z + z * r).project(viewport.camera);
      return [rect.left + ((p.x + 1) / 2) * rect.width, rect.top + ((1 - p.y) / 2) * rect.height];
    });
  }, points);
}

// Where a point given in cm ([x, y, z]) is on the page, as the pointer sees it ([clientX,
// clientY]).
export function toScreen(page, p) {
  return page.evaluate((p) => {
    const { viewport } = window.wispEditor;
    const rect = viewport.renderer.domElement.getBoundingClientRect();
    viewport.camera.updateMatrixWorld();
    const v = viewport.camera.position.clone().set(...p).project(viewport.camera);
    return [rect.left + ((v.x + 1) / 2) * rect.width, rect.top + ((1 - v.y) / 2) * rect.height];
  }, p);
}

// The constraints as the page holds them: the sections, the paths drawn (cm) and where the
// braid and updo handles are ({ role: [x, y, z] cm }: start, end, point, facing).
export function pageConstraints(page) {
  return page.evaluate(() => {
    const { constraints } = window.wispEditor;
    return {
      sections: constraints.sections, paths: constraints.paths,
      handles: Object.fromEntries(constraints.handles.children.filter((h) => h.userData.role)
        .map((h) => [h.userData.role, h.position.toArray()])),
    };
  });
}

// f({ strands, offsets, x, groups, center, radius }, arg) run in the page on the full hair
// (GET /api/hair and /api/attributes): x the points (cm), offsets each strand's first point,
// groups each strand's group (0: none), center and radius the head's (head units to cm).
// `f` is sent as its source: it may use only its arguments.
export function measureHair(page, token, f, arg) {
  return page.evaluate(async ([source, arg, token]) => {
    const headers = { "X-Wisp-Token": token };
    const hair = await (await fetch("/api/hair", { headers })).arrayBuffer();
    const attributes = await (await fetch("/api/attributes", { headers })).arrayBuffer();
    const [, strands] = new Uint32Array(hair, 8, 4);
    const offsets = new Uint32Array(hair, 24, strands + 1);
    const x = new Float32Array(hair, 24 + 4 * (strands + 1), 3 * offsets[strands]);
    const groups = new Int32Array(attributes, 16 + 4 * strands, strands);
    const { center, radius } = window.wispEditor.constraints;
    return (0, eval)(source)({ strands, offsets, x, groups, center: center.toArray(), radius }, arg);
  }, [f.toString(), arg, token]);
}

// The editor's hair exported (POST /api/export, editor.hair) and `wisp generate` of the
// style.toml Save wrote, both in `folder`, for a test to compare byte for byte: { editor,
// cli } (Buffers). Throws if the export is refused.
export async function exportAndGenerate(page, token, wisp, folder) {
  const status = await page.evaluate(async (token) => (await fetch("/api/export", {
    method: "POST", headers: { "X-Wisp-Token": token, "Content-Type": "application/json" },
    body: JSON.stringify({ name: "editor.hair" }),
  })).status, token);
  if (status !== 200) throw new Error(`export answered ${status}`);
  execFileSync(wisp, ["generate", "style.toml", "-o", "cli.hair", "--quiet"], { cwd: folder, stdio: "inherit" });
  return { editor: readFileSync(path.join(folder, "editor.hair")), cli: readFileSync(path.join(folder, "cli.hair")) };
}

// A mouse drag through `points` (client coordinates), `steps` moves between each two.
export async function dragThrough(page, points, steps = 6) {
  await page.mouse.move(...points[0]);
  await page.mouse.down();
  for (let k = 1; k < points.length; ++k)
    for (let i = 1; i <= steps; ++i)
      await page.mouse.move(points[k - 1][0] + ((points[k][0] - points[k - 1][0]) * i) / steps,
        points[k - 1][1] + ((points[k][1] - points[k - 1][1]) * i) / steps);
  await page.mouse.up();
}
