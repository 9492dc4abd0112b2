// Opens a page in headless Chromium (Debian's /usr/bin/chromium, driven by playwright-core),
// fails on any console error or page error, saves a full-page screenshot and checks that it is
// not blank: enough of its pixels differ from the background.
//
//   node tests/js/screenshot.mjs PAGE.html SHOT.png   -> JSON {errors, width, height, inkFraction}
import { reportFromBrowser } from "./browser.mjs";
import path from "node:path";

const [page_path, shot_path] = process.argv.slice(2);
if (!page_path || !shot_path) {
  console.error("usage: node screenshot.mjs PAGE.html SHOT.png");
  process.exit(2);
}
const result = { errors: [] };
await reportFromBrowser({ width: 1200, height: 900 }, result, async (context) => {
  const page = await context.newPage();
  page.on("console", (message) => {
    if (message.type() === "error") result.errors.push(`console: ${message.text()}`);
  });
  page.on("pageerror", (error) => result.errors.push(`page: ${error.message}`));
  // A self-contained page asks for nothing: any request but the page itself is an error.
  page.on("request", (request) => {
    if (!request.url().startsWith("file://") && !request.url().startsWith("data:")) {
      result.errors.push(`external request: ${request.url()}`);
    }
  });
  await page.goto("file://" + path.resolve(page_path), { waitUntil: "load" });
  const shot = await page.screenshot({ path: shot_path, fullPage: true });
  // Not blank: decode the screenshot in the page itself and count pixels that are not near-white.
  const stats = await page.evaluate(async (dataUrl) => {
    const image = new Image();
    image.src = dataUrl;
    await image.decode();
    const canvas = document.createElement("canvas");
    canvas.width = image.width;
    canvas.height = image.height;
    const context = canvas.getContext("2d");
    context.drawImage(image, 0, 0);
    const pixels = context.getImageData(0, 0, image.width, image.height).data;
    let ink = 0;
    const colours = new Set();
    for (let i = 0; i < pixels.length; i += 4 * 7) {
      if (pixels[i] < 235 || pixels[i + 1] < 235 || pixels[i + 2] < 235) ink += 1;
      colours.add((pixels[i] >> 4) * 256 + (pixels[i + 1] >> 4) * 16 + (pixels[i + 2] >> 4));
    }
    return { width: image.width, height: image.height, inkFraction: ink / (pixels.length / (4 * 7)), colours: colours.size };
  }, "data:image/png;base64," + shot.toString("base64"));
  Object.assign(result, stats);
  result.svgs = await page.locator("svg").count();
});
