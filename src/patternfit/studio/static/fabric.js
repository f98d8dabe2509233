// The fabric editor: a fabric's numbers in a designer's units (g/m², N/m, µN·m, mm), the
// virtual fabric tests run on them by the server (strip, cantilever, Cusick drape) with
// their readings and picture, and the edited fabric put into the session. SI units travel.
const $ = (id) => document.getElementById(id);

// field -> [label, unit shown, factor from SI to the unit shown]
export const FIELDS = {
  density: ["density", "g/m²", 1000],
  stretch_warp: ["stretch, warp", "N/m", 1],
  stretch_weft: ["stretch, weft", "N/m", 1],
  shear: ["shear", "N/m", 1],
  bending_warp: ["bending, warp", "µN·m", 1e6],
  bending_weft: ["bending, weft", "µN·m", 1e6],
  friction: ["friction", "", 1],
  thickness: ["thickness", "mm", 1000],
  // KES-F 2HB, the bending friction (0: none); kept so that a sheet's friction is not lost
  bending_hysteresis: ["bending hysteresis 2HB", "mN", 1000],
};
const G = 9.81;
const mm = (m) => (m === null || m === undefined ? "n/a" : `${(1000 * m).toFixed(1)} mm`);

export class FabricEditor {
  // api(path, opts): the page's request function; onUsed(answer): after the session changed
  constructor({ api, onUsed, onError }) {
    this.api = api; this.onUsed = onUsed; this.onError = onError;
    this.presets = {}; this.polling = false;
    const form = $("fab-fields");
    form.innerHTML = Object.entries(FIELDS).map(([k, [label, unit]]) =>
      `<label>${label} <input id="fab-${k}" type="number" step="any" required> ${unit}</label>`).join("");
    for (const k of Object.keys(FIELDS)) $(`fab-${k}`).oninput = () => this.derived();
    $("fab-preset").onchange = () => this.show({ ...this.presets[$("fab-preset").value] });
    for (const b of document.querySelectorAll("#fabric-panel button[data-test]")) b.onclick = () => this.run(b.dataset.test);
    $("fab-stop").onclick = () => this.api("/api/fabric/test/stop", { method: "POST", versioned: false }).catch(this.onError);
    $("fab-use").onclick = () => this.use();
    $("fabric-close").onclick = () => { $("fabric-panel").hidden = true; };
  }

  async open() {
    const f = await this.api("/api/fabric");
    this.presets = f.presets;
    $("fab-preset").innerHTML = `<option value="">the session's fabric</option>` +
      Object.keys(f.presets).map((n) => `<option>${n}</option>`).join("");
    this.presets[""] = f.session;
    this.show(f.session);
    $("fabric-panel").hidden = false;
    this.poll();
  }

  show(fab) {
    $("fab-name").value = fab.name;
    for (const [k, [, , factor]] of Object.entries(FIELDS)) $(`fab-${k}`).value = +(fab[k] * factor).toPrecision(6);
    this.derived();
  }

  // the numbers in SI units; null (and the field marked) when one is not a number
  values() {
    const out = { name: $("fab-name").value.trim() };
    for (const [k, [, , factor]] of Object.entries(FIELDS)) {
      const v = parseFloat($(`fab-${k}`).value);
      if (!Number.isFinite(v)) { $(`fab-${k}`).focus(); this.status(`${FIELDS[k][0]}: a number, please`); return null; }
      out[k] = v / factor;
    }
    return out;
  }

  // Peirce's bending length from the numbers, before any test
  derived() {
    const d = parseFloat($("fab-density").value) / 1000, b = parseFloat($("fab-bending_warp").value) / 1e6;
    $("fab-derived").textContent = d > 0 && b > 0 ? `bending length (B/ρg)^⅓, warp: ${mm(Math.cbrt(b / (d * G)))}` : "";
  }

  status(text) { $("fab-status").textContent = text; }

  async run(test) {
    const fabric = this.values();
    if (!fabric) return;
    try {
      await this.api("/api/fabric/test", { method: "POST", json: { test, fabric }, versioned: false });
      $("fab-picture").hidden = true; $("fab-table").innerHTML = "";
      this.poll();
    } catch (e) { this.status(`The test could not start: ${e.message}`); }
  }

  async poll() {
    if (this.polling) return;
    this.polling = true;
    try {
      for (;;) {
        const j = await this.api("/api/fabric/test");
        $("fab-progress").hidden = !j.running;
        for (const b of document.querySelectorAll("#fabric-panel button[data-test]")) b.disabled = j.running;
        $("fab-stop").disabled = !j.running;
        if (j.running) this.status(`${j.test} test of ${j.fabric}: ${j.text}, ${j.elapsed.toFixed(0)} s`);
        else { this.showResult(j); break; }
        await new Promise((r) => setTimeout(r, 400));
      }
    } finally { this.polling = false; }
  }

  async showResult(j) {
    if (!j.test) { this.status("no test run yet"); return; }
    if (j.stopped) { this.status(`${j.test} test stopped: no result`); return; }
    if (j.error) { this.status(`The ${j.test} test failed to run: ${j.error}`); return; }
    const r = j.result, rows = [];
    if (j.test === "strip") {
      rows.push(["elongation measured", mm(r.elongation_measured_m)], ["expected ρgL²/2k", mm(r.elongation_expected_m)],
                ["ratio", r.ratio === null ? "n/a" : r.ratio.toFixed(3)]);
    } else if (j.test === "cantilever") {
      rows.push(["bending length measured", mm(r.bending_length_measured_m)], [r.bending_length_expected_m === r.bending_length_elastic_m ? "expected (B/ρg)^⅓" : "expected, with its bending friction", mm(r.bending_length_expected_m)],
                ...(r.bending_length_expected_m === r.bending_length_elastic_m ? [] : [["(B/ρg)^⅓, without it", mm(r.bending_length_elastic_m)]]),
                ["ratio", r.ratio === null ? "n/a" : r.ratio.toFixed(3)], ["Peirce's formula", mm(r.peirce_length_m)]);
    } else {
      rows.push(["drape coefficient DC", `${r.drape_coefficient.toFixed(3)} (spread ${r.drape_coefficient_spread.toFixed(3)})`],
                ["nodes", `${r.nodes.toFixed(1)} (${r.nodes_min}–${r.nodes_max})`], ["starts", `${r.runs.length}`]);
    }
    rows.push(["checks", "passed"]);
    $("fab-table").innerHTML = rows.map(([k, v]) => `<tr><th>${k}</th><td>${v}</td></tr>`).join("");
    // the reasons are the server's words: set as text, never as markup
    if (!r.passed) $("fab-table").querySelector("tr:last-child td").textContent =
      `FAILED: ${(r.failures || []).join("; ") || "not at rest, or off the expected value"}`;
    $("fab-table").className = r.passed ? "" : "failed";
    this.status(`${j.test} test of ${j.fabric}: done in ${j.elapsed.toFixed(1)} s`);
    if (j.picture) {
      const blob = await (await fetch(`/api/fabric/test/picture?t=${Date.now()}`)).blob();
      if ($("fab-picture").src) URL.revokeObjectURL($("fab-picture").src);
      $("fab-picture").src = URL.createObjectURL(blob); $("fab-picture").hidden = false;
    }
  }

  async use() {
    const fabric = this.values();
    if (!fabric) return;
    try {
      const answer = await this.api("/api/fabric", { method: "POST", json: { fabric } });
      this.status(`the session now drapes in ${fabric.name} (a new history)`);
      await this.onUsed(answer);
    } catch (e) { this.status(`Not used: ${e.message}`); if (e.stale) this.onError(e); }
  }
}
