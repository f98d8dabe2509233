"""A dynamic drape on Newton's ``SolverStyle3D`` (NVIDIA Warp), the second engine.

The garment is placed and sewn exactly as for the static engine (:mod:`patternfit.sim.drape`:
placement, then the static solver's gravity-free sewing phase, which welds every seam pair
into one vertex), then handed to Style3D, which lets it fall under gravity in time until the
largest vertex speed stays below a threshold. Style3D ignores spring forces, so welding is
how seams hold. The flat panel mesh, turned so that each panel's grainline is the panel's
``u`` axis, is the rest shape. Units: metres, kilograms, seconds; ``y`` is up.

``newton`` and ``warp-lang`` are an optional extra (``pip install "patternfit[newton]"``),
imported here only when a Newton drape is asked for. Warp compiles its kernels on first use
(about a minute on a small CPU) and keeps them in its cache (``~/.cache/warp``, or
``WARP_CACHE_PATH``). The fabric mapping and the contact tuning are in
``docs/simulation.md``.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass

import numpy as np

from ..geometry import face_adjacency, face_cross
from ..defaults import DEFAULTS
from ..errors import ctrl_c
from ..mesh.garment import GarmentMesh
from ..pattern.model import Pattern
from .drape import CONTACT_MARGIN, Drape, drape
from .fabrics import Fabric, get_fabric
from .placement import place_on_body
from .schedule import Plan, run_plan
from .result import DrapeResult
from .settings import SolverSettings
from .solver import GarmentSolver

#: Style3D's hinge energy uses Bergou's weight 3 l^2 / (A1 + A2) as is; the static engine's
#: earlier hinge bending read B through that weight divided by 3.4 (its calibration against
#: the cantilever), so an edge stiffness of B / 3.4 keeps that calibration. The static engine
#: now bends by each triangle's curvature tensor ("Bending" in docs/simulation.md), which
#: this mapping does not follow: the engines' bending agrees only as the old hinge did.
BENDING_SCALE = 1.0 / 3.4

#: A stiffness continuation for :attr:`NewtonSettings.stretch_ramp`. Style3D moves a bending
#: mode by ~B (pi/L)^2 / k_stretch of the way per iteration (its matrix holds the stretch
#: stiffness), so at 1e-3 of the stretch stiffness a strip droops in ~150 frames; the
#: stiffer phases then only take back the small extra stretch.
STIFFNESS_RAMP = ((1.0e-3, 150), (1.0e-2, 30), (1.0e-1, 30))

MISSING = ("the Newton engine needs the optional packages 'newton' and 'warp-lang': "
           "pip install \"patternfit[newton]\"")


class NewtonMissingError(ImportError):
    """``newton`` / ``warp`` are not installed."""


def import_newton():
    """``(newton, warp)``, or :class:`NewtonMissingError` with the install command."""
    try:  # the optional extra, imported only when a Newton drape is asked for
        import warp as wp

        wp.config.quiet = True  # before newton initialises Warp: no per-module load lines
        import newton
    except ImportError as exc:
        raise NewtonMissingError(MISSING) from exc
    return newton, wp


def default_device() -> str:
    """``"cuda"`` when Warp sees a CUDA device, else ``"cpu"``."""
    _, wp = import_newton()
    return "cuda" if wp.is_cuda_available() else "cpu"


@dataclass(frozen=True)
class NewtonSettings:
    """Knobs of the Newton engine (SI units).

    Stopping (counted in the last phase, at the real stiffness, after ``stretch_ramp``): at
    rest when the largest vertex speed stays below ``speed_tol`` [m/s] for ``patience``
    consecutive frames after ``min_frames`` **and** no vertex moved more than ``rest_drift``
    [m] over the last ``window`` frames (a slow creep, which Style3D's projective-dynamics
    step produces on bending modes at speeds far below ``speed_tol``, is not rest);
    otherwise stopped at ``max_frames`` or ``time_limit`` [s] (not at rest).
    """

    fps: float = 30.0
    substeps: int = 1
    iterations: int = 5
    linear_iterations: int = 10
    max_frames: int = 300
    min_frames: int = 30
    time_limit: float = 300.0
    speed_tol: float = 0.01
    patience: int = 3
    #: frames over which the net displacement is measured (1 s at 30 fps)
    window: int = 30
    #: largest net vertex displacement over ``window`` frames still counted as rest [m]
    #: (5 µm/s: the measured creep of a cotton cantilever, 15 µm/s, is not rest)
    rest_drift: float = 5.0e-6
    #: body contact stiffness per vertex [N/m] (Newton's default, 10, lets a stretched
    #: garment sink millimetres into the body; see docs/simulation.md)
    contact_ke: float = 1.0e4
    contact_kd: float = 1.0e-5
    #: contact distance kept between vertex and body: fabric thickness + this [m]
    contact_radius: float = 0.0
    #: vertices found inside the body's distance field after a frame are pushed out to the
    #: fabric thickness (a position projection; velocity into the body is removed), so that
    #: "0 inside" holds whatever the stiffness; the count is reported (``projected``)
    project_contact: bool = True
    #: ... and so are points inside the cloth's edges, at most this far apart along their
    #: rest length [m] (0: vertices only; the static engine's ``SolverSettings.edge_contact``):
    #: with vertices alone, the 1.5K coat on male_average ended with some 300 edges through
    #: the body, the 1.5K skirt with 30-40
    edge_contact: float = 0.01
    self_collision: bool = True
    #: self-collision contact radius (Style3D's default 3 mm) [m]
    self_radius: float = 3.0e-3
    gravity: float = 9.80665
    #: random displacement along the vertex normals of a ``from_static`` start [m]
    perturbation: float = 2.0e-3
    seed: int = 0
    #: stiffness continuation: ``(scale, frames)`` phases run before the real fabric, with
    #: the stretch and shear stiffness (and Style3D's constant projective-dynamics matrix)
    #: multiplied by ``scale``; rest is tested in the last (real) phase only. ``()``: plain
    #: Style3D. :data:`STIFFNESS_RAMP` brings Peirce's cantilever to rest at its angle, but
    #: not a skirt on a body (see docs/simulation.md), so it is not the default.
    stretch_ramp: tuple[tuple[float, int], ...] = ()


def panel_rest(mesh: GarmentMesh) -> np.ndarray:
    """Flat vertices turned so that each panel's grainline lies along ``+u``.

    Returns
    -------
    (n, 2) float
        Rest coordinates [m]; Style3D's stiffness ``(k_u, k_v, k_shear)`` then reads as
        (warp, weft, shear).
    """
    uv = np.asarray(mesh.vertices, dtype=np.float64)
    g = np.asarray(mesh.grain, dtype=np.float64)[mesh.vertex_panel]
    g = g / np.linalg.norm(g, axis=1, keepdims=True)
    return np.column_stack([uv[:, 0] * g[:, 0] + uv[:, 1] * g[:, 1],
                            -uv[:, 0] * g[:, 1] + uv[:, 1] * g[:, 0]])


def edge_bending(rest: np.ndarray, tri_flat: np.ndarray, vertex_map: np.ndarray,
                 edges: np.ndarray, fabric: Fabric) -> np.ndarray:
    """Style3D bending stiffness of each hinge [N m]: ``B_e / 3.4`` with
    ``B_e = B_warp cos^2 phi + B_weft sin^2 phi`` (phi: the edge normal against the warp), as
    the static engine reads the fabric.

    rest : (n, 2) float, grain-aligned flat vertices [m]; tri_flat : (m, 3) int, flat
    triangles; vertex_map : (n,) int, flat -> simulated vertex; edges : (e, 2) int, the
    hinges' end vertices (simulated indices). Returns (e,) float.
    """
    a = tri_flat.ravel()
    b = np.roll(tri_flat, -1, axis=1).ravel()
    sa, sb = vertex_map[a], vertex_map[b]
    n = int(vertex_map.max()) + 1
    keys = np.minimum(sa, sb) * n + np.maximum(sa, sb)
    order = np.argsort(keys, kind="stable")
    want = np.minimum(edges[:, 0], edges[:, 1]) * n + np.maximum(edges[:, 0], edges[:, 1])
    hit = order[np.searchsorted(keys[order], want)]
    d = rest[b[hit]] - rest[a[hit]]
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return BENDING_SCALE * (fabric.bending_warp * d[:, 1] ** 2 + fabric.bending_weft * d[:, 0] ** 2)


def _vertex_normals(x: np.ndarray, tris: np.ndarray) -> np.ndarray:
    n = np.zeros_like(x)
    fn = face_cross(x, tris)
    for k in range(3):
        np.add.at(n, tris[:, k], fn)
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)


def mean_dihedral(x, triangles) -> float:
    """Mean unsigned dihedral angle over the interior edges of a triangle mesh [rad]: how
    folded a garment is (0 for a flat or smoothly rolled sheet in the limit).

    x : (n, 3) float [m]; triangles : (m, 3) int (shared vertices = shared edges).
    """
    tris = np.asanyarray(triangles, dtype=np.int64)
    fn = face_cross(x, tris)
    fn /= np.maximum(np.linalg.norm(fn, axis=1, keepdims=True), 1e-300)
    f0, f1 = face_adjacency(tris).T
    cos = np.clip((fn[f0] * fn[f1]).sum(axis=1), -1.0, 1.0)
    return float(np.arccos(cos).mean()) if len(cos) else 0.0


@dataclass(eq=False)
class NewtonScene:
    """A sewn garment on a body as a Newton model, ready to step.

    ``vertex_map`` (n,) maps flat vertices to Newton particles (welded pairs share one).
    """

    model: object
    solver: object
    state: object
    state_next: object
    control: object
    pipeline: object
    contacts: object
    vertex_map: np.ndarray
    triangles: np.ndarray
    device: str
    fabric: Fabric
    settings: NewtonSettings
    #: (m, 3) float32, the real Style3D stretch stiffness per triangle [N/m]
    tri_ke: np.ndarray | None = None

    def set_stretch_scale(self, scale: float) -> None:
        """Multiply the stretch stiffness by ``scale`` (1: the fabric's) and rebuild the
        solver, whose projective-dynamics matrix is assembled from it once."""
        if self.tri_ke is None:
            self.tri_ke = self.model.style3d.tri_aniso_ke.numpy().copy()
        self.model.style3d.tri_aniso_ke.assign(self.tri_ke * np.float32(scale))
        self.solver = _style3d_solver(self.model, self.settings)


def build_scene(mesh: GarmentMesh, x_sim, vertex_map, body, fabric: Fabric | str, *,
                settings: NewtonSettings | None = None, device: str | None = None) -> NewtonScene:
    """The Newton model of a garment whose welded state is ``x_sim``.

    Parameters
    ----------
    mesh : GarmentMesh
        The flat mesh (rest shape: its panels turned grain-on-u, :func:`panel_rest`).
    x_sim : (s, 3) float
        Start positions of the simulated (welded) vertices [m].
    vertex_map : (n,) int
        Flat vertex -> simulated vertex.
    body : patternfit.body.Body or a mesh
        Its mesh (``vertices`` (k, 3) [m], ``faces`` (j, 3)) and a Body's mittens
        (:meth:`~patternfit.body.Body.mittens`) become static collision shapes.
    fabric : Fabric or str
    settings : NewtonSettings, optional
    device : str, optional
        Warp device (``"cpu"``, ``"cuda"``, ``"cuda:1"``); default :func:`default_device`.
    """
    newton, wp = import_newton()
    s = settings or NewtonSettings()
    fabric = get_fabric(fabric)
    device = device or default_device()
    x_sim = np.asanyarray(x_sim, dtype=np.float64)
    vmap = np.asanyarray(vertex_map, dtype=np.int64)
    if x_sim.ndim != 2 or x_sim.shape[1] != 3 or len(x_sim) != vmap.max() + 1:
        raise ValueError("x_sim: expected (s, 3) positions, one per simulated vertex of "
                         "vertex_map")
    rest = panel_rest(mesh)
    tri_flat = np.asarray(mesh.triangles, dtype=np.int64)
    tri_sim = vmap[tri_flat]
    with wp.ScopedDevice(device):
        builder = newton.ModelBuilder(up_axis=newton.Axis.Y, gravity=(0.0, -s.gravity, 0.0))
        newton.solvers.SolverStyle3D.register_custom_attributes(builder)
        edge_start = len(builder.edge_indices)
        newton.solvers.style3d.add_cloth_mesh(
            builder, pos=wp.vec3(0.0, 0.0, 0.0), rot=wp.quat_identity(), vel=wp.vec3(0.0),
            vertices=x_sim.tolist(), indices=tri_sim.ravel().tolist(),
            panel_verts=rest.tolist(), panel_indices=tri_flat.ravel().tolist(),
            density=fabric.density,
            tri_aniso_ke=wp.vec3(fabric.stretch_warp, fabric.stretch_weft, fabric.shear),
            edge_aniso_ke=None, particle_radius=fabric.thickness + s.contact_radius)
        edges = np.asarray(builder.edge_indices[edge_start:], dtype=np.int64)
        ke = edge_bending(rest, tri_flat, vmap, edges[:, 2:4], fabric)
        for i, k in enumerate(ke.tolist()):
            builder.edge_bending_properties[edge_start + i] = (k, 0.0)
        cfg = newton.ModelBuilder.ShapeConfig(mu=fabric.friction, ke=s.contact_ke,
                                              kd=s.contact_kd)
        # the hands as the cloth meets them (Body.mittens), as in the distance field
        mittens = body.mittens() if hasattr(body, "mittens") else []
        for v, f in [(body.vertices, body.faces)] + [(m.vertices, m.faces) for m in mittens]:
            builder.add_shape_mesh(-1, mesh=newton.Mesh(np.asarray(v, np.float32),
                                                        np.asarray(f, np.int32).ravel()),
                                   cfg=cfg)
        model = builder.finalize()
        model.soft_contact_ke = s.contact_ke
        model.soft_contact_kd = s.contact_kd
        model.soft_contact_mu = fabric.friction
        solver = _style3d_solver(model, s)
        pipeline = newton.CollisionPipeline(model)
        contacts = pipeline.contacts()
        state, state_next = model.state(), model.state()
    return NewtonScene(model=model, solver=solver, state=state, state_next=state_next,
                       control=model.control(), pipeline=pipeline, contacts=contacts,
                       vertex_map=vmap, triangles=tri_sim, device=device, fabric=fabric,
                       settings=s)


def _style3d_solver(model, s: NewtonSettings):
    newton, _ = import_newton()
    solver = newton.solvers.SolverStyle3D(model, config=newton.solvers.SolverStyle3D.Config(
        iterations=s.iterations, linear_iterations=s.linear_iterations))
    if s.self_collision:
        solver.collision.radius = s.self_radius
    else:
        solver.collision = None
    return solver


@dataclass(frozen=True)
class RunResult:
    """Outcome of :func:`run_to_rest`: simulated positions ``x`` (s, 3) [m], frames, whether
    the speed criterion was met, the last frame's largest speed [m/s], seconds, reason, and
    how many vertex positions the contact projection corrected (summed over frames)."""

    x: np.ndarray
    frames: int
    at_rest: bool
    max_speed: float
    seconds: float
    stop_reason: str
    projected: int = 0
    #: largest net vertex displacement over the last ``window`` frames [m] (inf before that)
    drift: float = float("inf")


def _frame(scene: NewtonScene, field, dt: float, h: float, points=None) -> tuple[float, int]:
    """One frame of ``substeps`` steps, then the contact projection (of the vertices, and of
    the edge ``points``, :class:`~patternfit.sim.model.EdgePoints`, when given); returns the
    largest speed [m/s] and how many vertices were projected out of the body."""
    s = scene.settings
    scene.pipeline.collide(scene.state, scene.contacts)
    for _ in range(s.substeps):
        scene.state.clear_forces()
        scene.solver.step(scene.state, scene.state_next, scene.control, scene.contacts, dt)
        scene.state, scene.state_next = scene.state_next, scene.state
    v = scene.state.particle_qd.numpy()
    projected = 0
    if s.project_contact and field is not None:
        x = scene.state.particle_q.numpy().astype(np.float64)
        # a few steps: one gradient step of an interpolated field can fall short in creases
        # (crotch, armpits), and an edge point pushed out there can push its neighbour's in
        # (the 1.5K coat: 2-3 edges left through the body after 4 rounds, none after 10)
        for _ in range(10):
            d, g = field.query(x)
            low = d < 0.0
            x[low] += (h - d[low])[:, None] * g[low]
            vn = (v[low] * g[low]).sum(axis=1)
            v[low] -= np.minimum(vn, 0.0)[:, None] * g[low]
            moved = _project_points(x, v, field, h, points) if points is not None else 0
            if not low.any() and not moved:
                break
            projected = projected or int(low.sum()) + moved
        if projected:
            scene.state.particle_q.assign(x.astype(np.float32))
            scene.state.particle_qd.assign(v)
    return float(np.linalg.norm(v, axis=1).max()), projected


def _project_points(x, v, field, h: float, points) -> int:
    """Move the vertices of every edge or face point found inside the body (``points``,
    :class:`~patternfit.sim.model.EdgePoints`) so that the point lies ``h`` [m] out along
    the field's normal, each by its weight over the sum of the squared weights (the
    least motion that moves the point so), averaged where a vertex has several such points;
    their velocity into the body is removed. Edits ``x`` and ``v`` (s, 3) in place; returns
    how many vertices moved."""
    d, g = field.query(points.matrix @ x)
    low = np.flatnonzero(d < 0.0)
    if not len(low):
        return 0
    w = points.w[low]
    ids = points.ids[low]
    step = ((h - d[low]) / (w * w).sum(axis=1))[:, None, None] * w[:, :, None] \
        * g[low, None, :]
    # an edge point's third vertex has weight 0: it is not one of its vertices here
    mine = (w > 0.0).ravel()
    ids = ids.ravel()[mine]
    move = np.zeros_like(x)
    count = np.zeros(len(x))
    np.add.at(move, ids, step.reshape(-1, 3)[mine])
    np.add.at(count, ids, 1.0)
    hit = count > 0
    x[hit] += move[hit] / count[hit, None]
    normal = np.zeros_like(x)
    np.add.at(normal, ids, np.repeat(g[low], w.shape[1], axis=0)[mine])
    normal[hit] /= np.linalg.norm(normal[hit], axis=1)[:, None]
    vn = (v[hit] * normal[hit]).sum(axis=1)
    v[hit] -= np.minimum(vn, 0.0)[:, None] * normal[hit]
    return int(hit.sum())


def run_to_rest(scene: NewtonScene, *, field=None, points=None, progress=None) -> RunResult:
    """Step ``scene`` frame by frame until the largest vertex speed stays under
    ``speed_tol`` (see :class:`NewtonSettings`).

    field : DistanceField, optional
        Body distance field for the contact projection (``project_contact``).
    points : EdgePoints, optional
        Points inside the cloth's edges, in particle numbering, projected with the vertices
        (``edge_contact``).
    progress : callable, optional
        ``progress(frame, max speed [m/s], 0.0, elapsed [s])``; KeyboardInterrupt in it (or
        Ctrl-C) stops cleanly with the last state.
    """
    _, wp = import_newton()
    s = scene.settings
    dt = 1.0 / s.fps / s.substeps
    h = scene.fabric.thickness
    t0 = time.perf_counter()
    frame, speed, reason, at_rest, projected = 0, np.inf, "frames", False, 0
    drift = np.inf
    phases = [*s.stretch_ramp, (1.0, s.max_frames)]
    try:
        with wp.ScopedDevice(scene.device):
            for phase, (scale, n_frames) in enumerate(phases):
                real = phase == len(phases) - 1
                if len(phases) > 1:
                    scene.set_stretch_scale(scale)
                calm, drift = 0, np.inf
                # positions of the last ``window`` frames (ring buffer) for the drift test
                history = np.zeros((s.window, scene.model.particle_count, 3))
                for k in range(1, n_frames + 1):
                    speed, moved = _frame(scene, field, dt, h, points)
                    frame += 1
                    projected += moved
                    x_now = scene.state.particle_q.numpy().astype(np.float64)
                    if k > s.window:
                        drift = float(np.linalg.norm(x_now - history[k % s.window],
                                                     axis=1).max())
                    history[k % s.window] = x_now
                    if progress is not None:
                        progress(frame, speed, 0.0, time.perf_counter() - t0)
                    calm = calm + 1 if speed < s.speed_tol else 0
                    if real and k >= s.min_frames and calm >= s.patience \
                            and drift < s.rest_drift:
                        at_rest, reason = True, "at rest"
                        break
                    if time.perf_counter() - t0 > s.time_limit:
                        reason = "time"
                        break
                if reason == "time":
                    break
    except (KeyboardInterrupt, SystemError) as exc:
        if not ctrl_c(exc):
            raise
        reason = "interrupted"
    x = scene.state.particle_q.numpy().astype(np.float64)
    return RunResult(x=x, frames=frame, at_rest=at_rest, max_speed=speed,
                     seconds=time.perf_counter() - t0, stop_reason=reason, projected=projected,
                     drift=drift)


def _sim_positions(flat: np.ndarray, vertex_map: np.ndarray) -> np.ndarray:
    x = np.zeros((int(vertex_map.max()) + 1, 3))
    x[vertex_map] = flat
    return x


def _result(solver: GarmentSolver, flat: np.ndarray, vertex_map, run: RunResult) -> DrapeResult:
    checks = solver.checks(flat, converged=run.at_rest)
    return DrapeResult(x=flat, vertex_map=vertex_map, welded=True, iterations=run.frames,
                       seconds=run.seconds, converged=run.at_rest,
                       interrupted=run.stop_reason == "interrupted",
                       stop_reason="converged" if run.at_rest else run.stop_reason,
                       energy=float("nan"), checks=checks)


class EngineWarning(UserWarning):
    """The Newton engine leaves out part of what the fabric asks for."""


def newton_drape(pattern: Pattern, mesh: GarmentMesh, body,
                 fabric: Fabric | str = DEFAULTS.fabric, *,
                 settings: NewtonSettings | None = None, device: str | None = None,
                 from_static: Drape | None = None, clearance: float = 0.03,
                 spacing: float = 0.005, placed=None, sewing_iterations: int = 1500,
                 relax_iterations: int = 300, progress=None) -> Drape:
    """Drape ``mesh`` on ``body`` with Newton's Style3D until it comes to rest.

    Same interface and result as :func:`patternfit.sim.drape.drape` (positions per flat
    vertex [m], placement, checks, timing with ``engine = "newton"``).

    Parameters
    ----------
    pattern, mesh, body, fabric, clearance, spacing, placed, sewing_iterations, relax_iterations
        As for :func:`patternfit.sim.drape.drape` (a fabric with a bending hysteresis gets
        an :class:`EngineWarning`: Style3D drapes it without); the placement and the gravity-free
        sewing and relaxation are the static engine's
        (:meth:`patternfit.sim.schedule.Plan.sewing`, with the static drape's contact
        margin), so both engines start from the same sewn garment.
    settings : NewtonSettings, optional
    device : str, optional
        Warp device; default CUDA when present, else the CPU.
    from_static : Drape, optional
        Start at this static equilibrium (same mesh) with a small random displacement
        along the normals (``settings.perturbation``) instead of placing and sewing, so
        that folds form in a few frames.
    progress : callable, optional
        ``progress(step, value, 0.0, elapsed [s])``: the sewing phase's iterations and
        energy, then the frames and largest speed [m/s].
    """
    t0 = time.perf_counter()
    fabric = get_fabric(fabric)
    if fabric.bending_hysteresis:
        # Style3D has no frictional bending couple: say so rather than drape another fabric
        warnings.warn(EngineWarning(
            f"fabric {fabric.name!r}: the Newton engine drapes without its bending hysteresis "
            f"(2HB = {fabric.bending_hysteresis:g} N); the static engine models it "
            "(docs/simulation.md, 'Bending hysteresis')"), stacklevel=2)
    s = settings or NewtonSettings()
    import_newton()  # fail before any work when newton is missing
    t = time.perf_counter()
    field_ = body.contact_field(spacing)
    t_sdf = time.perf_counter() - t
    timing = {"distance_field_seconds": t_sdf}
    if from_static is not None:
        solver = from_static.solver
        vmap = np.asarray(from_static.result.vertex_map)
        x0 = from_static.placed
        x_sim = _sim_positions(from_static.positions, vmap)
        rng = np.random.default_rng(s.seed)
        x_sim = x_sim + (s.perturbation * rng.uniform(-1.0, 1.0, len(x_sim)))[:, None] \
            * _vertex_normals(x_sim, vmap[mesh.triangles])
        timing["sewing_iterations"] = 0
    else:
        x0 = place_on_body(pattern, mesh, body, clearance=clearance) if placed is None \
            else np.asanyarray(placed, dtype=np.float64)
        solver = GarmentSolver(mesh.vertices, mesh.triangles, mesh.grain[mesh.triangle_panel],
                               fabric, seam_pairs=mesh.seam_pairs, body=field_,
                               settings=SolverSettings(contact_margin=CONTACT_MARGIN))
        plan = Plan.sewing(sewing_iterations=sewing_iterations, relax_iterations=relax_iterations)
        run = run_plan(solver, plan, x0, progress=progress)
        sewn = run.result
        timing.update(sewing_seconds=run.seconds(*plan.names),
                      sewing_iterations=run.iterations(*plan.names))
        if not sewn.welded or sewn.interrupted:
            return Drape(positions=sewn.x[solver.model.vertex_map], placed=x0, result=sewn,
                         solver=solver, seconds=time.perf_counter() - t0,
                         timing={**timing, "engine": "newton"})
        vmap = np.asarray(sewn.vertex_map)
        x_sim = _sim_positions(sewn.x[solver.model.vertex_map], vmap)
    t = time.perf_counter()
    scene = build_scene(mesh, x_sim, vmap, body, fabric, settings=s, device=device)
    timing["build_seconds"] = time.perf_counter() - t
    # the static solver's welded model numbers its vertices as the particles are numbered
    points = solver.model.edge_points(s.edge_contact) if s.edge_contact > 0 else None
    run = run_to_rest(scene, field=field_, points=points, progress=progress)
    flat = run.x[vmap]
    result = _result(solver, flat, vmap, run)
    timing.update(engine="newton", device=scene.device, frames=run.frames,
                  max_speed=run.max_speed, newton_seconds=run.seconds,
                  drift_m=run.drift if np.isfinite(run.drift) else None,
                  projected_vertices=run.projected)
    return Drape(positions=flat, placed=x0, result=result, solver=solver,
                 seconds=time.perf_counter() - t0, timing=timing)


ENGINES = ("static", "newton")


def drape_with(engine: str, pattern: Pattern, mesh: GarmentMesh, body, fabric, *,
               settings: SolverSettings | None = None, device: str | None = None,
               from_static: bool = False, clearance: float = 0.03, progress=None) -> Drape:
    """Drape with ``engine`` (``"static"`` or ``"newton"``); ``from_static`` (newton only)
    drapes statically first and starts Newton there. ``settings`` are the static solver's
    (their ``time_limit`` [s] also bounds Newton's run)."""
    if engine not in ENGINES:
        raise ValueError(f"engine: expected one of {', '.join(ENGINES)}, got {engine!r}")
    if engine == "static":
        if from_static or device is not None:
            raise ValueError("from_static and device belong to the newton engine")
        return drape(pattern, mesh, body, fabric, settings=settings, clearance=clearance,
                     progress=progress)
    import_newton()
    ns = NewtonSettings(time_limit=settings.time_limit) if settings else NewtonSettings()
    start = drape(pattern, mesh, body, fabric, settings=settings, clearance=clearance,
                  progress=progress) if from_static else None
    d = newton_drape(pattern, mesh, body, fabric, settings=ns, device=device, from_static=start,
                     clearance=clearance, progress=progress)
    if start is not None:
        d.seconds += start.seconds
        d.timing["static_seconds"] = start.seconds
    return d
