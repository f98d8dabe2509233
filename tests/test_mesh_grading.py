"""Boundary sampling graded next to tiny stitched edges: GarmentCode's own files carry
stitched edges of 0.9 mm between edges of 10-30 cm (its jumpsuit), which Triangle, not
allowed to split boundary segments, meshed into 0.7 degree slivers at 25 asked."""

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patternfit.mesh import mesh_pattern
from patternfit.mesh.triangulate import _spacing
from patternfit.pattern.formats import load_any_pattern

TINY = 0.09  # cm: GarmentCode's 0.9 mm edge


def _panel(z: float) -> dict:
    """A 40 x 30 cm panel as GarmentCode writes one (cm, y up), its top split by a 0.9 mm
    edge near the middle, as GarmentCode's interface projection leaves them."""
    return {"vertices": [[0, 0], [40, 0], [40, 30], [20 + TINY, 30], [20, 30], [0, 30]],
            "edges": [{"endpoints": [i, (i + 1) % 6]} for i in range(6)],
            "translation": [-20.0, 100.0, z], "rotation": [0.0, 0.0, 0.0]}


@pytest.fixture(scope="module")
def mesh(tmp_path_factory):
    """Front and back sewn at both sides and along the split top (about 800 triangles)."""
    st = [[{"panel": "front", "edge": a}, {"panel": "back", "edge": b}]
          for a, b in ((1, 5), (5, 1), (2, 4), (3, 3), (4, 2))]
    path = tmp_path_factory.mktemp("gc") / "tiny_specification.json"
    path.write_text(json.dumps({"pattern": {"panels": {"front": _panel(10.0),
                                                       "back": _panel(-10.0)},
                                            "stitches": st},
                                "properties": {"units_in_meter": 100}}))
    return mesh_pattern(load_any_pattern(path), triangles=800)


def _min_angles(v, t):
    p = v[t]
    out = []
    for i in range(3):
        a, b = p[:, (i + 1) % 3] - p[:, i], p[:, (i + 2) % 3] - p[:, i]
        c = (a * b).sum(1) / np.linalg.norm(a, axis=1) / np.linalg.norm(b, axis=1)
        out.append(np.degrees(np.arccos(np.clip(c, -1, 1))))
    return np.min(out, axis=0)


def test_no_slivers_at_a_tiny_stitched_edge(mesh):
    assert 700 < mesh.n_triangles < 900
    assert _min_angles(mesh.vertices, mesh.triangles).min() > 24.9


def test_the_boundary_grows_gently_from_the_tiny_edge(mesh):
    for k in range(len(mesh.panel_names)):
        loop = mesh.loops(k)[0]
        pts = mesh.vertices[loop]
        seg = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)
        assert seg.min() == pytest.approx(TINY / 100, rel=1e-6)
        growth = np.maximum(seg / np.roll(seg, 1), np.roll(seg, 1) / seg)
        assert growth.max() < 1.6, growth.max()


def test_seam_sides_stay_paired_one_to_one(mesh):
    """Graded on both sides alike: consecutive pairs lie as far apart on either side, as
    shares of the side's length (the top's sides differ by the tiny edge: 19.91, 20 cm)."""
    checked = 0
    for s in np.unique(mesh.seam_index):
        pairs = mesh.seam_pairs[mesh.seam_index == s]
        if len(pairs) < 3:  # the tiny edge: its corners are listed with the seams beside it
            continue
        checked += 1
        va, vb = mesh.vertices[pairs[:, 0]], mesh.vertices[pairs[:, 1]]
        da = np.linalg.norm(np.diff(va, axis=0), axis=1)
        db = np.linalg.norm(np.diff(vb, axis=0), axis=1)
        assert np.allclose(da / da.sum(), db / db.sum(), rtol=1e-6), s
    assert checked == 4


@settings(max_examples=60, deadline=None)
@given(length=st.floats(0.005, 2.0), h=st.floats(0.005, 0.1),
       s0=st.floats(1e-4, 0.1), s1=st.floats(1e-4, 0.1))
def test_graded_spacing_runs_from_the_short_neighbour_up(length, h, s0, s1):
    n = max(1, round(length / h))
    u = _spacing(length, n, s0, s1)
    seg = np.diff(u) * length
    assert u[0] == 0.0 and u[-1] == 1.0 and len(u) >= n + 1
    assert np.all(seg > 0)
    own = length / n
    if min(s0, s1) >= 0.4 * own:  # nothing much shorter beside it: even, as before
        assert len(u) == n + 1 and np.allclose(seg, own)
        return
    # no segment much longer than the one beside it, nor than the even spacing; the end
    # segments near the short neighbours' size (within the rounding of the count)
    assert np.all(seg[1:] / seg[:-1] < 1.6) and np.all(seg[:-1] / seg[1:] < 1.6)
    assert seg.max() < 1.3 * own
    assert seg[0] < 2.5 * max(s0, seg.min()) and seg[-1] < 2.5 * max(s1, seg.min())
