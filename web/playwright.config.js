// End-to-end tests of the page (docs/web.md): Debian's Chromium, headless,
// against the page served by the release `morphogen serve` (built once by
// scripts/check.sh, passed as MORPHOGEN_RELEASE_BIN).
import { defineConfig } from "@playwright/test";

const port = Number(process.env.MORPHOGEN_WEB_PORT || 8123);
const morphogen = process.env.MORPHOGEN_RELEASE_BIN || "../target/release/morphogen";

export default defineConfig({
  testDir: "tests",
  // One browser at a time: the machine's cores run the simulations.
  workers: 1,
  // The tests wait on the page's worker for as long as it reports progress
  // (page.spec.js, `until`): no test has a deadline of its own, whatever
  // the machine's load. A click or a page load that has not happened after
  // a minute never will.
  timeout: 0,
  reporter: [["list"]],
  use: {
    actionTimeout: 60 * 1000,
    navigationTimeout: 60 * 1000,
    baseURL: `http://127.0.0.1:${port}/`,
    viewport: { width: 1200, height: 800 },
    launchOptions: {
      executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
      // As root, no sandbox; no GPU (WebGL in software); and none of
      // Chromium's own connections, which this machine's network refuses.
      args: [
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
      ],
    },
  },
  webServer: {
    command: `${morphogen} serve --port ${port} --dir dist`,
    url: `http://127.0.0.1:${port}/`,
    reuseExistingServer: false,
    timeout: 60 * 1000,
  },
});
