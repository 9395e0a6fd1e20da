// The page in a real browser: it loads, every preset's digest is its
// fixture's, a parameter change re-runs, every kind of model draws.
import { test, expect } from "@playwright/test";
import { readFileSync, readdirSync } from "node:fs";
import { fileURLToPath } from "node:url";

const root = fileURLToPath(new URL("../../", import.meta.url));

// A fixture's summary.toml fields (flat `key = value` lines).
function summary(name) {
  const text = readFileSync(`${root}fixtures/${name}/summary.toml`, "utf8");
  const field = (k) => text.match(new RegExp(`^${k} = "?([^"\\n]*)"?$`, "m"))?.[1];
  return { seed: field("seed"), digest: field("stream_digest"), frames: Number(field("frames")), bytes: Number(field("bytes")) };
}

// How long the page's worker may say nothing before a wait fails: a run
// reports progress every 100 ms, so silence this long is a run that hangs,
// however slow the machine. No wait below has a deadline of its own.
const SILENCE_MS = 60000;

// Waits until `done(activity)` holds (`window.morphogen.activity()`), for as
// long as the page's worker keeps talking; fails naming `what` once it has
// been silent for SILENCE_MS.
async function until(page, what, done) {
  let heard = -1;
  let since = Date.now();
  for (;;) {
    const a = await page.evaluate(() => window.morphogen.activity());
    if (await done(a)) return a;
    if (a.heard !== heard) {
      heard = a.heard;
      since = Date.now();
    } else if (Date.now() - since > SILENCE_MS) {
      throw new Error(`${what}: no word from the page's worker for ${SILENCE_MS / 1000} s (state ${a.state}, ${a.runs} runs)`);
    }
    await new Promise((r) => setTimeout(r, 50));
  }
}

// `promise`'s value, awaited for as long as the page's worker is working.
async function watched(page, what, promise) {
  let settled = false;
  const result = promise.finally(() => { settled = true; });
  result.catch(() => {});
  await until(page, what, () => settled);
  return result;
}

// Runs `action` (which starts a run on the page) and waits for that run to
// end: done, failed or stopped.
async function ran(page, what, action) {
  const before = (await page.evaluate(() => window.morphogen.activity())).runs;
  await action();
  return until(page, what, (a) => a.runs > before && a.state !== "running");
}

async function open(page, preset = "ram-horn") {
  const errors = [];
  page.on("pageerror", (e) => errors.push(e.message));
  await page.goto(`?preset=${preset}`);
  // The module and its WebAssembly, from this machine's server.
  await page.waitForFunction(() => window.morphogen !== undefined, null, { timeout: SILENCE_MS });
  await until(page, `the page's first run (${preset})`, (a) => a.ready);
  return errors;
}

// Every slider of the parameters shows the value its number box holds;
// how many parameters there are.
async function slidersMatchBoxes(page, name) {
  const rows = await page.locator("#controls label").evaluateAll((labels) =>
    labels.map((l) => [l.querySelector("input[type=number]").dataset.key, l.querySelector("input[type=range]").value, l.querySelector("input[type=number]").value]));
  expect(rows.filter(([, slider, box]) => Number(slider) !== Number(box)), `${name}: sliders that differ from their box`).toEqual([]);
  return rows.length;
}

// The pixel variance of a screenshot of the drawing, decoded in the page.
async function variance(page) {
  const png = (await page.locator("#view").screenshot()).toString("base64");
  return page.evaluate(async (b64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const c = new OffscreenCanvas(img.width, img.height);
    const g = c.getContext("2d");
    g.drawImage(img, 0, 0);
    const d = g.getImageData(0, 0, img.width, img.height).data;
    let sum = 0, sq = 0;
    const n = d.length / 4;
    for (let i = 0; i < d.length; i += 4) {
      const v = (d[i] + d[i + 1] + d[i + 2]) / 3;
      sum += v;
      sq += v * v;
    }
    return sq / n - (sum / n) ** 2;
  }, png);
}

test("the page loads, runs its first preset and shows the fixture's digest", async ({ page }) => {
  const errors = await open(page);
  await expect(page.locator("#digest")).toHaveText(summary("ram-horn").digest);
  const presets = await page.evaluate(() => window.morphogen.presets());
  expect(presets.map((p) => p.name).sort()).toEqual(readdirSync(`${root}scenarios`).filter((f) => f.endsWith(".toml")).map((f) => f.replace(/\.toml$/, "")).sort());
  expect(await slidersMatchBoxes(page, "ram-horn")).toBeGreaterThan(0);
  expect(errors).toEqual([]);
});

test("every built-in preset's digest is its fixture's", async ({ page }) => {
  await open(page);
  const presets = await page.evaluate(() => window.morphogen.presets());
  expect(presets.length).toBeGreaterThan(0);
  const wrong = [];
  for (const p of presets) {
    const want = summary(p.name);
    const got = await watched(page, p.name, page.evaluate(([n, s]) => window.morphogen.digest(n, s), [p.name, want.seed]));
    if (got !== want.digest) wrong.push(`${p.name}: ${got}, fixture ${want.digest}`);
  }
  expect(wrong).toEqual([]);
});

test("runScenario runs a scenario file's text with its own seed", async ({ page }) => {
  await open(page);
  for (const name of ["ram-horn", "croton-mcu"]) {
    const toml = readFileSync(`${root}scenarios/${name}.toml`, "utf8");
    const got = await watched(page, name, page.evaluate((t) => window.morphogen.runScenario(t), toml));
    const want = summary(name);
    expect(got).toEqual({ digest: want.digest, frames: want.frames, bytes: want.bytes });
  }
  await expect(watched(page, "a bad scenario", page.evaluate(() => window.morphogen.runScenario("name = 'x'\n[horn]\nyears = 99\n")))).rejects.toThrow(/horn/);
});

test("a parameter changed on the page re-runs and changes the digest", async ({ page }) => {
  await open(page, "ram-horn");
  const before = summary("ram-horn").digest;
  await expect(page.locator("#digest")).toHaveText(before);
  const years = page.locator('input[type=number][data-key="horn.years"]');
  await ran(page, "ram-horn with 3 years", async () => {
    await years.fill("3");
    await years.dispatchEvent("change");
  });
  await expect(page.locator("body")).toHaveAttribute("data-state", "done");
  await expect(page.locator("#digest")).not.toHaveText(before);
  await expect(page.locator("#digest")).toHaveText(/^[0-9a-f]{16}$/);
  expect(await slidersMatchBoxes(page, "ram-horn, 3 years")).toBeGreaterThan(0);
  const after = await page.locator("#digest").textContent();
  // The exported scenario carries the change: run from its text, it gives
  // the page's digest again.
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#export-toml")]);
  const toml = readFileSync(await download.path(), "utf8");
  expect(toml).toMatch(/years = 3/);
  expect((await watched(page, "the exported scenario", page.evaluate((t) => window.morphogen.runScenario(t), toml))).digest).toEqual(after);
  // And the exported stream is the run's bytes.
  const [stream] = await Promise.all([page.waitForEvent("download"), page.click("#export-stream")]);
  expect(readFileSync(await stream.path()).length).toBeGreaterThan(0);
});

test("a scenario, a grammar, a skeleton and PBM and PNG masks opened as files run", async ({ page }) => {
  await open(page, "croton-mcu");
  const digest = page.locator("#digest");
  const croton = summary("croton-mcu").digest;
  await expect(digest).toHaveText(croton);
  const opened = (what, file) => ran(page, what, () => page.setInputFiles("#file", file));
  // A mask for the mosaic shown: its left half only.
  await opened("a PBM mask", { name: "half.pbm", mimeType: "image/x-portable-bitmap", buffer: Buffer.from("P1\n4 2\n0 0 1 1\n0 0 1 1\n") });
  await expect(digest).not.toHaveText(croton);
  await expect(digest).toHaveText(/^[0-9a-f]{16}$/);
  const half = await digest.textContent();
  // A PNG mask (white allows): the watermelon picture of docs/mosaics.
  await opened("a PNG mask", `${root}docs/mosaics/watermelon-mcu.png`);
  await expect(digest).not.toHaveText(half);
  await expect(digest).not.toHaveText(croton);
  await expect(digest).toHaveText(/^[0-9a-f]{16}$/);
  await expect(page.locator("#status")).not.toHaveClass(/error/);
  // A scenario file: the preset's own gives its fixture.
  await opened("ram-horn.toml", `${root}scenarios/ram-horn.toml`);
  await expect(digest).toHaveText(summary("ram-horn").digest);
  await expect(page.locator("#summary")).toContainText("ram horn");
  // A grammar on its own.
  await opened("abop-2d-plant.lsys", `${root}grammars/abop-2d-plant.lsys`);
  await expect(digest).not.toHaveText(summary("ram-horn").digest);
  await expect(digest).toHaveText(/^[0-9a-f]{16}$/);
  await expect(page.locator("#status")).not.toHaveClass(/error/);
  // A grammar with a bone preset shown is its skeleton: the digest of
  // `morphogen run long-bone --grammar examples/wishbone.lsys`, then, with
  // long-bone's own grammar, its fixture.
  await ran(page, "long-bone", () => page.selectOption("#preset", "long-bone"));
  await expect(digest).toHaveText(summary("long-bone").digest);
  await opened("wishbone.lsys", `${root}examples/wishbone.lsys`);
  await expect(digest).toHaveText("da2e0f76063327c3");
  await opened("long-bone.lsys", `${root}grammars/long-bone.lsys`);
  await expect(digest).toHaveText(summary("long-bone").digest);
  await expect(page.locator("#status")).not.toHaveClass(/error/);
});

test("a long run shows progress and frames, and Stop ends it", async ({ page }) => {
  await open(page);
  // Stop is pressed from inside the page as soon as the run has shown a
  // frame and some progress: the worker's next message (its end, on a fast
  // machine) cannot come in between, so the run is still going then
  // however fast the machine is.
  const pressed = page.evaluate(() => new Promise((resolve) => {
    const progress = document.getElementById("progress");
    const frame = document.getElementById("frame");
    const stop = document.getElementById("stop");
    const observer = new MutationObserver(() => {
      if (document.body.dataset.state !== "running" || !(progress.value > 0) || frame.textContent === "") return;
      observer.disconnect();
      const shown = { progress: progress.value, frame: frame.textContent, stoppable: !stop.disabled };
      stop.click();
      resolve(shown);
    });
    observer.observe(progress, { attributes: true });
    observer.observe(frame, { childList: true, characterData: true, subtree: true });
  }));
  await page.selectOption("#preset", "croton-ageing");
  const shown = await watched(page, "croton-ageing's first frame", pressed);
  expect(shown.frame).toMatch(/^frame \d+/);
  expect(shown.progress).toBeGreaterThan(0);
  expect(shown.stoppable).toBe(true);
  await expect(page.locator("body")).toHaveAttribute("data-state", "stopped");
  await expect(page.locator("#status")).toHaveText("stopped");
  await expect(page.locator("#digest")).toHaveText("…");
  await expect(page.locator("#stop")).toBeDisabled();
  // The page goes on working after a stop.
  expect(await watched(page, "ram-horn after the stop", page.evaluate(() => window.morphogen.digest("ram-horn", 0)))).toEqual(summary("ram-horn").digest);
  await ran(page, "croton-ageing again", () => page.click("#run"));
  await expect(page.locator("body")).toHaveAttribute("data-state", "done");
  await expect(page.locator("#digest")).toHaveText(summary("croton-ageing").digest);
});

test("a screenshot of each kind of model is not blank", async ({ page }) => {
  await open(page);
  const presets = await page.evaluate(() => window.morphogen.presets());
  const kinds = new Map();
  for (const p of presets) if (!kinds.has(p.model) && (p.mcu || p.model === "surface-mosaic")) kinds.set(p.model, p.name);
  expect([...kinds.keys()].sort()).toEqual(["body", "bones", "curve", "horn", "lsystem", "mosaic", "surface-mosaic"]);
  for (const [kind, name] of kinds) {
    await ran(page, name, () => page.selectOption("#preset", name));
    await expect(page.locator("body")).toHaveAttribute("data-state", "done");
    await expect(page.locator("#digest")).toHaveText(summary(name).digest);
    // The L-system's parameters are its grammar's settings and constants.
    expect(await slidersMatchBoxes(page, name) > 0, `${name}: parameters shown`).toBe(true);
    const v = await variance(page);
    await page.locator("#view").screenshot({ path: `test-results/${kind}-${name}.png` });
    expect(v, `${kind} (${name}) pixel variance`).toBeGreaterThan(20);
  }
});

test("the MCU presets' run times in the browser", async ({ page }) => {
  await open(page);
  const presets = (await page.evaluate(() => window.morphogen.presets())).filter((p) => p.mcu);
  const rows = [];
  for (const p of presets) {
    const seed = summary(p.name).seed;
    // The best of three runs in the worker (the first warms up).
    let best = Infinity;
    for (let i = 0; i < 3; i++) best = Math.min(best, await watched(page, p.name, page.evaluate(([n, s]) => window.morphogen.time(n, s), [p.name, seed])));
    rows.push([p.name, best]);
  }
  console.log(rows.map(([n, ms]) => `${n.padEnd(24)} ${ms.toFixed(0).padStart(6)} ms`).join("\n"));
  console.log(`MCU presets: ${rows.length}, slowest ${Math.max(...rows.map((r) => r[1])).toFixed(0)} ms`);
  expect(rows.length).toBeGreaterThan(0);
});
