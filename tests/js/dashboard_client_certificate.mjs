// The page behind dashboard.tls_client_ca in a real browser (dashboard_tls_test.cpp serves it):
// headless Chromium shown the operator's .p12 from make-dashboard-client.sh, as a commander
// imports it, opens the page with the token and sees its event stream go live; the same browser
// without a certificate gets no page at all. Playwright presents the certificate for the page's
// origin from its own TLS connection (its clientCertificates option), not from Chromium's
// certificate store; the server's certificate is checked by the C++ tests, so it is not here.
//
//   node tests/js/dashboard_client_certificate.mjs URL P12 PASSWORD_FILE   -> JSON on stdout
import fs from "node:fs";
import { launchChromium } from "./browser.mjs";

const [url, p12, passwordFile] = process.argv.slice(2);
const origin = new URL(url).origin;
const result = { errors: [], responses: [], withCertificate: null, withoutCertificate: null };

// Opens `url` in a fresh browser with `options`; what the page showed, or why there was none.
async function visit(options) {
  const browser = await launchChromium({ width: 1000, height: 700 }, { ignoreHTTPSErrors: true, ...options });
  try {
    const page = await browser.context.newPage();
    page.on("console", (m) => { if (m.type() === "error") result.errors.push(`console: ${m.text()}`); });
    page.on("response", (r) => result.responses.push(`${r.status()} ${new URL(r.url()).pathname}`));
    const response = await page.goto(url, { waitUntil: "load", timeout: 15000 });
    await page.waitForFunction(() => document.getElementById("status").textContent === "live", null, { timeout: 15000 });
    return { status: response.status(), live: true };
  } catch (error) {
    return { failed: error.message.split("\n")[0] };
  } finally {
    await browser.close();
  }
}

try {
  const passphrase = fs.readFileSync(passwordFile, "utf8").trim();
  result.withCertificate = await visit({ clientCertificates: [{ origin, pfxPath: p12, passphrase }] });
  result.withoutCertificate = await visit({});
} catch (error) {
  result.errors.push(`browser: ${error.message}`);
}
console.log(JSON.stringify(result));
process.exit(result.errors.length === 0 ? 0 : 1);
