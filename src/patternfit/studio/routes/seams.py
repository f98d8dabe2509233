"""Requests of the seam tool beyond the edits (``add_seam``, ``remove_seam``,
``set_seam_ease`` go through ``POST /api/edit``): the seams suggested for the pattern."""

from __future__ import annotations

from fastapi import APIRouter, Depends

from ... import api
from ..requests import in_worker, studio_of
from ..state import Studio

router = APIRouter(prefix="/api/seams")


def _side(side) -> dict:
    return {"panel": side.panel, "edge": side.edge, "start": side.start, "end": side.end}


@router.get("/suggest")
async def suggest(studio: Studio = Depends(studio_of)):
    """The seams ``api.suggest_seams`` offers for the current pattern, best first: both
    sides, their lengths [m], the measured ease, the score in [0, 1] and the reasons."""
    def run():
        with studio.lock:
            pattern = studio.ensure().pattern
        return [{"name": g.seam.name, "a": _side(g.seam.a), "b": _side(g.seam.b),
                 "lengths": [pattern.seam_side_length(g.seam.a),
                             pattern.seam_side_length(g.seam.b)],
                 "ease": g.seam.ease, "reverse": g.seam.reverse, "score": g.score,
                 "reasons": list(g.reasons)}
                for g in api.suggest_seams(pattern)]
    return await in_worker(run)
