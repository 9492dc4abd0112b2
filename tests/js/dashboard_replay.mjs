// The dashboard's debrief view in a real browser: sarloc-dashboard --recording REC.mcap.
//
//   node tests/js/dashboard_replay.mjs URL OUTDIR   -> JSON on stdout
//
// It scrubs the timeline to the end and back to the start with the slider, then plays: the
// victims shown follow the cursor, without a reload; then a screenshot.
import { reportFromBrowser } from "./browser.mjs";
import path from "node:path";

const [url, outdir] = process.argv.slice(2);
const result = { errors: [] };
await reportFromBrowser({ width: 1400, height: 900 }, result, async (context) => {
  const page = await context.newPage();
  page.on("console", (m) => { if (m.type() === "error") result.errors.push(`console: ${m.text()}`); });
  page.on("pageerror", (e) => result.errors.push(`page: ${e.message}`));
  await page.goto(url, { waitUntil: "load" });
  await page.waitForSelector("#replay:not([hidden])", { timeout: 10000 });
  const victims = () => page.evaluate(() => [...document.querySelectorAll("#victims tbody tr .state")].map((td) => td.textContent));
  const scrub = async (where) => {
    await page.evaluate((w) => {
      const slider = document.getElementById("scrub");
      slider.value = w === "end" ? slider.max : slider.min;
      slider.dispatchEvent(new Event("change"));
    }, where);
    await page.waitForTimeout(1500);  // the server rebuilds, the stream brings the picture
  };
  await scrub("end");
  result.atEnd = await victims();
  // Incident command's search plan over the deposit: its strips drawn, labelled.
  result.stripsAtEnd = await page.evaluate(() => document.querySelectorAll("#map polygon.strip").length);
  result.stripLabels = await page.evaluate(() => [...document.querySelectorAll("#map text")].map((t) => t.textContent).filter((t) => t.startsWith("strip ")));
  // Triage: the FOUND victims in incident command's dig order, and its expected survivors.
  result.digsAtEnd = await page.evaluate(() => [...document.querySelectorAll("#digs tbody tr")].map((tr) => tr.dataset.dig));
  result.digSurvivors = await page.textContent("#dig-survivors");
  await page.screenshot({ path: path.join(outdir, "dashboard-replay-end.png") });
  await scrub("start");
  result.atStart = await victims();
  const before = Number(await page.inputValue("#scrub"));
  await page.selectOption("#rate", "16");
  await page.click("#play");
  await page.waitForTimeout(2500);
  result.advancedS = Number(await page.inputValue("#scrub")) - before;
  result.playLabel = await page.textContent("#play");
  await page.screenshot({ path: path.join(outdir, "dashboard-replay.png") });
});
