"""The mesh updater: boundary at stored arc-length fractions, interior by coordinates."""

import numpy as np
import pytest
from scipy.spatial import Delaunay

from patternfit.edit import (CoordinateCache, edit_curve, insert_dart, move_point,
                             panel_coordinates, update_mesh)
from patternfit.edit.remesh import remesh_panels
from patternfit.mesh import mesh_pattern, signed_areas
from patternfit.pattern import Edge, Loop, Panel, Pattern, PatternError

from scenes import two_panels


@pytest.fixture(scope="module")
def base():
    p = two_panels()
    return p, mesh_pattern(p, triangles=600)


def on_edges(pattern, mesh):
    """Distance of each boundary vertex from its edge point at the stored fraction."""
    gap = []
    for k, (pn, en) in enumerate(mesh.edge_names):
        sel = mesh.boundary_edge == k
        want = pattern.panel(pn).edge(en).point_at(mesh.boundary_param[sel])
        gap.append(np.linalg.norm(mesh.vertices[mesh.boundary_vertices[sel]] - want, axis=1))
    return np.concatenate(gap)


def test_update_follows_edit_and_keeps_topology(base):
    p, m = base
    q = edit_curve(p, "A", "top", (0.0, 0.08))
    m2, rep = update_mesh(p, q, m, return_report=True)
    assert rep.moved == ("A",) and rep.inverted == 0 and rep.remeshed == ()
    assert rep.min_angle > 15
    assert np.array_equal(m2.triangles, m.triangles)
    assert np.array_equal(m2.seam_pairs, m.seam_pairs)
    assert on_edges(q, m2).max() < 1e-12
    b = m.vertex_panel == 1
    assert np.array_equal(m2.vertices[b], m.vertices[b])          # other panel untouched
    assert (signed_areas(m2.vertices, m2.triangles) > 0).all()
    # interior vertices moved up, more near the bulging top than near the bottom
    a = m.panel_vertices(0)
    dy = m2.vertices[a, 1] - m.vertices[a, 1]
    assert dy.min() > -1e-9 and dy.max() > 0.035   # the curve bulges by 0.04 m


def test_identity_edit_and_cache_reuse(base):
    p, m = base
    assert np.array_equal(update_mesh(p, p, m).vertices, m.vertices)
    cache = CoordinateCache(m)
    frames = [edit_curve(p, "A", "top", (0.0, s)) for s in (0.01, 0.02, 0.03)]
    for q in frames:
        got = update_mesh(p, q, m, cache=cache).vertices
        np.testing.assert_allclose(got, update_mesh(p, q, m).vertices, atol=1e-12)
    assert list(cache.panels) == [0]                                  # computed once
    with pytest.raises(ValueError, match="cache"):
        update_mesh(p, frames[0], m.with_vertices(m.vertices), cache=cache)


def test_cache_adopts_the_panels_an_edit_left_alone(base):
    """A new mesh's cache takes over the old cache's coordinates of the panels whose
    vertices did not move: the same numbers as computed afresh, and the next update from
    the new mesh is the same as without a cache."""
    p, m = base
    old = CoordinateCache(m)
    for panel in range(len(m.panel_names)):
        old.get(panel)
    q = edit_curve(p, "A", "top", (0.0, 0.03))
    m2 = update_mesh(p, q, m, cache=old)
    new = CoordinateCache(m2)
    assert new.adopt(old) == [1]                   # panel A moved, B did not
    fresh = panel_coordinates(m2, 1)
    kept = new.panels[1]
    for name in ("control", "rows", "interior", "triangles", "weights"):
        np.testing.assert_array_equal(getattr(kept, name), getattr(fresh, name))
    assert not np.array_equal(new.get(0).weights, old.get(0).weights)
    r = edit_curve(q, "B", "top", (0.0, 0.02))
    np.testing.assert_allclose(update_mesh(q, r, m2, cache=new).vertices,
                               update_mesh(q, r, m2).vertices, atol=1e-9)
    # a mesh of another topology takes nothing
    assert CoordinateCache(mesh_pattern(p, triangles=300)).adopt(old) == []


def test_cache_shared_by_threads_computes_a_panel_once(base, monkeypatch):
    import threading

    from patternfit.edit import update

    p, m = base
    calls, gate = [], threading.Event()
    real = update.panel_coordinates

    def slow(mesh, panel):
        calls.append(panel)
        gate.wait(5)
        return real(mesh, panel)

    monkeypatch.setattr(update, "panel_coordinates", slow)
    cache, got = CoordinateCache(m), []
    threads = [threading.Thread(target=lambda: got.append(cache.get(0))) for _ in range(3)]
    for t in threads:
        t.start()
    gate.set()
    for t in threads:
        t.join(30)
    assert calls == [0] and len(got) == 3 and all(g is got[0] for g in got)


def test_partner_edit_moves_both_panels_and_seams_still_pair(base):
    p, m = base
    q = move_point(p, "A", "top", (0.0, 0.05), partner=True)
    m2, rep = update_mesh(p, q, m, return_report=True)
    assert set(rep.moved) == {"A", "B"}
    assert on_edges(q, m2).max() < 1e-12
    assert len(m2.seam_pairs) == len(m.seam_pairs)
    # sewn pairs sit at the same arc length on both sides
    a_len = q.panel("A").edge("right").length
    gap = []
    for i, j in m2.seam_pairs:
        ya = m2.vertices[i, 1] / a_len
        yb = m2.vertices[j, 1] / q.panel("B").edge("left").length
        gap.append(abs(ya - yb))
    assert max(gap) < 1e-6


def test_single_outline_uses_mec_holes_use_mvc(base):
    p, m = base
    assert panel_coordinates(m, 0).method == "mec"
    q = insert_dart(p, "A", "d", (0.2, 0.3), length=0.2, width=0.04)
    assert panel_coordinates(mesh_pattern(q, triangles=600), 0).method == "mvc"


def test_changed_edges_need_remesh(base):
    p, m = base
    q = insert_dart(p, "A", "d", (0.2, 0.3), length=0.2, width=0.04)
    mq = mesh_pattern(q, triangles=600)
    with pytest.raises(PatternError, match="re-mesh"):
        update_mesh(q, p, mq)


def test_quality_threshold_remeshes_only_that_panel(base):
    p, m = base
    q = edit_curve(p, "A", "top", (0.0, 0.02))
    m2, rep = update_mesh(p, q, m, min_angle=80.0, return_report=True)
    assert rep.remeshed == ("A",)
    assert (signed_areas(m2.vertices, m2.triangles) > 0).all()
    assert on_edges(q, m2).max() < 1e-12
    assert np.array_equal(m2.seam_index, m.seam_index)
    np.testing.assert_allclose(m2.vertices[m2.seam_pairs[:, 1]], m.vertices[m.seam_pairs[:, 1]])
    bv = m2.vertices[m2.panel_vertices(1)]
    np.testing.assert_allclose(bv, m.vertices[m.panel_vertices(1)])


def test_remesh_keeps_boundary_and_panels():
    p = two_panels()
    m = mesh_pattern(p, triangles=400)
    r = remesh_panels(m, [1])
    assert r.n_vertices == len(r.vertex_panel)
    np.testing.assert_allclose(r.vertices[r.boundary_vertices], m.vertices[m.boundary_vertices])
    assert (signed_areas(r.vertices, r.triangles) > 0).all()
    assert set(np.unique(r.vertex_panel[r.triangles[r.triangle_panel == 1]])) == {1}


def fig13():
    """Paper Fig. 13: a rectangle with an internal quadrilateral in its upper-left part."""
    outer = Loop("outline", (Edge.line("b", (0, 0), (10, 0)), Edge.line("r", (10, 0), (10, 6)),
                             Edge.line("t", (10, 6), (0, 6)), Edge.line("l", (0, 6), (0, 0))))
    quad = [(1.5, 3.0), (3.0, 3.0), (3.0, 4.5), (1.5, 4.5)]
    inner = Loop("quad", tuple(Edge.line(f"q{i}", quad[i], quad[(i + 1) % 4]) for i in range(4)))
    return Pattern("fig13", (Panel("rect", outer, (inner,)),))


def test_fig13_unit_move_no_flip_inside_hull():
    p = fig13()
    m = mesh_pattern(p, triangles=800)
    panel = p.panels[0]
    moved = tuple(e.transformed(np.eye(2), (1.0, 1.0)) for e in panel.inner[0].edges)
    q = p.with_panel(Panel("rect", panel.outline, (Loop("quad", moved),)))
    m2, rep = update_mesh(p, q, m, return_report=True)
    assert rep.inverted == 0
    assert (signed_areas(m2.vertices, m2.triangles) > 0).all()
    hull = Delaunay(np.array([[0, 0], [10, 0], [10, 6], [0, 6]], float))
    assert (hull.find_simplex(m2.vertices, tol=1e-9) >= 0).all()
    # the outer boundary is fixed, the quad moved by exactly one unit
    outer = m.boundary_vertices[m.boundary_loop == 0]
    np.testing.assert_allclose(m2.vertices[outer], m.vertices[outer])
    inner = m.boundary_vertices[m.boundary_loop == 1]
    np.testing.assert_allclose(m2.vertices[inner] - m.vertices[inner], 1.0)


def test_fused_quality_matches_mesh_quality(base):
    from patternfit.edit.update import _quality
    from patternfit.mesh import min_angle
    p, m = base
    v = m.vertices.copy()
    v[m.triangles[0, 0]] = v[m.triangles[0, 1]] + [1e-3, 1e-3]  # probably flips some
    flips, angle = _quality(v, m.triangles, 1e-12)
    assert flips == int((signed_areas(v, m.triangles) <= 1e-12).sum())
    assert angle == pytest.approx(min_angle(v, m.triangles), abs=1e-6)
