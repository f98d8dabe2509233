// The 2D pattern editor: panels side by side at true proportions, the mesh with its fit
// colours drawn by WebGL (three.js, one draw call for 20K triangles, cheap to redraw every
// frame of a drag), outlines and drag handles in an SVG on top. Lengths in metres.
import * as THREE from "three";

const SVGNS = "http://www.w3.org/2000/svg";
const GAP = 0.08;  // space between panels [m]
const PAD = 24;    // margin [px]
const SEAM_COLOURS = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf",
                      "#8c564b", "#e377c2", "#bcbd22", "#7f7f7f"];

export class Editor {
  constructor(canvas, svg, { onDrag, onDrop, onSelect, onClickPanel, onStale }) {
    this.canvas = canvas; this.svg = svg;
    this.onDrag = onDrag; this.onDrop = onDrop; this.onSelect = onSelect;
    this.onClickPanel = onClickPanel;
    // called when a preview does not fit the mesh shown (its vertex count differs): the
    // page should fetch the geometry again; without it the editor fetches it itself
    this.onStale = onStale || (() => this.refetchGeometry());
    this.geo = null; this.vertices = null; this.tool = "point"; this.showMesh = true;
    this.snap = false; this.selected = null; this.highlighted = -1;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
    this.renderer.setClearColor(0xffffff);
    this.scene = new THREE.Scene();
    this.camera = new THREE.OrthographicCamera(0, 1, 0, 1, -1, 1);  // screen pixels, y down
    new ResizeObserver(() => this.layout()).observe(canvas.parentElement);
    svg.addEventListener("pointerdown", (e) => this.pointerDown(e));
    svg.addEventListener("pointermove", (e) => this.pointerMove(e));
    svg.addEventListener("pointerup", (e) => this.pointerUp(e));
  }

  // geometry from /api/geometry
  setGeometry(geo) {
    this.geo = geo; this.staleWarned = false;
    this.vertices = Float64Array.from(geo.vertices);
    const tp = geo.triangle_panel, tri = geo.triangles, v = this.vertices;
    const np = geo.panel_names.length;
    const lo = Array.from({ length: np }, () => [Infinity, Infinity]);
    const hi = Array.from({ length: np }, () => [-Infinity, -Infinity]);
    for (let t = 0; t < tp.length; t++) {
      const p = tp[t];
      for (let c = 0; c < 3; c++) {
        const i = tri[3 * t + c];
        lo[p][0] = Math.min(lo[p][0], v[2 * i]); lo[p][1] = Math.min(lo[p][1], v[2 * i + 1]);
        hi[p][0] = Math.max(hi[p][0], v[2 * i]); hi[p][1] = Math.max(hi[p][1], v[2 * i + 1]);
      }
    }
    // panel offsets: left to right, bottoms aligned (as fit.pictures.flat_layout)
    this.offsets = []; let x0 = 0;
    for (let p = 0; p < np; p++) {
      this.offsets.push([x0 - lo[p][0], -lo[p][1]]);
      x0 += hi[p][0] - lo[p][0] + GAP;
    }
    this.extent = [x0 - GAP, Math.max(...hi.map((h, p) => h[1] - lo[p][1]))];
    this.vertexPanel = new Int32Array(v.length / 2);
    for (let t = 0; t < tp.length; t++) for (let c = 0; c < 3; c++) this.vertexPanel[tri[3 * t + c]] = tp[t];
    this.buildScene();
    this.layout();
  }

  layout() {
    const r = this.canvas.parentElement.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    this.W = r.width; this.H = r.height;
    if (r.width < 2 || r.height < 2) return;
    this.renderer.setPixelRatio(dpr);
    this.renderer.setSize(r.width, r.height, false);
    Object.assign(this.camera, { right: r.width, bottom: r.height });
    this.camera.updateProjectionMatrix();
    if (!this.geo) return;
    this.k = Math.min((this.W - 2 * PAD) / this.extent[0], (this.H - 2 * PAD - 16) / this.extent[1]);
    this.drawMesh(); this.drawOverlay();
  }

  // pattern point of panel p [m] -> screen [px]
  sx(p, x) { return PAD + (x + this.offsets[p][0]) * this.k; }
  sy(p, y) { return this.H - PAD - (y + this.offsets[p][1]) * this.k; }

  // A drag preview: flat vertices (2n,) [m] of the mesh shown. Returns whether it was
  // drawn: not while the drag's preview is refused (the mesh stays at the last accepted
  // preview), nor when the count differs from the mesh's (the preview belongs to another
  // mesh: the geometry is fetched again, never a half-mapped mesh).
  setPreview(vertices) {
    if (!this.geo || (this.drag && this.drag.refused)) return false;
    if (!vertices || vertices.length !== this.geo.vertices.length ||
        Array.prototype.some.call(vertices, (x) => !Number.isFinite(x))) {
      if (vertices && vertices.length !== this.geo.vertices.length && !this.staleWarned) {
        this.staleWarned = true;
        console.warn(`preview has ${vertices.length / 2} vertices, the mesh ${this.geo.vertices.length / 2}: fetching the geometry again`);
        this.onStale();
      }
      return false;
    }
    this.vertices = vertices; this.drawMesh();
    return true;
  }

  // The server accepted the preview for ``offset`` [m]: the drag moves again.
  acceptPreview(offset) {
    const d = this.drag;
    if (!d) return;
    d.accepted = offset.slice();
    if (d.refused) { d.refused = false; this.moveHandle(d, d.offset); }
  }

  // The server refused the drag's preview (the edit would be refused): the mesh and the
  // handle stay where the last accepted preview put them until a preview is accepted
  // again. Returns true for the first refusal of a drag only, so that the page shows the
  // message once rather than for every pointer move.
  refusePreview() {
    const d = this.drag;
    if (!d) return false;
    const first = !d.refusals;
    d.refusals = (d.refusals || 0) + 1;
    if (!d.refused) {
      d.refused = true;
      this.moveHandle(d, d.accepted);
    }
    return first;
  }

  moveHandle(d, offset) {
    d.h.el.setAttribute("cx", this.sx(d.h.p, d.h.x + offset[0]));
    d.h.el.setAttribute("cy", this.sy(d.h.p, d.h.y + offset[1]));
  }

  // GET /api/geometry again (a preview of another mesh arrived) and show it
  async refetchGeometry() {
    try {
      const r = await fetch("/api/geometry");
      if (!r.ok) return;
      const geo = await r.json();
      if (window.studio) window.studio.geometry = geo;  // the page's copy, for its drags
      this.setGeometry(geo);
    } catch (err) {
      console.warn("geometry could not be fetched again", err);
    }
  }

  highlight(t) { this.highlighted = t; this.drawMesh(); }

  // the mesh as one triangle soup (flat colour per triangle) and its unique edges
  buildScene() {
    const geo = this.geo, tri = geo.triangles, m = tri.length / 3;
    this.scene.clear();
    const col = new Float32Array(9 * m), c = new THREE.Color();
    for (let t = 0; t < m; t++) {
      if (geo.colors) c.setRGB(geo.colors[3 * t] / 255, geo.colors[3 * t + 1] / 255, geo.colors[3 * t + 2] / 255, THREE.SRGBColorSpace);
      else c.setRGB(0.91, 0.925, 0.894, THREE.SRGBColorSpace);
      for (let k = 0; k < 3; k++) col.set([c.r, c.g, c.b], 9 * t + 3 * k);
    }
    const g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.BufferAttribute(new Float32Array(9 * m), 3));
    g.setAttribute("color", new THREE.BufferAttribute(col, 3));
    this.fill = new THREE.Mesh(g, new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.DoubleSide }));
    const seen = new Set(), edges = [], n = geo.vertices.length / 2;
    for (let t = 0; t < m; t++) {
      for (let k = 0; k < 3; k++) {
        const a = tri[3 * t + k], b = tri[3 * t + (k + 1) % 3];
        const key = a < b ? a * n + b : b * n + a;
        if (!seen.has(key)) { seen.add(key); edges.push(a, b); }
      }
    }
    this.edges = Uint32Array.from(edges);
    const w = new THREE.BufferGeometry();
    w.setAttribute("position", new THREE.BufferAttribute(new Float32Array(3 * this.edges.length), 3));
    this.wire = new THREE.LineSegments(w, new THREE.LineBasicMaterial({ color: 0x282828, transparent: true, opacity: 0.35 }));
    const h = new THREE.BufferGeometry();
    h.setAttribute("position", new THREE.BufferAttribute(new Float32Array(9), 3));
    this.hi = new THREE.LineLoop(h, new THREE.LineBasicMaterial({ color: 0x000000 }));
    this.grid = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0xeeeeee }));
    // flat 2D: painter's order, no depth test
    [this.grid, this.fill, this.wire, this.hi].forEach((o, i) => { o.renderOrder = i; o.material.depthTest = false; o.material.depthWrite = false; });
    this.scene.add(this.grid, this.fill, this.wire, this.hi);
  }

  drawMesh() {
    if (!this.geo || !this.fill || !this.W) return;
    const v = this.vertices, tri = this.geo.triangles, k = this.k;
    if (v.length !== 2 * this.vertexPanel.length) return;  // never a half-mapped mesh
    const X = new Float32Array(v.length / 2), Y = new Float32Array(v.length / 2);
    for (let i = 0; i < X.length; i++) {
      const p = this.vertexPanel[i];
      X[i] = PAD + (v[2 * i] + this.offsets[p][0]) * k;
      Y[i] = this.H - PAD - (v[2 * i + 1] + this.offsets[p][1]) * k;
    }
    const put = (attr, ids) => {
      const a = attr.array;
      for (let j = 0; j < ids.length; j++) { a[3 * j] = X[ids[j]]; a[3 * j + 1] = Y[ids[j]]; }
      attr.needsUpdate = true;
    };
    put(this.fill.geometry.getAttribute("position"), tri);
    this.wire.visible = this.showMesh;
    if (this.showMesh) put(this.wire.geometry.getAttribute("position"), this.edges);
    const t = this.highlighted;
    this.hi.visible = t >= 0 && t < tri.length / 3;
    if (this.hi.visible) put(this.hi.geometry.getAttribute("position"), [tri[3 * t], tri[3 * t + 1], tri[3 * t + 2]]);
    // 10 cm grid
    const gl = [];
    for (let x = PAD; x < this.W; x += 0.1 * k) gl.push(x, 0, 0, x, this.H, 0);
    for (let y = this.H - PAD; y > 0; y -= 0.1 * k) gl.push(0, y, 0, this.W, y, 0);
    this.grid.geometry.setAttribute("position", new THREE.Float32BufferAttribute(gl, 3));
    this.renderer.render(this.scene, this.camera);
  }

  el(name, attrs, parent) {
    const e = document.createElementNS(SVGNS, name);
    for (const [a, val] of Object.entries(attrs)) e.setAttribute(a, val);
    (parent || this.svg).appendChild(e);
    return e;
  }

  // handles of the current tool: {x, y (pattern m), panel, op, args}
  handles() {
    const out = [];
    this.geo.panels.forEach((panel, p) => {
      panel.loops.forEach((loop, li) => {
        if (li > 0) {
          if (this.tool === "dart") {
            const pts = loop.edges.map((e) => e.points[0]);
            const c = pts.reduce((s, q) => [s[0] + q[0] / pts.length, s[1] + q[1] / pts.length], [0, 0]);
            out.push({ p, x: c[0], y: c[1], key: `${panel.name}/${loop.name}`, op: "move_dart",
                       args: { panel: panel.name, name: loop.name } });
          }
          return;
        }
        for (const e of loop.edges) {
          const base = { panel: panel.name };
          if (this.tool === "point") {
            out.push({ p, x: e.points[0][0], y: e.points[0][1], key: `${panel.name}/${e.name}`,
                       op: "move_point", args: { ...base, corner: e.name }, partner: true });
          } else if (this.tool === "edge") {
            const m = e.polyline[12];
            out.push({ p, x: m[0], y: m[1], key: `${panel.name}/${e.name}`, op: "move_edge",
                       args: { ...base, edge: e.name }, partner: true });
          } else if (this.tool === "curve" && e.kind !== "arc") {
            if (e.kind === "line") {
              const m = e.polyline[12];
              out.push({ p, x: m[0], y: m[1], key: `${panel.name}/${e.name}/1`, op: "edit_curve",
                         args: { ...base, edge: e.name, control: 1 }, partner: true });
            } else {
              for (let c = 1; c < e.points.length - 1; c++) {
                out.push({ p, x: e.points[c][0], y: e.points[c][1], key: `${panel.name}/${e.name}/${c}`,
                           op: "edit_curve", args: { ...base, edge: e.name, control: c }, partner: true });
              }
            }
          }
        }
      });
    });
    return out;
  }

  drawOverlay() {
    const svg = this.svg;
    while (svg.firstChild) svg.removeChild(svg.firstChild);
    if (!this.geo) return;
    const seamColour = new Map();
    this.geo.seams.forEach((s, i) => {
      const c = SEAM_COLOURS[i % SEAM_COLOURS.length];
      seamColour.set(s.a.join("/"), c); seamColour.set(s.b.join("/"), c);
    });
    this.geo.panels.forEach((panel, p) => {
      for (const loop of panel.loops) {
        for (const e of loop.edges) {
          const d = e.polyline.map((q, i) => `${i ? "L" : "M"}${this.sx(p, q[0]).toFixed(1)},${this.sy(p, q[1]).toFixed(1)}`).join("");
          const c = seamColour.get(`${panel.name}/${e.name}`);
          if (c) this.el("path", { d, class: "seam", stroke: c });
          this.el("path", { d, class: "outline" });
          if (e.kind !== "line" && this.tool === "curve") {
            const cp = e.points.map((q, i) => `${i ? "L" : "M"}${this.sx(p, q[0])},${this.sy(p, q[1])}`).join("");
            this.el("path", { d: cp, stroke: "#88a", "stroke-dasharray": "3 3", fill: "none" });
          }
        }
      }
      const xs = panel.loops[0].edges.flatMap((e) => e.polyline.map((q) => q[0]));
      const ys = panel.loops[0].edges.flatMap((e) => e.polyline.map((q) => q[1]));
      const t = this.el("text", { x: this.sx(p, (Math.min(...xs) + Math.max(...xs)) / 2),
                                  y: this.sy(p, Math.max(...ys)) - 6, class: "panel-name", "text-anchor": "middle" });
      t.textContent = panel.name;
    });
    this.handleList = this.handles();
    this.handleList.forEach((h, i) => {
      const el = this.el("circle", { cx: this.sx(h.p, h.x), cy: this.sy(h.p, h.y), r: 6,
                                     class: "handle" + (this.selected && this.selected.key === h.key ? " selected" : ""),
                                     "data-index": i, "data-key": h.key, "data-panel": h.args.panel });
      h.el = el;
    });
  }

  setTool(tool) { this.tool = tool; this.selected = null; this.drawOverlay(); }

  snapOffset(o) { return this.snap ? o.map((c) => Math.round(c / 0.005) * 0.005) : o; }

  pointerDown(e) {
    const i = e.target.getAttribute && e.target.getAttribute("data-index");
    if (i === null || i === undefined) {
      if (this.tool === "dart" && this.geo) this.clickPanel(e);
      return;
    }
    const h = this.handleList[+i];
    this.drag = { h, x0: e.clientX, y0: e.clientY, offset: [0, 0], moved: false,
                  accepted: [0, 0], refused: false, refusals: 0 };
    this.svg.setPointerCapture(e.pointerId);
    e.preventDefault();
  }

  pointerMove(e) {
    if (!this.drag) return;
    const d = this.drag;
    const raw = [(e.clientX - d.x0) / this.k, -(e.clientY - d.y0) / this.k];
    d.offset = this.snapOffset(raw);
    if (Math.hypot(e.clientX - d.x0, e.clientY - d.y0) > 2) d.moved = true;
    if (!d.moved) return;
    // a refused preview holds the handle at the last accepted offset; the page still asks
    // for the new offsets, so that the drag moves again once one is accepted
    if (!d.refused) this.moveHandle(d, d.offset);
    this.onDrag(d.h, d.offset);
  }

  pointerUp(e) {
    if (!this.drag) return;
    const d = this.drag; this.drag = null;
    if (d.moved) this.onDrop(d.h, d.offset);
    else { this.selected = d.h; this.drawOverlay(); this.onSelect(d.h); }
  }

  // pattern coordinates [m] of a click, and the panel under it (by bounding box)
  clickPanel(e) {
    const r = this.svg.getBoundingClientRect();
    const X = e.clientX - r.left, Y = e.clientY - r.top;
    this.geo.panels.forEach((panel, p) => {
      const x = (X - PAD) / this.k - this.offsets[p][0];
      const y = (this.H - PAD - Y) / this.k - this.offsets[p][1];
      const pts = panel.loops[0].edges.flatMap((ed) => ed.polyline);
      if (inside(pts, x, y)) this.onClickPanel(panel.name, [x, y]);
    });
  }
}

function inside(poly, x, y) {
  let c = false;
  for (let i = 0, j = poly.length - 1; i < poly.length; j = i++) {
    const [xi, yi] = poly[i], [xj, yj] = poly[j];
    if ((yi > y) !== (yj > y) && x < ((xj - xi) * (y - yi)) / (yj - yi) + xi) c = !c;
  }
  return c;
}
