// The studio page: loop controls, the 2D editor and the 3D view over the server's session.
// Lengths sent to the server are metres; the page shows centimetres.
import { Editor } from "/static/editor.js";
import { View3D } from "/static/view3d.js";
import { getArrays } from "/static/arrays.js";
import { FabricEditor } from "/static/fabric.js";
import { SeamTool } from "/static/seams.js";

const $ = (id) => document.getElementById(id);
// revision: the session version this tab last saw; stale: another tab changed the session
// since (this tab must reload); fields: the session fields last shown
const studio = { state: null, geometry: null, revision: null, dragStats: {}, stale: false, fields: null };
window.studio = studio;

// The banner: ``cause`` names what the message is about ("edit", "drape", "export",
// "upload", "session"); done(cause) clears it once that cause is gone (the next edit
// applied, the next drape started, ...), so no banner outlives what it says.
function message(text, kind = "error", cause = null) {
  $("message-text").textContent = text || ""; $("message").className = text ? kind : "hidden";
  $("reload-btn").hidden = kind !== "stale";
  studio.messageCause = text ? cause : null;
}
function done(...causes) {
  if (!studio.stale && causes.includes(studio.messageCause)) message("");
}

// This tab missed a change made in another tab: the server refused the change (409) and
// nothing was applied; the tab is told to reload rather than stack its change on top.
function staleNotice(text) {
  studio.stale = true;
  message(text || "the session was changed in another tab: reload this tab to see it", "stale");
}
function fail(e, cause = null) { if (e.stale) staleNotice(e.message); else message(e.message, "error", cause); }
$("reload-btn").onclick = async () => {
  studio.stale = false; message(""); studio.fields = null;
  try { await refresh(); view.setBody(await getArrays("/api/body")); } catch (e) { fail(e); }
};

// The token the server embedded in this page: every request that changes something (and
// every export) carries it, so that no other site's page can drive the studio.
const TOKEN = document.querySelector('meta[name="patternfit-token"]').content;
const TOKEN_HEADERS = { "X-Patternfit-Token": TOKEN };
const JSON_HEADERS = { ...TOKEN_HEADERS, "Content-Type": "application/json" };

// Every state-changing request carries the session version this tab last saw
// (``versioned``): the server refuses it with 409 when another tab changed the session since.
async function api(path, { method = "GET", json, form, versioned = method !== "GET" } = {}) {
  const opts = { method };
  if (method !== "GET") {
    opts.headers = form ? TOKEN_HEADERS : JSON_HEADERS;
    const seen = versioned && studio.revision !== null ? studio.revision : undefined;
    if (form) {
      opts.body = form;
      if (seen !== undefined) path += `${path.includes("?") ? "&" : "?"}revision=${seen}`;
    } else {
      opts.body = JSON.stringify({ ...(json || {}), ...(seen !== undefined ? { revision: seen } : {}) });
    }
  }
  const r = await fetch(path, opts);
  const body = r.headers.get("content-type")?.includes("json") ? await r.json() : null;
  if (!r.ok) {
    const err = new Error((body && body.error) || `${r.status} ${r.statusText}`);
    err.stale = r.status === 409 && !!(body && body.stale);
    if (err.stale) staleNotice(err.message);
    throw err;
  }
  if (body && body.revision !== undefined) studio.revision = body.revision;
  return body;
}

const editor = new Editor($("mesh2d"), $("overlay"), {
  onDrag: dragPreview, onDrop: (h, offset) => applyEdit(h, offset),
  onSelect: (h) => { $("selected").textContent = `selected: ${h.key} (${h.op.replace("_", " ")})`; done("edit"); },
  onClickPanel: insertDart, scaleEl: $("scale"), readoutEl: $("readout"),
  onPick: () => seamTool.showPicked(),
  onTape: (text) => { $("tape-readout").textContent = text ? `tape: ${text}` : "drag from one point to another; shift-drag pans"; },
});
$("fit-btn").onclick = () => editor.fit();
const seamTool = new SeamTool({ editor, edit: (op, args) => edit(op, args), api: (path) => api(path) });
studio.seamTool = seamTool;
studio.editor = editor;
const view = new View3D($("view3d"), {
  onHover: (t, value) => {
    editor.highlight(t);
    $("hover-value").textContent = value === null ? "" :
      (view.map === "area_change" ? `area change ${(100 * value).toFixed(1)} %` : `${view.map} stretch ${(100 * value).toFixed(1)} %`);
  },
});

// -- loading ----------------------------------------------------------------------------
// The state and the geometry are asked for at once (the page load: together with the
// options, the body, the garment and the verdict), the garment and the verdict otherwise as
// soon as the state says they changed; the meshes are drawn once all of them are there (in
// headless Chromium each frame drawn in between is a slow software-rendered frame).
function fetchState({ geometry = true } = {}) {
  return { state: api("/api/state"), geometry: geometry ? getArrays("/api/geometry") : null };
}

async function refresh({ geometry = true, fetched = null } = {}) {
  const asked = fetched || fetchState({ geometry });
  const s = await asked.state;
  studio.revision = s.revision;
  showFields(s.fields);
  const r = s.fitting_ratio;
  // a drape that failed its checks (off the body, collapsed, ...) is no fit: red, "failed"
  // and why, never green; a stopped drape recorded nothing: ϖ stays unknown, "stopped"
  $("ratio").textContent = r === null ? (s.stopped ? "— stopped" : "—") : (s.failed ? `failed: ${clip(s.failed, 90)}` : `${(100 * r).toFixed(2)} %`);
  $("ratio").dataset.value = r === null ? "" : r;
  $("ratio").className = r === null ? (s.stopped ? "stopped" : "") : (s.failed ? "failed" : (r >= s.threshold ? "fits" : "off"));
  $("ratio").style.color = s.failed ? FAILED_RED : "";
  $("ratio").title = s.failed ? `the drape failed: ${s.failed} (ϖ ${(100 * r).toFixed(2)} % is not a fit)` :
    (s.stopped ? "the drape of this state was stopped before it finished: nothing of it was recorded" : "");
  $("source").textContent = `${s.info.source || ""} · ${s.info.body || ""} · ${s.fabric} · ${s.triangles} triangles`;
  $("history").innerHTML = "";
  for (const h of s.history) {
    const li = document.createElement("li");
    li.textContent = `${h.label}  ${h.fitting_ratio === null ? (h.stopped ? "drape stopped, ϖ unknown" : "") : (h.failed ? "failed: " + clip(h.failed, 60) : "ϖ " + (100 * h.fitting_ratio).toFixed(1) + " %")}`;
    li.className = (h.current ? "current" : "") + (h.stopped ? " stopped" : "");
    if (h.failed) { li.style.color = FAILED_RED; li.title = `the drape failed: ${h.failed}`; }
    $("history").appendChild(li);
  }
  drawRatioHistory(s.history);
  $("undo-btn").disabled = !s.can_undo; $("redo-btn").disabled = !s.can_redo;
  if (s.save_error) message(s.save_error, "error", "save"); else done("save");
  $("drape-btn").textContent = s.draped || s.history.some((h) => h.fitting_ratio !== null) ? "Re-drape" : "Drape";
  if (geometry) {
    // the garment is fetched when its drape changed (an edit keeps the drape: it is only
    // marked "not re-draped"), at the same time as the geometry
    const garmentChanged = s.drape_id !== studio.drapeId || !s.draped;
    const garment = garmentChanged && s.draped ? (asked.garment || getArrays("/api/garment3d")) : null;
    const verdictKey = `${s.drape_id}/${s.maps_stale}`;
    const verdict = verdictKey === studio.verdictKey ? null :
      (s.draped && !s.maps_stale ? (asked.verdict || api("/api/verdict")) : Promise.resolve({}));
    if (verdict) verdict.catch(() => {});  // awaited below: a refusal is reported there
    const [geo, garmentData] = await Promise.all([asked.geometry, garment]);
    studio.geometry = geo;
    editor.setGeometry(studio.geometry);
    seamTool.show();
    $("grade-panel").innerHTML = studio.geometry.panel_names.map((n) => `<option>${n}</option>`).join("");
    if (garmentChanged) {
      view.setGarment(garmentData);
      studio.drapeId = s.drape_id;
    }
    view.setStale(s.maps_stale);
    if (verdict) {
      studio.verdictKey = verdictKey;
      showVerdict(await verdict);  // words only: drawn after the meshes
    }
    showLegend();
  }
  // maps of a drape older than the pattern: greyed, and said so
  $("stale-2d").hidden = !(s.maps_stale && studio.geometry && studio.geometry.colors);
  $("stale-3d").hidden = !(s.maps_stale && s.draped);
  studio.state = s;  // set last: the page is consistent with it from here on
  if (s.drape.running) pollDrape();
}

// The session fields (garment, size, body, fabric, engine, triangles) show the session's
// own values: set on load and whenever the session's change (a new session, an upload,
// another tab), not on every refresh, so that a choice being made for "New session" stays.
function showFields(fields) {
  const key = JSON.stringify(fields);
  if (!fields || studio.fields === key) return;
  studio.fields = key;
  for (const k of ["garment", "size", "body", "fabric", "engine"]) {
    const sel = $(k), v = String(fields[k]);
    for (const o of [...sel.options]) if (o.dataset.uploaded) o.remove();
    if (![...sel.options].some((o) => o.value === v)) {
      // an uploaded body or fabric is no preset: shown, marked, and refused by "New session"
      const o = document.createElement("option");
      o.value = v; o.textContent = `${v} (opened file)`; o.dataset.uploaded = "1";
      sel.appendChild(o);
    }
    sel.value = v;
  }
  $("triangles").value = fields.triangles;
}

// the report's fit verdict, where it gives one: the overall word and why, and the regions
// that do not fit (with their ease); every region, with its reason, on hover
function showVerdict(v) {
  const el = $("verdict"), regions = Object.entries(v.region_verdicts || {});
  el.hidden = v.verdict === undefined && !regions.length;
  const word = (x) => (typeof x === "string" ? x : String(x.verdict));
  const ease = (x) => (x && typeof x.ease_cm === "number" ? ` (${x.ease_cm >= 0 ? "+" : ""}${x.ease_cm.toFixed(1)} cm)` : "");
  const off = regions.filter(([, x]) => word(x) !== "fits").map(([k, x]) => `${k}: ${word(x)}${ease(x)}`);
  el.textContent = el.hidden ? "" : [v.verdict !== undefined ? `verdict: ${v.verdict}` : "",
    v.verdict_reason ? clip(String(v.verdict_reason), 120) : "", off.join(" · ")].filter(Boolean).join("\n");
  el.title = regions.map(([k, x]) => `${k}: ${word(x)}${ease(x)}${x && x.reason ? " — " + x.reason : ""}`).join("\n");
}

const FAILED_RED = "#ff6b6b";
const clip = (text, n) => (text.length > n ? text.slice(0, n - 1) + "…" : text);

function drawRatioHistory(history) {
  const svg = $("ratio-history"), W = 160, H = 36;
  const pts = history.map((h, i) => [i, h.fitting_ratio, h.failed]).filter((p) => p[1] !== null);
  if (!pts.length) { svg.innerHTML = ""; return; }
  const lo = Math.min(...pts.map((p) => p[1]), 0.9), hi = Math.max(...pts.map((p) => p[1]), 1.0);
  const n = Math.max(history.length - 1, 1);
  const xy = pts.map(([i, r]) => [4 + (i / n) * (W - 8), H - 4 - ((r - lo) / (hi - lo || 1)) * (H - 8)]);
  svg.innerHTML = `<polyline points="${xy.map((p) => p.join(",")).join(" ")}" fill="none" stroke="#9fdc8f" stroke-width="2"/>` +
    xy.map((p, k) => `<circle cx="${p[0]}" cy="${p[1]}" r="2.5" fill="${pts[k][2] ? FAILED_RED : "#fff"}"/>`).join("");
}

function showLegend() {
  const data = view.data, ul = $("legend");
  ul.innerHTML = "";
  if (!data) return;
  for (const row of data.maps[view.map].legend) {
    const li = document.createElement("li");
    li.innerHTML = `<span class="swatch" style="background:rgb(${row.rgb.join(",")})"></span>${row.label}`;
    ul.appendChild(li);
  }
}

// -- editing ----------------------------------------------------------------------------
// inflight: a drag preview asked for and not answered yet
let inflight = false;

function dragArgs(h, offset) {
  const args = { ...h.args, offset };
  if (h.partner) args.partner = $("partner").checked;
  return args;
}

// Live drag: exact previews from the server, asked for by a worker (drag_worker.js: one
// request in flight, the newest offset wins, whatever the main thread is busy with) and,
// between them, the mesh moved on the page by the drag's linear basis (how every vertex
// moves per metre of offset), redrawn once per animation frame.
let live = null, drags = 0;
const dragWorker = new Worker("/static/drag_worker.js");
dragWorker.postMessage({ token: TOKEN });
dragWorker.onmessage = (e) => previewArrived(e.data);

function dragPreview(h, offset) {
  if (!live || live.h !== h) startLive(h);
  live.offset = offset;
  inflight = true;
  dragWorker.postMessage({ id: live.id, req: { op: h.op, args: dragArgs(h, offset) } });
  if (!live.raf) live.raf = requestAnimationFrame(drawLive);
}

// the drag is over (dropped or cancelled): a preview still on its way is dropped
function endLive() {
  live = null;
  dragWorker.postMessage({ cancel: true });
}

function startLive(h) {
  const me = { h, id: ++drags, base: Float32Array.from(studio.geometry.vertices), baseOffset: [0, 0], basis: null, offset: [0, 0], raf: 0 };
  live = me;
  fetch("/api/drag/basis", { method: "POST", headers: JSON_HEADERS, body: JSON.stringify({ op: h.op, args: dragArgs(h, [0, 0]) }) })
    .then((r) => (r.ok ? r.arrayBuffer() : null))
    .then((b) => {
      const basis = b && new Float32Array(b);
      if (basis && live === me && basis.every(Number.isFinite)) me.basis = basis;  // checked once
    });
}

function drawLive() {
  const L = live;
  if (!L) return;
  L.raf = 0;
  const t0 = performance.now();
  let v = L.base;
  if (L.basis) {
    const n = v.length, dx = L.offset[0] - L.baseOffset[0], dy = L.offset[1] - L.baseOffset[1];
    if (!L.shown || L.shown.length !== n) L.shown = new Float32Array(n);  // one buffer a drag
    v = L.shown;
    for (let i = 0; i < n; i++) v[i] = L.base[i] + L.basis[i] * dx + L.basis[n + i] * dy;
  }
  editor.setPreview(v, { moved: L.moved, trusted: true });
  const st = studio.dragStats, t1 = performance.now();
  st.frames = (st.frames || 0) + 1; st.drawMs = (st.drawMs || 0) + (t1 - t0);
  if (!st.t0) st.t0 = t1;
  st.t1 = t1;
  if (st.frames > 1) $("drag-rate").textContent = `live mesh: ${(1000 * (st.frames - 1) / (st.t1 - st.t0)).toFixed(0)} frames/s, ${(st.exact || 0)} exact updates`;
}

// an answer of the drag worker: an exact preview, a refusal, or nothing left in flight
function previewArrived(m) {
  if (m.idle) { inflight = false; return; }
  const L = live;
  if (!L || L.id !== m.id || m.network) return;  // a drag that is over; the server gone
  if (m.ok && !m.finite) {
    if (editor.refusePreview()) message("This move cannot be shown: the preview came back broken", "error", "edit");
  } else if (m.ok) {
    L.moved = m.moved.split(",").filter(Boolean);
    editor.acceptPreview(m.req.args.offset);
    L.base = new Float32Array(m.buffer); L.baseOffset = m.req.args.offset;
    studio.dragStats.exact = (studio.dragStats.exact || 0) + 1;
    if (!L.raf) L.raf = requestAnimationFrame(drawLive);
  } else if (editor.refusePreview()) {
    // once per drag; the preview stops moving
    message(`This move cannot be made: ${m.error}`, "error", "edit");
  }
}

// The drop applies the edit at once: a preview still on its way is not waited for (its
// answer finds the drag over and is dropped); the server's edit reuses the coordinates the
// previews computed, or waits for the ones being computed.
async function applyEdit(h, offset) {
  endLive();
  await edit(h.op, dragArgs(h, offset));
}

async function edit(op, args) {
  try {
    await api("/api/edit", { method: "POST", json: { op, args } });
    done("edit");
  } catch (err) {
    fail(err, "edit");
    // not applied: put the pattern back as this tab last saw it (a dragged handle snaps back)
    if (err.stale) { editor.setGeometry(studio.geometry); return; }
  }
  await refresh();
}

async function insertDart(panel, centre) {
  const names = new Set(studio.geometry.panels.find((p) => p.name === panel).loops.map((l) => l.name));
  let i = 1; while (names.has(`dart${i}`)) i++;
  await edit("insert_dart", { panel, name: `dart${i}`, centre,
                              length: +$("dart-length").value / 100, width: +$("dart-width").value / 100 });
}

$("apply-offset").onclick = () => {
  const h = editor.selected;
  if (!h) { message("Select a handle first: click it", "error", "edit"); return; }
  edit(h.op, dragArgs(h, [+$("dx").value / 100, +$("dy").value / 100]));
};
$("resize-dart").onclick = () => {
  const h = editor.selected;
  if (!h || h.op !== "move_dart") { message("Select a dart first: click its handle", "error", "edit"); return; }
  edit("resize_dart", { ...h.args, length: +$("dart-length").value / 100, width: +$("dart-width").value / 100 });
};
$("grade-btn").onclick = () => edit("grade", { panel: $("grade-panel").value, sx: +$("grade-sx").value / 100,
                                               sy: +$("grade-sy").value / 100, partner: $("partner").checked });
async function step(which) {
  try { await api(`/api/${which}`, { method: "POST" }); done("edit"); } catch (e) { fail(e, "edit"); if (e.stale) return; }
  await refresh();
}
$("undo-btn").onclick = () => step("undo");
$("redo-btn").onclick = () => step("redo");

// Shortcuts: Ctrl+Z undoes the pattern, Ctrl+Shift+Z and Ctrl+Y redo it (Cmd on a Mac),
// except in a text field, where they stay the field's own; Escape cancels a drag or the
// selection; f fits the pattern to the 2D view.
const TEXT_INPUTS = new Set(["text", "number", "search", "email", "url", "tel", "password"]);
function inTextField(el) {
  if (!el) return false;
  if (el.isContentEditable || el.tagName === "TEXTAREA") return true;
  return el.tagName === "INPUT" && TEXT_INPUTS.has((el.type || "text").toLowerCase());
}
function cancelDrag() {
  const dragging = !!editor.drag;
  editor.drag = null;  // the pointer's release then drops nothing
  endLive();
  editor.selected = null;
  if (studio.geometry) editor.setGeometry(studio.geometry);  // handles and mesh back in place
  $("selected").textContent = dragging ? "drag cancelled" : "click a handle to select it";
}
document.addEventListener("keydown", (e) => {
  if (e.key === "Escape") { if (editor.drag || editor.selected) { cancelDrag(); e.preventDefault(); } return; }
  const plain = !e.ctrlKey && !e.metaKey && !e.altKey && !inTextField(document.activeElement);
  // f: fit the pattern to the 2D view; the tool keys; Delete: the tape
  if (plain && e.key === "f") { editor.fit(); e.preventDefault(); return; }
  if (plain && !e.shiftKey && TOOL_KEYS[e.key]) { setTool(TOOL_KEYS[e.key]); e.preventDefault(); return; }
  if (plain && (e.key === "Delete" || e.key === "Backspace")) {
    if (editor.tool === "seam") { if (seamTool.deleteSelected()) e.preventDefault(); }
    else if (editor.tape) { editor.clearTape(); e.preventDefault(); }
    return;
  }
  if (!(e.ctrlKey || e.metaKey) || e.altKey || inTextField(document.activeElement)) return;
  const k = e.key.toLowerCase();
  const which = k === "z" ? (e.shiftKey ? "redo" : "undo") : (k === "y" && !e.shiftKey ? "redo" : null);
  if (!which) return;
  e.preventDefault();
  if (editor.drag || polling || !studio.state) return;
  if (which === "undo" ? studio.state.can_undo : studio.state.can_redo) step(which);
});
// one form at a time: the active tool's
function setTool(tool) {
  const radio = document.querySelector(`input[name=tool][value=${tool}]`);
  if (!radio || editor.drag) return;
  radio.checked = true;
  editor.setTool(tool);
  for (const f of document.querySelectorAll(".tool-form")) f.hidden = !f.dataset.tools.split(" ").includes(tool);
}
for (const r of document.querySelectorAll("input[name=tool]")) r.onchange = () => setTool(r.value);
setTool("point");
const TOOL_KEYS = { p: "point", e: "edge", c: "curve", d: "dart", g: "grade", m: "measure", s: "seam" };
$("tape-clear").onclick = () => editor.clearTape();
$("show-mesh").onchange = () => { editor.showMesh = $("show-mesh").checked; editor.drawMesh(); };
$("snap-points").onchange = () => { editor.snapPoints = $("snap-points").checked; };
$("snap-grid").onchange = () => { editor.snapGrid = $("snap-grid").checked; };
editor.snapPoints = $("snap-points").checked; editor.snapGrid = $("snap-grid").checked;
$("map").onchange = () => { view.setMap($("map").value); showLegend(); };

// -- drape ------------------------------------------------------------------------------
let polling = false;
$("drape-btn").onclick = async () => {
  try { await api("/api/drape", { method: "POST" }); done("drape", "edit"); pollDrape(); } catch (e) { fail(e, "drape"); }
};
$("correct-btn").onclick = async () => {
  try { await api("/api/correct", { method: "POST" }); done("drape", "edit"); pollDrape(); } catch (e) { fail(e, "drape"); }
};
// stopping changes nothing of the session: it needs no version
$("stop-btn").onclick = () => api("/api/drape/stop", { method: "POST", versioned: false }).catch(fail);

// "draping: phase 3/3 (draping under gravity), iteration 812 of this phase, 1 225 in all"
const PHASE_WORDS = { sewing: "closing the seams", relaxing: "relaxing the sewn garment",
                      draping: "draping under gravity", settling: "settling" };
function phaseText(j) {
  if (!j.phase) return "starting";
  return `${j.phase} (${j.phase_index + 1}/${j.phases.length}: ${PHASE_WORDS[j.phase] || j.phase}), ` +
    `iteration ${j.phase_iteration} of this phase, ${j.iteration} in all`;
}

async function pollDrape() {
  if (polling) return;
  polling = true; $("stop-btn").disabled = false; $("drape-btn").disabled = true;
  const correctWas = $("correct-btn").disabled; $("correct-btn").disabled = true;
  let seen = 0;
  $("progress").classList.remove("stopped");
  try {
    for (;;) {
      const j = await api("/api/drape");
      $("progress").value = j.fraction;  // monotone: the server never lowers it
      const rounds = j.rounds.map((r) => (r.failed ? `round ${r.iteration}: failed (${clip(r.failed, 60)})` : `round ${r.iteration}: ϖ ${(100 * r.fitting_ratio).toFixed(2)} %, ${r.edits} edits`));
      const head = j.kind === "correct" ? `correcting: ${rounds.join("; ")}${rounds.length ? "; " : ""}` : "";
      // a finished drape says so: its last phase's line is no longer what is running
      const state = j.stopped ? "stopped: " : (j.stopping ? "stopping: " :
        (j.running ? "" : (j.error ? "did not finish: " : "done: ")));
      $("drape-status").textContent = head + state +
        `${phaseText(j)}, ${j.elapsed.toFixed(1)} s` + (j.step ? `, step ${(j.step * 1000).toFixed(3)} mm` : "") +
        // how far from a force balance says more than the energy about how long is left
        (j.running && j.residual !== null ? `, force residual ${j.residual >= 100 ? j.residual.toFixed(0) : j.residual.toPrecision(3)} × weight (rest ≤ ${j.residual_rest})` : "");
      if (j.rounds.length > seen) { seen = j.rounds.length; await refresh(); }  // each round's edit shows
      if (!j.running) {
        if (j.stopped) {
          $("progress").classList.add("stopped");
          message(`${j.kind === "correct" ? "Correction" : "Drape"} stopped in ${j.phase || "its start"} ` +
            `after ${j.iteration} iterations: nothing of the stopped drape was recorded` +
            (j.kind === "correct" ? `, no fit outcome (${j.rounds.length} rounds finished)` : "; ϖ of this state stays unknown"), "warning", "drape");
        } else if (j.error) message(`The ${j.kind === "correct" ? "correction" : "drape"} did not finish: ${j.error}`, "error", "drape");
        else if (j.result && j.result.failed) message(`Correction stopped: ${j.result.failed}`, "error", "drape");
        else if (j.result) message(correctionText(j), "warning", "drape");
        break;
      }
      await new Promise((r) => setTimeout(r, 250));
    }
    polling = false;
    await refresh();
  } finally {
    polling = false; $("stop-btn").disabled = true; $("drape-btn").disabled = false;
    $("correct-btn").disabled = correctWas;
  }
}

// What a finished correction reached, and what its corrected pattern reads draped afresh
// (placed, sewn and draped from the start, as a garment made from it is put on: the loop's
// drapes go on from its first one, and the two may differ, or the fresh one fail).
function correctionText(j) {
  const r = j.result, f = r.fresh_drape;
  if (f && f.passed === false)
    return `Fit not reached: the corrected pattern draped afresh failed its checks (${clip((f.reasons || []).join("; "), 160)})`;
  let text = r.reached ? `Fit reached: ϖ ${(100 * r.fitting_ratio).toFixed(2)} %` : `Fit not reached after ${j.rounds.length - 1} rounds`;
  if (f) {
    text += `; the corrected pattern draped afresh: ϖ ${f.fitting_ratio === null ? "not finite" : (100 * f.fitting_ratio).toFixed(2) + " %"}, verdict ${f.verdict || "n/a"}`;
    if (f.verdict !== r.verdict) text += ` (the loop's: ${r.verdict}; its drapes went on from the first one, where the garment may sit otherwise than one made from the pattern and put on)`;
  }
  return text;
}

// -- session, files ---------------------------------------------------------------------
// A session replaced (new, a file opened, a fabric used) is moved into the session folder's
// archive, never deleted: the page says where (the server's answer ``archived``).
const keptIn = (answer) => (answer && answer.archived ? `the previous session was kept in ${answer.archived} in the session folder` : "");
const fabricEditor = new FabricEditor({
  api, onError: fail,
  onUsed: async (answer) => {
    studio.fields = null; await refresh(); done("session", "edit", "drape");
    if (keptIn(answer)) message(`Now in ${answer.name}: ${keptIn(answer)}`, "warning", "session");
  },
});
studio.fabricEditor = fabricEditor;
$("fabric-open").onclick = () => fabricEditor.open().catch(fail);
$("new-btn").onclick = async () => {
  try {
    const answer = await api("/api/new", { method: "POST", json: { garment: $("garment").value, size: $("size").value,
      body: $("body").value, fabric: $("fabric").value, engine: $("engine").value, triangles: +$("triangles").value } });
    done("session", "edit", "drape", "upload", "export");
    if (keptIn(answer)) message(`New session: ${keptIn(answer)}`, "warning", "session");
  } catch (e) { fail(e, "session"); if (e.stale) return; }
  await refresh(); view.setBody(await getArrays("/api/body"));
};
for (const [id, kind] of [["upload", "pattern"], ["upload-body", "body"], ["upload-fabric", "fabric"]]) {
  $(id).onchange = async () => {
    const f = $(id).files[0];
    if (!f) return;
    const form = new FormData(); form.append("file", f);
    try {
      const opened = await api(`/api/upload?kind=${kind}`, { method: "POST", form });
      await refresh();
      if (kind === "body") view.setBody(await getArrays("/api/body"));
      // a fabric file without friction or thickness (an ARCSim material) says what it took
      const assumed = (opened && opened.assumed) || [];
      message(`Opened ${f.name}${assumed.length ? `: ${assumed.join("; ")}` : ""}${keptIn(opened) ? `; ${keptIn(opened)}` : ""}`, "warning", "upload");
    } catch (e) { if (e.stale) fail(e); else message(`Could not open ${f.name}: ${e.message}`, "error", "upload"); }
    $(id).value = "";
  };
}

// exports need the token too (they do heavy work), which a plain link cannot send: fetch the
// file and hand it to the browser as a download
// A long export (a PDF takes ~20 s on the coat) shows a running bar and its seconds; one
// export at a time.
let exporting = null;
async function download(event) {
  event.preventDefault();
  const a = event.currentTarget, name = a.getAttribute("download");
  if (exporting) return;
  const t0 = performance.now();
  const tick = () => { $("export-status").textContent = `exporting ${name}… ${((performance.now() - t0) / 1000).toFixed(0)} s`; };
  tick(); $("export-progress").hidden = false;
  exporting = setInterval(tick, 250);
  for (const x of $("exports").querySelectorAll("a")) x.classList.add("busy");
  try {
    const r = await fetch(a.getAttribute("href"), { headers: TOKEN_HEADERS });
    if (!r.ok) throw new Error((await r.json()).error);
    const blob = await r.blob();
    const url = URL.createObjectURL(blob);
    const link = document.createElement("a");
    link.href = url; link.download = name;
    document.body.appendChild(link); link.click(); link.remove();
    setTimeout(() => URL.revokeObjectURL(url), 10000);
    $("export-status").textContent = `exported ${name} (${(blob.size / 1024).toFixed(0)} KB) in ${((performance.now() - t0) / 1000).toFixed(1)} s`;
    done("export");
  } catch (e) {
    $("export-status").textContent = "";
    message(`Could not export ${name}: ${e.message}`, "error", "export");
  } finally {
    clearInterval(exporting); exporting = null; $("export-progress").hidden = true;
    for (const x of $("exports").querySelectorAll("a")) x.classList.remove("busy");
  }
}

// another tab may write the same session: this tab is told to reload (its changes would be
// refused meanwhile, never stacked on an edit it has not seen)
setInterval(async () => {
  if (polling || inflight || editor.drag || studio.stale) return;
  try {
    const s = await (await fetch("/api/state")).json();
    if (studio.revision !== null && s.revision !== studio.revision) {
      staleNotice(`the session was changed in another tab (version ${s.revision}; this tab shows version ${studio.revision}): reload this tab to see it`);
    }
  } catch (e) { /* server gone: the next action shows it */ }
}, 3000);

async function start() {
  // everything the page shows is asked for at once; the session fields are filled in once
  // the options are there
  // the garment and the verdict before the state says whether there is a drape: refused
  // (409) when there is none, and then not used
  const first = { ...fetchState(), garment: getArrays("/api/garment3d"), verdict: api("/api/verdict") };
  for (const p of Object.values(first)) p.catch(() => {});
  const body = getArrays("/api/body");
  body.catch(() => {});
  const o = await api("/api/options");
  const fill = (id, items, labels) => { $(id).innerHTML = items.map((v) => `<option value="${v}" title="${labels ? labels[v] : ""}">${v}</option>`).join(""); };
  fill("garment", Object.keys(o.garments), o.garments); fill("size", o.sizes); fill("body", o.bodies);
  fill("fabric", o.fabrics);
  // the engines: each one the studio can drape with, and the others with why not
  $("engine").innerHTML = o.engines.map((e) => `<option value="${e.name}" title="${e.note}"${e.usable ? "" : " disabled"}>${e.name}${e.usable ? "" : ` (${e.installed ? "not in the studio yet" : "not installed"})`}</option>`).join("");
  $("exports").innerHTML = o.exports.map((n) => `<a href="/api/export/${n}" download="${n}">${n}</a>`).join("");
  for (const a of $("exports").querySelectorAll("a")) a.onclick = download;
  $("correct-btn").disabled = !o.correct_available;
  $("correct-btn").title = o.correct_available ? "" : "automatic correction is not available in this version";
  await refresh({ fetched: first });  // the session fields come from /api/state (showFields)
  view.setBody(await body);
  document.body.dataset.ready = "1";
}
start().catch(fail);
