// The page's worker: loads the WebAssembly module (web/wasm) and runs
// scenarios off the main thread, posting progress, frames and the result.
// Stopping a run is terminating this worker (main.js starts a new one).
import init, { fileValue, presets, Scenario } from "./pkg/morphogen_web.js";

const ready = init();

// The scenario a request names: a built-in preset or TOML text, with its
// parameter changes ([key, value] pairs, as `--set`).
function load(msg) {
  const base = msg.toml !== undefined ? Scenario.fromToml(msg.toml) : Scenario.preset(msg.preset);
  const sets = msg.sets || [];
  if (sets.length === 0) return base;
  const changed = base.withSets(sets.map((s) => s[0]), sets.map((s) => String(s[1])));
  base.free();
  return changed;
}

function describe(s) {
  return { info: JSON.parse(s.info()), controls: JSON.parse(s.controls()), toml: s.toml() };
}

// A frame's arrays, moved (not copied) to the page.
function frameMessage(id, f) {
  const frame = {
    index: f.index,
    time: f.time,
    lines: f.lines,
    lineColours: f.lineColours,
    triangles: f.triangles,
    triangleColours: f.triangleColours,
    points: f.points,
    pointKinds: f.pointKinds,
    chart: f.chart,
  };
  f.free();
  const buffers = ["lines", "lineColours", "triangles", "triangleColours", "points", "pointKinds"]
    .map((k) => frame[k].buffer);
  postMessage({ id, type: "frame", frame }, buffers);
}

self.onmessage = async (event) => {
  const msg = event.data;
  const { id } = msg;
  try {
    await ready;
    if (msg.op === "presets") {
      postMessage({ id, type: "done", presets: JSON.parse(presets()) });
      return;
    }
    if (msg.op === "file") {
      postMessage({ id, type: "done", value: fileValue(msg.key, msg.name, msg.bytes) });
      return;
    }
    const s = load(msg);
    try {
      if (msg.op === "load") {
        postMessage({ id, type: "done", ...describe(s) });
        return;
      }
      const seed = BigInt(msg.seed ?? JSON.parse(s.info()).seed);
      const start = performance.now();
      // Progress at most every 100 ms, also where nothing is drawn: the
      // page (and its tests) can tell a long run from a stuck one.
      const progress = (done, total) => postMessage({ id, type: "progress", done, total });
      const result = msg.live
        ? s.run(seed, msg.everyMs ?? 100, (f) => frameMessage(id, f), progress)
        : s.digest(seed, msg.everyMs ?? 100, progress);
      const ms = performance.now() - start;
      const stream = result.stream;
      const reply = { id, type: "done", digest: result.digest, frames: result.frames, bytes: stream.length, ms };
      result.free();
      if (msg.keepStream) {
        reply.stream = stream;
        postMessage(reply, [stream.buffer]);
      } else {
        postMessage(reply);
      }
    } finally {
      s.free();
    }
  } catch (e) {
    postMessage({ id, type: "error", message: String(e && e.message ? e.message : e) });
  }
};
