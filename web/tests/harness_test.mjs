// Test of the browser tests' harness (registered in ctest as editor_harness_cleans_up): a test
// run with withEditor that fails a check (fail() throws) still closes its browser and stops
// its server, keeps its folder to look into and marks the run failed; one that passes
// leaves no server, no browser and no folder behind.
//   node web/tests/harness_test.mjs WISP_EXE OUT_DIR
import { failWith, testArguments, withEditor } from "./harness.mjs";
import { existsSync, rmSync } from "node:fs";

const { wisp } = testArguments();
const fail = failWith("harness test");
const files = { "style.toml": "[roots]\nstrands = 500\nwisps = 50\npoints_per_strand = 8\n" };
const stopped = (server) => server.exitCode !== null || server.signalCode !== null;

// A failed check inside the test.
let seen = null, thrown = null;
try {
  await withEditor(wisp, { prefix: "harness-fail", files }, async ({ page, folder, server, browser }) => {
    seen = { folder, server, browser, drawn: await page.evaluate(() => document.body.dataset.ready) };
    failWith("harness test (a failure it expects)")("a failed check");
  });
} catch (e) {
  thrown = e;
}
const failed = process.exitCode;
process.exitCode = 0;
if (!seen || seen.drawn !== "1") fail("the test did not run on a page that had drawn its hair");
if (thrown?.message !== "a failed check") fail(`the failed check was not thrown on: ${thrown}`);
if (failed !== 1) fail(`the failed check left the exit code ${failed}`);
if (!stopped(seen.server)) fail("the server still runs after a failed check");
if (seen.browser.isConnected()) fail("the browser is still open after a failed check");
if (!existsSync(seen.folder)) fail("the failed test's folder was removed");
rmSync(seen.folder, { recursive: true, force: true });
console.log(`a failed check: thrown on, exit code 1, server stopped (${seen.server.signalCode ?? seen.server.exitCode}), ` +
  "browser closed, folder kept");

// A test that passes.
const result = await withEditor(wisp, { prefix: "harness-pass", files }, async ({ folder, server, browser }) => {
  seen = { folder, server, browser };
  return "done";
});
if (result !== "done") fail(`withEditor resolved to ${result}, not the test's result`);
if (!stopped(seen.server) || seen.browser.isConnected()) fail("a passing test left the server or the browser running");
if (existsSync(seen.folder)) fail("a passing test left its folder");
if (process.exitCode) fail(`a passing test left the exit code ${process.exitCode}`);
console.log("a passing test: its result, server stopped, browser closed, folder removed");
