// Browser test of the updo's facing arrow (registered in ctest as
// editor_updo_arrow_readable_from_any_side): a 3,000-strand style with an [[updo]] on the
// upper back of the head, its arrow seen from three sides.
//   - Pointing at the camera (the camera on the arrow's line, in front of its tip) the
//     arrow shows ⊙: the sign fully shown, 32 px across whatever the distance, and on the
//     canvas a ring in the arrow's colour 11 px round the tip, with a dark outline outside
//     it, in each of four directions; ⊗ hidden.
//   - Pointing away (the camera on its line behind the bun) it shows ⊗, not ⊙.
//   - Seen across, neither sign: the arrow is a cone 22 px long on the screen at 60 cm and
//     at 140 cm (sized in pixels, not cm).
// Screenshots go to OUT_DIR.
//   node web/tests/arrow_test.mjs WISP_EXE OUT_DIR
import { failWith, testArguments, toScreen, withEditor } from "./harness.mjs";
import path from "node:path";

const { wisp, outDir } = testArguments();
const fail = failWith("updo arrow test");
const style = `[roots]
strands = 3000
wisps = 150
points_per_strand = 24

[maps]
length = { procedural = "front", low = 34, high = 44 }

[growth]
part = "none"
front = "back"

[[updo]]
point = [0, 0.55, -1.05]
facing = [0, 0.3, -1]
`;

await withEditor(wisp, { prefix: "arrow", files: { "style.toml": style } }, async ({ page, settle }) => {
  await settle();
  await page.click("#tie");
  // The arrow's head (the facing handle): where it is, the way it points, its colour.
  const arrow = await page.evaluate(() => {
    const { constraints } = window.wispEditor;
    const head = constraints.handles.children.find((h) => h.userData.role === "facing");
    const centre = constraints.handles.children.find((h) => h.userData.role === "point");
    if (!head || !centre) return null;
    const d = head.position.clone().sub(centre.position).normalize();
    return { tip: head.position.toArray(), d: d.toArray(), color: [head.material].flat()[0].color.getHexString() };
  });
  if (!arrow) fail("the updo has no facing arrow");
  // The camera at `at` (cm) looking at the tip, drawn at once; then what the page shows
  // of the arrow: each sign's opacity and size (px), the cone's length on the screen (px).
  const view = async (at) => {
    await page.evaluate(([at, tip]) => {
      const { viewport } = window.wispEditor;
      viewport.camera.position.set(...at);
      viewport.controls.target.set(...tip);
      viewport.controls.update();
      viewport.renderNow();
    }, [at, arrow.tip]);
    return page.evaluate(() => {
      const { viewport, constraints } = window.wispEditor;
      const { camera, renderer } = viewport;
      const rect = renderer.domElement.getBoundingClientRect();
      const toPx = (p) => {
        const v = p.clone().project(camera);
        return [((v.x + 1) / 2) * rect.width, ((1 - v.y) / 2) * rect.height];
      };
      const out = {};
      for (const h of constraints.handles.children) {
        if (h.userData.sign) {
          const right = new camera.position.constructor().setFromMatrixColumn(camera.matrixWorld, 0);
          const [a, b] = [toPx(h.position), toPx(h.position.clone().addScaledVector(right, h.scale.x))];
          out[h.userData.sign] = { opacity: h.material.opacity, px: Math.hypot(a[0] - b[0], a[1] - b[1]) };
        }
        if (h.userData.role === "facing") {
          const axis = new camera.position.constructor(0, 1, 0).applyQuaternion(h.quaternion).multiplyScalar(h.scale.y / 2);
          const [a, b] = [toPx(h.position.clone().add(axis)), toPx(h.position.clone().sub(axis))];
          out.cone = Math.hypot(a[0] - b[0], a[1] - b[1]);
        }
      }
      return out;
    });
  };
  const along = (k) => arrow.tip.map((v, i) => v + k * arrow.d[i]);
  const near = (a, b, tolerance) => Math.abs(a - b) <= tolerance;

  // Pointing at the camera: ⊙, 32 px at 50 cm and at 120 cm; its ring on the canvas.
  for (const distance of [50, 120]) {
    const seen = await view(along(distance));
    console.log(`pointing at the camera from ${distance} cm: ${JSON.stringify(seen)}`);
    if (!(seen.toward?.opacity > 0.99) || !near(seen.toward.px, 32, 1) || seen.away?.opacity !== 0)
      fail(`the arrow pointing at the camera does not show ⊙ at 32 px: ${JSON.stringify(seen)}`);
  }
  await page.screenshot({ path: path.join(outDir, "arrow-toward.png") });
  const [x, y] = await toScreen(page, arrow.tip);
  const ring = await page.evaluate(([x, y]) => {
    const canvas = window.wispEditor.viewport.renderer.domElement;
    const copy = document.createElement("canvas");
    [copy.width, copy.height] = [canvas.width, canvas.height];
    const g = copy.getContext("2d");
    g.drawImage(canvas, 0, 0);
    const rect = canvas.getBoundingClientRect();
    const scale = canvas.width / rect.width;
    const at = (dx, dy) => Array.from(g.getImageData(Math.round((x - rect.left + dx) * scale), Math.round((y - rect.top + dy) * scale), 1, 1).data.slice(0, 3));
    return [[0, -1], [1, 0], [0, 1], [-1, 0]].map(([u, v]) => ({ ring: at(10.9 * u, 10.9 * v), outside: at(13.6 * u, 13.6 * v) }));
  }, [x, y]);
  const want = [0, 2, 4].map((k) => parseInt(arrow.color.slice(k, k + 2), 16));
  console.log(`the ring 11 px round the tip (${x.toFixed(1)}, ${y.toFixed(1)}): ${JSON.stringify(ring)} (the arrow's colour ${want})`);
  for (const { ring: c, outside } of ring) {
    if (Math.max(...c.map((v, k) => Math.abs(v - want[k]))) > 48) fail(`no ring of the arrow's colour round the tip: ${JSON.stringify(ring)}`);
    if (Math.max(...outside) > 100) fail(`the ring has no dark outline: ${JSON.stringify(ring)}`);
  }

  // Pointing away: ⊗.
  const away = await view(along(-90));
  console.log(`pointing away: ${JSON.stringify(away)}`);
  if (!(away.away?.opacity > 0.99) || away.toward?.opacity !== 0) fail(`the arrow pointing away does not show ⊗: ${JSON.stringify(away)}`);
  await page.screenshot({ path: path.join(outDir, "arrow-away.png") });

  // Across: no sign; the cone as long on the screen near and far.
  const across = arrow.d[1] > 0.9 ? [1, 0, 0] : [arrow.d[2], 0, -arrow.d[0]].map((v) => v / Math.hypot(arrow.d[0], arrow.d[2]));
  for (const distance of [60, 140]) {
    const seen = await view(arrow.tip.map((v, i) => v + distance * across[i]));
    console.log(`across from ${distance} cm: ${JSON.stringify(seen)}`);
    if (seen.toward?.opacity !== 0 || seen.away?.opacity !== 0 || !near(seen.cone, 22, 1))
      fail(`seen across, the arrow is not a 22 px cone without a sign: ${JSON.stringify(seen)}`);
  }
  await page.screenshot({ path: path.join(outDir, "arrow-across.png") });
});
