"""The studio's exports: the current pattern, the draped garment or the fit report as the
bytes of one file."""

from __future__ import annotations

import tempfile
from pathlib import Path

from .. import api
from ..fit.colormap import FitScale
from ..fit.outputs import write_garment
from ..fit.pictures import fit_colours
from ..fit.report import failure, fit_report, write_report
from ..pattern.formats import save_any_pattern
from .payload import stale_maps
from .jobs import Refused
from .state import Studio

#: the files the page offers, and what each holds
EXPORTS = {
    "pattern.json": "pattern", "pattern.dxf": "pattern", "pattern.seams.json": "pattern",
    "pattern.svg": "pattern", "pattern.pdf": "pattern", "garment.glb": "garment",
    "garment.obj": "garment", "report.json": "report",
}
#: the DXF's side file (seams, edge names, notches, a stated anchor), which a CAD tool's
#: DXF has no place for: without it a DXF read back is unsewn, and hangs where its panels
#: say (a skirt stated as hung from the neck, exported and opened again, hung from the waist)
SIDE_FILE = "pattern.seams.json"


def export(studio: Studio, name: str) -> bytes:
    """The bytes of export ``name`` (a key of ``EXPORTS``), written into a folder of its own
    under the session's ``exports/`` (removed again): an export running while another one,
    or an edit, writes can never hand out a half-written file."""
    (studio.folder / "exports").mkdir(exist_ok=True)
    with studio.lock, tempfile.TemporaryDirectory(dir=studio.folder / "exports") as tmp:
        s = studio.ensure()
        path = Path(tmp) / name
        kind = EXPORTS[name]
        if kind == "pattern":
            fit = studio.views.fit(s.state) if s.positions is not None \
                and path.suffix in (".svg", ".pdf") and not stale_maps(s.state) else None
            colours = None if fit is None else (
                s.mesh.vertices, s.mesh.triangles,
                # a failed drape's colours would read as a fit (as the page's maps decide)
                fit_colours(FitScale(), fit.area_change, failure(s.state.checks)),
                s.mesh.triangle_panel)
            written = save_any_pattern(s.pattern, path.with_name("pattern.dxf")
                                       if name == SIDE_FILE else path, fit=colours)
            path = next(p for p in written if p.name == name)
        elif s.positions is None:
            raise Refused("there is no drape to export yet: drape the garment first")
        elif stale_maps(s.state):
            raise Refused("the 3D state is from the drape before the last edit: re-drape "
                          "first")
        elif kind == "garment":
            fit = studio.views.fit(s.state)
            path = write_garment(path, s.pattern, s.mesh, s.positions, fit, report(s, fit),
                                 state="draped", scale=FitScale())
        else:
            path = write_report(report(s, studio.views.fit(s.state)), path)
        return Path(path).read_bytes()


def report(s, fit) -> dict:
    """The fit report of session ``s``'s draped state (what ``report.json`` holds), whose
    fit evaluation is ``fit``, with its fit measures and verdict as the CLI's report has
    them (``api.judge_state``): per region and overall, "failed" for a drape that failed its
    checks (no fit word may be read from its ϖ); and, as the CLI's, the garment, the body
    and the fabric it was draped on and in (by name) and what the pattern's reader warned of
    (``pattern_warnings``)."""
    st = s.state
    measures, verdict = api.judge_state(st.pattern, st.mesh, st.positions, fit, s.body,
                                        s.fabric, checks=st.checks)
    said = list(st.pattern.meta.get("warnings") or [])
    return fit_report(s.mesh, fit, state="draped",
                      extra={"garment": st.pattern.name, "body": s.body.name,
                             "fabric": s.fabric.name,
                             "checks": st.checks, "history": s.summary(),
                             **({"pattern_warnings": said} if said else {}),
                             **measures.report(), **verdict.report()})


#: the report's keys of a fit verdict, shown by the page when the report has them
VERDICT_KEYS = ("verdict", "verdict_reason", "region_verdicts")


def verdict(studio: Studio) -> dict:
    """The fit verdict of the current drape: the report's ``VERDICT_KEYS`` it has (none when
    the report gives no verdict, or nothing is draped, or the drape is older than the
    pattern)."""
    with studio.lock:
        s = studio.ensure()
        if s.positions is None or stale_maps(s.state):
            return {}
        full = report(s, studio.views.fit(s.state))
    return {k: full[k] for k in VERDICT_KEYS if k in full}
