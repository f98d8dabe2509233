"""Requests of the fabric editor: the presets' and the session's fabric numbers, a virtual
fabric test of edited numbers (started, followed, stopped, its picture), and the edited
fabric put into the session."""

from __future__ import annotations

from dataclasses import replace
from typing import Annotated, Literal

from fastapi import APIRouter, Depends, Request
from fastapi.responses import Response
from pydantic import AfterValidator, BaseModel, BeforeValidator, ConfigDict

from ... import api
from ..requests import Revisioned, body, in_worker, studio_of
from ..jobs import Refused
from ..state import Studio

router = APIRouter(prefix="/api/fabric")


def _named(fabric):
    """A fabric's name as the page shows it and the session stores it: 1 to 60 characters,
    no slashes (a ``Fabric``'s numbers are checked by ``Fabric`` itself, their weight over
    their thickness by :func:`~patternfit.api.check_bulk`)."""
    name = fabric.name.strip() if isinstance(fabric.name, str) else ""
    if not name or len(name) > 60 or any(c in name for c in "/\\\0"):
        raise ValueError("name: a name of 1 to 60 characters, without slashes")
    return api.check_bulk(replace(fabric, name=name))


def _preset_or_values(value):
    """A preset's name stands for its values (``{"fabric": "denim"}`` was refused as "Input
    should be a dictionary or an instance of Fabric"); a name is never read as a file."""
    if isinstance(value, str):
        name = value.strip().lower().replace("-", "_").replace(" ", "_")
        if name not in api.fabric_names():  # never a file: a name is read as no path
            # the same answer whatever was sent (a path is not echoed)
            raise ValueError(f"not a fabric's name (presets: {', '.join(api.list_fabrics())}, "
                             "their short names and the published ids of `patternfit "
                             "fabrics`); or give the fabric's values")
        return api.read_fabric(name).to_dict()
    if not isinstance(value, (dict, api.Fabric)):
        raise ValueError("expected a preset's name or the fabric's values (an object, as "
                         "GET /api/fabric gives them)")
    return value


#: a fabric in a request: a preset's name, or its constants, SI units as ``Fabric`` (kg/m^2,
#: N/m, N m, -, m), which the dataclass itself checks (a value out of its plausible range
#: names the field)
FabricValues = Annotated[api.Fabric, BeforeValidator(_preset_or_values),
                         AfterValidator(_named)]


class FabricTest(BaseModel):
    """``POST /api/fabric/test``: which test, on which numbers."""

    model_config = ConfigDict(extra="ignore")
    test: Literal["strip", "cantilever", "cusick"]
    fabric: FabricValues


class UseFabric(Revisioned):
    """``POST /api/fabric``: the session continues in this fabric (a new history)."""

    fabric: FabricValues


@router.get("")
def fabrics(studio: Studio = Depends(studio_of)):
    """The presets' numbers and the session's fabric (SI units)."""
    session = studio.session
    return {"presets": {name: api.read_fabric(name).to_dict() for name in api.list_fabrics()},
            "session": None if session is None else session.fabric.to_dict(),
            "ranges": {k: list(v) for k, v in api.FABRIC_RANGES.items()}}


@router.post("/test")
async def start_test(request: Request, req: FabricTest = Depends(body(FabricTest))):
    lab = request.app.state.fabric_lab
    lab.start(req.test, req.fabric)
    return lab.job.as_dict()


@router.get("/test")
def test_progress(request: Request):
    return request.app.state.fabric_lab.job.as_dict()


@router.post("/test/stop")
def stop_test(request: Request):
    request.app.state.fabric_lab.stop()
    return request.app.state.fabric_lab.job.as_dict()


@router.get("/test/picture")
def test_picture(request: Request):
    picture = request.app.state.fabric_lab.job.picture
    if picture is None:
        raise Refused("this test has no picture (yet)")
    return Response(picture, media_type="image/png", headers={"Cache-Control": "no-store"})


@router.post("")
async def use_fabric(req: UseFabric = Depends(body(UseFabric)),
                     studio: Studio = Depends(studio_of)):
    def run():
        fabric = req.fabric
        archived = studio.start_from(fabric=fabric, labels={"fabric": fabric.name},
                                     revision=req.revision)
        return {"ok": True, "revision": studio.revision, "name": fabric.name,
                "archived": archived}
    return await in_worker(run)
