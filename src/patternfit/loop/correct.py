"""Automatic fit correction: from the drape's stretch to corner moves a pattern maker makes.

The method (``docs/fit-correction.md``): across the grain, the fabric a panel lacks at a
height h along its grainline is the integral of the excess weft stretch over the panel's
width there, Σ a_t (weft_t − 1)⁺ / Δh over the triangles of a band Δh high; the corners of
the panel's seam edges at that height move outward by half of it each (both sides of the
panel), so a panel that is mirror-symmetric stays so. Along the grain, excess warp stretch
lengthens the panel below its anchored top. Only stretch counts (no growth where the
garment is loose); sewn corners move by the same amount on both panels of a seam, so
seams still match; edges keep their kind (lines stay lines, curves keep their shape near
the other end), so outlines stay smooth. Lengths in metres.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np
from scipy.optimize import nnls

from ..constants import tol
from ..defaults import DEFAULTS
from ..edit import close_seams, move_corner
from ..fit.lengths import risen
from ..fit.measures import FitMeasures, fit_measures
from ..fit.metrics import FitResult
from ..fit.verdict import Verdict, judge_garment
from ..fit.verdict_rules import VerdictRules, ease_range
from ..mesh.garment import GarmentMesh
from ..pattern.errors import PatternError
from ..pattern.model import Pattern
from ..pattern.validate import check_pattern
from ..sim.checks import crossing_reasons, seam_gap_reason
from .ease_limit import cap_moves
from .lengthen import hem_edges, hem_moves
from .regions import find_regions
from .symmetry import mirrored_triangles, other_side, symmetric_moves
from .widen import edge_moves, let_out_moves, opening_moves


#: the region verdicts the loop may stop at, and the words it lets out regions for
GOALS = {"tight": ("too tight",), "fits": ("too tight", "tight")}


@dataclass(frozen=True)
class CorrectionSettings:
    """Knobs of the automatic correction.

    threshold : float     ϖ to reach [-] (``DEFAULTS.threshold``) ...
    rules : VerdictRules  ... with no region too tight by the fit verdict
                          (:mod:`patternfit.fit.verdict`) ...
    take_in : bool        ... and, when True, none too loose (loose regions are taken in);
    goal : str            the worst region verdict the loop may stop at: "tight" (no
                          region too tight, the issue's rule) or "fits" (none tight
                          either: tight regions are let out too).
    max_iterations : int  correction rounds (edit + re-drape) at most.
    gain : float          share of the measured lack of fabric added per round [-].
    max_move : float      largest corner move of one round [m] ...
    max_let_out : float   ... and of one round letting out (or taking in) regions [m]:
                          the 3K Table 2 coat let out 10 cm at the armpit in one round
                          crossed itself on the re-drape (119 pairs).
    band : float          height of the bands the lack of width is measured in [m].
    min_move : float      corner moves smaller than this are left out [m].
    warp_min : float      mean excess warp stretch of a panel below which it is not
                          lengthened [-].
    min_angle : float     the mesh follows the edits without re-meshing down to this
                          smallest triangle angle [degrees]: a re-meshed panel loses the
                          warm start, and the corrected 22K coat draped cold crossed itself.
    step_backs : int      a re-drape worse than the drape its edit was made from (failed
                          its checks where that one passed, or a region turned too tight)
                          is undone and the edit made again at half its size, this many
                          times at most.
    """

    threshold: float = DEFAULTS.threshold
    rules: VerdictRules = VerdictRules()
    take_in: bool = False
    goal: str = "tight"
    max_iterations: int = 3
    gain: float = 1.0
    max_move: float = 0.12
    max_let_out: float = 0.05
    band: float = 0.10
    min_move: float = 1e-3
    warp_min: float = 0.02
    min_angle: float = 10.0
    step_backs: int = 2

    def __post_init__(self):
        if self.goal not in GOALS:
            raise ValueError(f"goal: {self.goal!r} is not one of {', '.join(GOALS)}")


@dataclass(frozen=True)
class CornerMove:
    """A move of the corner where ``edge`` starts on ``panel`` by ``offset`` (2,) [m]."""

    panel: str
    edge: str
    offset: tuple

    def to_dict(self) -> dict:
        dx, dy = self.offset
        return {"op": "move_point", "panel": self.panel, "corner": self.edge,
                "offset_cm": [round(dx * 100, 2), round(dy * 100, 2)],
                "cm": round(float(np.hypot(dx, dy)) * 100, 2)}


@dataclass
class Iteration:
    """One round of the loop: ϖ of the drape, its regions, the edits made after it, time."""

    index: int
    fitting_ratio: float
    regions: list
    edits: list
    seconds: float
    checks: dict | None = None
    verdict: Verdict | None = None
    measures: dict | None = None  # FitMeasures.report(): gap_mm, ease_cm, pressure_kpa
    measured: FitMeasures | None = field(default=None, repr=False)  # for the pictures
    stepped_back: list = field(default_factory=list)  # why each undone re-drape was worse
    risen: dict = field(default_factory=dict)  # limb → how far its end rose since drape 0 [m]

    def to_dict(self) -> dict:
        return {"iteration": self.index, "fitting_ratio": self.fitting_ratio,
                "regions": [r.to_dict() for r in self.regions],
                "edits": [e.to_dict() for e in self.edits], "seconds": self.seconds,
                "stepped_back": self.stepped_back,
                "limbs_risen_cm": {k: round(100.0 * v, 2) for k, v in self.risen.items()},
                "checks": self.checks, **(self.measures or {}),
                **(self.verdict.report() if self.verdict is not None else {})}


@dataclass
class Correction:
    """Outcome of :func:`correct`: the iterations (0 = the first drape), whether the fit
    was reached, and the corrected pattern. ``failed`` says why the loop stopped without
    editing when a drape was no fit at all (:func:`refusal`), else None."""

    iterations: list[Iteration] = field(default_factory=list)
    reached: bool = False
    pattern: Pattern | None = None
    seconds: float = 0.0
    failed: str | None = None

    @property
    def fitting_ratio(self) -> float:
        return self.iterations[-1].fitting_ratio

    @property
    def edited(self) -> bool:
        """Whether the loop ran to its end (not refused, :attr:`failed`) with edits made:
        its :attr:`pattern` is a new one to make, and drape afresh
        (``api.fresh_drape``)."""
        return not self.failed and self.pattern is not None \
            and any(it.edits for it in self.iterations)

    @property
    def verdict(self) -> str | None:
        """The final drape's overall verdict."""
        v = self.iterations[-1].verdict if self.iterations else None
        return None if v is None else v.overall

    def to_dict(self) -> dict:
        last = self.iterations[-1]
        return {"fitting_ratio": self.fitting_ratio, "reached": self.reached,
                "verdict": self.verdict,
                "region_verdicts": last.verdict.report()["region_verdicts"]
                if last.verdict is not None else {},
                "seconds": self.seconds, "correction_rounds": len(self.iterations) - 1,
                "edits_made": sum(len(it.edits) for it in self.iterations),
                "failed": self.failed,
                "iterations": [it.to_dict() for it in self.iterations]}


def propose_moves(pattern: Pattern, mesh: GarmentMesh, fit: FitResult, *,
                  settings: CorrectionSettings = CorrectionSettings()) -> list[CornerMove]:
    """Corner moves that give every panel the fabric its drape lacks (see the module).

    Parameters
    ----------
    pattern : Pattern
        The pattern ``mesh`` was made from.
    mesh : GarmentMesh
    fit : FitResult
        The fit of the drape of ``mesh``.
    settings : CorrectionSettings

    Returns
    -------
    list of CornerMove
    """
    seamed = {(side.panel, side.edge) for s in pattern.seams for side in (s.a, s.b)}
    centroid = mesh.vertices[mesh.triangles].mean(axis=1)
    moves: dict[tuple, np.ndarray] = {}
    for pi, name in enumerate(mesh.panel_names):
        panel = pattern.panel(name)
        tris = mesh.panel_triangles(pi)
        g = mesh.grain[pi]
        c = np.array([-g[1], g[0]])
        a = fit.area_2d[tris]
        warp_excess = float(a @ np.clip(fit.warp[tris] - 1.0, 0.0, None) / a.sum())
        outline = panel.outline.polygon()
        axis = float(np.median(outline @ c))
        hmax = float((outline @ g).max())
        half_width = 0.5 * float(np.ptp(outline @ c))
        edges = panel.outline.edges
        corners = [e.name for k, e in enumerate(edges)
                   if (name, e.name) in seamed or (name, edges[k - 1].name) in seamed]
        across = _across_moves(mesh, pi, panel, fit, tris, centroid[tris], g, c, axis,
                               half_width, corners, settings)
        for e in edges:
            if e.name not in corners:
                continue
            p = np.asarray(e.start, dtype=np.float64)
            d = across[e.name] * c
            if warp_excess > settings.warp_min:
                # the top is anchored on the body (waist, neck): grow downwards
                d = d - g * warp_excess * (hmax - p @ g)
            moves[(name, e.name)] = settings.gain * d
    return finish_moves(pattern, mesh, moves, settings)


def _across_moves(mesh: GarmentMesh, pi: int, panel, fit: FitResult, tris, centroid, g, c,
                  axis: float, half_width: float, corners: list, settings) -> dict:
    """Signed move across the grain [m] (along ``c``) of each corner in ``corners``.

    Each outline vertex p of the panel should move outward by the width the fabric lacks
    between the panel's axis and p, in a band ``settings.band`` high around p:
    D(p) = Σ a_t (weft_t − 1)⁺ / Δh over the band's triangles on p's side and nearer the
    axis. A corner move carries the outline points of its two edges along, linearly in their
    arc-length fraction; the outward sizes of the corners off the axis (≥ 0: nothing is
    taken in) are fitted to D over all outline vertices by non-negative least squares.
    """
    excess = fit.area_2d[tris] * np.clip(fit.weft[tris] - 1.0, 0.0, None)
    h_t, x_t = centroid @ g, centroid @ c - axis
    loop = mesh.loops(pi)[0]
    pts = mesh.vertices[loop]
    h_p, x_p = pts @ g, pts @ c - axis
    hmin, hmax = float(h_t.min()), float(h_t.max())
    lo = np.maximum(h_p - settings.band / 2, hmin)
    hi = np.minimum(h_p + settings.band / 2, hmax)
    inband = (h_t[None, :] >= lo[:, None]) & (h_t[None, :] <= hi[:, None])
    inside = (x_t[None, :] * np.sign(x_p)[:, None] > 0) & \
        (np.abs(x_t)[None, :] <= np.abs(x_p)[:, None])
    want = ((inband & inside) @ excess) / np.maximum(hi - lo, tol.merge) * np.sign(x_p)

    edges = panel.outline.edges
    names = [e.name for e in edges]
    free = [n for n in corners
            if abs(np.asarray(panel.edge(n).start) @ c - axis) > 0.2 * half_width]
    col = {n: j for j, n in enumerate(free)}
    side = np.array([np.sign(np.asarray(panel.edge(n).start) @ c - axis) for n in free])
    where = {int(v): i for i, v in enumerate(mesh.boundary_vertices)}
    rows = np.array([where[int(v)] for v in loop])
    k_edge = np.array([names.index(mesh.edge_names[k][1]) for k in mesh.boundary_edge[rows]])
    s = mesh.boundary_param[rows]
    A = np.zeros((len(loop), len(free)))
    for i, (k, t) in enumerate(zip(k_edge, s)):
        for n, w in ((names[k], 1.0 - t), (names[(k + 1) % len(names)], t)):
            if n in col:
                A[i, col[n]] += w * side[col[n]]
    used = A.any(axis=1)
    if not free or not used.any():
        return {n: 0.0 for n in corners}
    # a faint pull to zero keeps a corner with few outline points near it well posed
    ridge = 1e-2 * np.eye(len(free))
    u, _ = nnls(np.vstack([A[used], ridge]), np.concatenate([want[used], np.zeros(len(free))]))
    return {n: float(u[col[n]] * side[col[n]]) if n in col else 0.0 for n in corners}


def _corner_partner(pattern: Pattern, panel: str, edge: str):
    """(panel, edge whose start is the same sewn point) across each full-length seam."""
    p = pattern.panel(panel)
    li, k = p.locate(edge)
    loop = p.loops[li].edges
    prev = loop[k - 1].name
    for s in pattern.seams:
        for mine, other in ((s.a, s.b), (s.b, s.a)):
            if mine.panel != panel or (mine.start, mine.end) != (0.0, 1.0) \
                    or (other.start, other.end) != (0.0, 1.0):
                continue
            op = pattern.panel(other.panel)
            oli, ok = op.locate(other.edge)
            onext = op.loops[oli].edges[(ok + 1) % len(op.loops[oli].edges)].name
            if mine.edge == edge:       # our corner is the start of this seam side
                yield other.panel, (onext if s.reverse else other.edge)
            elif mine.edge == prev:     # ... or its end
                yield other.panel, (other.edge if s.reverse else onext)


def _share_sewn_corners(pattern: Pattern, moves: dict) -> None:
    """Sewn corners get the same outward move size on both panels (the mean of their
    demands), each along its own panel's direction, so seam sides keep equal lengths."""
    groups: dict = {}
    for key in list(moves):
        group = {key}
        frontier = [key]
        while frontier:
            for q in _corner_partner(pattern, *frontier.pop()):
                if q in moves and q not in group:
                    group.add(q)
                    frontier.append(q)
        groups[frozenset(group)] = group
    for group in groups.values():
        if len(group) < 2:
            continue
        size = np.mean([np.linalg.norm(moves[k]) for k in group])
        for k in group:
            n = np.linalg.norm(moves[k])
            if n > 0:
                moves[k] = moves[k] * (size / n)


def apply_moves(pattern: Pattern, moves: list[CornerMove]) -> Pattern:
    """The pattern with all corner moves made at once; seam sides left of unequal length
    (panels that are not congruent) are closed by the smallest extra moves of the corners
    of each seam's second side (:func:`close_seams`); an eased seam keeps the length ratio
    it had in ``pattern`` (not its full stated ease). Refuses (``PatternError``) a result
    that fails ``check_pattern``."""
    new = pattern
    for mv in moves:
        new = new.with_panel(move_corner(new.panel(mv.panel), mv.edge, np.asarray(mv.offset)))
    new = close_seams(new, like=pattern)
    check_pattern(new)
    return new


def fit_reached(fit: FitResult, verdict: Verdict, settings: CorrectionSettings,
                rises: dict | None = None) -> bool:
    """ϖ at the threshold, the drape not failed, no limb's end risen beyond the length
    tolerance (``rises``: limb → rise [m], :func:`~patternfit.fit.lengths.risen`) and no
    region too tight by the verdict (with ``settings.goal`` "fits", none tight either; with
    ``settings.take_in``, none too loose and the garment not slid)."""
    if fit.fitting_ratio < settings.threshold or verdict.overall == "failed" or rises:
        return False
    if any(verdict.worst(word) for word in GOALS[settings.goal]):
        return False
    return not (settings.take_in and (verdict.overall == "too loose"
                                       or verdict.worst("too loose")))


def measure_state(session, rules: VerdictRules) -> tuple[FitResult, FitMeasures, Verdict]:
    """The fit, the fit measures and the verdict of the session's current drape (with the
    contact distance of the solver that draped it, and its distance field's grid: the
    body's own field, without the floor)."""
    fit = session.evaluate()
    solver = session._drape.solver if session._drape is not None else None
    margin = solver.settings.contact_margin if solver is not None else 0.003
    field = session.body.distance_field(solver.model.body.spacing) \
        if solver is not None and solver.model.body is not None else None
    m = fit_measures(session.mesh, session.state.positions, session.body, session.fabric,
                     field, reach=max(session.fabric.thickness, margin))
    return fit, m, judge_garment(session.pattern, fit, m, session.fabric,
                                 session.state.checks, rules)


def refusal(checks: dict | None, fitting_ratio: float) -> str | None:
    """Why no correction may be made from a drape with these ``checks`` (the session
    state's: solver and on-body checks) and ϖ, or None: the garment is not on the body where
    its pattern says (fell, lies at the feet, slid off its anchor, collapsed; the on-body
    checks, :mod:`patternfit.sim.onbody`), it did not come to rest (stopped at its
    iteration or time limit: a shape still moving), cloth lies inside the body or goes
    through it between its vertices, its seams are open, or ϖ is not finite. Its stretch
    says nothing about the pattern (a first drape stopped after 5 iterations, 57 vertices
    inside the body, was edited from: 12 edits; a skirt hung from the neck with 6 cloth
    edges through the body was given 4). A drape that failed only by crossed triangles (a
    few pairs pooled in a fold) is still corrected from; its checks travel with the
    round."""
    if not np.isfinite(fitting_ratio):
        return "the drape's fitting ratio is not finite"
    checks = checks or {}
    if checks.get("on_body") is False:
        reasons = checks.get("on_body_reasons") or ["not on the body"]
        return "the drape failed: " + "; ".join(str(r) for r in reasons)
    why = []
    if checks.get("equilibrium") is False:
        rms = checks.get("residual_rms")
        why.append("not at rest" if rms is None
                   else f"not at rest (residual rms {rms:.3g} of a vertex's weight)")
    if checks.get("inside_vertices"):
        why.append(f"{checks['inside_vertices']} vertices inside the body")
    why += crossing_reasons(checks.get("edges_in_body") or 0, checks.get("faces_in_body") or 0,
                            0)
    why += [r for r in [seam_gap_reason(checks.get("seam_gap_max_mm") or 0.0)] if r]
    if why:
        return "the drape failed: " + "; ".join(why)
    return None


def correct(session, *, settings: CorrectionSettings = CorrectionSettings(),
            progress: Callable | None = None, drape_progress: Callable | None = None
            ) -> Correction:
    """Run the loop on a :class:`~patternfit.loop.DesignSession`: drape (if not yet),
    evaluate, find the regions, edit, re-drape warm-started, until the fit is reached or
    ``settings.max_iterations`` rounds were made.

    ``progress(iteration: Iteration)`` is called after each drape is evaluated;
    ``drape_progress`` goes to the solver. Returns the :class:`Correction`; the session
    holds every state (one per round) for undo. A re-drape worse than the drape its edit
    was made from (off the body where that one was on it, failed its checks where that one
    passed, or a region turned too tight) steps back: the edit is undone and made again at
    half its size (:func:`_step_back`; ``Iteration.stepped_back`` says why). A drape that
    is no fit at all (:func:`refusal`) stops the loop, ``Correction.failed`` saying why:
    the first drape without an edit; a re-drape still no fit after the step-backs with its
    round's edits undone, the session and the pattern given back at the last drape that
    was one. A drape that failed only by crossed triangles is edited from. A sleeve
    or trouser leg (a limb with a hem of its own,
    :func:`~patternfit.loop.lengthen.hem_edges`) whose end rose along the limb by more than
    ``settings.rules.length_tolerance_cm`` from the first drape is no fit: the next round
    lengthens it at its hem (:func:`~patternfit.loop.lengthen.hem_moves`;
    ``Iteration.risen``).
    """
    out = Correction()
    t_all = time.perf_counter()
    for index in range(settings.max_iterations + 1):
        t0 = time.perf_counter()
        # a state read back from a saved session is draped on from its own rest first (at
        # rest it stops at once): its saved checks are those of the version that saved it,
        # and a dress stated as hung from the waist passed in them and was edited from
        if index > 0 or session.state.positions is None or session.state.fitting_ratio is None \
                or session.next_start() == "continued":
            session.redrape(progress=drape_progress)
        fit, measures, verdict = measure_state(session, settings.rules)
        stepped: list[str] = []
        if index > 0:
            stepped, (fit, measures, verdict) = _step_back(
                session, out.iterations[-1], (fit, measures, verdict), settings,
                drape_progress)
        regions = find_regions(session.mesh, fit)
        rises = {k: v for k, v in risen(
            out.iterations[0].measured.limb_ends, measures.limb_ends,
            settings.rules.length_tolerance_cm / 100.0).items()
            if hem_edges(session.pattern, session.mesh, session.state.positions,
                         measures.vertex_region, session.body, k)} if index > 0 else {}
        reached = fit_reached(fit, verdict, settings, rises)
        it = Iteration(index, fit.fitting_ratio, regions, [], 0.0, session.state.checks,
                       verdict, measures.report(), measures, stepped, rises)
        out.failed = refusal(session.state.checks, fit.fitting_ratio)
        if out.failed and index > 0:
            # the last round's edits, halved as often as allowed, still drape to no fit:
            # undone, so that the pattern given back is the last one that draped to one
            session.undo()
            last = out.iterations[-1]
            out.failed = (f"the drape after round {index}'s {len(last.edits)} edits failed "
                          f"({out.failed.removeprefix('the drape failed: ')}): they were "
                          f"undone, the pattern is the one draped in round {index - 1}")
            last.edits = []
            break
        if out.failed:
            reached = False
        elif not reached and index < settings.max_iterations:
            # a drape that failed only by crossed triangles is still edited from (as the
            # corner moves always were): its regions judged as if it had passed
            judged = verdict if verdict.overall != "failed" else judge_garment(
                session.pattern, fit, measures, session.fabric, None, settings.rules)
            it.edits = _edit(session, fit, measures, judged, settings, rises)
        it.seconds = time.perf_counter() - t0
        out.iterations.append(it)
        if progress is not None:
            progress(it)
        if reached or not it.edits:  # fit reached, the limit hit, or nothing left to change
            out.reached = reached
            break
    out.pattern = session.pattern
    out.seconds = time.perf_counter() - t_all
    return out


def region_moves(session, fit: FitResult, measures: FitMeasures, verdict: Verdict,
                 settings: CorrectionSettings) -> dict:
    """Corner offsets ``{(panel, edge): (2,) [m]}`` of the edge translations
    (:mod:`patternfit.loop.widen`) for every region the verdict calls too tight (with
    ``settings.goal`` "fits", tight as well: by default they are left, as letting them
    out in the same round crossed the 22K Table 2 coat's re-drape, 69–71 pairs) — by the
    length its stretch lacks over the region's width, down to a quarter of the tight
    threshold — and, with ``settings.take_in``, too loose — its side edges inward by its
    ease beyond the middle of the style's range, shared by the panels it spans and their
    two sides. Two regions asking one corner count once, the larger ask.

    Both sides are edited alike (a pattern maker's rule on a symmetric body): a region is
    taken with its left/right partner (``bicep_left`` with ``bicep_right``; too tight if
    either is, by the higher stretch; too loose by their mean ease) and its triangles with
    their mirror images (:func:`~patternfit.loop.symmetry.mirrored_triangles`), so that a
    drape come to rest a little askew finds the same edges on both sides."""
    moves: dict = {}
    names = list(measures.regions)
    target = 0.25 * settings.rules.tight_share * (verdict.stretch_limit or 0.0)
    mesh = session.mesh
    done: set = set()
    for name in verdict.regions:
        if name in done:
            continue
        pair = [n for n in (name, other_side(name)) if n in names]
        done.update(pair)
        judged = {n: verdict.regions[n] for n in pair if n in verdict.regions}
        tris = mirrored_triangles(session.pattern, mesh, np.flatnonzero(
            np.isin(measures.triangle_region, [names.index(n) for n in pair])))
        tight = [r.stretch_p90 or 0.0 for r in judged.values()
                 if r.verdict in GOALS[settings.goal]]
        loose = [(n, r.ease_cm) for n, r in judged.items()
                 if r.verdict == "too loose" and r.ease_cm is not None]
        found: dict = {}
        if tight:
            found = let_out_moves(session.pattern, mesh, session.state.positions, tris,
                                  target, least=max(tight))
            for key, d in opening_moves(session.pattern, mesh, session.state.positions, tris,
                                        target, least=max(tight)).items():
                found[key] = found.get(key, 0.0) + d
        elif settings.take_in and loose:
            body = {k: sec.body_cm for k, sec in measures.sections.items()}
            lo, hi = ease_range(verdict.style, loose[0][0], body) or (None, None)
            if hi is None:
                continue
            middle = hi if lo is None else 0.5 * (lo + hi)
            ease = float(np.mean([r.ease_cm for r in judged.values()
                                  if r.ease_cm is not None]))
            panels = np.unique(mesh.triangle_panel[tris])
            for pi in panels:
                g = mesh.grain[pi]
                found.update(edge_moves(session.pattern, mesh, int(pi),
                                        tris[mesh.triangle_panel[tris] == pi],
                                        np.array([-g[1], g[0]]),  # across: the girth's way
                                        -0.01 * (ease - middle) / len(panels)))
        for key, d in found.items():
            # regions asking one corner (bust and biceps at the armpit) read the same
            # missing cloth: the larger ask, not their sum
            if key not in moves or np.linalg.norm(d) > np.linalg.norm(moves[key]):
                moves[key] = d
    return moves


def finish_moves(pattern: Pattern, mesh: GarmentMesh, offsets: dict,
                 settings: CorrectionSettings = CorrectionSettings()) -> list[CornerMove]:
    """Corner moves from offsets ``{(panel, edge): (2,) [m]}``: sewn corners given the same
    size and mirrored corners mirrored moves (as :func:`propose_moves` does), each capped
    at ``settings.max_move``, those under ``settings.min_move`` left out."""
    offsets = dict(offsets)
    for _ in range(3):  # both are averages: alternating them converges
        _share_sewn_corners(pattern, offsets)
        offsets = symmetric_moves(pattern, mesh, offsets)
    moves = []
    for (pname, ename), d in offsets.items():
        n = float(np.linalg.norm(d))
        if n < settings.min_move:
            continue
        if n > settings.max_move:
            d = d * (settings.max_move / n)
        moves.append(CornerMove(pname, ename, (float(d[0]), float(d[1]))))
    return moves


def _edit(session, fit: FitResult, measures: FitMeasures, verdict: Verdict,
          settings: CorrectionSettings, rises: dict | None = None) -> list[CornerMove]:
    """Propose and apply one round of moves — the corner moves across the grain while ϖ
    is short, else the edge translations where the verdict says a region is too tight (or
    too loose, taking in) — sewn corners shared and symmetry kept, and the limbs whose
    end rose (``rises``) lengthened at their hems; halve them if the result is refused."""
    # both read the same lack of fabric: the edge translations only once the corner
    # moves have brought ϖ to the threshold (they cannot reach what is left)
    extra = {} if fit.fitting_ratio < settings.threshold else \
        region_moves(session, fit, measures, verdict, settings)
    if fit.fitting_ratio < settings.threshold:
        moves = propose_moves(session.pattern, session.mesh, fit, settings=settings)
    else:
        moves = finish_moves(session.pattern, session.mesh, extra,
                             replace(settings, max_move=settings.max_let_out))
    if verdict.style is not None:
        # a let-out stops at the style's ease range (a take-in only narrows: never held)
        moves = cap_moves(session.pattern, session.mesh, measures, verdict, moves)
    if rises:
        # a cuff moved along the sleeve widens no girth: added after the ease limit
        hem = hem_moves(session.pattern, session.mesh, session.state.positions,
                        measures.vertex_region, session.body, rises)
        moves = _summed(moves, finish_moves(session.pattern, session.mesh, hem,
                                            replace(settings, max_move=settings.max_let_out)))
    return _make(session, moves, "edge translations (corner moves)" if extra
                 else "corner moves", settings)


def _summed(*lists: list) -> list:
    """One move per corner: the offsets of ``lists`` of corner moves added."""
    total: dict = {}
    for mv in (m for moves in lists for m in moves):
        total[(mv.panel, mv.edge)] = total.get((mv.panel, mv.edge), 0.0) + np.asarray(mv.offset)
    return [CornerMove(p, e, (float(d[0]), float(d[1]))) for (p, e), d in total.items()]


def _make(session, moves: list, what: str, settings: CorrectionSettings) -> list:
    """Apply ``moves`` as one recorded edit (``correct: N <what>, X cm in all``) of the
    session's pattern; halve them while the result is refused (4 times at most). Returns
    the moves made (none when every try was refused)."""
    for _ in range(4):
        if not moves:
            return []
        try:
            new = apply_moves(session.pattern, moves)
        except PatternError:
            moves = _halved(moves)
            continue
        total = sum(np.hypot(*m.offset) for m in moves) * 100
        session.apply_pattern(new, label=f"correct: {len(moves)} {what}, "
                              f"{total:.1f} cm in all",
                              edit={"op": "correct", "args": {"moves": [m.to_dict()
                                                                        for m in moves]}},
                              min_angle=settings.min_angle)
        return moves
    return []


def _halved(moves: list) -> list:
    return [replace(m, offset=(0.5 * m.offset[0], 0.5 * m.offset[1])) for m in moves]


def _worse(last: Iteration, checks: dict | None, verdict: Verdict,
           fitting_ratio: float) -> str | None:
    """Why the drape with ``checks``, ``verdict`` and ϖ, made from ``last``'s drape by its
    edits, is worse than that one, or None: it is no fit at all (:func:`refusal`: off the
    body) where ``last``'s was one, it failed its checks where ``last``'s passed, or a
    region reads too tight where none did."""
    off = refusal(checks, fitting_ratio)
    if off and not refusal(last.checks, last.fitting_ratio):
        return off
    if (last.checks or {}).get("passed") and (checks or {}).get("passed") is False:
        return "; ".join(str(r) for r in checks.get("reasons") or ["its checks failed"])
    before = last.verdict
    if before is not None and before.overall != "failed" and not before.worst("too tight") \
            and verdict.worst("too tight"):
        return verdict.reason
    return None


def _step_back(session, last: Iteration, measured: tuple, settings: CorrectionSettings,
               drape_progress: Callable | None) -> tuple[list[str], tuple]:
    """When the re-drape after ``last``'s edits (its fit, measures and verdict:
    ``measured``) is worse than ``last``'s drape (:func:`_worse`: failed its checks, or a
    region turned too tight), undo the edit and make it again at half its size, re-draped,
    up to ``settings.step_backs`` times: the edit is what changed. (The 22K Table 2 coat's
    fourth let-out left a panel's triangles too thin, the re-meshed coat draped cold
    pressed its forearms at 12 kPa.) ``last.edits`` become the moves finally made. Returns
    why each undone re-drape was worse, and the fit, measures and verdict of the drape
    kept."""
    why: list[str] = []
    while last.edits and len(why) < settings.step_backs:
        reason = _worse(last, session.state.checks, measured[2], measured[0].fitting_ratio)
        if reason is None:
            break
        why.append(reason)
        session.undo()
        last.edits = _make(session, _halved(last.edits), "moves (stepped back: halved)",
                           settings)
        if last.edits:
            session.redrape(progress=drape_progress)
        measured = measure_state(session, settings.rules)
    return why, measured
