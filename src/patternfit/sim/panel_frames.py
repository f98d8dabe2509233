"""The panels' flat frames made ready for placement, and imported 3D placements judged.

Our own patterns are drafted upright (y up, the hem of every body panel at y = 0), so each
panel's flat frame already says where it goes in height. Other tools' frames do not: a DXF
piece may lie turned in the marker, a GarmentCode sleeve is drafted along x, every
GarmentCode panel has its own origin. :func:`upright_frames` turns each panel so that its
"up" is +y and, where the seams say the frames disagree in height, stacks them so that the
seams meet. :func:`implausible_placements` says which imported 3D placements are not around
the body (older GarmentCode templates put panels at the feet or 25 m below). Metres.
"""

from __future__ import annotations

import numpy as np

from ..mesh.garment import GarmentMesh
from ..pattern.model import Pattern
from ..pattern.roles import PanelRole, panel_roles, upright_turn

#: seams between body panels whose sides' mean heights differ by more than this [m] mean
#: the flat frames are not drafted in one height frame
FRAME_MISMATCH = 0.05
#: an imported placement is implausible when a panel's median distance from the body
#: surface exceeds this [m], ...
PLACED_FAR = 0.40
#: ... or more than this share of its vertices lie inside the body [-], or the top of the
#: body panels lies farther than this [m] from the height the garment hangs from: a
#: placement made for another body (GarmentCode's shirt for its 1.72 m mean body sat 11 cm
#: below a 1.78 m body's neck and slid off it; its flare skirt, within 1 cm of the waist,
#: draped as placed)
PLACED_INSIDE = 0.3
PLACED_HEIGHT = 0.05

#: body measurement giving the height of each anchor (:attr:`Pattern.anchor`) [m]
ANCHOR_HEIGHT = {"waist": "waist_height", "neck": "neck_base_height"}


class PlacementWarning(UserWarning):
    """An imported placement was not used (it is not around the body)."""


def _up_direction(pattern: Pattern, mesh: GarmentMesh, pi: int, role: PanelRole,
                  roles: dict[str, PanelRole]) -> np.ndarray | None:
    """The direction (2,) in panel ``pi``'s flat frame that should point up the body (for a
    sleeve: towards the shoulder); None to keep the frame as it is."""
    panel = pattern.panels[pi]
    uv = mesh.vertices[mesh.panel_vertices(pi)]
    if role.kind in ("waistband", "collar", "cuff"):
        size = np.ptp(uv, axis=0)
        return None if size[0] >= size[1] else np.array([1.0, 0.0])  # length across the body
    if role.part.startswith("arm"):
        # towards the cap: the edges sewn to body panels
        mids = [panel.edge(side.edge).point_at([0.5])[0]
                for seam in pattern.seams for side, other in ((seam.a, seam.b), (seam.b, seam.a))
                if side.panel == panel.name and not roles[other.panel].part.startswith("arm")]
        if mids:  # snapped to the frame's axes: a drafted sleeve runs along x or y
            d = np.mean(mids, axis=0) - uv.mean(axis=0)
            k = int(np.argmax(np.abs(d)))
            if abs(d[k]) > 1e-6:
                return np.eye(2)[k] * np.sign(d[k])
    if panel.placement.rotation is not None and any(panel.placement.rotation):
        up = panel.placement.rotation_matrix().T @ np.array([0.0, 1.0, 0.0])
        if np.hypot(up[0], up[1]) > 0.5:
            return up[:2] / np.hypot(up[0], up[1])
    return np.asarray(panel.grainline, dtype=np.float64)


def _turned_over(pattern: Pattern, roles: dict[str, PanelRole]) -> list[int]:
    """The panels to turn over before placing, so that every panel is seen from outside.

    Two panels seen from outside are sewn end to start when their outlines run the same way
    round (``Seam.reverse`` says whether a seam is). The body panels (bodice, skirt, leg)
    drawn counter-clockwise, as ours are, are seen from outside; from them, along the seams,
    every other panel is turned over where its seam says it is seen from inside: a
    GarmentCode back panel (drawn clockwise as seen from the front, sewn end to start to
    the front), a panel sewn wrong side out (GarmentCode's ``right_wrong``: a lapel, a
    facing). A DXF's right piece of a pair runs clockwise but is its left piece mirrored,
    seen from outside: its seams (start to start) say so, and it is not turned."""
    index = {p.name: i for i, p in enumerate(pattern.panels)}
    ccw = {p.name: p.outline.signed_area() >= 0 for p in pattern.panels}
    body = [p.name for p in pattern.panels if roles[p.name].kind in ("bodice", "skirt", "leg")]
    seeds = [n for n in body if ccw[n]] or body
    flip = {n: False for n in seeds}
    grew = True
    while grew:
        grew = False
        for s in pattern.seams:
            for here, there in ((s.a.panel, s.b.panel), (s.b.panel, s.a.panel)):
                if here == there or here not in flip or there in flip:
                    continue
                seen = ccw[here] != flip[here]  # its way round once turned (if it is)
                flip[there] = ccw[there] != (seen if s.reverse else not seen)
                grew = True
    return [index[n] for n, turned in flip.items() if turned]


def upright_frames(pattern: Pattern, mesh: GarmentMesh,
                   roles: dict[str, PanelRole]) -> np.ndarray:
    """Flat positions (n, 2) [m] of ``mesh`` with every panel turned upright about its own
    centre (:func:`~patternfit.pattern.roles.upright_turn`), a panel seen from inside (a
    GarmentCode back panel, one sewn wrong side out: :func:`_turned_over`) turned over about its vertical middle so that every panel is seen from outside, and,
    when a seam between body
    panels joins edges more than :data:`FRAME_MISMATCH` apart in height at both of its ends,
    body panels shifted in height, panel by panel from the first along the seams, so that
    each seam's two sides meet at the end where they met best.
    Arm panels keep their height (they are placed along the arm)."""
    flat = mesh.vertices.copy()
    for pi in range(len(pattern.panels)):
        role = roles[pattern.panels[pi].name]
        up = _up_direction(pattern, mesh, pi, role, roles)
        if up is None or abs(up[0]) < 1e-9 and up[1] > 0:
            continue
        ids = mesh.panel_vertices(pi)
        c = flat[ids].mean(axis=0)
        flat[ids] = (flat[ids] - c) @ upright_turn(up).T + c
    for pi in _turned_over(pattern, roles):
        ids = mesh.panel_vertices(pi)
        flat[ids, 0] = 2.0 * flat[ids, 0].mean() - flat[ids, 0]
    body = {p.name for p in pattern.panels if not roles[p.name].part.startswith("arm")}
    index = {p.name: i for i, p in enumerate(pattern.panels)}
    # per seam between two body panels: its sewn vertex pairs (a's side first)
    seams = [(s, mesh.seam_pairs[mesh.seam_index == k]) for k, s in enumerate(pattern.seams)
             if s.a.panel in body and s.b.panel in body and s.a.panel != s.b.panel]

    def mismatch(pairs) -> float:
        """How far side a lies above side b [m], at the end of the seam where they meet
        best: frames shifted apart differ at both ends, a side eased or graded longer (a
        hem let down) at one end only."""
        d = flat[pairs[[0, -1], 0], 1] - flat[pairs[[0, -1], 1], 1]
        return float(d[np.argmin(np.abs(d))])

    if not seams or max(abs(mismatch(pairs)) for _, pairs in seams) <= FRAME_MISMATCH:
        return flat
    done = {next(p.name for p in pattern.panels if p.name in body)}
    grew = True
    while grew:
        grew = False
        for s, pairs in seams:
            for here, there, sign in ((s.a, s.b, 1.0), (s.b, s.a, -1.0)):
                if here.panel in done and there.panel not in done:
                    flat[mesh.panel_vertices(index[there.panel]), 1] += sign * mismatch(pairs)
                    done.add(there.panel)
                    grew = True
    return flat


def implausible_placements(pattern: Pattern, mesh: GarmentMesh, body, *,
                           spacing: float = 0.005) -> list[str]:
    """The panels whose explicit 3D placement is not around ``body``, each with the reason:
    not finite, outside the body's height (below the feet, above the head), its median
    distance from the body surface over :data:`PLACED_FAR`, or more than
    :data:`PLACED_INSIDE` of it inside the body; or, all of them near the body, the body
    panels' top farther than :data:`PLACED_HEIGHT` from the height the garment hangs from
    (:attr:`Pattern.anchor`: a garment at the feet). Empty when every explicit placement is
    plausible (or there is none)."""
    field = None
    height = float(body.vertices[:, 1].max())
    out = []
    roles = panel_roles(pattern)
    tops = {}
    for pi, panel in enumerate(pattern.panels):
        if not panel.placement.explicit:
            continue
        x = panel.placement.transform(mesh.vertices[mesh.panel_vertices(pi)])
        if roles[panel.name].kind not in ("sleeve", "cuff", "hood", "collar"):
            tops[panel.name] = float(x[:, 1].max())
        if not np.isfinite(x).all():
            out.append(f"{panel.name} (not finite)")
            continue
        y = float(np.median(x[:, 1]))
        if not -0.05 <= y <= height + 0.05:
            out.append(f"{panel.name} (at height {y:.2f} m; the body spans 0–{height:.2f} m)")
            continue
        field = field or body.distance_field(spacing)
        d, _ = field.query(x)
        if float(np.median(d)) > PLACED_FAR:
            out.append(f"{panel.name} ({float(np.median(d)):.2f} m from the body)")
        elif float(np.mean(d < 0)) > PLACED_INSIDE:
            out.append(f"{panel.name} ({float(np.mean(d < 0)) * 100:.0f}% inside the body)")
    if tops and not out:  # each panel near the body: is the garment at its height?
        anchor = pattern.anchor
        want = float(body.measurements[ANCHOR_HEIGHT[anchor]])
        top = max(tops.values())
        if abs(top - want) > PLACED_HEIGHT:
            where = "neck base" if anchor == "neck" else "waist"
            out += [f"{n} (the garment's top at {top:.2f} m, its {where} at {want:.2f} m)"
                    for n in tops]
    return out
