"""The solver's settings: stopping rules, contact, friction, self-collision, sewing and the
Newton and L-BFGS knobs (SI units: m, s, N). A drape's phases change some of them
(``schedule.Phase.overrides``)."""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, fields

import numpy as np

from ..arguments import number
from ..constants import GRAVITY, tol

#: the stopping rules (``SolverSettings.stop``)
STOP_RULES = ("force", "kinematic")
#: bounds of the numeric settings besides ">= 0": a time limit above 0 (or infinite), a
#: share of the stretch stiffness at most 1
_BOUNDS = {"time_limit": {"low_open": True}, "compression": {"high": 1.0}}


@dataclass(frozen=True)
class SolverSettings:
    """Knobs of the solver; defaults are the measured design of METHOD.md 5.1.

    Stopping: converged when, for ``patience`` consecutive iterations, the largest vertex
    step is below ``step_tol`` [m] and the energy drop of the iteration is below
    ``energy_tol`` times the larger of the total drop so far and the work of lifting the
    garment (gravity and external forces) by 0.1 m, and no vertex has moved more than
    ``drift_tol`` [m] over the last ``window`` iterations, or since the start when fewer
    (so that a pause of the solver in a slow slide or fold is not taken for rest, while a
    warm start from an equilibrium still stops at once); or stopped at ``max_iterations`` /
    ``time_limit`` [s] (not converged).
    """

    max_iterations: int = 5000
    time_limit: float = 300.0
    #: stopping rule: "force" stops at a force balance (``residual_rms`` and
    #: ``residual_p99`` below): L-BFGS steps until the kinematic rule below holds, then
    #: Newton steps until the forces balance; "kinematic" is the earlier rule on steps,
    #: energy drop and drift (``step_tol`` ... ``drift_tol``) with L-BFGS alone, kept for
    #: stages whose end is only a start (the gravity-free relaxation, the coarse drape) and
    #: to compare with: its states are not at rest by the force measure (docs/simulation.md)
    stop: str = "force"
    #: equilibrium: the residual |F_i| / (m_i g) over the free vertices (F_i the total force
    #: -dE/dx_i of the energy minimised, m_i the lumped mass, g = 9.80665 m/s^2) has an rms
    #: at most this [-] ...
    residual_rms: float = tol.rest_rms
    #: ... and a 99th percentile at most this [-] (looser values stop the solver sooner,
    #: but its checks' ``equilibrium`` still asks for ``tol.rest_rms`` / ``tol.rest_p99``)
    residual_p99: float = tol.rest_p99
    #: Newton: the Hessian gets the regulariser m / newton_dt^2 [s] (rigid motions of a
    #: garment without support or friction are otherwise singular)
    newton_dt: float = 1.0
    #: Newton: conjugate gradients stop at this residual, relative to the gradient [-] ...
    newton_cg_tol: float = 0.05
    #: ... or after this many iterations; when more than ``newton_refactor`` were needed
    #: the preconditioner is refactored from the current Hessian (a cholespy factorisation
    #: cost some 40 solves: small-garment suite 14.2 -> 11.5 s CPU against 40, 12.5 at 8;
    #: the block factor costs some 25: 6, 10 and 25 within the noise on the 22K coat)
    newton_cg_max: int = 100
    newton_refactor: int = 15
    #: Newton: the preconditioner also keeps the bending's entries between vertices that
    #: share no triangle (across an edge), instead of moving them onto the diagonal. More
    #: fill, so slower on a garment (22K coat first drape 68 s against ~30 s), but a
    #: bending-dominated strip comes to rest: the wool cantilever at 24 edges per bending
    #: length 7 s against 35 s, and with its bending friction 11.5 s against a stall after
    #: 250 s (docs/fabrics.md); the fabric kit's cantilever sets it
    newton_bending_preconditioner: bool = False
    #: Newton: iterations between outer updates (``refresh`` for L-BFGS)
    newton_refresh: int = 4
    #: force rule: L-BFGS hands over to Newton after this many iterations at the latest. A
    #: flared skirt's hem kept creeping under L-BFGS, so the kinematic rule never held:
    #: eight gores, 2K triangles, 5,000 L-BFGS iterations at a residual of 1-10, where
    #: Newton from there came to rest in 105
    newton_after: int = 2500
    #: Newton: a full step is extended (x2 while the energy falls) only when its energy drop
    #: exceeds this many times the quadratic model's prediction [-]
    newton_extend: float = 1.25
    #: ... and only while the force residual's rms exceeds this many times ``residual_rms``
    #: [-]: nearer rest a doubled step overshoots the stiff directions it was not taken for
    #: (the 22K coat's hem re-drape: one vertex of an eased sleeve cap swung to and fro
    #: for 100 Newton steps, every other step doubled)
    newton_extend_above: float = 10.0
    step_tol: float = 5e-5
    energy_tol: float = 1e-5
    patience: int = 5
    window: int = 50
    drift_tol: float = 1e-3
    history: int = 10
    #: largest vertex displacement of one iteration [m]
    max_step: float = 5e-3
    #: least distance kept from the body [m] when larger than the fabric's thickness: the
    #: trilinear distance field departs from the true surface by up to about half a grid
    #: step, so a margin of that size keeps the cloth off the real body mesh (cloth-cloth
    #: distances keep the thickness)
    contact_margin: float = 0.0
    #: contact pressure per metre of penetration into the thickness layer [N/m^3]
    contact_stiffness: float = 1e7
    #: depth into the layer over which the contact stiffness grows from 0 to its value [m]
    #: (``kernels.contact_law``: a stiffness that jumps at the layer's edge made Newton's
    #: steps chatter on vertices lying there)
    contact_onset: float = 1e-4
    #: body contact is also felt at points inside each cloth edge, evenly spaced at most
    #: this far apart along its rest length [m] (0: at the vertices only). A straight edge
    #: lying over a curved body cuts into it by about L^2 / 8R between two vertices held
    #: clear (a 5 cm edge round a 3.5 cm forearm: 9 mm): the 3K coat on male_average had
    #: 156 edges through the body and no vertex inside (docs/simulation.md, "Contact
    #: between the vertices"); and inside each triangle more than twice this across, on a
    #: grid as fine (a bust into a coarse dress's triangle, feet through coarse hems)
    edge_contact: float = 0.01
    #: share of the contact stiffness put on the preconditioner's diagonal [-]
    contact_precond: float = 0.3
    #: vertices closer than thickness + this get the contact diagonal [m]
    contact_band: float = 5e-3
    #: pseudo time step of the mass regulariser m / dt^2 in the preconditioner [s]
    precond_dt: float = 0.1
    #: refactor when the contact diagonal changed on more than this share of vertices ...
    refactor_share: float = 0.02
    #: ... or the rest of the matrix by more than this relative (Frobenius) change; below it
    #: the old factor stays a good initial Hessian (e.g. after a small pattern edit)
    refactor_change: float = 0.02
    #: iterations between outer updates (friction anchors, self pairs, sewing ramp)
    refresh: int = 25
    #: friction is switched on this many iterations after the seams are welded
    friction_delay: int = 100
    #: the start is a saved rest of this mesh (``drape(start=...)``): each contact's stiffness
    #: scale (x4 per update found inside, which a saved drape does not keep) is read back as
    #: the power of 4 that balances its vertex (:func:`outer_updates.saved_contact_scale`)
    saved_rest: bool = False
    #: tangential slip at which friction reaches the Coulomb limit [m]
    friction_slip: float = 1e-3
    self_collision: bool = True
    #: self-collision pairs are sought within this share of the mean edge length [-]
    self_detect: float = 1.0
    #: cloth-cloth distance kept, as a share of the mean edge length (at least the thickness)
    self_gap: float = 0.1
    #: once the seams are welded, every pair search also looks for crossed triangles and
    #: turns the repulsion of each crossing's vertex to the side it came from
    #: (``crossings.wrong_sides``): the lagged pairs otherwise hold a crossing made
    #: while sewing (the sewing solve has no self-collision) for good (2K trousers: 10
    #: crossed pairs at their crotch at rest without it, none with it)
    untangle: bool = True
    #: stretch stiffness kept in compression, as a share [-]: 1 (full stiffness) makes
    #: cloth fold rather than shrink (bending carries the buckling; docs/simulation.md)
    compression: float = 1.0
    seam_stiffness: float = 1e3
    seam_growth: float = 4.0
    seam_stiffness_max: float = 1e7
    #: a seam pair pulls at most with the contact force of its vertices at this depth into
    #: the thickness layer [m] (0: unbounded springs), so that contact wins over sewing;
    #: once the springs are at their stiffest, the bound grows by ``seam_growth`` at each
    #: outer update where the widest gap did not shrink by 5 %, so that a seam held open by a
    #: pinch (arm against torso) still closes
    seam_pull: float = 1e-3
    #: the preconditioner sees a seam spring as the pull over this gap at most [m]
    seam_precond_gap: float = 1e-2
    #: seam pairs are welded once every gap is below this [m]
    weld_gap: float = 5e-4
    #: return right after the weld (stop_reason "welded"), e.g. to sew without gravity and
    #: drape in a second solve
    stop_at_weld: bool = False
    gravity: tuple = (0.0, -GRAVITY, 0.0)

    def __post_init__(self):
        # every front end passes through here (the CLI's --set, the studio, the API): a
        # value of the wrong kind used to fail deep in a compiled kernel, a time limit of 0
        # ran no iteration and reported the sewing as failed
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(f.default, bool):
                if not isinstance(value, (bool, np.bool_)):
                    raise ValueError(f"{f.name}: expected true or false, got {value!r:.40}")
            elif isinstance(f.default, (int, float)):
                whole = isinstance(f.default, int)
                if whole and not isinstance(value, numbers.Integral):  # 5.0 is no count
                    raise ValueError(f"{f.name}: expected a whole number >= 0, got "
                                     f"{value!r:.40}")
                if not (f.name == "time_limit" and value == math.inf):  # no limit
                    number(value, f.name, low=0.0, integer=whole, **_BOUNDS.get(f.name, {}))
        if self.stop not in STOP_RULES:
            raise ValueError(f"stop: one of {', '.join(STOP_RULES)}, got {self.stop!r:.40}")
        g = self.gravity
        if not (isinstance(g, tuple) and len(g) == 3
                and all(isinstance(c, numbers.Real) and math.isfinite(c) for c in g)):
            raise ValueError(f"gravity: expected 3 finite numbers [m/s^2], got {g!r:.60}")
