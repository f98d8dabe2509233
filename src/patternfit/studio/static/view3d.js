// The 3D view: body and draped garment coloured by a fit map; orbit, zoom, pan; hover reads
// the value under the cursor. Positions in metres, y up.
import * as THREE from "three";
import { OrbitControls } from "/static/vendor/OrbitControls.js";

const GREY = new THREE.Color(0.35, 0.35, 0.35);  // linear: the 2D editor's sRGB grey

export class View3D {
  constructor(container, { onHover }) {
    this.container = container; this.onHover = onHover;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xdfe4e8);
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 20);
    this.camera.position.set(0, 1.1, 3.2);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.set(0, 1.0, 0);
    this.controls.addEventListener("change", () => this.render());
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(1, 2, 3); this.scene.add(sun);
    this.raycaster = new THREE.Raycaster();
    this.garment = null; this.body = null; this.data = null; this.map = "area_change";
    this.renderer.domElement.addEventListener("pointermove", (e) => this.hover(e));
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }

  resize() {
    const r = this.container.getBoundingClientRect();
    if (r.width < 2 || r.height < 2) return;
    this.renderer.setSize(r.width, r.height);
    this.camera.aspect = r.width / r.height; this.camera.updateProjectionMatrix();
    this.render();
  }

  // one render per animation frame however many changes ask for it (a session's load
  // sets the garment, its colours, the stale state and the body, each of which rendered)
  render() {
    if (this.frame) return;
    this.frame = requestAnimationFrame(() => { this.frame = 0; this.renderer.render(this.scene, this.camera); });
  }

  setBody(body) {
    if (this.body) this.scene.remove(this.body);
    const g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.Float32BufferAttribute(body.vertices, 3));
    g.setIndex(new THREE.BufferAttribute(Uint32Array.from(body.faces), 1)); g.computeVertexNormals();
    this.body = new THREE.Mesh(g, new THREE.MeshStandardMaterial({ color: 0xc8b9a6, roughness: 0.9 }));
    this.scene.add(this.body);
    g.computeBoundingBox();
    const c = g.boundingBox.getCenter(new THREE.Vector3());
    this.controls.target.copy(c); this.camera.position.set(c.x, c.y + 0.1, c.z + 3.0);
    this.controls.update(); this.render();
  }

  // garment from /api/garment3d (typed arrays), or null to clear; ``stale``: the pattern
  // was edited since this drape (its colours fade to grey, see setStale)
  setGarment(data) {
    this.data = data;
    if (this.garment) { this.scene.remove(this.garment); this.garment.geometry.dispose(); this.garment = null; }
    if (!data) { this.render(); return; }
    const p = data.positions, t = data.triangles, m = t.length / 3;
    // unshared corners so each triangle shows its own flat colour
    const pos = new Float32Array(9 * m);
    for (let i = 0; i < 3 * m; i++) for (let c = 0; c < 3; c++) pos[3 * i + c] = p[3 * t[i] + c];
    const g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.BufferAttribute(pos, 3));
    g.setAttribute("color", new THREE.BufferAttribute(new Float32Array(9 * m), 3));
    g.computeVertexNormals();
    this.garment = new THREE.Mesh(g, new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide }));
    this.scene.add(this.garment);
    this.setMap(this.map);
  }

  // the drape shown is older than the pattern (true) or the pattern's own (false)
  setStale(stale) {
    if (this.stale === stale) return;
    this.stale = stale;
    if (this.garment) this.setMap(this.map);
  }

  setMap(name) {
    this.map = name;
    if (!this.garment) { this.render(); return; }
    const rgb = this.data.maps[name].colors, col = this.garment.geometry.getAttribute("color");
    const m = rgb.length / 3;
    // the server's colours are sRGB; three.js lights in linear space
    const tmp = new THREE.Color();
    for (let t = 0; t < m; t++) {
      tmp.setRGB(rgb[3 * t] / 255, rgb[3 * t + 1] / 255, rgb[3 * t + 2] / 255, THREE.SRGBColorSpace);
      if (this.stale) tmp.lerp(GREY, 0.7);
      for (let c = 0; c < 3; c++) col.setXYZ(3 * t + c, tmp.r, tmp.g, tmp.b);
    }
    col.needsUpdate = true;
    this.render();
  }

  hover(e) {
    if (!this.garment) return;
    const r = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    const hit = this.raycaster.intersectObject(this.garment)[0];
    this.onHover(hit ? hit.faceIndex : -1, hit ? this.data.maps[this.map].values[hit.faceIndex] : null);
  }
}
