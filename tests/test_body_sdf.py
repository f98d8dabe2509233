"""Body distance field: sign, accuracy against exact closest points, disk cache."""

import igl
import numpy as np
import pytest
import trimesh

from patternfit.body import DistanceField, load_body


@pytest.fixture(autouse=True)
def _cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PATTERNFIT_CACHE", str(tmp_path / "cache"))


@pytest.fixture(scope="module")
def body():
    return load_body("female_thin")


def test_sign_inside_and_outside(body, tmp_path):
    field = body.distance_field(spacing=0.02)
    centre = body.landmarks["waist"]
    d, g = field.query([centre, centre + [0, 0, 0.5], centre + [0, 1.5, 0], [0, -0.5, 0]])
    assert d[0] < -0.05 and (d[1:] > 0.1).all()
    assert field.query(centre + [0, 0, 0.3])[1][0, 2] > 0.9  # gradient points away


def test_matches_exact_closest_point_near_surface(body):
    spacing = 0.01
    field = body.distance_field(spacing=spacing)
    rng = np.random.default_rng(0)
    tm = trimesh.Trimesh(body.vertices, body.faces, process=False)
    on, tri = trimesh.sample.sample_surface(tm, 2000, seed=1)
    p = on + tm.face_normals[tri] * rng.uniform(-0.01, 0.03, (len(on), 1))
    # Reference: exact closest point and exact (not fast) winding number; trimesh's own
    # closest_point would need rtree, which is not a dependency.
    f = body.faces.astype(np.int64)
    sq = igl.point_mesh_squared_distance(p, body.vertices, f)[0]
    inside = igl.winding_number(body.vertices, f, p) > 0.5
    exact = np.where(inside, -np.sqrt(sq), np.sqrt(sq))
    for m in body.mittens():  # the field is of the body joined with its mittens
        hf = m.faces.astype(np.int64)
        sq = igl.point_mesh_squared_distance(p, m.vertices, hf)[0]
        inside = igl.winding_number(m.vertices, hf, p) > 0.5
        exact = np.minimum(exact, np.where(inside, -np.sqrt(sq), np.sqrt(sq)))
    d, _ = field.query(p)
    err = np.abs(d - exact)
    # Trilinear interpolation of a distance is exact on flat parts; creases (fingers,
    # armpits) cost more: almost every point within half a cell.
    assert np.mean(err < 0.5 * spacing) > 0.98
    assert np.median(err) < 0.1 * spacing


def test_cache_round_trip(body, tmp_path):
    a = DistanceField.from_mesh(body.vertices, body.faces, spacing=0.03)
    files = list((tmp_path / "cache").glob("sdf-*.npz"))
    assert len(files) == 1
    b = DistanceField.from_mesh(body.vertices, body.faces, spacing=0.03)
    np.testing.assert_array_equal(a.values, b.values)
    assert np.allclose(a.origin, b.origin) and a.spacing == b.spacing
    c = DistanceField.from_mesh(body.vertices + [0.01, 0, 0], body.faces, spacing=0.03)
    assert len(list((tmp_path / "cache").glob("sdf-*.npz"))) == 2
    assert np.allclose(c.origin, a.origin + [0.01, 0, 0])


def test_a_field_cached_by_other_code_is_built_anew(body, tmp_path, monkeypatch):
    from patternfit.body import sdf

    DistanceField.from_mesh(body.vertices, body.faces, spacing=0.04)
    assert len(list((tmp_path / "cache").glob("sdf-*.npz"))) == 1
    # the same mesh and grid, cached by another version of the construction
    monkeypatch.setattr(sdf, "_build_id", lambda: b"an older construction")
    DistanceField.from_mesh(body.vertices, body.faces, spacing=0.04)
    assert len(list((tmp_path / "cache").glob("sdf-*.npz"))) == 2


def test_query_outside_grid_and_gradient():
    x = np.linspace(-1, 1, 21)
    grid = np.sqrt(sum(c**2 for c in np.meshgrid(x, x, x, indexing="ij"))) - 0.5
    field = DistanceField([-1, -1, -1], 0.1, grid)
    d, g = field.query([[0.75, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    assert d[0] == pytest.approx(0.25, abs=1e-6)
    assert d[1] == pytest.approx(2.5, abs=1e-6)  # border value + distance to the grid box
    assert g[0, 0] == pytest.approx(1.0, abs=0.01) and np.abs(g[0, 1:]).max() < 0.1
    assert d[2] < -0.4


def test_bad_input_refused():
    with pytest.raises(ValueError, match="vertices"):
        DistanceField.from_mesh(np.zeros((0, 3)), np.zeros((0, 3), int))
    with pytest.raises(ValueError, match="NaN"):
        DistanceField.from_mesh([[np.nan, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    with pytest.raises(ValueError, match="faces"):
        DistanceField.from_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 5]])


def test_the_contact_field_stands_the_body_on_the_floor(body):
    """What the cloth meets: the body's field joined with the half-space under its soles
    (y = 0), the smaller distance at every grid node; the floor ends with the grid."""
    field = body.distance_field(spacing=0.02)
    floor = body.contact_field(spacing=0.02)
    assert body.contact_field(spacing=0.02) is floor  # kept on the body
    assert np.array_equal(floor.origin, field.origin) and floor.spacing == field.spacing
    y = field.origin[1] + field.spacing * np.arange(field.shape[1])
    plane = np.broadcast_to((y - body.vertices[:, 1].min())[None, :, None], field.shape)
    assert np.array_equal(floor.values, np.minimum(field.values, plane.astype(np.float32)))
    # beside the feet, 3 cm up: the floor is nearer than the body; below it: inside
    beside = body.landmarks["waist"] * [1, 0, 1] + [0.0, 0.03, 0.25]
    d_body, d_floor = field.query([beside])[0][0], floor.query([beside])[0][0]
    assert d_floor == pytest.approx(0.03, abs=2e-3) and d_body > 0.1
    assert floor.query([beside - [0.0, 0.05, 0.0]])[0][0] < 0.0
    # high up the body is all there is; past the grid's end nothing holds the cloth up
    assert floor.query([[0.0, 1.0, 0.4]])[0][0] == field.query([[0.0, 1.0, 0.4]])[0][0]
    past = [floor.upper[0] + 0.5, 0.03, 0.0]
    assert floor.query([past])[0][0] > 0.4
