// The page: pick a preset or drop a scenario, change its parameters, run
// it in a worker frame by frame, export what it made. `window.morphogen`
// is the page's interface for tests (docs/web.md).
import { View } from "./view.js";

const $ = (id) => document.getElementById(id);

// One worker at a time; stopping terminates it and starts another.
// `heard` counts the worker's messages: a run reports progress at least
// every 100 ms, so a count that stands still is a run that is stuck.
class Engine {
  constructor() {
    this.next = 1;
    this.pending = new Map();
    this.heard = 0;
    this.start();
  }

  start() {
    this.worker = new Worker(new URL("./worker.js", import.meta.url), { type: "module" });
    this.worker.onmessage = (e) => {
      const msg = e.data;
      this.heard++;
      const p = this.pending.get(msg.id);
      if (!p) return;
      if (msg.type === "done") {
        this.pending.delete(msg.id);
        p.resolve(msg);
      } else if (msg.type === "error") {
        this.pending.delete(msg.id);
        p.reject(new Error(msg.message));
      } else {
        p.onEvent(msg);
      }
    };
  }

  request(msg, onEvent = () => {}) {
    const id = this.next++;
    return new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject, onEvent });
      this.worker.postMessage({ ...msg, id });
    });
  }

  stop() {
    this.worker.terminate();
    for (const p of this.pending.values()) p.reject(new Error("stopped"));
    this.pending.clear();
    this.start();
  }
}

const engine = new Engine();
const view = new View($("view"));

// What is loaded: a preset name or TOML text, and the changed parameters.
const state = { source: null, sets: new Map(), info: null, toml: "", stream: null, running: false, runs: 0 };

function source() {
  return state.source.toml !== undefined ? { toml: state.source.toml } : { preset: state.source.preset };
}

function setStatus(text, error = false) {
  $("status").textContent = text;
  $("status").classList.toggle("error", error);
}

async function load(src) {
  if (state.running) engine.stop();
  state.source = src;
  state.sets = new Map();
  const d = await engine.request({ op: "load", ...source() });
  state.info = d.info;
  state.toml = d.toml;
  $("seed").value = d.info.seed;
  $("summary").textContent = d.info.summary;
  buildControls(d.controls);
  view.reset(d.info.model, d.info.colours);
  await run();
}

function buildControls(controls) {
  const box = $("controls");
  box.replaceChildren();
  for (const c of controls) {
    const row = document.createElement("label");
    row.className = "control";
    row.title = c.doc ? `${c.key}: ${c.doc} (${c.min} to ${c.max})` : `${c.key} (${c.min} to ${c.max})`;
    const name = document.createElement("span");
    name.textContent = c.key.replace(/^[a-z]+\./, "");
    const number = document.createElement("input");
    number.type = "number";
    number.min = c.min;
    number.max = c.max;
    number.step = c.whole ? 1 : "any";
    number.value = c.value;
    number.dataset.key = c.key;
    const slider = document.createElement("input");
    slider.type = "range";
    // Any whole number (or any number) of the range: a coarser step would
    // snap the slider away from the value its box holds.
    slider.min = c.min;
    slider.max = c.max;
    slider.step = c.whole ? 1 : "any";
    slider.value = c.value;
    const changed = (v) => {
      state.sets.set(c.key, v);
      rerun();
    };
    slider.oninput = () => { number.value = slider.value; };
    slider.onchange = () => changed(slider.value);
    number.onchange = () => { slider.value = number.value; changed(number.value); };
    row.append(name, slider, number);
    box.append(row);
  }
}

let timer = null;
function rerun() {
  clearTimeout(timer);
  timer = setTimeout(() => run(), 150);
}

async function run() {
  if (state.running) engine.stop();
  // A newer run supersedes this one: only the newest updates the page.
  const token = (state.token = (state.token || 0) + 1);
  state.runs++;
  state.running = true;
  state.stream = null;
  $("stop").disabled = false;
  $("digest").textContent = "…";
  $("frame").textContent = "";
  $("progress").value = 0;
  setStatus("running");
  document.body.dataset.state = "running";
  const sets = [...state.sets.entries()];
  try {
    const d = await engine.request(
      { op: "run", ...source(), sets, seed: $("seed").value, live: true, everyMs: 100, keepStream: true },
      (e) => {
        if (e.type === "progress") $("progress").value = e.total ? e.done / e.total : 1;
        else if (e.type === "frame") {
          view.show(e.frame);
          $("frame").textContent = `frame ${e.frame.index}, t = ${e.frame.time.toFixed(2)}`;
        }
      },
    );
    state.stream = d.stream;
    if (sets.length > 0) state.toml = (await engine.request({ op: "load", ...source(), sets })).toml;
    $("digest").textContent = d.digest;
    $("progress").value = 1;
    setStatus(`${d.frames} frames, ${d.bytes} bytes in ${d.ms.toFixed(0)} ms`);
    document.body.dataset.state = "done";
  } catch (e) {
    if (e.message !== "stopped" && token === state.token) {
      setStatus(e.message, true);
      document.body.dataset.state = "error";
    }
  } finally {
    if (token === state.token) {
      state.running = false;
      $("stop").disabled = true;
    }
  }
}

function download(name, blob) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

// The file key `key` of the scenario shown set to `file`, inline (as
// `morphogen run --mask` or `--set bones.grammar=FILE` does), then a run.
async function setFile(key, file) {
  const bytes = new Uint8Array(await file.arrayBuffer());
  const { value } = await engine.request({ op: "file", key, name: file.name, bytes });
  state.sets.set(key, value);
  return run();
}

// A dropped or chosen file: a scenario (TOML, its files inline); an
// L-system grammar (.lsys): the skeleton of the bone scenario shown, or else
// wrapped into a scenario of its own; or a mask (.pbm, .png) for the mosaic
// shown.
async function openFile(file) {
  if (file.name.endsWith(".pbm") || file.name.endsWith(".png")) {
    if (!state.info || !state.info.model.endsWith("mosaic")) throw new Error("a mask is for a mosaic: pick one first");
    return setFile("mosaic.mask", file);
  }
  if (file.name.endsWith(".lsys") && state.info && state.info.model === "bones") {
    return setFile("bones.grammar", file);
  }
  const text = await file.text();
  if (file.name.endsWith(".lsys")) {
    const name = file.name.replace(/\.lsys$/, "").toLowerCase().replace(/[^a-z0-9._-]/g, "-").slice(0, 32) || "grammar";
    const toml = `name = "${name}"\nseed = 0\n\n[lsystem]\ngrammar = { text = '''\n${text}''' }\n`;
    return load({ toml });
  }
  return load({ toml: text });
}

async function main() {
  const { presets } = await engine.request({ op: "presets" });
  const select = $("preset");
  for (const p of presets) {
    const o = document.createElement("option");
    o.value = p.name;
    o.textContent = `${p.name} (${p.model}${p.mcu ? ", MCU" : ""})`;
    select.append(o);
  }
  select.onchange = () => load({ preset: select.value }).catch((e) => setStatus(e.message, true));
  $("file").onchange = () => $("file").files[0] && openFile($("file").files[0]).catch((e) => setStatus(e.message, true));
  const drop = document.body;
  drop.ondragover = (e) => { e.preventDefault(); };
  drop.ondrop = (e) => {
    e.preventDefault();
    const f = e.dataTransfer.files[0];
    if (f) openFile(f).catch((err) => setStatus(err.message, true));
  };
  $("run").onclick = () => run();
  $("seed").onchange = () => run();
  $("stop").onclick = () => {
    engine.stop();
    state.running = false;
    $("stop").disabled = true;
    setStatus("stopped");
    document.body.dataset.state = "stopped";
  };
  $("export-stream").onclick = () => state.stream && download(`${state.info.name}.bin`, new Blob([state.stream]));
  $("export-toml").onclick = () => download(`${state.info.name}.toml`, new Blob([state.toml], { type: "text/plain" }));
  $("export-png").onclick = async () => download(`${state.info.name}.png`, await (await fetch(view.png())).blob());

  window.morphogen = {
    presets: () => presets.map((p) => ({ ...p })),
    // The stream digest of preset `name` run with `seed` (16 hex digits).
    digest: async (name, seed) => (await engine.request({ op: "run", preset: name, seed: String(seed) })).digest,
    // Runs a scenario file's text with its own seed.
    runScenario: async (toml) => {
      const d = await engine.request({ op: "run", toml });
      return { digest: d.digest, frames: d.frames, bytes: d.bytes };
    },
    // For tests and timing: the run time in the worker, in ms.
    time: async (name, seed) => (await engine.request({ op: "run", preset: name, seed: String(seed) })).ms,
    // What the page is doing, for tests that wait on it: runs started, the
    // state of the last (running, done, error, stopped), the worker's
    // messages so far and whether the page has loaded.
    activity: () => ({ runs: state.runs, state: document.body.dataset.state, heard: engine.heard, ready: document.body.dataset.ready === "yes" }),
    // The page's own flow: load a preset, set parameters, run and draw.
    show: async (name, sets = {}) => {
      select.value = name;
      await load({ preset: name });
      if (Object.keys(sets).length > 0) {
        for (const [k, v] of Object.entries(sets)) state.sets.set(k, v);
        await run();
      }
      return $("digest").textContent;
    },
  };
  const first = new URLSearchParams(location.search).get("preset") || "ram-horn";
  select.value = first;
  await load({ preset: select.value });
  document.body.dataset.ready = "yes";
}

main().catch((e) => setStatus(e.message, true));
