// The 2D pattern editor: panels side by side at true proportions, the mesh with its fit
// colours drawn by WebGL (three.js, one draw call for 20K triangles, cheap to redraw every
// frame of a drag), outlines and drag handles in an SVG on top. Lengths in metres.
// One view transform maps pattern metres to screen pixels for drawing, hit-testing and
// dragging: X = ox + (x + offset_p.x) k, Y = oy - (y + offset_p.y) k (k px per metre, the
// zoom included). The wheel zooms about the pointer, dragging the background pans, fit()
// fits the pattern to the view. While a handle is dragged the moved panels' outlines and
// seams follow every preview, and the lengths of the edges and seams touching the point are
// shown near the pointer. Snapping: a dragged point (and each end of the measuring tape)
// jumps onto pattern points within SNAP_PX, or onto the 1 cm grid. The tape measures
// between two points of the layout (true distance when both lie on one panel).
import * as THREE from "three";
import { getArrays } from "/static/arrays.js";

const SVGNS = "http://www.w3.org/2000/svg";
const GAP = 0.08;  // space between panels [m]
const PAD = 24;    // margin [px]
const ZOOM = [0.5, 40];  // zoom limits, relative to the fitted view
const SNAP_PX = 8;       // snapping distance to a pattern point [px]
const GRID = 0.01;       // the grid snapped to [m]
const STALE_GREY = 0.7;  // how far colours of a drape older than the pattern fade to grey
const GREY = new THREE.Color(0.62, 0.62, 0.62);
const SEAM_COLOURS = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf",
                      "#8c564b", "#e377c2", "#bcbd22", "#7f7f7f"];
const PLAIN = [232, 236, 228];  // the mesh before any drape, sRGB bytes (0.91, 0.925, 0.894)
// the mesh shaders: each corner's screen position [px] fetched from the vertex texture
const AT_VERTEX = `precision highp float; precision highp int; precision highp sampler2D;
uniform mat4 projectionMatrix; uniform mat4 modelViewMatrix; uniform sampler2D screen;
in float position;  // the mesh vertex of this corner
vec4 place() {
  int i = int(position + 0.5), w = textureSize(screen, 0).x;
  return projectionMatrix * modelViewMatrix * vec4(texelFetch(screen, ivec2(i % w, i / w), 0).xy, 0.0, 1.0);
}
`;
const FILL_VERTEX = AT_VERTEX + `uniform float stale; in vec3 color; out vec3 vColor;
vec3 linear(vec3 c) { return mix(c * 0.0773993808, pow(c * 0.9478672986 + 0.0521327014, vec3(2.4)), step(vec3(0.04045), c)); }
vec3 srgb(vec3 c) { return mix(c * 12.92, 1.055 * pow(c, vec3(0.41666)) - 0.055, step(vec3(0.0031308), c)); }
void main() { vColor = srgb(mix(linear(color), vec3(${GREY.r}), stale)); gl_Position = place(); }`;
const FILL_FRAGMENT = `precision highp float; in vec3 vColor; out vec4 fragColor;
void main() { fragColor = vec4(vColor, 1.0); }`;
const WIRE_VERTEX = AT_VERTEX + "void main() { gl_Position = place(); }";
const WIRE_FRAGMENT = `precision highp float; uniform vec4 colour; out vec4 fragColor;
void main() { fragColor = colour; }`;

export class Editor {
  constructor(canvas, svg, { onDrag, onDrop, onSelect, onClickPanel, onStale, onTape, onPick, scaleEl, readoutEl }) {
    this.canvas = canvas; this.svg = svg;
    this.scaleEl = scaleEl || null; this.readoutEl = readoutEl || null;
    this.readoutSize = [0, 0];
    if (readoutEl) new ResizeObserver(() => { this.readoutSize = [readoutEl.offsetWidth, readoutEl.offsetHeight]; }).observe(readoutEl);
    this.k = 1; this.fitK = 1; this.ox = PAD; this.oy = 0; this.userView = false; this.viewKey = null;
    this.pan = null; this.readout = "";
    this.onDrag = onDrag; this.onDrop = onDrop; this.onSelect = onSelect;
    this.onClickPanel = onClickPanel;
    this.onTape = onTape || (() => {});
    // the seam tool: the edges picked ({panel, edge}, at most two) and the seam selected
    this.onPick = onPick || (() => {});
    this.picked = []; this.seamSelected = null;
    this.snapPoints = true; this.snapGrid = false; this.tape = null; this.snapMark = null;
    // called when a preview does not fit the mesh shown (its vertex count differs): the
    // page should fetch the geometry again; without it the editor fetches it itself
    this.onStale = onStale || (() => this.refetchGeometry());
    this.geo = null; this.vertices = null; this.tool = "point"; this.showMesh = true;
    this.selected = null; this.highlighted = -1;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
    this.renderer.setClearColor(0xffffff);
    this.scene = new THREE.Scene();
    this.camera = new THREE.OrthographicCamera(0, 1, 0, 1, -1, 1);  // screen pixels, y down
    new ResizeObserver(() => this.layout()).observe(canvas.parentElement);
    svg.addEventListener("pointerdown", (e) => this.pointerDown(e));
    svg.addEventListener("pointermove", (e) => this.pointerMove(e));
    svg.addEventListener("pointerup", (e) => this.pointerUp(e));
    svg.addEventListener("wheel", (e) => this.wheel(e), { passive: false });
  }

  // geometry from /api/geometry
  setGeometry(geo) {
    this.geo = geo; this.staleWarned = false;
    this.vertices = Float64Array.from(geo.vertices);
    this.rest = this.vertices;  // the mesh at rest: live outlines move with the preview's displacement
    this.embedCache = new Map();
    const key = geo.panel_names.join("/");
    if (key !== this.viewKey) { this.viewKey = key; this.userView = false; }
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
    this.panelTriangles = Array.from({ length: np }, () => []);
    for (let t = 0; t < tp.length; t++) this.panelTriangles[tp[t]].push(t);
    // edge name -> [loop, edge] of each panel (seams name edges by panel and edge)
    this.edgeIndex = geo.panels.map((panel) => {
      const m = new Map();
      panel.loops.forEach((loop, li) => loop.edges.forEach((e, ei) => m.set(e.name, [li, ei])));
      return m;
    });
    // the points snapped to: corners, edge midpoints and curve controls, per panel [m]
    this.points = geo.panels.map((panel) => panel.loops.flatMap((loop) => loop.edges.flatMap(
      (e) => [e.points[0], e.polyline[12], ...(e.kind === "line" ? [] : e.points.slice(1, -1))])));
    this.buildScene();
    this.layout();
    this.prepareEmbeddings(geo);
  }

  // the outlines' places in the mesh (for live outlines) found while the page is idle, one
  // panel at a time, so that the first frame of a drag does not search the mesh (a 22K
  // coat's front: ~0.3 s)
  prepareEmbeddings(geo) {
    const idle = window.requestIdleCallback || ((f) => setTimeout(f, 30));
    const work = (p) => {
      if (this.geo !== geo || p >= geo.panels.length) return;
      this.embedding(p);
      idle(() => work(p + 1));
    };
    idle(() => work(0));
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
    this.fitK = Math.min((this.W - 2 * PAD) / this.extent[0], (this.H - 2 * PAD - 16) / this.extent[1]);
    if (!this.userView) {
      // the pattern centred in the free room (a wide pattern in a tall view sat at the bottom)
      this.k = this.fitK;
      this.ox = (this.W - this.k * this.extent[0]) / 2;
      this.oy = this.H - (this.H - 16 - this.k * this.extent[1]) / 2;
    }
    this.redraw();
  }

  redraw() { this.drawMesh(); this.drawOverlay(); this.showScale(); }

  get zoom() { return this.k / this.fitK; }

  // the whole pattern in view (the "fit" button, the f key)
  fit() {
    this.userView = false;
    if (this.drag || !this.geo) return;
    this.layout();
  }

  // zoom by ``factor`` about the screen point (X, Y) [px, relative to the editor]: the
  // pattern point under it stays under it
  zoomAt(X, Y, factor) {
    if (!this.geo || this.drag) return;
    const z = Math.min(ZOOM[1], Math.max(ZOOM[0], this.zoom * factor));
    const k = z * this.fitK, f = k / this.k;
    this.ox = X - (X - this.ox) * f; this.oy = Y + (this.oy - Y) * f; this.k = k;
    this.userView = true;
    this.redraw();
  }

  panBy(dx, dy) {
    this.ox += dx; this.oy += dy; this.userView = true;
    this.redraw();
  }

  wheel(e) {
    e.preventDefault();
    const r = this.svg.getBoundingClientRect();
    const dy = e.deltaY * (e.deltaMode === 1 ? 40 : e.deltaMode === 2 ? 800 : 1);
    this.zoomAt(e.clientX - r.left, e.clientY - r.top, 2 ** (-dy / 500));
  }

  showScale() {
    if (!this.scaleEl || !this.geo) return;
    const minor = 0.01 * this.k >= 6;
    this.scaleEl.textContent = `zoom ${this.zoom.toFixed(2)}× · 1 px ≈ ${(1000 / this.k).toPrecision(2)} mm · grid 10 cm${minor ? " (1 cm)" : ""}`;
  }

  // pattern point of panel p [m] -> screen [px], and back
  sx(p, x) { return this.ox + (x + this.offsets[p][0]) * this.k; }
  sy(p, y) { return this.oy - (y + this.offsets[p][1]) * this.k; }
  px(p, X) { return (X - this.ox) / this.k - this.offsets[p][0]; }
  py(p, Y) { return (this.oy - Y) / this.k - this.offsets[p][1]; }

  // A drag preview: flat vertices (2n,) [m] of the mesh shown. Returns whether it was
  // drawn: not while the drag's preview is refused (the mesh stays at the last accepted
  // preview), nor when the count differs from the mesh's (the preview belongs to another
  // mesh: the geometry is fetched again, never a half-mapped mesh).
  // ``moved``: the names of the panels it moves (the server's X-Moved), so that the
  // outlines to redraw need no search; ``trusted``: made on the page from checked arrays
  // (no check of every number again in each frame)
  setPreview(vertices, { moved = null, trusted = false } = {}) {
    if (!this.geo || (this.drag && this.drag.refused)) return false;
    if (!vertices || vertices.length !== this.geo.vertices.length ||
        (!trusted && !allFinite(vertices))) {
      if (vertices && vertices.length !== this.geo.vertices.length && !this.staleWarned) {
        this.staleWarned = true;
        console.warn(`preview has ${vertices.length / 2} vertices, the mesh ${this.geo.vertices.length / 2}: fetching the geometry again`);
        this.onStale();
      }
      return false;
    }
    this.vertices = vertices; this.drawMesh();
    if (this.drag) {
      if (moved) for (const name of moved) { const p = this.geo.panel_names.indexOf(name); if (p >= 0) (this.drag.live = this.drag.live || new Set()).add(p); }
      this.drawLiveOutlines(!!moved); this.showReadout();
    }
    return true;
  }

  // -- live outlines: each outline point follows the displacement of the mesh triangle it
  // lies in (barycentric), so a preview of any edit moves the outlines with the mesh

  // barycentric place of pattern point (x, y) of panel p in its nearest triangle
  locate(p, x, y) {
    const v = this.rest, tri = this.geo.triangles;
    let best = null, bestScore = -Infinity;
    for (const t of this.panelTriangles[p]) {
      const a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
      const x0 = v[2 * a], y0 = v[2 * a + 1], x1 = v[2 * b], y1 = v[2 * b + 1], x2 = v[2 * c], y2 = v[2 * c + 1];
      const det = (y1 - y2) * (x0 - x2) + (x2 - x1) * (y0 - y2);
      if (Math.abs(det) < 1e-18) continue;
      const l0 = ((y1 - y2) * (x - x2) + (x2 - x1) * (y - y2)) / det;
      const l1 = ((y2 - y0) * (x - x2) + (x0 - x2) * (y - y2)) / det;
      const l2 = 1 - l0 - l1, score = Math.min(l0, l1, l2);
      if (score > bestScore) { bestScore = score; best = [a, b, c, l0, l1, l2]; if (score >= 0) break; }
    }
    return best;
  }

  // the embedding of panel p's outline points (cached until the next geometry)
  embedding(p) {
    let emb = this.embedCache.get(p);
    if (!emb) {
      emb = this.geo.panels[p].loops.map((loop) => loop.edges.map((e) => e.polyline.map((q) => this.locate(p, q[0], q[1]))));
      this.embedCache.set(p, emb);
    }
    return emb;
  }

  moved(q, b) {
    if (!b) return q;
    const v = this.vertices, r = this.rest;
    let dx = 0, dy = 0;
    for (let c = 0; c < 3; c++) { const i = b[c]; dx += b[3 + c] * (v[2 * i] - r[2 * i]); dy += b[3 + c] * (v[2 * i + 1] - r[2 * i + 1]); }
    return [q[0] + dx, q[1] + dy];
  }

  // panels whose mesh the preview moved
  movedPanels() {
    const v = this.vertices, r = this.rest, out = new Set();
    if (v === r) return out;
    for (let i = 0; i < this.vertexPanel.length; i++) {
      if (Math.abs(v[2 * i] - r[2 * i]) > 1e-7 || Math.abs(v[2 * i + 1] - r[2 * i + 1]) > 1e-7) out.add(this.vertexPanel[i]);
    }
    return out;
  }

  // the polyline [m] of edge (li, ei) of panel p as the preview shows it
  livePolyline(p, li, ei) {
    const e = this.geo.panels[p].loops[li].edges[ei];
    if (!this.drag || !this.drag.live || !this.drag.live.has(p)) return e.polyline;
    const emb = this.embedding(p)[li][ei];
    return e.polyline.map((q, j) => this.moved(q, emb[j]));
  }

  pathOf(p, pts) {
    return pts.map((q, i) => `${i ? "L" : "M"}${this.sx(p, q[0]).toFixed(1)},${this.sy(p, q[1]).toFixed(1)}`).join("");
  }

  // redraw the outlines, seams and other handles of the panels the preview moved
  drawLiveOutlines(known = false) {
    const d = this.drag;
    if (!d || !this.edgeEls) return;
    d.live = d.live || new Set();
    if (!known && !d.knownLive) for (const p of this.movedPanels()) d.live.add(p);
    d.knownLive = d.knownLive || known;
    for (const p of d.live) {
      for (const { li, ei, els } of this.edgeEls[p]) {
        const path = this.pathOf(p, this.livePolyline(p, li, ei));
        for (const el of els) el.setAttribute("d", path);
      }
    }
    for (const h of this.handleList) {
      if (h === d.h || !d.live.has(h.p)) continue;
      if (h.emb === undefined) h.emb = this.locate(h.p, h.x, h.y);
      const q = this.moved([h.x, h.y], h.emb);
      h.el.setAttribute("cx", this.sx(h.p, q[0])); h.el.setAttribute("cy", this.sy(h.p, q[1]));
    }
  }

  // -- the length read-out: the edges touching the dragged handle [cm] and the seams on
  // them, both sides and their difference [mm]
  readoutText() {
    const d = this.drag;
    if (!d || !d.h.touch) return "";
    const len = (pts) => { let s = 0; for (let i = 1; i < pts.length; i++) s += Math.hypot(pts[i][0] - pts[i - 1][0], pts[i][1] - pts[i - 1][1]); return s; };
    const p = d.h.p, panel = this.geo.panels[p].name;
    const edgeLen = (pname, ename) => {
      const q = this.geo.panels.findIndex((x) => x.name === pname);
      const at = q >= 0 && this.edgeIndex[q].get(ename);
      return at ? len(this.livePolyline(q, at[0], at[1])) : NaN;
    };
    const lines = [], touched = new Set();
    const parts = d.h.touch.map(([li, ei]) => {
      const e = this.geo.panels[p].loops[li].edges[ei];
      touched.add(`${panel}/${e.name}`);
      return `${e.name} ${(100 * len(this.livePolyline(p, li, ei))).toFixed(1)} cm`;
    });
    lines.push(`${panel}: ${parts.join(" · ")}`);
    for (const s of this.geo.seams) {
      if (!touched.has(s.a.join("/")) && !touched.has(s.b.join("/"))) continue;
      const a = edgeLen(...s.a), b = edgeLen(...s.b), diff = 1000 * (a - b);
      lines.push(`seam ${s.name}: ${s.a.join("/")} ${(100 * a).toFixed(1)} cm | ${s.b.join("/")} ${(100 * b).toFixed(1)} cm · Δ ${diff >= 0 ? "+" : "−"}${Math.abs(diff).toFixed(1)} mm`);
    }
    return lines.join("\n");
  }

  showReadout(e) {
    const el = this.readoutEl, d = this.drag;
    this.readout = d && d.moved ? this.readoutText() : "";
    if (!el) return;
    if (!this.readout) { el.hidden = true; return; }
    el.textContent = this.readout; el.hidden = false;
    if (e) d.pointer = [e.clientX, e.clientY];
    if (d.pointer) {
      // the editor's place (fixed during a drag) and the box's size as last laid out
      // (kept by a ResizeObserver): a frame of a drag forces no layout
      const r = d.rect || (d.rect = this.svg.getBoundingClientRect());
      const X = d.pointer[0] - r.left, Y = d.pointer[1] - r.top;
      const [w, hgt] = this.readoutSize;
      el.style.left = `${Math.max(2, X + 16 + w > this.W ? X - 16 - w : X + 16)}px`;
      el.style.top = `${Math.max(2, Math.min(this.H - hgt - 2, Y + 16))}px`;
    }
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
      const geo = await getArrays("/api/geometry");
      if (window.studio) window.studio.geometry = geo;  // the page's copy, for its drags
      this.setGeometry(geo);
    } catch (err) {
      console.warn("geometry could not be fetched again", err);
    }
  }

  highlight(t) { this.highlighted = t; this.drawMesh(); }

  // The mesh as one triangle soup (flat colour per triangle) and its unique edges, whose
  // corners name their mesh vertex: the vertices' screen positions [px] live in a float
  // texture, so a frame of a drag uploads n vertices (88 KB at 22K triangles) rather than
  // every corner of every triangle and edge (1.6 MB), and the page's work per frame is a
  // loop over the vertices. Colours stay the server's sRGB bytes; a drape older than the
  // pattern fades them towards grey in linear light, as three.js's Color.lerp did.
  buildScene() {
    const geo = this.geo, tri = geo.triangles, m = tri.length / 3, n = geo.vertices.length / 2;
    this.gridView = null;
    // an edit that kept the mesh's topology (a drag's drop) keeps the scene: only the
    // colours change (the vertices are drawn from the texture every frame)
    if (!this.fill || this.screenCount !== n || !sameArray(this.meshEdges.triangles, tri)) this.buildMesh(tri, n);
    const col = this.fill.geometry.getAttribute("color"), c = col.array, rgb = geo.colors;
    for (let t = 0; t < m; t++) {
      for (let k = 0; k < 9; k++) c[9 * t + k] = rgb ? rgb[3 * t + (k % 3)] : PLAIN[k % 3];
    }
    col.needsUpdate = true;
    this.fill.material.uniforms.stale.value = rgb && geo.stale ? STALE_GREY : 0;
  }

  // the scene of a mesh of triangles (3m,) over n vertices
  buildMesh(tri, n) {
    for (const o of this.scene.children) o.geometry.dispose();
    this.scene.clear();
    this.meshEdges = { triangles: tri, edges: uniqueEdges(tri, n) };
    this.edges = this.meshEdges.edges;
    this.screenCount = n;
    const W = Math.min(1024, Math.max(1, n)), H = Math.max(1, Math.ceil(n / W));
    if (!this.screenPos || this.screenPos.image.width !== W || this.screenPos.image.height !== H) {
      if (this.screenPos) this.screenPos.dispose();
      this.screenPos = new THREE.DataTexture(new Float32Array(2 * W * H), W, H, THREE.RGFormat, THREE.FloatType);
      this.screenPos.magFilter = this.screenPos.minFilter = THREE.NearestFilter;
    }
    const g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.BufferAttribute(Float32Array.from(tri), 1));
    g.setAttribute("color", new THREE.BufferAttribute(new Uint8Array(3 * tri.length), 3, true));
    const uniforms = { screen: { value: this.screenPos } };
    this.fill = new THREE.Mesh(g, new THREE.RawShaderMaterial({
      glslVersion: THREE.GLSL3, vertexShader: FILL_VERTEX, fragmentShader: FILL_FRAGMENT, side: THREE.DoubleSide,
      uniforms: { ...uniforms, stale: { value: 0 } } }));
    const w = new THREE.BufferGeometry();
    w.setAttribute("position", new THREE.BufferAttribute(Float32Array.from(this.edges), 1));
    this.wire = new THREE.LineSegments(w, new THREE.RawShaderMaterial({
      glslVersion: THREE.GLSL3, vertexShader: WIRE_VERTEX, fragmentShader: WIRE_FRAGMENT, transparent: true,
      uniforms: { ...uniforms, colour: { value: new THREE.Vector4(0x28 / 255, 0x28 / 255, 0x28 / 255, 0.35) } } }));
    // their "position" is a vertex number, not a place: never culled, no bounds computed
    for (const o of [this.fill, this.wire]) {
      o.frustumCulled = false;
      o.geometry.boundingSphere = new THREE.Sphere(new THREE.Vector3(), Infinity);
    }
    const h = new THREE.BufferGeometry();
    h.setAttribute("position", new THREE.BufferAttribute(new Float32Array(9), 3));
    this.hi = new THREE.LineLoop(h, new THREE.LineBasicMaterial({ color: 0x000000 }));
    this.grid = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0xe2e2e2 }));
    this.gridMinor = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0xf3f3f3 }));
    // flat 2D: painter's order, no depth test
    [this.gridMinor, this.grid, this.fill, this.wire, this.hi].forEach((o, i) => { o.renderOrder = i; o.material.depthTest = false; o.material.depthWrite = false; });
    this.scene.add(this.gridMinor, this.grid, this.fill, this.wire, this.hi);
  }

  drawMesh() {
    if (!this.geo || !this.fill || !this.W) return;
    const v = this.vertices, tri = this.geo.triangles, k = this.k, vp = this.vertexPanel;
    if (v.length !== 2 * vp.length) return;  // never a half-mapped mesh
    const P = this.screenPos.image.data, off = this.offsets, ox = this.ox, oy = this.oy;
    for (let i = 0; i < vp.length; i++) {
      const o = off[vp[i]];
      P[2 * i] = ox + (v[2 * i] + o[0]) * k;
      P[2 * i + 1] = oy - (v[2 * i + 1] + o[1]) * k;
    }
    this.screenPos.needsUpdate = true;
    this.wire.visible = this.showMesh;
    const t = this.highlighted;
    this.hi.visible = t >= 0 && t < tri.length / 3;
    if (this.hi.visible) {
      const a = this.hi.geometry.getAttribute("position");
      for (let c = 0; c < 3; c++) { const i = tri[3 * t + c]; a.array[3 * c] = P[2 * i]; a.array[3 * c + 1] = P[2 * i + 1]; }
      a.needsUpdate = true;
    }
    // 10 cm grid, and a 1 cm one when zoomed in far enough; both follow the view (built
    // again only when the view changed, not in every frame of a drag)
    const view = `${this.ox},${this.oy},${k},${this.W},${this.H}`;
    if (view === this.gridView) { this.renderer.render(this.scene, this.camera); return; }
    this.gridView = view;
    const lines = (step) => {
      const gl = [], s = step * k;
      for (let x = this.ox + Math.ceil(-this.ox / s) * s; x < this.W; x += s) gl.push(x, 0, 0, x, this.H, 0);
      for (let y = this.oy + Math.ceil(-this.oy / s) * s; y < this.H; y += s) gl.push(0, y, 0, this.W, y, 0);
      return new THREE.Float32BufferAttribute(gl, 3);
    };
    this.grid.geometry.setAttribute("position", lines(0.1));
    this.gridMinor.visible = 0.01 * k >= 6;
    if (this.gridMinor.visible) this.gridMinor.geometry.setAttribute("position", lines(0.01));
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
                       args: { panel: panel.name, name: loop.name }, touch: loop.edges.map((_, ei) => [li, ei]) });
          }
          return;
        }
        const n = loop.edges.length;
        loop.edges.forEach((e, ei) => {
          const base = { panel: panel.name };
          const prev = [li, (ei + n - 1) % n], self = [li, ei], next = [li, (ei + 1) % n];
          if (this.tool === "point") {
            out.push({ p, x: e.points[0][0], y: e.points[0][1], key: `${panel.name}/${e.name}`,
                       op: "move_point", args: { ...base, corner: e.name }, partner: true, touch: [prev, self] });
          } else if (this.tool === "edge") {
            const m = e.polyline[12];
            out.push({ p, x: m[0], y: m[1], key: `${panel.name}/${e.name}`, op: "move_edge",
                       args: { ...base, edge: e.name }, partner: true, touch: [prev, self, next] });
          } else if (this.tool === "curve" && e.kind !== "arc") {
            if (e.kind === "line") {
              const m = e.polyline[12];
              out.push({ p, x: m[0], y: m[1], key: `${panel.name}/${e.name}/1`, op: "edit_curve",
                         args: { ...base, edge: e.name, control: 1 }, partner: true, touch: [self] });
            } else {
              for (let c = 1; c < e.points.length - 1; c++) {
                out.push({ p, x: e.points[c][0], y: e.points[c][1], key: `${panel.name}/${e.name}/${c}`,
                           op: "edit_curve", args: { ...base, edge: e.name, control: c }, partner: true, touch: [self] });
              }
            }
          }
        });
      });
    });
    return out;
  }

  drawOverlay() {
    const svg = this.svg;
    while (svg.firstChild) svg.removeChild(svg.firstChild);
    if (this.readoutEl && !this.drag) this.readoutEl.hidden = true;
    if (!this.geo) return;
    this.edgeEls = this.geo.panels.map(() => []);
    const seamColour = new Map();
    this.geo.seams.forEach((s, i) => {
      const c = SEAM_COLOURS[i % SEAM_COLOURS.length];
      seamColour.set(s.a.join("/"), c); seamColour.set(s.b.join("/"), c);
    });
    this.geo.panels.forEach((panel, p) => {
      panel.loops.forEach((loop, li) => {
        loop.edges.forEach((e, ei) => {
          const d = this.pathOf(p, e.polyline);
          const c = seamColour.get(`${panel.name}/${e.name}`), els = [];
          if (c) els.push(this.el("path", { d, class: "seam", stroke: c }));
          els.push(this.el("path", { d, class: "outline" }));
          this.edgeEls[p].push({ li, ei, els });
          if (e.kind !== "line" && this.tool === "curve") {
            const cp = e.points.map((q, i) => `${i ? "L" : "M"}${this.sx(p, q[0])},${this.sy(p, q[1])}`).join("");
            this.el("path", { d: cp, stroke: "#88a", "stroke-dasharray": "3 3", fill: "none" });
          }
        });
      });
      const xs = panel.loops[0].edges.flatMap((e) => e.polyline.map((q) => q[0]));
      const ys = panel.loops[0].edges.flatMap((e) => e.polyline.map((q) => q[1]));
      const t = this.el("text", { x: this.sx(p, (Math.min(...xs) + Math.max(...xs)) / 2),
                                  y: this.sy(p, Math.max(...ys)) - 6, class: "panel-name", "text-anchor": "middle" });
      t.textContent = panel.name;
    });
    if (this.tool === "seam") this.drawEdgeTargets();
    this.handleList = this.handles();
    this.handleList.forEach((h, i) => {
      const el = this.el("circle", { cx: this.sx(h.p, h.x), cy: this.sy(h.p, h.y), r: 6,
                                     class: "handle" + (this.selected && this.selected.key === h.key ? " selected" : ""),
                                     "data-index": i, "data-key": h.key, "data-panel": h.args.panel });
      h.el = el;
    });
    this.snapEl = null;
    this.drawTape();
  }

  // the seam tool's targets: each edge as a wide transparent stroke to click, the picked
  // ones and the selected seam's sides tinted
  drawEdgeTargets() {
    const sel = this.geo.seams.find((s) => s.name === this.seamSelected);
    const sides = new Set(sel ? [sel.a.join("/"), sel.b.join("/")] : []);
    const picked = new Set(this.picked.map((q) => `${q.panel}/${q.edge}`));
    this.geo.panels.forEach((panel, p) => panel.loops.forEach((loop) => loop.edges.forEach((e) => {
      const key = `${panel.name}/${e.name}`;
      this.el("path", { d: this.pathOf(p, e.polyline), "data-panel": panel.name, "data-edge": e.name,
                        class: "edge-hit" + (picked.has(key) ? " picked" : "") + (sides.has(key) ? " seam-selected" : "") });
    })));
  }

  pickEdges(list) { this.picked = list.slice(0, 2); this.drawOverlay(); this.onPick(this.picked); }

  highlightSeam(name) { this.seamSelected = name; this.drawOverlay(); }

  setTool(tool) {
    if (this.drag) return;
    this.tool = tool; this.selected = null;
    this.svg.style.cursor = tool === "measure" ? "crosshair" : "";
    this.drawOverlay();
  }

  // -- snapping: a point of panel p [m] moved onto the nearest pattern point within SNAP_PX
  // (``panel``: of that panel only; else any panel, in layout metres), else onto the grid.
  // Returns [x, y] in the same frame and sets ``snapMark`` (screen) when it snapped.
  snapPoint(p, x, y, { exclude = null, anyPanel = false } = {}) {
    this.snapMark = null;
    if (this.snapPoints) {
      let best = null, bestD = SNAP_PX;
      const X = this.sx(p, x), Y = this.sy(p, y);
      this.points.forEach((pts, q) => {
        if (!anyPanel && q !== p) return;
        for (const pt of pts) {
          if (exclude && q === p && Math.hypot(pt[0] - exclude[0], pt[1] - exclude[1]) < 1e-9) continue;
          const d = Math.hypot(this.sx(q, pt[0]) - X, this.sy(q, pt[1]) - Y);
          if (d < bestD) { bestD = d; best = [q, pt]; }
        }
      });
      if (best) {
        const [q, pt] = best;
        this.snapMark = [this.sx(q, pt[0]), this.sy(q, pt[1])];
        // back in panel p's frame (the same point on the screen)
        return [this.px(p, this.snapMark[0]), this.py(p, this.snapMark[1])];
      }
    }
    if (this.snapGrid) {
      // the grid drawn on the screen: layout metres from the view's origin
      const gx = Math.round((x + this.offsets[p][0]) / GRID) * GRID - this.offsets[p][0];
      const gy = Math.round((y + this.offsets[p][1]) / GRID) * GRID - this.offsets[p][1];
      this.snapMark = [this.sx(p, gx), this.sy(p, gy)];
      return [gx, gy];
    }
    return [x, y];
  }

  drawSnapMark() {
    if (this.snapEl) { this.snapEl.remove(); this.snapEl = null; }
    if (this.snapMark) this.snapEl = this.el("circle", { cx: this.snapMark[0], cy: this.snapMark[1], r: 9, class: "snap-mark" });
  }

  // -- the measuring tape: ends in layout metres (panel 0's frame), the panel of each end
  // (the snapped point's, else the one under it, else null)
  tapeEnd(e) {
    const r = this.svg.getBoundingClientRect();
    const X = e.clientX - r.left, Y = e.clientY - r.top;
    const [x, y] = this.snapPoint(0, this.px(0, X), this.py(0, Y), { anyPanel: true });
    const Xs = this.sx(0, x), Ys = this.sy(0, y);
    let panel = null;
    this.geo.panels.forEach((pn, q) => {
      if (panel === null && inside(pn.loops[0].edges.flatMap((ed) => ed.polyline), this.px(q, Xs), this.py(q, Ys), 1e-6)) panel = q;
    });
    return { x, y, panel };
  }

  tapeText() {
    const t = this.tape;
    if (!t || !t.b) return "";
    const d = Math.hypot(t.b.x - t.a.x, t.b.y - t.a.y);
    const names = [t.a.panel, t.b.panel].map((q) => (q === null ? "outside" : this.geo.panels[q].name));
    const same = t.a.panel !== null && t.a.panel === t.b.panel;
    return `${(100 * d).toFixed(2)} cm` + (same ? ` on ${names[0]}` : ` (${names.join(" to ")}: as laid out)`);
  }

  drawTape() {
    if (this.tapeEls) this.tapeEls.forEach((el) => el.remove());
    this.tapeEls = [];
    const t = this.tape;
    if (!t || !t.b || !this.geo) return;
    const A = [this.sx(0, t.a.x), this.sy(0, t.a.y)], B = [this.sx(0, t.b.x), this.sy(0, t.b.y)];
    this.tapeEls.push(this.el("line", { x1: A[0], y1: A[1], x2: B[0], y2: B[1], class: "tape" }));
    for (const P of [A, B]) this.tapeEls.push(this.el("circle", { cx: P[0], cy: P[1], r: 3.5, class: "tape-end" }));
    const label = this.el("text", { x: (A[0] + B[0]) / 2 + 8, y: (A[1] + B[1]) / 2 - 8, class: "tape-label", id: "tape-label" });
    label.textContent = `${(100 * Math.hypot(t.b.x - t.a.x, t.b.y - t.a.y)).toFixed(2)} cm`;
    this.tapeEls.push(label);
  }

  clearTape() { this.tape = null; this.drawTape(); this.onTape(""); }

  pointerDown(e) {
    const i = e.target.getAttribute && e.target.getAttribute("data-index");
    const edge = e.target.getAttribute && e.target.getAttribute("data-edge");
    if (this.geo && this.tool === "seam" && edge) {
      // a third pick starts a new pair
      const q = { panel: e.target.getAttribute("data-panel"), edge };
      const same = this.picked.findIndex((x) => x.panel === q.panel && x.edge === q.edge);
      if (same >= 0) this.pickEdges(this.picked.filter((_, k) => k !== same));
      else this.pickEdges(this.picked.length >= 2 ? [q] : [...this.picked, q]);
      e.preventDefault();
      return;
    }
    if (this.geo && this.tool === "measure" && e.button === 0 && !e.shiftKey) {
      // the tape: from here to where the pointer is released
      const a = this.tapeEnd(e);
      this.tape = { a, b: a, measuring: true };
      this.svg.setPointerCapture(e.pointerId);
      e.preventDefault();
      return;
    }
    if (i === null || i === undefined) {
      // the background: a drag pans the view, a click (dart tool) inserts a dart
      if (!this.geo) return;
      this.pan = { x0: e.clientX, y0: e.clientY, ox: this.ox, oy: this.oy, moved: false };
      this.svg.setPointerCapture(e.pointerId);
      e.preventDefault();
      return;
    }
    const h = this.handleList[+i];
    this.drag = { h, x0: e.clientX, y0: e.clientY, offset: [0, 0], moved: false,
                  accepted: [0, 0], refused: false, refusals: 0 };
    this.svg.setPointerCapture(e.pointerId);
    e.preventDefault();
  }

  pointerMove(e) {
    if (this.tape && this.tape.measuring) {
      this.tape.b = this.tapeEnd(e);
      this.drawTape(); this.drawSnapMark();
      this.onTape(this.tapeText());
      return;
    }
    if (this.pan) {
      const P = this.pan, dx = e.clientX - P.x0, dy = e.clientY - P.y0;
      if (Math.hypot(dx, dy) > 2) P.moved = true;
      if (!P.moved) return;
      this.ox = P.ox + dx; this.oy = P.oy + dy; this.userView = true;
      this.redraw();
      return;
    }
    if (!this.drag) return;
    const d = this.drag;
    // screen motion / k: k is px per metre at the current zoom
    const raw = [(e.clientX - d.x0) / this.k, -(e.clientY - d.y0) / this.k];
    const to = this.snapPoint(d.h.p, d.h.x + raw[0], d.h.y + raw[1], { exclude: [d.h.x, d.h.y] });
    d.offset = [to[0] - d.h.x, to[1] - d.h.y];
    if (this.snapEl || this.snapMark) this.drawSnapMark();
    if (Math.hypot(e.clientX - d.x0, e.clientY - d.y0) > 2) d.moved = true;
    if (!d.moved) return;
    // a refused preview holds the handle at the last accepted offset; the page still asks
    // for the new offsets, so that the drag moves again once one is accepted
    if (!d.refused) this.moveHandle(d, d.offset);
    this.showReadout(e);
    this.onDrag(d.h, d.offset);
  }

  pointerUp(e) {
    if (this.tape && this.tape.measuring) {
      this.tape.measuring = false;
      this.snapMark = null; this.drawSnapMark();
      if (Math.hypot(this.tape.b.x - this.tape.a.x, this.tape.b.y - this.tape.a.y) < 1e-9) this.tape = null;
      this.drawTape();
      this.onTape(this.tapeText());
      return;
    }
    if (this.pan) {
      const P = this.pan; this.pan = null;
      if (!P.moved && this.tool === "dart" && this.geo) this.clickPanel(e);
      return;
    }
    if (!this.drag) return;
    const d = this.drag; this.drag = null;
    this.readout = ""; if (this.readoutEl) this.readoutEl.hidden = true;
    this.snapMark = null; this.drawSnapMark();
    if (d.moved) this.onDrop(d.h, d.offset);
    else { this.selected = d.h; this.drawOverlay(); this.onSelect(d.h); }
  }

  // pattern coordinates [m] of a click, and the panel under it
  clickPanel(e) {
    const r = this.svg.getBoundingClientRect();
    const X = e.clientX - r.left, Y = e.clientY - r.top;
    this.geo.panels.forEach((panel, p) => {
      const x = this.px(p, X), y = this.py(p, Y);
      const pts = panel.loops[0].edges.flatMap((ed) => ed.polyline);
      if (inside(pts, x, y)) this.onClickPanel(panel.name, [x, y]);
    });
  }
}

// whether (x, y) lies inside the polygon ``poly`` (or within ``tol`` of it)
function inside(poly, x, y, tol = 0) {
  for (let i = 0, j = poly.length - 1; tol > 0 && i < poly.length; j = i++) {
    if (segmentDistance(poly[j], poly[i], x, y) <= tol) return true;
  }
  let c = false;
  for (let i = 0, j = poly.length - 1; i < poly.length; j = i++) {
    const [xi, yi] = poly[i], [xj, yj] = poly[j];
    if ((yi > y) !== (yj > y) && x < ((xj - xi) * (y - yi)) / (yj - yi) + xi) c = !c;
  }
  return c;
}

// each edge of the triangles (3m,) once, as vertex pairs (2e,): sorted by (a, b), a < b
function uniqueEdges(tri, n) {
  const keys = new Float64Array(tri.length);
  for (let t = 0; t < tri.length; t += 3) {
    for (let k = 0; k < 3; k++) {
      const a = tri[t + k], b = tri[t + (k + 1) % 3];
      keys[t + k] = a < b ? a * n + b : b * n + a;
    }
  }
  keys.sort();
  const out = [];
  for (let j = 0; j < keys.length; j++) {
    if (j && keys[j] === keys[j - 1]) continue;
    const a = Math.floor(keys[j] / n);
    out.push(a, keys[j] - a * n);
  }
  return Uint32Array.from(out);
}

function sameArray(a, b) {
  if (a === b) return true;
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
  return true;
}

function allFinite(a) {
  for (let i = 0; i < a.length; i++) if (!Number.isFinite(a[i])) return false;
  return true;
}

function segmentDistance(a, b, x, y) {
  const dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
  const t = l2 > 0 ? Math.max(0, Math.min(1, ((x - a[0]) * dx + (y - a[1]) * dy) / l2)) : 0;
  return Math.hypot(a[0] + t * dx - x, a[1] + t * dy - y);
}
