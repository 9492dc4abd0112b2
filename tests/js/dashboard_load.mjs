// The dashboard's page under load (sarloc-bench-dashboard): frame (render) times, push delay,
// and how old responders' samples are when the browser has them, over SECONDS.
//
//   node tests/js/dashboard_load.mjs URL SECONDS -> JSON
import { launchChromium } from "./browser.mjs";

const [url, seconds = "30"] = process.argv.slice(2);
const result = { errors: [] };
const browser = await launchChromium({ width: 1400, height: 900 });
try {
  const page = await browser.context.newPage();
  page.on("console", (m) => { if (m.type() === "error") result.errors.push(`console: ${m.text()}`); });
  page.on("pageerror", (e) => result.errors.push(`page: ${e.message}`));
  await page.goto(url, { waitUntil: "load" });
  await page.waitForTimeout(5000);  // settle: the first snapshot, the first frames
  await page.evaluate(() => { window.sarlocFrameTimes.length = 0; window.sarlocLatencies.length = 0; window.sarlocSampleAgesMs.length = 0; });
  await page.waitForTimeout(Number(seconds) * 1000);
  const t = await page.evaluate(() => ({ frames: window.sarlocFrameTimes.slice(), push: window.sarlocLatencies.slice(), ages: window.sarlocSampleAgesMs.slice(),
    victims: document.querySelectorAll("#victims tbody tr").length, members: document.querySelectorAll("tr[data-member]").length }));
  const q = (v, p) => { const s = [...v].sort((a, b) => a - b); return s.length ? s[Math.min(s.length - 1, Math.floor(p * s.length))] : null; };
  Object.assign(result, { victims: t.victims, members: t.members,
    frameMs: { n: t.frames.length, median: q(t.frames, 0.5), p95: q(t.frames, 0.95) },
    pushMs: { n: t.push.length, p50: q(t.push, 0.5), p99: q(t.push, 0.99) },
    sampleAgeMs: { n: t.ages.length, p50: q(t.ages, 0.5), p99: q(t.ages, 0.99) } });
} catch (e) {
  result.errors.push(`browser: ${e.message}`);
} finally {
  await browser.close();
}
console.log(JSON.stringify(result));
