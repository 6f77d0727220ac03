// Browser test of `wisp edit` (registered in ctest as editor.*): starts the server on a
// small style, loads the page in Debian's Chromium (headless, software GL) with
// playwright-core, and checks that hair is drawn, that a slider changes the geometry and
// that undo restores it. Screenshots go to $WISP_EDITOR_SHOTS (default: the build folder).
//   node web/tests/editor_test.mjs WISP_EXE OUT_DIR
import { failWith, launchChromium, openEditor, startEditor, styleSetter, tempFolder, testArguments } from "./harness.mjs";
import { rmSync } from "node:fs";
import path from "node:path";

const { wisp, outDir } = testArguments();
const fail = failWith("editor test");

// In a folder of its own: the editor autosaves into the style's folder (the current one).
const folder = tempFolder("editor");
const { server, url, token } = await startEditor(wisp, ["--preset", "short"], folder);

let browser;
try {
  browser = await launchChromium();
  const page = await openEditor(browser, url);
  // A few thousand strands keep software GL quick.
  await page.waitForSelector("[data-path='roots.strands']");
  const set = styleSetter(page, token);
  if (await set("roots.strands", 3000) !== 200) fail("could not set roots.strands");
  await set("roots.wisps", 150);
  await page.reload();
  await page.waitForSelector("body[data-ready='1']", { timeout: 120000 });

  // Pixel coverage: the fraction of the view that is not background.
  const coverage = () => page.evaluate(() => {
    const canvas = document.querySelector("#view canvas");
    const gl = canvas.getContext("webgl2");
    const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const pixels = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
    let hit = 0, sum = 0;
    for (let i = 0; i < pixels.length; i += 4) {
      const d = Math.abs(pixels[i] - 0x24) + Math.abs(pixels[i + 1] - 0x26) + Math.abs(pixels[i + 2] - 0x2b);
      if (d > 30) { ++hit; sum += pixels[i] * 3 + pixels[i + 1] * 7 + pixels[i + 2] * 11 + (i % 9973); }
    }
    return { fraction: hit / (w * h), signature: sum };
  });
  await page.evaluate(() => document.getElementById("show-head").click());  // hair alone
  const hair = await coverage();
  console.log(`hair coverage ${(100 * hair.fraction).toFixed(1)}%`);
  if (hair.fraction < 0.02) fail(`the hair covers only ${(100 * hair.fraction).toFixed(2)}% of the view`);
  await page.evaluate(() => document.getElementById("show-head").click());
  await page.screenshot({ path: path.join(outDir, "editor.png") });

  // A slider: κ of eq. (5). Moving it changes the drawn hair; undo restores it.
  const before = await coverage();
  const slider = page.locator("input[type=range][data-path='solve.stiffness']");
  // While it moves, the coarse masters come first, then the strands.
  const moving = await page.evaluate(() => window.wispEditor.viewport.stats());
  await slider.evaluate((e) => { e.value = 3; e.dispatchEvent(new Event("input")); });
  await page.waitForFunction((n) => window.wispEditor.viewport.stats().mastersDrawn > n, moving.mastersDrawn, { timeout: 60000 });
  await page.waitForFunction((n) => {
    const s = window.wispEditor.viewport.stats();
    return s.updates > n + 1 && !s.masters;
  }, moving.updates, { timeout: 60000 });
  console.log(`while κ moves: masters, then ${(await page.evaluate(() => window.wispEditor.viewport.stats())).strands} strands`);
  await slider.evaluate((e) => { e.value = 6; e.dispatchEvent(new Event("input")); e.dispatchEvent(new Event("change")); });
  await page.waitForFunction(() => document.getElementById("hud").textContent.includes("strands"));
  await page.waitForTimeout(3000);
  const after = await coverage();
  console.log(`stiffness 6: coverage ${(100 * after.fraction).toFixed(1)}% (was ${(100 * before.fraction).toFixed(1)}%)`);
  if (after.signature === before.signature) fail("moving solve.stiffness did not change the picture");
  await page.screenshot({ path: path.join(outDir, "editor-stiff.png") });
  await page.keyboard.press("Control+z");
  await page.waitForTimeout(3000);
  const undone = await coverage();
  if (undone.signature !== before.signature) fail("undo did not restore the picture");
  const value = await page.locator("input[type=range][data-path='solve.stiffness']").inputValue();
  console.log(`undo: stiffness back to ${value}`);

  // A bad value shows the reader's message beside its control.
  // The number box beside the slider takes what the slider's range would clamp.
  await page.locator("input[type=range][data-path='roots.points_per_strand'] + input.number").evaluate((e) => {
    e.value = 2;
    e.dispatchEvent(new Event("change"));
  });
  await page.waitForTimeout(1000);
  const messages = await page.locator(".field.invalid .message").allTextContents();
  console.log(`bad value: ${messages.join(" | ")}`);
  if (!messages.some((m) => m.includes("must be ≥ 4"))) fail("a bad value showed no message");
} finally {
  if (browser) await browser.close();
  server.kill("SIGINT");
  rmSync(folder, { recursive: true, force: true });
}
