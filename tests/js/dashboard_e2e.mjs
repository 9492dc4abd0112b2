// The dashboard in a real browser against a running mission (mission_test.cpp runs it while
// sarloc-mission --dashboard runs): headless Debian chromium driven by playwright-core.
//
//   node tests/js/dashboard_e2e.mjs URL OUTDIR KILLED_ID   -> JSON on stdout
//
// It watches without ever reloading: victims and their states as they change, the killed
// responder's link, an alarm acknowledged with a wrong token (refused) and with the right one
// (accepted, then shown acknowledged), whether the header says the DDS data is authenticated,
// the page's Content-Security-Policy, render times and push latency; then a screenshot.
import { reportFromBrowser } from "./browser.mjs";
import path from "node:path";

const [url, outdir, killed] = process.argv.slice(2);
const result = { errors: [], statesSeen: {}, linkLostSeen: false, ackRefusedStatus: null, ackAccepted: false, victimCount: 0 };
await reportFromBrowser({ width: 1400, height: 900 }, result, async (context) => {
  const page = await context.newPage();
  page.on("console", (m) => { if (m.type() === "error") result.errors.push(`console: ${m.text()}`); });
  page.on("pageerror", (e) => result.errors.push(`page: ${e.message}`));
  page.on("request", (r) => { if (!r.url().startsWith(new URL(url).origin) && !r.url().startsWith("data:")) result.errors.push(`external request: ${r.url()}`); });
  const response = await page.goto(url, { waitUntil: "load" });
  result.csp = response.headers()["content-security-policy"] ?? null;
  await page.waitForFunction(() => document.getElementById("status").textContent === "live", null, { timeout: 15000 });
  result.addressBar = page.url();  // the token opened a session and left it
  await page.waitForFunction(() => document.getElementById("dds").textContent !== "DDS: ?", null, { timeout: 15000 });
  result.ddsTrust = await page.evaluate(() => ({ text: document.getElementById("dds").textContent, className: document.getElementById("dds").className }));
  const deadline = Date.now() + 60000;
  let alarmId = null;
  while (Date.now() < deadline) {
    const seen = await page.evaluate(() => [...document.querySelectorAll("#victims tbody tr")].map((tr) => [tr.dataset.victim, tr.querySelector(".state").textContent]));
    for (const [id, state] of seen) {
      const list = (result.statesSeen[id] ??= []);
      if (list[list.length - 1] !== state) list.push(state);
    }
    result.victimCount = seen.length;
    const link = await page.locator(`tr[data-member="${killed}"] .link`).textContent().catch(() => null);
    if (link === "lost") result.linkLostSeen = true;
    if (alarmId === null) {
      alarmId = await page.evaluate((who) => {
        for (const li of document.querySelectorAll("#alarms li")) if (li.textContent.includes(`Link lost ${who}`)) return li.dataset.alarm;
        return null;
      }, killed);
      if (alarmId !== null) {
        // From outside the page: a refused request in the page would log a console error.
        const refused = await fetch(`${new URL(url).origin}/api/alarms/${alarmId}/ack`, { method: "POST", headers: { Authorization: "Bearer not-the-token" } });
        result.ackRefusedStatus = refused.status;
        await page.locator(`button.ack[data-alarm="${alarmId}"]`).click();
      }
    } else if (!result.ackAccepted) {
      result.ackAccepted = await page.evaluate((id) => {
        const li = document.querySelector(`#alarms li[data-alarm="${id}"]`);
        return li !== null && li.textContent.includes("acknowledged by dashboard");
      }, alarmId);
    }
    const everyFound = Object.values(result.statesSeen).length >= 2 && Object.values(result.statesSeen).every((s) => s[s.length - 1] === "FOUND");
    if (everyFound && result.linkLostSeen && result.ackAccepted) break;
    await page.waitForTimeout(200);
  }
  const timing = await page.evaluate(() => ({ frames: window.sarlocFrameTimes.slice(), latencies: window.sarlocLatencies.slice() }));
  const percentile = (values, p) => { const v = [...values].sort((a, b) => a - b); return v.length ? v[Math.min(v.length - 1, Math.floor(p * v.length))] : null; };
  result.frameMs = { count: timing.frames.length, median: percentile(timing.frames, 0.5), p95: percentile(timing.frames, 0.95) };
  result.pushLatencyMs = { count: timing.latencies.length, p50: percentile(timing.latencies, 0.5), p99: percentile(timing.latencies, 0.99) };
  // Map labels stay legible at the fitted zoom (a CSS rule once overrode their per-zoom size
  // and drew them 50 px high).
  result.labelHeightsPx = await page.evaluate(() => [...document.querySelectorAll("#map text")].map((t) => t.getBoundingClientRect().height));
  // A screen read at a glance: no two map labels overlap; tables have headers; a FOUND victim
  // says when; the header names the incident and the time; a legend explains the symbols.
  result.glance = await page.evaluate(() => {
    const boxes = [...document.querySelectorAll("#map text")].map((t) => ({ text: t.textContent, r: t.getBoundingClientRect() }));
    const overlaps = [];
    for (let i = 0; i < boxes.length; ++i) for (let j = i + 1; j < boxes.length; ++j) {
      const a = boxes[i].r, b = boxes[j].r;
      const w = Math.min(a.right, b.right) - Math.max(a.left, b.left), h = Math.min(a.bottom, b.bottom) - Math.max(a.top, b.top);
      if (w > 1 && h > 1) overlaps.push(`${boxes[i].text} / ${boxes[j].text}`);
    }
    return {
      labelOverlaps: overlaps,
      teamHeaders: [...document.querySelectorAll("#teams table")].map((t) => t.querySelectorAll("th").length),
      positionCells: Object.fromEntries([...document.querySelectorAll("#teams tr[data-member]")].map((tr) => [tr.dataset.member, tr.querySelector("td.position").textContent])),
      foundCells: [...document.querySelectorAll("#victims tbody tr")].filter((tr) => tr.querySelector(".state").textContent === "FOUND").map((tr) => tr.querySelector(".found").textContent),
      incident: document.getElementById("incident").textContent,
      wall: document.getElementById("wall").textContent,
      legendItems: document.querySelectorAll("#legend span").length,
      areas: document.getElementById("area").options.length,
    };
  });
  result.screenshot = path.join(outdir, "dashboard.png");
  await page.screenshot({ path: result.screenshot });
});
