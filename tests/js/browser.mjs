// Headless Chromium for sarloc's browser tests: Debian's /usr/bin/chromium (SARLOC_CHROMIUM
// overrides it) driven by playwright-core, with a fresh profile that is removed afterwards.
import { chromium } from "playwright-core";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";

// `options`: more of playwright's context options (clientCertificates, ignoreHTTPSErrors).
export async function launchChromium(viewport, options = {}) {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), "sarloc-chromium-"));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.SARLOC_CHROMIUM ?? "/usr/bin/chromium",
    headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-extensions"],
    viewport,
    ...options,
  });
  return {
    context,
    close: async () => {
      await context.close();
      fs.rmSync(profile, { recursive: true, force: true });
    },
  };
}

// Runs `body(context)` in a fresh headless Chromium, an error it throws recorded in
// result.errors; then prints `result` as JSON and exits 0 when it holds no error, else 1.
export async function reportFromBrowser(viewport, result, body) {
  const browser = await launchChromium(viewport);
  try {
    await body(browser.context);
  } catch (error) {
    result.errors.push(`browser: ${error.message}`);
  } finally {
    await browser.close();
  }
  console.log(JSON.stringify(result));
  process.exit(result.errors.length === 0 ? 0 : 1);
}
