"""Tolerances and physical constants in one place (SI units: metres, seconds, kilograms)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Tolerances:
    """Geometric tolerances, all in metres unless stated."""

    #: two points closer than this are the same point (outline closure, seam ends) [m]
    merge: float = 1e-6
    #: an edge shorter than this is degenerate [m]
    edge_length: float = 1e-5
    #: the two sides of a seam may differ in length by at most this much [m] ...
    seam_length: float = 2e-3
    #: ... or by this fraction of their mean length, whichever is larger [-]
    seam_length_rel: float = 0.005
    #: triangles whose area is below this are degenerate [m^2]
    area: float = 1e-12
    #: two seam ranges on one edge may overlap by this fraction of the edge (the rounding
    #: of fractions written to files) [-]
    seam_range_overlap: float = 1e-9
    #: how far an edge re-fitted to a DXF's points may stray from them [m]
    dxf_fit: float = 5e-5
    #: consecutive DXF points closer than this are one point: CAD tools repeat every turn
    #: point, and inch files round 1e-4 in (2.5e-6 m) apart [m]
    dxf_repeat: float = 5e-5
    #: how far an edge fitted to a DXF polyline may stray from it anywhere along it, both
    #: ways (curve to polyline, polyline to curve); also the most a reader may simplify a
    #: foreign file's outline by (merging collinear runs and tiny edges) [m]
    dxf_span: float = 5e-4
    #: how far a DXF polyline written for a curve may stray from it [m]
    dxf_sample: float = 2e-5
    #: how far from an outline edge a DXF notch may lie and still mark it [m]
    notch_reach: float = 1e-3
    #: how far apart (in arc-length fraction) two edges' notches may lie and still match [-]
    notch_match: float = 0.02
    #: a draped vertex counts as inside the body (a penetration) when the body's distance
    #: field puts it deeper than this [m]: the field is trilinear on a 5 mm grid, and the
    #: contact keeps cloth 3 mm clear, so a drape at rest sits well above it
    penetration: float = 1e-3
    #: a saved mesh's boundary vertex may lie this far from the point of its pattern edge
    #: its arc-length fraction names (meshing and the mesh update put it there exactly;
    #: the mesh of another size lies centimetres off) [m]
    mesh_on_edge: float = 1e-5
    #: a mesh's boundary segment may be this much longer than the one before it along a
    #: loop, where a short edge (GarmentCode's 0.9 mm stitched edges) meets a long one:
    #: Triangle may not split boundary segments (to keep seam sides paired), so an abrupt
    #: change makes slivers (0.7 degrees at 25 asked) [-]
    mesh_growth: float = 0.3
    #: a neighbouring edge's boundary segments shorter than this share of a piece's own
    #: spacing make the piece's segments grade towards them (Triangle copes with less abrupt
    #: changes; the built-in garments' meshes at 1,500 triangles stay as they were) [-]
    mesh_grade: float = 0.4
    #: a drape is at rest (its ``equilibrium``) only when the residual force |F_i| / (m_i g)
    #: over its free vertices has an rms at most this [-] ...
    rest_rms: float = 0.01
    #: ... and a 99th percentile at most this [-], whatever rule or settings stopped the
    #: solver (looser settings or the kinematic rule read "at rest" at rms 0.24 and 1.6)
    rest_p99: float = 0.1


tol = Tolerances()

#: standard gravity [m/s^2]
GRAVITY = 9.80665

#: length of one file unit in metres
UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254}


@dataclass(frozen=True)
class Limits:
    """Caps on what an input may ask for, so that a small file or request cannot exhaust
    memory or time. Every reader and front end checks against these; a value beyond one is
    refused with an error naming the limit."""

    #: polyline segments in one panel's outline and inner loops, after curve sampling [-]
    segments_per_panel: int = 20_000
    #: edges (lines, curves, arcs) in one pattern [-]
    edges_per_pattern: int = 50_000
    #: panels in one pattern [-]
    panels: int = 500
    #: the largest coordinate (absolute) a pattern point may have [m]
    extent: float = 20.0
    #: the farthest a placement may put a panel [m]: far placements (GarmentCode files put
    #: panels 25 m below) are placed anew, absurd ones refused
    translation: float = 1_000.0
    #: triangles a mesh may be asked for [-]
    triangles: int = 2_000_000
    #: a saved garment's mesh.npz, as a file and unpacked (about 50 bytes a triangle) [bytes]
    mesh_bytes: int = 64 * 2_000_000
    #: a saved garment's positions.npy (24 bytes a vertex, fewer vertices than triangles)
    #: [bytes]
    positions_bytes: int = 24 * 2_000_000 + 4096
    #: vertices of a body mesh [-]
    body_vertices: int = 5_000_000
    #: bytes of a DXF file (ezdxf holds many times a file's size in memory) [bytes]
    dxf_bytes: int = 32 * 1024 * 1024
    #: bytes of a file upload to the studio [bytes]
    upload_bytes: int = 32 * 1024 * 1024
    #: bytes of a JSON request body to the studio (the page's requests are a few hundred)
    #: [bytes]
    json_body_bytes: int = 1024 * 1024
    #: seconds one heavy studio request (mesh, drape, export) may take [s]
    request_seconds: float = 600.0
    #: largest scale factor an edit may apply (and smallest: its inverse) [-]
    edit_scale: float = 10.0
    #: largest ease a seam may state (:attr:`~patternfit.pattern.model.Seam.ease`: longer
    #: side / shorter side - 1); 1.0 is a 2:1 gather [-]
    seam_ease: float = 1.0
    #: a drape fails with more vertices inside the body (deeper than
    #: :attr:`Tolerances.penetration`), or more edges through it between their vertices,
    #: than this [-] ...
    body_penetrations: int = 0
    #: ... or more triangle pairs crossing each other than this [-]: GarmentCode's dataset
    #: rejects above 35 body and 300 self intersections; a drape at rest here has none
    self_intersections: int = 0
    #: ... or a seam still open wider than this [mm]: the solver welds its pairs below
    #: ``SolverSettings.weld_gap`` (0.5 mm)
    seam_gap_mm: float = 0.5


limits = Limits()
