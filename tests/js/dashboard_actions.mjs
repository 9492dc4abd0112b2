// The operator's buttons in a real browser (dashboard_actions_test.cpp serves the page with a
// picture of its own, no DDS): the page opens a session with the token in its address, then
// clicks "dig first" on the second victim of the dig order and "dug out" on a FOUND victim, then
// draws a deposit: four corners clicked on the map around the dug-out victim (top left first,
// clockwise on screen), one drag between them that must add none, and "send deposit"; then
// edits the planned deposit: one corner dragged, "send deposit".
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
    if (path.startsWith("/api/")) result.statuses[path] = r.status();
  });
  await page.goto(url, { waitUntil: "load" });
  await page.waitForFunction(() => document.getElementById("status").textContent === "live", null, { timeout: 15000 });
  const first = page.locator(`button.dig-first[data-victim="${digFirst}"]`);
  await first.waitFor({ timeout: 10000 });
  // One rescuer per signal: the victim row's "sent", and the line for a transmitter not yet placed.
  result.sentTo = await page.locator(`#victims tr[data-victim="${dugOut}"] .pursuer`).textContent();
  result.unplacedPursuits = await page.locator("#unplaced-pursuits").textContent();
  await Promise.all([page.waitForResponse((r) => r.url().endsWith(`/api/victims/${digFirst}/dig-first`)), first.click()]);
  const dug = page.locator(`button.dug-out[data-victim="${dugOut}"]`);
  await dug.waitFor({ timeout: 10000 });
  await Promise.all([page.waitForResponse((r) => r.url().endsWith(`/api/victims/${dugOut}/dug-out`)), dug.click()]);

  await page.locator("#draw").click();
  // Draw mode shown, and a frame drawn since: the map is where the clicks will land.
  await page.locator("#draw-send").waitFor({ state: "visible", timeout: 5000 });
  await page.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
  // The map is redrawn whole each frame: read the victim's ellipse where it is now.
  const [cx, cy] = await page.evaluate((id) => {
    const b = document.querySelector(`#map ellipse[data-victim="${id}"]`).getBoundingClientRect();
    return [b.x + b.width / 2, b.y + b.height / 2];
  }, dugOut);
  const d = 60;
  result.mapTopBefore = await page.evaluate(() => document.getElementById("map").getBoundingClientRect().top);
  const corners = [[cx - d, cy - d], [cx + d, cy - d], [cx + d, cy + d], [cx - d, cy + d]];
  for (const [i, [x, y]] of corners.entries()) {
    await page.mouse.click(x, y);
    if (i === 1) {  // a drag off the corners pans the map, adds no corner; pans back
      const [sx, sy] = [x - 20, y + 20];  // 28 px from the corner: a press on one would move it
      await page.mouse.move(sx, sy);
      await page.mouse.down();
      await page.mouse.move(sx + 40, sy + 40, { steps: 4 });
      await page.mouse.up();
      await page.mouse.move(sx, sy);
      await page.mouse.down();
      await page.mouse.move(sx - 40, sy - 40, { steps: 4 });
      await page.mouse.up();
    }
  }
  // The map is redrawn on the next animation frame: wait for it (a fifth corner would show too).
  await page.waitForFunction(() => document.querySelectorAll("#map circle.drawn-corner").length >= 4, null, { timeout: 5000 })
    .catch(() => {});
  await page.waitForTimeout(200);
  result.drawnCorners = await page.locator("#map circle.drawn-corner").count();
  result.mapTopAfter = await page.evaluate(() => document.getElementById("map").getBoundingClientRect().top);
  // The no-data banner comes and goes with the data: it must not move the map either.
  result.mapTopWithBanner = await page.evaluate(() => {
    const banner = document.getElementById("banner"), was = banner.hidden, top = [];
    for (const hidden of [true, false]) {
      banner.hidden = hidden;
      top.push(document.getElementById("map").getBoundingClientRect().top);
    }
    banner.hidden = was;
    return top;
  });
  await Promise.all([page.waitForResponse((r) => r.url().endsWith("/api/deposit")), page.locator("#draw-send").click()]);
  await page.locator("#draw").waitFor({ state: "visible", timeout: 5000 });  // the page left drawing once sent

  // Editing the deposit incident command plans over (the test's plan: 0,0 80,0 80,100 0,100):
  // the view framed on it, its corners shown, the first dragged 40 px to the right (no corner added, the map not
  // panned), and sent.
  await page.locator("#edit").waitFor({ state: "visible", timeout: 5000 });
  await page.locator("#edit").click();
  await page.waitForFunction(() => document.querySelectorAll("#map circle.drawn-corner").length >= 3, null, { timeout: 5000 });
  result.editCorners = await page.locator("#map circle.drawn-corner").count();
  const [ex, ey] = await page.evaluate(() => {
    const b = document.querySelector("#map circle.drawn-corner").getBoundingClientRect();
    return [b.x + b.width / 2, b.y + b.height / 2];
  });
  result.viewBoxBeforeEdit = await page.evaluate(() => document.getElementById("map").getAttribute("viewBox"));
  await page.mouse.move(ex, ey);
  await page.mouse.down();
  await page.mouse.move(ex + 40, ey, { steps: 5 });
  await page.mouse.up();
  await page.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
  result.editedCorners = await page.locator("#map circle.drawn-corner").count();
  result.viewBoxAfterEdit = await page.evaluate(() => document.getElementById("map").getAttribute("viewBox"));
  await Promise.all([page.waitForResponse((r) => r.url().endsWith("/api/deposit")), page.locator("#draw-send").click()]);
});
