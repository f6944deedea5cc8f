// The demo page: pickers, play/pause/step/reset, both cameras on canvases, status and counters.
// Everything runs in the WebAssembly module (vifo_web.js); this file only wires the page to it.
// URL parameters preset the pickers (task, condition, cue, init, seed, policy, size, wrist=0,
// autoplay=1), so a link can open a given episode.
import init, { VifoDemo, tasks, instances, languageConditions, policies } from "./vifo_web.js";

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);
let demo = null;
let demoConfig = "";
let status = null;
let playing = false;
let cueList = [];
let firstFrameShown = false;
// fps: frames drawn in the current one-second window; ms per step: mean wasm step + draw time.
let fpsWindow = { start: 0, frames: 0 };
let stepMs = { total: 0, count: 0 };
let lastStep = 0;

function showError(err) {
  $("error").textContent = err ? String(err.message ?? err) : "";
}

// URL presets that match no option, reported once the page is up.
const unmatched = [];

function fill(select, items, value) {
  select.replaceChildren(...items.map(([v, text]) => new Option(text, v)));
  if (value !== undefined && items.some(([v]) => v === value)) select.value = value;
}

// Presets a picker from the URL parameter `name`, noting a value it does not offer.
function preset(select, items, name, fallback) {
  const wanted = params.get(name);
  fill(select, items, wanted ?? fallback);
  if (wanted !== null && select.value !== wanted) unmatched.push(`${name}=${wanted} is not one of the choices; showing ${select.value}`);
}

function fillCues(preset) {
  cueList = instances($("task").value);
  const families = [...new Map(cueList.map((c) => [c.family, `${c.family} ${c.family_name}`]))];
  const presetCue = cueList.find((c) => c.id === preset);
  fill($("family"), families, presetCue?.family ?? $("family").value);
  fillVariants(presetCue?.id);
  return !preset || presetCue !== undefined;
}

function fillVariants(preset) {
  const family = $("family").value;
  const variants = cueList.filter((c) => c.family === family).map((c) => [c.id, c.variant + (c.paper ? "" : " (full set only)")]);
  fill($("variant"), variants, preset);
}

// A new module-side demo when the frame size or camera set changes.
function ensureDemo() {
  const size = Number($("size").value);
  const wrist = $("wrist").checked;
  const config = `${size}/${wrist}`;
  if (config === demoConfig) return;
  demo?.free();
  demo = new VifoDemo(size, wrist);
  demoConfig = config;
  for (const id of ["agentview", "wristview"]) {
    $(id).width = size;
    $(id).height = size;
  }
  $("wrist-figure").style.display = wrist ? "" : "none";
}

// "keyboard": the person at the page drives the arm; the module's policies do the rest.
const KEYBOARD = "keyboard";

// Keys held down, and the end-effector delta action they make: arrows move in the table plane
// (x forward, y left), R/F up and down, Q/E turn about z; G toggles the gripper. While Play runs
// the held keys drive every step; paused, each key press is one step.
const held = new Set();
let gripper = -1;
const KEYS = { ArrowUp: [0, 1], ArrowDown: [0, -1], ArrowLeft: [1, 1], ArrowRight: [1, -1], r: [2, 1], f: [2, -1], q: [5, 1], e: [5, -1] };

function keyboardAction() {
  const action = [0, 0, 0, 0, 0, 0, gripper];
  for (const key of held) {
    const [axis, sign] = KEYS[key];
    action[axis] += 0.5 * sign;
  }
  return action;
}

// A key (or its button on the page's pad) goes down: G toggles the gripper, the others are
// held; paused, it is one step. Returns false for keys that drive nothing.
function press(key) {
  if (key === "g") gripper = -gripper;
  else if (key in KEYS) held.add(key);
  else return false;
  if (!playing && status && !status.done) guarded(stepOnce)();
  return true;
}

function listenToKeys() {
  const typing = (e) => ["INPUT", "SELECT", "TEXTAREA"].includes(e.target.tagName);
  const keyOf = (e) => (e.key.length === 1 ? e.key.toLowerCase() : e.key);
  window.addEventListener("keydown", (e) => {
    if ($("policy").value !== KEYBOARD || typing(e)) return;
    if (press(keyOf(e))) e.preventDefault();
  });
  window.addEventListener("keyup", (e) => held.delete(keyOf(e)));
  window.addEventListener("blur", () => held.clear());
  // The pad's buttons are the same keys for a touch screen: held while the finger is down.
  for (const button of document.querySelectorAll("#pad button")) {
    const key = button.dataset.key;
    button.addEventListener("pointerdown", (e) => {
      e.preventDefault();
      button.setPointerCapture?.(e.pointerId);
      press(key);
    });
    for (const up of ["pointerup", "pointercancel", "lostpointercapture"]) {
      button.addEventListener(up, () => held.delete(key));
    }
    button.addEventListener("contextmenu", (e) => e.preventDefault());
  }
}

function setPolicy() {
  const keyboard = $("policy").value === KEYBOARD;
  $("keys").hidden = !keyboard;
  $("pad").hidden = !keyboard;
  // The module holds still for the keyboard: stepAction carries the person's action.
  demo.setPolicy(keyboard ? "zero" : $("policy").value);
}

function reset() {
  showError(null);
  ensureDemo();
  setPolicy();
  // As text: a benchmark seed needs all 64 bits, more than a JavaScript number holds.
  const seedText = $("seed").value.trim();
  const seed = seedText === "" ? undefined : seedText;
  const condition = $("condition").value;
  const cue = condition === "original" ? null : $("variant").value || null;
  // Until this reset succeeds there is no episode to step: a refused one (an init state out of
  // range) must not leave Step and Play advancing the previous episode.
  status = null;
  status = demo.reset($("task").value, Number($("init").value), cue, condition, seed);
  stepMs = { total: 0, count: 0 };
  draw();
}

function draw() {
  const size = demo.size;
  const put = (canvas, rgba) => {
    const image = new ImageData(new Uint8ClampedArray(rgba.buffer, rgba.byteOffset, rgba.length), size, size);
    canvas.getContext("2d").putImageData(image, 0, 0);
  };
  put($("agentview"), demo.agentview());
  if ($("wrist").checked) put($("wristview"), demo.wrist());
  showStatus();
  if (!firstFrameShown) {
    firstFrameShown = true;
    $("first-frame-ms").textContent = Math.round(performance.now());
  }
  fpsWindow.frames += 1;
  const now = performance.now();
  if (now - fpsWindow.start >= 1000) {
    $("fps").textContent = playing ? (fpsWindow.frames * 1000 / (now - fpsWindow.start)).toFixed(1) : "0";
    fpsWindow = { start: now, frames: 0 };
  }
}

function flag(value) {
  return value === null || value === undefined ? "–" : value ? "yes" : "no";
}

function showStatus() {
  $("instruction").textContent = status.instruction === "" ? "(empty)" : status.instruction;
  $("cue").textContent = status.cue ?? "(no cue)";
  $("steps").textContent = status.steps;
  $("budget").textContent = status.budget;
  $("cue-success").textContent = flag(status.cue_success);
  $("language-success").textContent = flag(status.language_success);
  $("done").textContent = status.done ? "yes" : "no";
  $("state-hash").textContent = status.state_hash;
  $("seed-shown").textContent = status.seed;
  $("step-ms").textContent = stepMs.count ? (stepMs.total / stepMs.count).toFixed(1) : "–";
  $("predicates").replaceChildren(...status.predicates.map((p) => {
    const li = document.createElement("li");
    li.innerHTML = `<span class="${p.holds ? "yes" : "no"}">${p.holds ? "✓" : "✗"}</span> ${p.task}: <code></code>`;
    li.querySelector("code").textContent = p.atom;
    return li;
  }));
}

function stepOnce() {
  const t0 = performance.now();
  status = $("policy").value === KEYBOARD ? demo.stepAction(keyboardAction()) : demo.step();
  lastStep = t0;
  draw();
  stepMs.total += performance.now() - t0;
  stepMs.count += 1;
}

// One control step per animation frame while playing, or per 50 ms of wall time (the 20 Hz of
// LIBERO's control) with "real time".
function tick() {
  if (!playing) return;
  try {
    if ($("realtime").checked && performance.now() - lastStep < 50) {
      requestAnimationFrame(tick);
      return;
    }
    stepOnce();
    if (status.done) setPlaying(false);
    else requestAnimationFrame(tick);
  } catch (err) {
    setPlaying(false);
    showError(err);
  }
}

function setPlaying(on) {
  playing = on;
  $("play").textContent = on ? "Pause" : "Play";
  if (!on) $("fps").textContent = "0";
  fpsWindow = { start: performance.now(), frames: 0 };
  if (on) requestAnimationFrame(tick);
}

function guarded(f) {
  return () => {
    try {
      f();
    } catch (err) {
      setPlaying(false);
      showError(err);
    }
  };
}

async function main() {
  await init();
  const taskList = tasks();
  preset($("task"), taskList.map((t) => [t.key, `${t.key}: ${t.instruction}`]), "task", "libero_goal/0");
  preset($("condition"), languageConditions().map((c) => [c, c]), "condition", "authorized");
  preset($("policy"), [...policies().map((p) => [p, p]), [KEYBOARD, "keyboard (you drive)"]], "policy", "expert-cue");
  listenToKeys();
  const sizes = [...$("size").options].map((o) => [o.value, o.text]);
  preset($("size"), sizes, "size", "128");
  if (params.get("wrist") === "0") $("wrist").checked = false;
  if (params.has("init")) $("init").value = params.get("init");
  if (params.has("seed")) $("seed").value = params.get("seed");
  const cueFound = fillCues(params.get("cue"));
  $("task").onchange = guarded(() => { fillCues(); reset(); });
  $("family").onchange = guarded(() => { fillVariants(); reset(); });
  for (const id of ["variant", "condition", "init", "seed", "size", "wrist"]) $(id).onchange = guarded(reset);
  $("policy").onchange = guarded(() => { setPolicy(); if (status) status = demo.status(); });
  $("reset").onclick = guarded(() => { setPlaying(false); reset(); });
  $("step").onclick = guarded(() => { setPlaying(false); if (status && !status.done) stepOnce(); });
  $("play").onclick = guarded(() => setPlaying(!playing && status !== null && !status.done));
  for (const b of document.querySelectorAll("button")) b.disabled = false;
  $("loading").hidden = true;
  reset();
  if (!cueFound) unmatched.push(`cue ${params.get("cue")} is not an instance of ${$("task").value}; showing ${$("variant").value}`);
  if (unmatched.length > 0) showError(unmatched.join("; "));
  document.body.dataset.ready = "1";
  if (params.get("autoplay") === "1") setPlaying(true);
}

main().catch(showError);

// For scripts and the browser test: the page's demo object.
window.vifo = { get demo() { return demo; }, get status() { return status; } };
