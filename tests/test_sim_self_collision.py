"""Edge-edge self-repulsion: the pairs that vertex-triangle repulsion cannot see."""

import numpy as np
import pytest

from patternfit.sim import kernels

# two skew edges, 5 mm apart, crossing when seen from above; a third sharing a vertex
X = np.array([[0.0, 0.0, 0.0], [0.02, 0.0, 0.0],
              [0.01, -0.01, 0.005], [0.01, 0.01, 0.005], [0.02, 0.02, 0.0]])
EDGES = np.array([[0, 1], [2, 3], [1, 4]])
ROOT = np.arange(len(X))


def test_crossing_edges_are_paired_with_their_nearest_points():
    pairs, st, normal = kernels.near_edge_pairs(X, EDGES, 0.01, 0.02, ROOT)
    assert pairs.tolist() == [[0, 1]]  # (0, 2) share vertex 1; (1, 2) are over 10 mm apart
    assert st[0] == pytest.approx([0.5, 0.5])
    assert normal[0] == pytest.approx([0.0, 0.0, -1.0])
    assert len(kernels.near_edge_pairs(X, EDGES, 0.004, 0.02, ROOT)[0]) == 0


def test_repulsion_is_the_gradient_of_its_energy_and_pushes_apart():
    pairs, st, normal = kernels.near_edge_pairs(X, EDGES, 0.01, 0.02, ROOT)
    k = np.full(len(X), 50.0)
    rng = np.random.default_rng(1)
    x = X + rng.normal(scale=5e-4, size=X.shape)
    grad = np.zeros_like(x)
    energy = kernels.edge_repulsion(x, EDGES, pairs, st, normal, 0.008, k, grad)
    assert energy > 0.0
    h = 1e-8
    for i in range(4):
        for c in range(3):
            xp = x.copy()
            xp[i, c] += h
            ep = kernels.edge_repulsion(xp, EDGES, pairs, st, normal, 0.008, k, np.zeros_like(x))
            assert (ep - energy) / h == pytest.approx(grad[i, c], abs=1e-5)
    # the forces (-grad) push the upper edge up and the lower one down
    assert -grad[2:4, 2].sum() > 0.0 and -grad[0:2, 2].sum() < 0.0
    # beyond the radius: nothing
    g = np.zeros_like(x)
    assert kernels.edge_repulsion(x, EDGES, pairs, st, normal, 0.002, k, g) == 0.0
    assert not g.any()
