"""L-BFGS directions: the two-loop recursion over the last steps (METHOD.md 5.1)."""

from __future__ import annotations

import numpy as np

from . import kernels


class LBFGS:
    """Two-loop recursion with a given initial inverse Hessian (vectors flattened, (3n,)),
    the last ``size`` (step [m], gradient change [N]) pairs kept in a ring."""

    def __init__(self, size: int):
        self.size = size
        self.count = 0
        self.head = 0
        self.S = self.Y = None
        self.rho = np.zeros(size)

    def reset(self):
        """Forget the pairs (the next direction is the initial Hessian's)."""
        self.count = 0

    def push(self, s, y):
        """Keep the step ``s`` (3n,) [m] and gradient change ``y`` (3n,) [N] unless their
        curvature ``s . y`` is not clearly positive."""
        sy = kernels.dot(s, y)
        if not sy > 1e-12 * np.sqrt(kernels.dot(s, s) * kernels.dot(y, y)):
            return
        if self.S is None or self.S.shape[1] != len(s):
            self.S = np.empty((self.size, len(s)))
            self.Y = np.empty((self.size, len(s)))
            self.count = self.head = 0
        self.S[self.head] = s
        self.Y[self.head] = y
        self.rho[self.head] = 1.0 / sy
        self.head = (self.head + 1) % self.size
        self.count = min(self.count + 1, self.size)

    def direction(self, g, h0):
        """Descent direction (3n,) [m] for the gradient ``g`` (3n,) [N]; ``h0(q)`` applies
        the initial inverse Hessian."""
        q = g.copy()
        if not self.count:
            return -h0(q)
        alphas = np.empty(self.count)
        kernels.lbfgs_back(self.S, self.Y, self.rho, self.count, self.head, q, alphas)
        r = h0(q)
        kernels.lbfgs_forward(self.S, self.Y, self.rho, self.count, self.head, r, alphas)
        return -r
