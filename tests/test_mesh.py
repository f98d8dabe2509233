import numpy as np
import pytest

from patternfit.mesh import GarmentMesh, mesh_pattern, min_angle, signed_areas
from patternfit.pattern import Edge, Loop, Panel, Pattern
from patternfit.pattern.library import GARMENTS, build


def _check_mesh(pattern, mesh, *, angle=25.0):
    # area of every panel within 0.5 %
    areas = mesh.triangle_areas()
    for i, panel in enumerate(pattern.panels):
        got = areas[mesh.triangle_panel == i].sum()
        assert got == pytest.approx(panel.area(), rel=5e-3), panel.name
    assert min_angle(mesh.vertices, mesh.triangles) >= angle - 1e-9
    assert np.all(signed_areas(mesh.vertices, mesh.triangles) > 0)  # counter-clockwise
    tri = np.sort(mesh.triangles, axis=1)
    assert len(np.unique(tri, axis=0)) == len(tri)  # no duplicates
    assert np.all(np.diff(tri, axis=1) > 0)  # no repeated corners
    # every seam: the same vertex count on both sides, pairs at matching arc length
    for si, seam in enumerate(pattern.seams):
        pairs = mesh.seam_pairs[mesh.seam_index == si]
        assert len(pairs) >= 2
        a, b = pairs[:, 0], pairs[:, 1]
        assert len(np.unique(a)) == len(np.unique(b)) == len(pairs)
        assert np.all(mesh.vertex_panel[a] == pattern.panel_index(seam.a.panel))
        assert np.all(mesh.vertex_panel[b] == pattern.panel_index(seam.b.panel))
        da = np.linalg.norm(np.diff(mesh.vertices[a], axis=0), axis=1)
        db = np.linalg.norm(np.diff(mesh.vertices[b], axis=0), axis=1)
        assert np.allclose(np.cumsum(da) / da.sum(), np.cumsum(db) / db.sum(), atol=0.02)


@pytest.mark.parametrize("name", list(GARMENTS))
def test_builtin_garments_mesh(name):
    pattern = build(name, "M")
    mesh = mesh_pattern(pattern, triangles=2500)
    assert abs(mesh.n_triangles - 2500) / 2500 < 0.05
    _check_mesh(pattern, mesh)


def test_seam_sub_ranges_and_orientation(two_rectangles):
    mesh = mesh_pattern(two_rectangles, triangles=800)
    _check_mesh(two_rectangles, mesh)
    v = mesh.vertices
    # s1: A.right (x=0.5, upward) sewn reversed to B.left (x=0, downward): same heights
    for si in range(2):
        pairs = mesh.seam_pairs[mesh.seam_index == si]
        assert np.allclose(v[pairs[:, 0], 1], v[pairs[:, 1], 1])
    s2 = mesh.seam_pairs[mesh.seam_index == 1]
    assert v[s2, 1].min() == pytest.approx(0.4) and v[s2, 1].max() == pytest.approx(0.8)


def test_inner_loop_is_a_hole():
    outer = Loop("outline", [Edge.line("a", (0, 0), (1, 0)), Edge.line("b", (1, 0), (1, 1)),
                             Edge.line("c", (1, 1), (0, 1)), Edge.line("d", (0, 1), (0, 0))])
    dart = Loop("dart", [Edge.line("l1", (0.4, 0.2), (0.5, 0.7)),
                         Edge.line("l2", (0.5, 0.7), (0.6, 0.2)),
                         Edge.line("l3", (0.6, 0.2), (0.4, 0.2))])
    p = Pattern("p", (Panel("x", outer, (dart,)),))
    mesh = mesh_pattern(p, triangles=1500)
    _check_mesh(p, mesh)
    assert mesh.triangle_areas().sum() == pytest.approx(1.0 - 0.5 * 0.2 * 0.5, rel=1e-9)
    assert len(mesh.loops(0)) == 2
    centroids = mesh.vertices[mesh.triangles].mean(axis=1)
    inside = (centroids[:, 1] > 0.25) & (centroids[:, 1] < 0.6) & \
             (np.abs(centroids[:, 0] - 0.5) < 0.02)
    assert not inside.any()


def test_boundary_bookkeeping():
    pattern = build("skirt", "M")
    mesh = mesh_pattern(pattern, triangles=1200)
    for (panel, edge_name) in mesh.edge_names:
        ids, params = mesh.edge_vertices(panel, edge_name)
        edge = pattern.panel(panel).edge(edge_name)
        assert params[0] == 0.0 and np.all(np.diff(params) > 0)
        assert np.allclose(mesh.vertices[ids], edge.point_at(params), atol=1e-12)


def test_save_load_round_trip(tmp_path):
    mesh = mesh_pattern(build("trousers", "S"), triangles=1000)
    back = GarmentMesh.load(mesh.save(tmp_path / "m.npz"))
    for k in GarmentMesh.__dataclass_fields__:
        a, b = getattr(mesh, k), getattr(back, k)
        assert (a == b) if isinstance(a, tuple) else np.array_equal(a, b), k


def test_bad_arguments(two_rectangles):
    with pytest.raises(ValueError, match="min_angle"):
        mesh_pattern(two_rectangles, min_angle=40)
    with pytest.raises(ValueError, match="triangles"):
        mesh_pattern(two_rectangles, triangles=1)


@pytest.mark.parametrize("name", list(GARMENTS))
def test_builtin_seams_pair_matching_heights(name):
    # every built-in garment is drafted with its hem at y = 0 in all panels, so the two
    # vertices of a seam pair sit at the same height unless the seam runs across (crotch)
    pattern = build(name, "M")
    mesh = mesh_pattern(pattern, triangles=1500)
    y = mesh.vertices[:, 1]
    arm = {p.name for p in pattern.panels if p.placement.part.startswith("arm")}
    for si, seam in enumerate(pattern.seams):
        if (seam.a.panel in arm) != (seam.b.panel in arm):
            continue  # a set-in sleeve's flat frame runs along the arm, not the body
        pairs = mesh.seam_pairs[mesh.seam_index == si]
        dy = np.abs(y[pairs[:, 0]] - y[pairs[:, 1]])
        assert dy.max() < 0.035, (seam.name, dy.max())


@pytest.mark.parametrize("name", list(GARMENTS))
def test_builtin_seams_join_the_same_side_of_the_body(name):
    # placed around the body, both vertices of a seam pair are on the same side (x), and
    # a seam named *_l lies on the body's left (+x)
    from patternfit.sim.placement import place_on_cylinders
    pattern = build(name, "M")
    mesh = mesh_pattern(pattern, triangles=1500)
    x = place_on_cylinders(pattern, mesh)
    for si, seam in enumerate(pattern.seams):
        if seam.name.startswith("centre"):
            continue  # joins the left and right halves
        pairs = mesh.seam_pairs[mesh.seam_index == si]
        xa, xb = x[pairs[:, 0], 0], x[pairs[:, 1], 0]
        far = (np.abs(xa) > 0.05) & (np.abs(xb) > 0.05)
        assert np.all(np.sign(xa[far]) == np.sign(xb[far])), seam.name
        if seam.name.endswith("_l"):
            assert np.median(xa) > 0, seam.name
