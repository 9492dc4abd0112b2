// Headless Chromium for sarloc's browser tests: Debian's /usr/bin/chromium (SARLOC_CHROMIUM
// overrides it) driven by playwright-core, with a fresh profile that is removed afterwards.
import { chromium } from "playwright-core";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";

export async function launchChromium(viewport) {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), "sarloc-chromium-"));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.SARLOC_CHROMIUM ?? "/usr/bin/chromium",
    headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-extensions"],
    viewport,
  });
  return {
    context,
    close: async () => {
      await context.close();
      fs.rmSync(profile, { recursive: true, force: true });
    },
  };
}
