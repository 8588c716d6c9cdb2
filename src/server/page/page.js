// rtlab serve: the page. Plain JavaScript, no build step, nothing fetched but this server's
// API. Sections: state and helpers · controls · image view · render · explanation (samples,
// ray generation, ledger, diagram, ray tree) · steps · compare · live scene.
"use strict";

const $ = (id) => document.getElementById(id);
const STREAM = "page-" + Math.random().toString(36).slice(2);
const PRIMARY = ["no-shadows", "no-reflections", "no-refractions", "no-textures", "max-depth",
  "spp", "sampler", "filter", "course-stage", "mistake"];

const state = {
  image: null,          // ImageBitmap of the image shown
  pixels: null,         // its RGBA bytes (ImageData)
  kind: "",             // "preview" or "full"
  passOptions: "",      // the options that give the pass shown (its x-rtlab-pass-options)
  explaining: 0,        // the number of the newest explanation asked for
  bundling: 0,          // the number of the newest bundle figure asked for
  bundleAbort: null,    // its AbortController, while it is on its way
  explainedQuery: "",   // the options the explanation shown was made with
  width: 0, height: 0,
  zoom: 1, panX: 0, panY: 0, fitted: true,
  selected: null,       // {x, y}
  explanation: null,
  sample: 0,            // index into explanation.samples
  highlight: null,      // preorder index of the ray drawn in bold
  generation: 0,        // counts re-renders; stale answers are dropped
  version: 0,
  controller: null,
};

function el(tag, attrs, ...kids) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === "class") e.className = v;
    else if (k.startsWith("on")) e.addEventListener(k.slice(2), v);
    else e.setAttribute(k, v);
  }
  for (const k of kids) e.append(k instanceof Node ? k : document.createTextNode(String(k)));
  return e;
}

// Numbers as the CLI's text shows them: short, no noise.
function num(x) {
  if (x === null || x === undefined) return "—";
  if (x === 0) return "0";
  const a = Math.abs(x);
  if (a < 1e-4 || a >= 1e6) return x.toExponential(2);
  return String(Number(x.toPrecision(5)));
}
const vec = (v) => "(" + v.map(num).join(", ") + ")";
const rgbCss = (c) => `rgb(${c.map((x) => Math.round(255 * Math.min(1, Math.max(0, x)))).join(",")})`;
const swatch = (c) => el("span", { class: "swatch", style: "background:" + rgbCss(c) });
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];

async function getText(url) {
  const r = await fetch(url);
  const t = await r.text();
  if (!r.ok) throw new Error(t.trim());
  return t;
}
async function getJson(url) { return JSON.parse(await getText(url)); }

// ---------------------------------------------------------------- controls
let options = { render: [], aov: [] };

async function buildControls() {
  options = await getJson("/api/options");
  const sw = $("switches"), more = $("more");
  sw.textContent = ""; more.textContent = "";
  const byName = new Map(options.render.map((o) => [o.name, o]));
  const ordered = PRIMARY.filter((n) => byName.has(n)).map((n) => byName.get(n));
  for (const o of options.render) if (!PRIMARY.includes(o.name)) ordered.push(o);
  for (const o of ordered) {
    const target = PRIMARY.includes(o.name) ? sw : more;
    let input;
    if (o.flag) {
      input = el("input", { type: "checkbox", "data-option": o.name });
    } else if (o.choices.length) {
      input = el("select", { "data-option": o.name }, el("option", { value: "" }, "(scene's)"),
        ...o.choices.map((c) => el("option", { value: c }, c)));
    } else if (o.suggestions && o.suggestions.length) {
      // Free text (a list such as "a,b"), the known names offered as you type.
      input = el("input", { type: "text", "data-option": o.name, placeholder: "none", list: "list-" + o.name });
      target.append(el("datalist", { id: "list-" + o.name }, ...o.suggestions.map((c) => el("option", { value: c }))));
    } else {
      input = el("input", { type: "text", "data-option": o.name, placeholder: "scene's" });
    }
    input.id = "opt-" + o.name;
    input.addEventListener("change", rerender);
    target.append(el("label", { title: o.help }, input, o.flag ? o.name : o.name + " "));
    if (!o.flag) target.lastChild.append(input); // value field after its name
  }
  const aov = el("select", { id: "opt-aov" }, el("option", { value: "" }, "colour"),
    ...options.aov.map((a) => el("option", { value: a }, a)));
  aov.addEventListener("change", rerender);
  sw.append(el("label", { title: "an arbitrary output variable instead of the colour (render --aov)" }, "AOV ", aov));
  // As many samples as time permits: after the full image, passes 3, 4, … (4× the samples
  // each) until this many seconds have gone; the last complete pass stays (render --time-budget).
  const refine = el("input", { type: "number", id: "opt-refine", min: "0", step: "0.5", placeholder: "off" });
  refine.addEventListener("change", rerender);
  sw.append(el("label", { title: "after the full image, keep refining with passes 3, 4, … (4× the samples each) until this many seconds have gone; the last complete pass stays, = rtlab render --passes K" }, "refine (s) ", refine));
}

// The query that explains the pixels of the image shown: the page's options, with those of
// the pass shown (its subsample, sampler and spp) in their place.
function shownQuery() {
  const pass = new URLSearchParams(state.passOptions || "");
  return join(renderQuery([...pass.keys()]), state.passOptions || "");
}

// The render options chosen on the page, as a query string (flags as bare keys).
function renderQuery(except) {
  const parts = [];
  for (const input of document.querySelectorAll("[data-option]")) {
    const name = input.dataset.option;
    if (except && except.includes(name)) continue;
    if (input.type === "checkbox") { if (input.checked) parts.push(encodeURIComponent(name)); }
    else if (input.value.trim() !== "") parts.push(encodeURIComponent(name) + "=" + encodeURIComponent(input.value.trim()));
  }
  return parts.join("&");
}
const join = (...qs) => qs.filter((q) => q).join("&");

// ---------------------------------------------------------------- image view
const view = $("view");
const ctx = view.getContext("2d");

function fit() {
  if (!state.width) return;
  const vw = $("viewport").clientWidth;
  view.width = vw;
  view.height = Math.round(vw * state.height / state.width);
  state.zoom = view.width / state.width;
  state.panX = 0; state.panY = 0; state.fitted = true;
  draw();
}

function draw() {
  ctx.imageSmoothingEnabled = false;
  ctx.clearRect(0, 0, view.width, view.height);
  if (!state.image) return;
  const z = state.zoom;
  ctx.drawImage(state.image, state.panX, state.panY, state.width * z, state.height * z);
  if (z >= 8) { // the pixel grid
    ctx.strokeStyle = "rgba(255,255,255,0.25)";
    ctx.lineWidth = 1;
    ctx.beginPath();
    const x0 = Math.max(0, Math.floor(-state.panX / z)), x1 = Math.min(state.width, Math.ceil((view.width - state.panX) / z));
    const y0 = Math.max(0, Math.floor(-state.panY / z)), y1 = Math.min(state.height, Math.ceil((view.height - state.panY) / z));
    for (let x = x0; x <= x1; x++) { const px = Math.round(state.panX + x * z) + 0.5; ctx.moveTo(px, state.panY + y0 * z); ctx.lineTo(px, state.panY + y1 * z); }
    for (let y = y0; y <= y1; y++) { const py = Math.round(state.panY + y * z) + 0.5; ctx.moveTo(state.panX + x0 * z, py); ctx.lineTo(state.panX + x1 * z, py); }
    ctx.stroke();
  }
  if (state.selected) {
    const { x, y } = state.selected;
    const s = Math.max(z, 6);
    ctx.strokeStyle = "#ffd400"; ctx.lineWidth = 2;
    ctx.strokeRect(state.panX + (x + 0.5) * z - s / 2 - 1, state.panY + (y + 0.5) * z - s / 2 - 1, s + 2, s + 2);
  }
  $("zoom-level").textContent = (z >= 1 ? Math.round(z * 10) / 10 : z.toFixed(2)) + "×";
}

// Canvas-pixel position of a mouse event → image pixel (or null outside the image).
function pixelAt(ev) {
  const r = view.getBoundingClientRect();
  const cx = (ev.clientX - r.left) * view.width / r.width, cy = (ev.clientY - r.top) * view.height / r.height;
  const x = Math.floor((cx - state.panX) / state.zoom), y = Math.floor((cy - state.panY) / state.zoom);
  return x >= 0 && y >= 0 && x < state.width && y < state.height ? { x, y, cx, cy } : null;
}

function zoomAt(factor, cx, cy) {
  const z = Math.min(64, Math.max(0.25, state.zoom * factor));
  state.panX = cx - (cx - state.panX) * z / state.zoom;
  state.panY = cy - (cy - state.panY) * z / state.zoom;
  state.zoom = z; state.fitted = false;
  draw();
}

let drag = null;
view.addEventListener("mousedown", (ev) => { drag = { x: ev.clientX, y: ev.clientY, panX: state.panX, panY: state.panY, moved: false }; });
window.addEventListener("mouseup", () => { setTimeout(() => { drag = null; }, 0); });
view.addEventListener("mousemove", (ev) => {
  if (drag && (ev.buttons & 1)) {
    const r = view.getBoundingClientRect(), k = view.width / r.width;
    const dx = (ev.clientX - drag.x) * k, dy = (ev.clientY - drag.y) * k;
    if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
    if (drag.moved) { state.panX = drag.panX + dx; state.panY = drag.panY + dy; state.fitted = false; draw(); }
  }
  const p = pixelAt(ev);
  if (!p || !state.pixels) { $("readout").textContent = "—"; return; }
  const i = 4 * (p.y * state.width + p.x), d = state.pixels.data;
  $("readout").textContent = `(${p.x}, ${p.y})  bytes ${d[i]}, ${d[i + 1]}, ${d[i + 2]}  ${state.kind}`;
});
view.addEventListener("click", (ev) => {
  if (drag && drag.moved) return;
  const p = pixelAt(ev);
  if (p) select(p.x, p.y);
});
view.addEventListener("wheel", (ev) => {
  ev.preventDefault();
  const r = view.getBoundingClientRect();
  zoomAt(ev.deltaY < 0 ? 1.25 : 0.8, (ev.clientX - r.left) * view.width / r.width, (ev.clientY - r.top) * view.height / r.height);
}, { passive: false });
$("zoom-in").addEventListener("click", () => zoomAt(2, view.width / 2, view.height / 2));
$("zoom-out").addEventListener("click", () => zoomAt(0.5, view.width / 2, view.height / 2));
$("zoom-fit").addEventListener("click", fit);
window.addEventListener("resize", () => { if (state.fitted) fit(); });

// ---------------------------------------------------------------- render
async function loadImage(url, signal) {
  const r = await fetch(url, { signal });
  if (r.status === 409) return null; // superseded by a newer render of ours
  if (!r.ok) throw new Error((await r.text()).trim());
  const bmp = await createImageBitmap(await r.blob(), { colorSpaceConversion: "none", premultiplyAlpha: "none" });
  // An AOV's legend: how to read its colours, as `rtlab render --aov` prints it.
  const header = (name) => {
    const v = r.headers.get(name);
    return v === null ? null : decodeURIComponent(v.replace(/\+/g, " "));
  };
  bmp.legend = header("x-rtlab-aov-legend");
  bmp.passOptions = header("x-rtlab-pass-options") || "";
  return bmp;
}

// Shows an image; a preview is stretched to the full image's size `w`×`h` with big pixels.
function show(bmp, kind, query, w, h) {
  w = w || bmp.width; h = h || bmp.height;
  const sized = w !== state.width || h !== state.height;
  const off = new OffscreenCanvas(w, h);
  const octx = off.getContext("2d");
  octx.imageSmoothingEnabled = false;
  octx.drawImage(bmp, 0, 0, w, h);
  state.image = off; state.kind = kind; state.passOptions = bmp.passOptions || "";
  state.width = w; state.height = h;
  state.pixels = octx.getImageData(0, 0, w, h, { colorSpace: "srgb" });
  view.dataset.state = kind;
  view.dataset.query = query;
  if (sized || state.fitted) fit(); else draw();
}

// The legend of the AOV shown (none for the colour image).
function showLegend(text) {
  const l = $("aov-legend");
  l.hidden = !text;
  l.textContent = text ? text + "\nA clicked pixel is explained as the colour image's pixel." : "";
}

function setStatus(text, error) {
  const s = $("render-state");
  s.textContent = text;
  s.className = error ? "error" : "";
}

// The progressive render's passes (`rtlab render --passes K`): pass 1 first, the preview
// (the scene's subsample times 4: one pixel in 4×4 traced, the filter stretched over the
// rest, for a scene that traces every pixel), then pass 2, the scene's
// own settings: the full image; the selected pixel's explanation follows. A newer call
// makes older answers stale (and cancels them on the server).
async function rerender() {
  const my = ++state.generation;
  if (state.controller) state.controller.abort();
  const controller = new AbortController();
  state.controller = controller;
  const q = renderQuery();
  const aov = $("opt-aov") ? $("opt-aov").value : "";
  const own = join(aov ? "aov=" + encodeURIComponent(aov) : "", "stream=" + STREAM);
  const cli = aov ? " --aov " + aov : "";
  const stale = () => my !== state.generation;
  view.dataset.state = "rendering";
  try {
    const t0 = performance.now();
    const info = await getJson("/api/scene?" + q);
    if (stale()) return;
    showSceneInfo(info);
    if (info.width * info.height > 64 * 64) {
      setStatus("pass 1, the preview (4× the scene's subsample)…");
      const p = await loadImage("/api/render.png?" + join(q, "pass=1", own), controller.signal);
      if (stale()) return;
      if (p) {
        show(p, "preview", q);
        showLegend(p.legend);
        setStatus(`pass 1 (preview, = rtlab render --passes 1${cli}) after ${Math.round(performance.now() - t0)} ms; pass 2, the full image…`);
      }
    }
    const img = await loadImage("/api/render.png?" + join(q, own), controller.signal);
    if (stale() || !img) return;
    show(img, "full", q);
    showLegend(img.legend);
    setStatus(`pass 2, the full image (= rtlab render${cli}), ${state.width}×${state.height}, ${Math.round(performance.now() - t0)} ms` + (q ? "  ·  " + q : ""));
    if (state.selected) explain();
    if (!$("steps").hidden) loadSteps();
    await refinePasses(q, own, cli, controller, stale, t0);
  } catch (e) {
    if (e.name === "AbortError" || stale()) return;
    view.dataset.state = "error";
    setStatus(e.message, true);
  }
}

// Passes 3, 4, … after the full image while the "refine for" seconds last (counted from the
// first pass, as render --time-budget counts): each pass is asked for with its deadline, and
// one still running at the deadline is abandoned; the last complete pass stays, with its
// --passes K.
async function refinePasses(q, own, cli, controller, stale, t0) {
  const seconds = Number($("opt-refine").value);
  if (!(seconds > 0)) return;
  const deadline = t0 + seconds * 1000;
  for (let k = 3; ; k++) {
    const left = deadline - performance.now();
    if (left <= 0) { setStatus(statusOf(k - 1, cli, t0, `the ${seconds} s were spent`)); return; }
    const pass = new AbortController();
    const parent = () => pass.abort();
    controller.signal.addEventListener("abort", parent);
    let late = false;
    const timer = setTimeout(() => { late = true; pass.abort(); }, Math.min(left, 2 ** 31 - 1));
    setStatus(statusOf(k - 1, cli, t0, `pass ${k} (4× the samples)…`));
    try {
      const img = await loadImage("/api/render.png?" + join(q, `pass=${k}`, own), pass.signal);
      if (stale() || !img) return;
      show(img, "full", q);
      showLegend(img.legend);
      if (state.selected) explain();
    } catch (e) {
      if (stale()) return;
      if (e.name !== "AbortError" || !late) {
        // The sequence's end (the samplers' or the page's limits): said, and the pass stays.
        setStatus(statusOf(k - 1, cli, t0, `no pass ${k}: ${e.message.replace(/^error: /, "")}`));
        return;
      }
      setStatus(statusOf(k - 1, cli, t0, `pass ${k} abandoned at the ${seconds} s`));
      return;
    } finally {
      clearTimeout(timer);
      controller.signal.removeEventListener("abort", parent);
    }
  }
}

// "pass K (= rtlab render --passes K), …": the pass shown and how to make it again.
function statusOf(k, cli, t0, then) {
  const what = k === 2 ? "the full image" : `${state.passOptions.replace(/&/g, ", ").replace(/=/g, " ")}`;
  return `pass ${k}, ${what} (= rtlab render --passes ${k}${cli}), after ${Math.round(performance.now() - t0)} ms; ${then}`;
}

function showSceneInfo(s) {
  state.sceneInfo = s;
  $("scene-name").textContent = s.file.split(/[\\/]/).pop();
  $("scene-name").title = s.file + " (watched: save it to re-render)";
  const obj = s.objects.map((o) => `${o.name} (${o.shape}, ${o.material})`).join(", ");
  const lights = s.lights.map((l) => `${l.name} (${l.kind})`).join(", ");
  $("scene-info").textContent = `${s.width}×${s.height}, ${s.render.spp} spp ${s.render.sampler}, max depth ${s.render.max_depth} · objects: ${obj} · lights: ${lights} · ${s.materials.length} material(s)`;
}

// ---------------------------------------------------------------- explanation
function select(x, y) {
  state.selected = { x, y };
  state.highlight = null;
  draw();
  explain();
}

async function explain() {
  const { x, y } = state.selected;
  const q = shownQuery();
  // Only the newest request's answer is shown (refining asks again for every pass).
  const my = ++state.explaining;
  try {
    const e = await getJson(`/api/explain?${join(`x=${x}&y=${y}`, q)}`);
    if (my !== state.explaining) return;
    state.explanation = e;
    state.explainedQuery = q; // what the diagram draws with, the explanation's own settings
    $("explanation").dataset.query = q;
    const own = e.samples.findIndex((s) => s.pixel[0] === x && s.pixel[1] === y);
    state.sample = Math.max(0, own);
    showExplanation();
  } catch (err) {
    $("explain-empty").hidden = false;
    if (my !== state.explaining) return;
    $("explain-empty").className = "error";
    $("explain-empty").textContent = err.message;
    $("explanation").hidden = true;
  }
}

// The colour a ray's ledger adds up to: ambient + Σ lights (diffuse + specular) + reflected
// + transmitted, clamped when the tracer clamped it. A miss is the background.
function ledgerSum(ray) {
  const s = ray.shading;
  if (!s) return ray.color;
  let c = s.ambient;
  for (const l of s.lights) c = add(c, add(l.diffuse, l.specular));
  c = add(add(c, s.reflected), s.transmitted);
  if (ray.clamped) c = c.map((v) => Math.min(1, Math.max(0, v)));
  return c;
}

function showExplanation() {
  const e = state.explanation;
  $("explain-empty").hidden = true;
  $("explanation").hidden = false;
  const [x, y] = e.pixel;
  $("px-title").textContent = `Pixel (${x}, ${y})`;
  $("px-summary").replaceChildren(swatch(e.color), ` colour ${vec(e.color)} → bytes ${e.encoded.join(", ")}`);
  showSamples(e);
  const s = e.samples[state.sample];
  if (!s) { $("generation").textContent = "this pixel traces no samples of its own"; showBundle(null); return; }
  showGeneration(s);
  showLedger(s);
  showDiagram();
  showBundle(s);
  $("tree").replaceChildren(rayTree(s.ray, { n: 0 }));
}

function showSamples(e) {
  const rows = [];
  let sum = [0, 0, 0];
  e.samples.forEach((s, i) => {
    const c = ledgerSum(s.ray);
    sum = add(sum, scale(c, s.weight));
    const tr = el("tr", { class: i === state.sample ? "sel" : "" },
      el("td", {}, el("input", { type: "radio", name: "sample", ...(i === state.sample ? { checked: "" } : {}),
        onchange: () => { state.sample = i; state.highlight = null; showExplanation(); } })),
      el("td", {}, `${s.index}` + (s.pixel[0] !== e.pixel[0] || s.pixel[1] !== e.pixel[1] ? ` of (${s.pixel})` : "")),
      el("td", { class: "num" }, vec(s.film)),
      el("td", { class: "num" }, num(s.weight)),
      el("td", { class: "num" }, swatch(c), " ", vec(c)));
    rows.push(tr);
  });
  const total = el("tr", { class: "sum" }, el("td", {}), el("td", { colspan: 3 }, "pixel = Σ weight × sample colour"),
    el("td", { class: "num", id: "pixel-sum", "data-rgb": sum.join(",") }, swatch(sum), " ", vec(sum)));
  $("samples").replaceChildren(el("table", {},
    el("tr", {}, el("th", {}), el("th", {}, "sample"), el("th", {}, "film point"), el("th", {}, "weight"), el("th", {}, "colour (its ledger's sum)")),
    ...rows, total),
    el("p", { class: "hint" }, `bytes: ${e.encoded.join(", ")} (the pixel's colour encoded as the render encodes it)`));
}

function showGeneration(s) {
  const r = s.ray, c = s.camera;
  $("generation").replaceChildren(el("ol", {},
    el("li", {}, `sample point on the film: ${vec(s.film)} (pixel ${s.pixel[0]}, ${s.pixel[1]} plus the sampler's offset)`),
    el("li", {}, `normalised device coordinates, x and y scaled to [−1, 1]: ${vec(c.ndc)}`),
    el("li", {}, `on the canonical view volume's far plane z = −1: ${vec(c.film_point)}`),
    el("li", {}, `back to world space by the inverse normalising transformation: ${vec(c.world_point)}`),
    el("li", {}, `eye P = ${vec(r.origin)}, direction d = normalise(world point − P) = ${vec(r.direction)}`),
    el("li", {}, `points on the ray: P + t·d, t ≥ 0`)));
}

// The specular exponent n of the object's material, from the scene's description ("n" when
// it is not known).
function shininess(object) {
  const info = state.sceneInfo;
  const o = info && info.objects.find((x) => x.name === object);
  const m = o && info.materials.find((x) => x.name === o.material);
  return m && typeof m.shininess === "number" ? num(m.shininess) : "n";
}

function showLedger(s) {
  const r = s.ray;
  if (!r.shading) {
    $("ledger").replaceChildren(el("p", {}, `The camera ray misses everything: the background ${vec(r.color)}.`));
    return;
  }
  const sh = r.shading, rows = [];
  const row = (term, how, c, cls) => rows.push(el("tr", { class: cls || "" }, el("td", {}, term), el("td", {}, how), el("td", { class: "num" }, swatch(c), " ", vec(c))));
  row("ambient", "ka·La·Oa", sh.ambient);
  for (const l of sh.lights) {
    const vis = l.visible ? (l.visibility < 1 ? `, ${num(l.visibility)} of it visible` : "") : ", in shadow";
    row(`light ${l.light}: diffuse`, `f_att ${num(l.attenuation)} · n·l ${num(l.n_dot_l)}${l.spot !== 1 ? " · spot " + num(l.spot) : ""}${vis}`, l.diffuse);
    row(`light ${l.light}: specular`, `(r·v)^n = ${num(l.r_dot_v)}^${shininess(r.hit.object)} = ${num(l.r_dot_v_pow)}`, l.specular);
  }
  for (const l of sh.ignored_lights || []) row(`light ${l.light} (ignored)`, "left out by the settings: not added", add(l.diffuse, l.specular), "ignored");
  row("reflected", "ks·Or·I_r (the reflection ray's colour × its weight)", sh.reflected);
  row("transmitted", "kt·Ot·I_t (the refraction ray's colour × its weight)", sh.transmitted);
  const sum = ledgerSum(r);
  rows.push(el("tr", { class: "sum" }, el("td", {}, "sum"), el("td", {}, r.clamped ? "clamped to [0, 1]" : "= this sample's colour"),
    el("td", { class: "num", id: "ledger-sum", "data-rgb": sum.join(",") }, swatch(sum), " ", vec(sum))));
  $("ledger").replaceChildren(el("table", {}, ...rows),
    el("p", { class: "hint" }, `hit ${r.hit.object} at t = ${num(r.hit.t)}; the tracer's colour for this ray: ${vec(r.color)}`));
}

function showDiagram() {
  const { x, y } = state.selected;
  const hl = state.highlight === null ? "" : `highlight=${state.highlight}`;
  $("diagram").src = `/api/diagram.png?${join(`x=${x}&y=${y}`, `sample=${state.sample}`, "plane=" + $("plane").value, hl, state.explainedQuery)}`;
}
$("plane").addEventListener("change", () => { if (state.selected) showDiagram(); });

// The bundle of camera rays sample `s` was traced in (`rtlab explain --bundle-diagram
// --sample K`, chapter 13), or the CLI's one line saying why there is none (--traversal
// single, the adaptive sampler, a scene without a mesh); nothing for no sample. Only the
// newest request is shown, and a newer one aborts the one before.
async function showBundle(s) {
  const my = ++state.bundling;
  const img = $("bundle"), why = $("bundle-why");
  if (state.bundleAbort) state.bundleAbort.abort();
  state.bundleAbort = null;
  if (!s) {
    if (img.src.startsWith("blob:")) URL.revokeObjectURL(img.src);
    img.removeAttribute("src");
    img.hidden = true;
    why.hidden = true;
    return;
  }
  const abort = new AbortController();
  state.bundleAbort = abort;
  const url = `/api/bundle.png?${join(`x=${s.pixel[0]}&y=${s.pixel[1]}`, `index=${s.index}`, state.explainedQuery)}`;
  try {
    const r = await fetch(url, { signal: abort.signal });
    if (!r.ok) throw new Error((await r.text()).trim().replace(/^error: (argument [^:]+: )?/, ""));
    const blob = await r.blob();
    if (my !== state.bundling) return;
    if (img.src.startsWith("blob:")) URL.revokeObjectURL(img.src);
    img.src = URL.createObjectURL(blob);
    img.hidden = false;
    why.hidden = true;
  } catch (err) {
    if (my !== state.bundling || err.name === "AbortError") return;
    const m = err.message;
    why.textContent = m.charAt(0).toUpperCase() + m.slice(1) + (m.endsWith(".") ? "" : ".");
    why.hidden = false;
    img.hidden = true;
  }
}

function rayTitle(r) {
  const kind = { camera: "camera ray", shadow: "shadow ray", reflection: "reflection ray", refraction: "refraction ray", transmission: "transmission ray" }[r.kind] || r.kind;
  let what;
  if (r.kind === "shadow") what = r.hit ? `blocked by ${r.hit.object} at t = ${num(r.hit.t)}` : "reaches the light";
  else if (r.hit) what = `hits ${r.hit.object} at t = ${num(r.hit.t)}`;
  else what = "misses: background";
  const end = { miss: "", blocked: "", shaded: "", max_depth: ", stops: maximum depth", cutoff: ", stops: contribution too small", total_internal_reflection: ", total internal reflection" }[r.end] ?? (r.end ? ", " + r.end : "");
  return `${kind}, depth ${r.depth}${r.channel ? " (" + r.channel + ")" : ""}: ${what}${end}`;
}

// The ray tree, numbered in the order the tracer cast the rays (the diagram's order).
function rayTree(r, counter) {
  const k = counter.n++;
  const label = el("span", { class: "ray-label" + (state.highlight === k ? " highlighted" : ""), "data-ray": k, title: "draw this ray in bold in the diagram" }, `#${k + 1} ${rayTitle(r)}`);
  label.addEventListener("click", (ev) => {
    ev.preventDefault();
    state.highlight = state.highlight === k ? null : k;
    document.querySelectorAll(".ray-label").forEach((l) => l.classList.toggle("highlighted", Number(l.dataset.ray) === state.highlight));
    showDiagram();
  });
  const d = el("details", { class: "ray " + r.kind, open: "" }, el("summary", {}, label, " ", swatch(r.color)));
  d.append(el("div", { class: "mono hint" }, `P = ${vec(r.origin)}, d = ${vec(r.direction)}${r.weight ? ", weight " + vec(r.weight) : ""}, colour ${vec(r.color)}`));
  for (const t of r.tests) d.append(testWorking(t, r.hit));
  if (r.hit) {
    const h = r.hit;
    d.append(el("div", {}, `hit: point ${vec(h.point)}, normal ${vec(h.normal)} (${h.surface}); object space: point ${vec(h.object_space.point)}, normal ${vec(h.object_space.normal)}` +
      (h.barycentric ? `; barycentric (α, β, γ) = ${vec(h.barycentric)}` : "")));
  }
  for (const c of r.children) d.append(rayTree(c, counter));
  return d;
}

// One intersection test with its working: the quadratic, D and the roots; each candidate t
// kept or tossed and why; Cramer's rule for triangles.
function testWorking(t, hit) {
  const won = hit && hit.object === t.object && t.t !== null && Math.abs(t.t - hit.t) < 1e-12;
  // A hit farther than one already found is not the test's answer (t is null), but it is
  // not a miss either: say so, as the text of explain does.
  const farther = t.t === null && (t.candidates || []).find((c) => (c.note || "").startsWith("tossed: farther"));
  const found = t.t !== null ? `t = ${num(t.t)}` : farther ? `t = ${num(farther.t)}, farther than a hit already found` : "no hit";
  const summary = `test ${t.object} (${t.shape}): ${found}` + (won ? " — closest, the hit" : "");
  const d = el("details", { class: "test" }, el("summary", {}, summary));
  if (t.quadratic) {
    const q = t.quadratic;
    const verdict = { two: "two real roots", tangent: q.rounded_to_zero ? "tangent (D was tiny and taken as 0)" : "tangent (D = 0)", one: "a = 0: linear, one root", none: "D < 0: no real root, the ray misses" }[q.roots] || q.roots;
    d.append(el("div", { class: "mono" }, `${q.surface}: a t² + b t + c = 0 with a = ${num(q.a)}, b = ${num(q.b)}, c = ${num(q.c)}`),
      el("div", { class: "mono" }, `D = b² − 4ac = ${num(q.discriminant)} → ${verdict}`));
  }
  if (t.barycentric) {
    const b = t.barycentric;
    d.append(el("div", { class: "mono" }, `Cramer's rule: det = ${num(b.determinant)}, β = ${num(b.beta)}, γ = ${num(b.gamma)}, α = 1 − β − γ = ${num(b.alpha)}, t = ${num(b.t)}` +
      " (inside iff β ≥ 0, γ ≥ 0, β + γ ≤ 1)"));
  }
  if (t.triangles_tested !== undefined) d.append(el("div", {}, `${t.triangles_tested} triangle(s) tested` + (t.mesh_bvh_nodes !== undefined ? `, ${t.mesh_bvh_nodes} mesh BVH nodes` : "")));
  if (t.candidates.length) {
    d.append(el("ul", {}, ...t.candidates.map((c) => {
      const kept = c.note.startsWith("kept");
      return el("li", { class: kept ? "kept" : "tossed" }, `t = ${num(c.t)} on ${c.surface}, point ${vec(c.point)}: ${c.note}`);
    })));
  }
  if (t.csg) d.append(el("pre", { class: "mono" }, JSON.stringify(t.csg, null, 1).slice(0, 4000)));
  if (t.blob) d.append(el("div", { class: "hint" }, "blob: root search recorded (see rtlab explain --format text)"));
  return d;
}

// ---------------------------------------------------------------- steps
let steps = [];
async function loadSteps() {
  try {
    $("steps-caption").textContent = "rendering the steps…";
    steps = await getJson("/api/steps?" + renderQuery());
    const s = $("steps-slider");
    s.max = String(Math.max(0, steps.length - 1));
    if (Number(s.value) > steps.length - 1) s.value = "0";
    showStep();
  } catch (e) { $("steps-caption").textContent = e.message; }
}
function showStep() {
  const i = Number($("steps-slider").value);
  if (!steps[i]) return;
  $("steps-count").textContent = `${i + 1} / ${steps.length}`;
  $("steps-caption").textContent = steps[i].caption;
  $("steps-frame").src = `/api/steps/frame.png?${join("i=" + i, renderQuery())}`;
}
$("steps-slider").addEventListener("input", showStep);
let playing = null;
$("steps-play").addEventListener("click", () => {
  if (playing) { clearInterval(playing); playing = null; $("steps-play").textContent = "play"; return; }
  $("steps-play").textContent = "pause";
  playing = setInterval(() => {
    const s = $("steps-slider");
    s.value = String((Number(s.value) + 1) % Math.max(1, steps.length));
    showStep();
  }, 1200);
});

// ---------------------------------------------------------------- compare
// A comparison's two renders run on streams of their own: a newer comparison cancels them on
// the server, and so does leaving the tab (`stopCompare`), so that they do not hold the
// server's threads while Explore waits for an explanation.
let compareController = null;
function stopCompare() {
  if (compareController) compareController.abort();
  compareController = null;
}

async function runCompare() {
  $("cmp-error").textContent = "";
  $("cmp-count").textContent = "";
  stopCompare();
  const controller = new AbortController();
  compareController = controller;
  const base = renderQuery();
  try {
    const [a, b] = await Promise.all(["cmp-a", "cmp-b"].map((id) =>
      loadImage("/api/render.png?" + join(base, $(id).value.trim(), `stream=${STREAM}-${id}`), controller.signal)));
    if (!a || !b || controller.signal.aborted) return;
    if (a.width !== b.width || a.height !== b.height) {
      $("cmp-error").textContent = `A is ${a.width}×${a.height} and B ${b.width}×${b.height}: only images of one size compare pixel by pixel`;
      return;
    }
    const put = (img, bmp) => { const c = document.createElement("canvas"); c.width = bmp.width; c.height = bmp.height; c.getContext("2d").drawImage(bmp, 0, 0); img.src = c.toDataURL(); return c.getContext("2d").getImageData(0, 0, bmp.width, bmp.height); };
    const da = put($("cmp-img-a"), a), db = put($("cmp-img-b"), b);
    const diff = $("cmp-diff");
    diff.width = a.width; diff.height = a.height;
    const out = diff.getContext("2d").createImageData(a.width, a.height);
    let count = 0;
    for (let i = 0; i < da.data.length; i += 4) {
      let any = false;
      for (let c = 0; c < 3; c++) { const v = Math.abs(da.data[i + c] - db.data[i + c]); out.data[i + c] = Math.min(255, 4 * v); any = any || v > 0; }
      out.data[i + 3] = 255; count += any;
    }
    diff.getContext("2d").putImageData(out, 0, 0);
    $("cmp-count").textContent = `(${count} of ${a.width * a.height} pixels differ)`;
  } catch (e) {
    controller.abort(); // the other render of the two, if still running
    if (e.name !== "AbortError") $("cmp-error").textContent = e.message;
  }
}
$("cmp-run").addEventListener("click", runCompare);

// ---------------------------------------------------------------- diff
async function runDiff(file) {
  $("diff-error").textContent = "";
  $("diff-result").hidden = true;
  if (!file) return;
  if (file.size > 16 * 1024 * 1024) { $("diff-error").textContent = "the image is larger than 16 MB"; return; }
  const q = join(renderQuery(), "tolerance=" + encodeURIComponent($("diff-tolerance").value));
  try {
    const body = await file.arrayBuffer();
    const post = (extra) => fetch("/api/diff?" + join(q, extra), { method: "POST", body, headers: { "Content-Type": "image/png" } });
    const r = await post("");
    const text = await r.text();
    if (!r.ok) { $("diff-error").textContent = text; return; }
    const rep = JSON.parse(text);
    const m = rep.metrics;
    $("diff-verdict").textContent = rep.verdict === "same"
      ? `same: ${m.diff_percent} % of the pixels differ by more than ${m.tolerance} levels`
      : `different: ${m.diff_percent} % of the pixels differ by more than ${m.tolerance} levels (largest ${m.max}); ${rep.regions_found} region(s)`;
    $("diff-diagnosis").textContent = rep.diagnosis.length
      ? "most likely: " + rep.diagnosis.map((d) => `${d.names.join(" + ")} (regions ${d.regions.join(", ")})`).join("; ")
      : "";
    const rows = rep.regions.map((g, i) => el("tr", {},
      el("td", {}, String(i + 1)),
      el("td", {}, String(g.pixels)),
      el("td", {}, g.objects.map((o) => `${o.name} (${o.surfaces.join(", ")})`).join(", ")),
      el("td", { class: "num" }, "(" + g.mean_difference.map((v) => (v > 0 ? "+" : "") + v).join(", ") + ")"),
      el("td", {}, g.terms.length && g.terms_explained >= 0.5 ? `${g.terms[0].says} (${Math.round(100 * g.terms[0].explained)} %)` : "—"),
      el("td", {}, g.mistakes.length ? `${g.mistakes[0].names.join(" + ")} (${Math.round(100 * g.mistakes[0].explained)} %)` : "—"),
      el("td", {}, el("button", { type: "button", class: "diff-show", onclick: () => showPixel(g.pixel[0], g.pixel[1]) }, `explain ${g.pixel[0]},${g.pixel[1]}`))));
    $("diff-regions").replaceChildren(rows.length ? el("table", {},
      el("tr", {}, ...["region", "pixels", "objects", "yours − expected", "best term", "best mistake", "what it should be"].map((h) => el("th", {}, h))),
      ...rows) : "");
    $("diff-result").hidden = false;
    const f = await post("format=png");
    if (f.ok) $("diff-figure").src = URL.createObjectURL(await f.blob());
  } catch (e) { $("diff-error").textContent = e.message; }
}
function showPixel(x, y) {
  document.querySelector('nav button[data-mode="explore"]').click();
  select(x, y);
}
$("diff-file").addEventListener("change", () => runDiff($("diff-file").files[0]));
$("diff").addEventListener("dragover", (ev) => ev.preventDefault());
$("diff").addEventListener("drop", (ev) => { ev.preventDefault(); runDiff(ev.dataTransfer.files[0]); });
window.rtlabDiff = runDiff;

// ---------------------------------------------------------------- modes, live scene
for (const b of document.querySelectorAll("nav button")) {
  b.addEventListener("click", () => {
    document.querySelectorAll("nav button").forEach((x) => x.classList.toggle("on", x === b));
    for (const m of ["explore", "steps", "compare", "diff"]) $(m).hidden = m !== b.dataset.mode;
    if (b.dataset.mode === "steps") loadSteps();
    if (b.dataset.mode === "compare") runCompare(); else stopCompare();
    if (b.dataset.mode === "explore" && state.fitted) fit();
  });
}
$("big").addEventListener("change", () => document.body.classList.toggle("big", $("big").checked));

function listen() {
  const events = new EventSource("/api/events");
  events.addEventListener("scene", (ev) => {
    const s = JSON.parse(ev.data);
    const banner = $("scene-error");
    if (s.error) {
      banner.hidden = false;
      banner.textContent = s.error + "\n(the last good image stays; fix the file and save)";
      document.body.dataset.sceneError = "1";
      return;
    }
    banner.hidden = true;
    delete document.body.dataset.sceneError;
    if (s.version !== state.version) {
      const first = state.version === 0;
      state.version = s.version;
      document.body.dataset.version = String(s.version);
      if (!first) rerender();
    }
  });
}

// Hooks for the browser tests (and the curious): the shown image's bytes, base64 RGB.
window.rtlab = {
  state,
  rgbBase64() {
    const d = state.pixels.data, out = new Uint8Array(d.length / 4 * 3);
    for (let i = 0, j = 0; i < d.length; i += 4) { out[j++] = d[i]; out[j++] = d[i + 1]; out[j++] = d[i + 2]; }
    let s = "";
    for (let i = 0; i < out.length; i += 0x8000) s += String.fromCharCode.apply(null, out.subarray(i, i + 0x8000));
    return btoa(s);
  },
  // Client coordinates of pixel (x, y)'s centre, for a real click there.
  clientPoint(x, y) {
    const r = view.getBoundingClientRect();
    return [r.left + (state.panX + (x + 0.5) * state.zoom) * r.width / view.width,
      r.top + (state.panY + (y + 0.5) * state.zoom) * r.height / view.height];
  },
};

(async function start() {
  try { await buildControls(); } catch (e) { setStatus(e.message, true); }
  listen();
  await rerender();
})();
