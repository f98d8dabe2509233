// The seam tool: pick two edges in the 2D editor (the seam tool, key s), see their lengths
// and difference, set the ease, sew them; the pattern's seams listed with both sides, ease,
// "set ease" and "unpick"; seams suggested by the server (score, reasons) sewn with a click.
// Lengths from the server [m], shown in cm / mm; ease as longer / shorter − 1, shown in %.
const $ = (id) => document.getElementById(id);
const cm = (m) => `${(100 * m).toFixed(1)} cm`;
const dmm = (m) => `${m >= 0 ? "+" : "−"}${Math.abs(1000 * m).toFixed(1)} mm`;
const esc = (t) => String(t).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);

export class SeamTool {
  // edit(op, args): the page's edit request; api: its request function
  constructor({ editor, edit, api }) {
    this.editor = editor; this.edit = edit; this.api = api;
    this.selected = null;  // a seam's name (Delete unpicks it)
    $("seam-sew").onclick = () => this.sew();
    $("seam-clear").onclick = () => { editor.pickEdges([]); this.show(); };
    $("seam-suggest").onclick = () => this.suggest();
    $("seam-ease").oninput = () => this.showPicked();
  }

  // lengths of the geometry's edges: "panel/edge" -> m
  lengthOf(panel, edge) {
    const p = this.editor.geo.panels.find((q) => q.name === panel);
    const e = p && p.loops.flatMap((l) => l.edges).find((x) => x.name === edge);
    return e ? e.length : NaN;
  }

  show() { this.showPicked(); this.showSeams(); }

  showPicked() {
    const picked = this.editor.picked || [];
    const [a, b] = picked.map((s) => ({ ...s, length: this.lengthOf(s.panel, s.edge) }));
    let text = a ? `A: ${a.panel}/${a.edge} ${cm(a.length)}` : "click an edge (A), then its partner (B)";
    if (b) {
      const longer = Math.max(a.length, b.length), shorter = Math.min(a.length, b.length);
      text += `\nB: ${b.panel}/${b.edge} ${cm(b.length)}\nΔ ${dmm(a.length - b.length)} · ease if sewn as they are ${(100 * (longer / shorter - 1)).toFixed(1)} %`;
    } else if (a) text += "\nnow click its partner (B)";
    $("seam-picked").textContent = text;
    $("seam-sew").disabled = !b;
  }

  showSeams() {
    const geo = this.editor.geo, rows = geo.seams.map((s) => {
      const la = s.lengths ? s.lengths[0] : this.lengthOf(...s.a), lb = s.lengths ? s.lengths[1] : this.lengthOf(...s.b);
      const sel = this.selected === s.name ? " class=\"selected\"" : "";
      return `<li data-seam="${esc(s.name)}"${sel}><b>${esc(s.name)}</b><br>${esc(s.a.join("/"))} ${cm(la)} | ` +
        `${esc(s.b.join("/"))} ${cm(lb)} · Δ ${dmm(la - lb)}<br>ease ` +
        `<input type="number" step="0.5" min="0" value="${s.ease ? +(100 * s.ease).toFixed(2) : 0}"> % ` +
        `<button data-act="ease">set</button> <button data-act="remove">unpick</button></li>`;
    });
    $("seam-list").innerHTML = rows.length ? rows.join("") :
      "<li>no seams: pick two edges, or ask for suggestions</li>";
    for (const tr of $("seam-list").querySelectorAll("li[data-seam]")) {
      const name = tr.dataset.seam;
      tr.onclick = (e) => {
        if (e.target.tagName === "INPUT" || e.target.tagName === "BUTTON") return;
        this.selected = name; this.editor.highlightSeam(name); this.showSeams();
      };
      tr.querySelector("[data-act=remove]").onclick = () => this.remove(name);
      tr.querySelector("[data-act=ease]").onclick = () =>
        this.edit("set_seam_ease", { name, ease: +tr.querySelector("input").value / 100 });
    }
  }

  async sew() {
    const [a, b] = this.editor.picked || [];
    if (!b) return;
    const args = { a: { panel: a.panel, edge: a.edge }, b: { panel: b.panel, edge: b.edge }, reverse: $("seam-reverse").checked };
    const ease = $("seam-ease").value.trim();
    if (ease !== "") args.ease = +ease / 100;  // empty: measured from the sides
    await this.edit("add_seam", args);
    this.editor.pickEdges([]);
    this.show();
  }

  async remove(name) {
    if (this.selected === name) this.selected = null;
    await this.edit("remove_seam", { name });
    this.show();
  }

  // Delete in the seam tool: unpick the selected seam
  deleteSelected() {
    if (!this.selected) return false;
    this.remove(this.selected);
    return true;
  }

  async suggest() {
    $("seam-suggestions").innerHTML = "<li>looking for seams…</li>";
    try {
      const list = await this.api("/api/seams/suggest");
      if (!list.length) { $("seam-suggestions").innerHTML = "<li>no seam suggested: every edge is sewn or has no partner</li>"; return; }
      $("seam-suggestions").innerHTML = list.map((s, i) =>
        `<li><button data-i="${i}">sew</button> <b>${esc(s.a.panel)}/${esc(s.a.edge)}</b> + <b>${esc(s.b.panel)}/${esc(s.b.edge)}</b> ` +
        `${cm(s.lengths[0])} | ${cm(s.lengths[1])} · score ${s.score.toFixed(2)}${s.ease ? ` · ease ${(100 * s.ease).toFixed(1)} %` : ""}` +
        `<div class="small">${s.reasons.map(esc).join("; ")}</div></li>`).join("");
      for (const btn of $("seam-suggestions").querySelectorAll("button")) {
        const s = list[+btn.dataset.i];
        btn.onclick = async () => {
          await this.edit("add_seam", { a: s.a, b: s.b, ease: s.ease, reverse: s.reverse, name: s.name });
          btn.closest("li").remove();
          this.show();
        };
      }
    } catch (e) { $("seam-suggestions").innerHTML = `<li>${esc(e.message)}</li>`; }
  }
}
