// The operator's buttons in a real browser (dashboard_actions_test.cpp serves the page with a
// picture of its own, no DDS): the page opens a session with the token in its address, then
// clicks "dig first" on the second victim of the dig order and "dug out" on a FOUND victim.
//
//   node tests/js/dashboard_actions.mjs URL DIG_FIRST_VICTIM DUG_OUT_VICTIM   -> JSON on stdout
import { reportFromBrowser } from "./browser.mjs";

const [url, digFirst, dugOut] = process.argv.slice(2);
const result = { errors: [], statuses: {} };
await reportFromBrowser({ width: 1400, height: 900 }, result, async (context) => {
  const page = await context.newPage();
  page.on("console", (m) => { if (m.type() === "error") result.errors.push(`console: ${m.text()}`); });
  page.on("pageerror", (e) => result.errors.push(`page: ${e.message}`));
  page.on("response", (r) => {
    const path = new URL(r.url()).pathname;
    if (path.startsWith("/api/victims/")) result.statuses[path] = r.status();
  });
  await page.goto(url, { waitUntil: "load" });
  await page.waitForFunction(() => document.getElementById("status").textContent === "live", null, { timeout: 15000 });
  const first = page.locator(`button.dig-first[data-victim="${digFirst}"]`);
  await first.waitFor({ timeout: 10000 });
  await Promise.all([page.waitForResponse((r) => r.url().endsWith(`/api/victims/${digFirst}/dig-first`)), first.click()]);
  const dug = page.locator(`button.dug-out[data-victim="${dugOut}"]`);
  await dug.waitFor({ timeout: 10000 });
  await Promise.all([page.waitForResponse((r) => r.url().endsWith(`/api/victims/${dugOut}/dug-out`)), dug.click()]);
});
