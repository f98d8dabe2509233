"""The studio's request bodies as pydantic models, the dependency that reads and checks one,
and the worker-thread runner of heavy work.

A body is read capped at ``limits.json_body_bytes`` and parsed by
:func:`patternfit.files.parse_json_text` (finite numbers, bounded nesting) before the model
checks it; a body that fails raises ``ValueError`` naming the field, which the app's one
exception handler answers with 400. Fields a request does not take are ignored (a revision
given is always checked).
"""

from __future__ import annotations

import reprlib
from typing import Annotated, Any

import anyio
from fastapi import HTTPException, Request
from pydantic import (BaseModel, BeforeValidator, ConfigDict, StrictInt, StrictStr,
                      ValidationError, field_validator, model_validator)

from ..arguments import number
from ..body.builtin import list_bodies
from ..constants import limits
from ..edit import seam_side
from ..errors import InputError
from ..files import parse_json_text
from ..pattern.library import GARMENTS
from ..pattern.sizes import SIZE_NAMES
from ..sim.fabrics import FABRICS
from .guard import read_capped
from .state import ENGINES, Studio

#: bodies up to this size [bytes] are parsed on the server's loop (microseconds); larger
#: ones, up to ``limits.json_body_bytes``, in a worker thread
INLINE_BODY = 16 * 1024
#: triangle counts a new session may ask for
TRIANGLES = (100, 60000)


def _one_of(known):
    """A check that a given value is one of ``known()`` (names shown in the message); a
    field left out is None and not checked."""
    def check(value):
        names = known()
        if not isinstance(value, str) or value not in names:
            raise ValueError(f"expected one of {', '.join(names)}")
        return value
    return BeforeValidator(check)


class Revisioned(BaseModel):
    """A change from a tab that names the session revision it last saw (None: a script that
    does not say, not checked)."""

    model_config = ConfigDict(extra="ignore")
    revision: StrictInt | None = None


class NewSession(Revisioned):
    """``POST /api/new``: a session on built-in garment, size, body, fabric, engine."""

    garment: Annotated[str | None, _one_of(lambda: list(GARMENTS))] = None
    size: Annotated[str | None, _one_of(lambda: list(SIZE_NAMES))] = None
    body: Annotated[str | None, _one_of(list_bodies)] = None
    fabric: Annotated[str | None, _one_of(lambda: list(FABRICS))] = None
    engine: Annotated[str | None, _one_of(lambda: list(ENGINES))] = None
    triangles: StrictInt | None = None

    @field_validator("triangles")
    @classmethod
    def _triangles(cls, n):
        if n is not None and not TRIANGLES[0] <= n <= TRIANGLES[1]:
            raise ValueError(f"expected a whole number in {TRIANGLES[0]}..{TRIANGLES[1]}")
        return n

    def given(self) -> dict:
        """The fields the request gave (the rest keep the studio's defaults)."""
        return {k: v for k, v in self.model_dump(exclude={"revision"}).items() if v is not None}


def _flag(value, name: str) -> None:
    if not isinstance(value, bool):
        raise ValueError(f"{name}: expected true or false, got {reprlib.repr(value)}")


def _whole(value, name: str) -> None:
    # a bool is an int to Python, and a JSON 1.0 would reach the tool as a float index
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"{name}: expected a whole number, got {reprlib.repr(value)}")


def _point(value, name: str) -> None:
    if not isinstance(value, list) or len(value) != 2:
        raise ValueError(f"{name}: expected a point [x, y], got {reprlib.repr(value)}")
    for i, c in enumerate(value):
        number(c, f"{name}[{i}]")


def _name(value, name: str) -> None:
    if not isinstance(value, str):
        raise ValueError(f"{name}: expected a name (text), got {reprlib.repr(value)}")


#: how each kind of editing-tool argument is checked (a refusal names the argument)
_KINDS = {"flag": _flag, "whole": _whole, "number": number, "point": _point, "name": _name,
          "side": seam_side}
#: the arguments of each editing tool (``patternfit.edit``'s signatures) and their kinds;
#: ``?``: null is taken too (the tool's default)
EDIT_ARGS = {
    "move_point": {"panel": "name", "corner": "name", "offset": "point", "partner": "flag"},
    "move_edge": {"panel": "name", "edge": "name", "offset": "point", "partner": "flag"},
    "edit_curve": {"panel": "name", "edge": "name", "offset": "point", "control": "whole",
                   "partner": "flag"},
    "lengthen": {"panel": "name", "a": "point", "b": "point", "amount": "number",
                 "partner": "flag"},
    "grade": {"panel": "name?", "sx": "number", "sy": "number", "about": "point?",
              "partner": "flag"},
    "insert_dart": {"panel": "name", "name": "name", "centre": "point", "length": "number",
                    "width": "number", "axis": "point", "shape": "name"},
    "move_dart": {"panel": "name", "name": "name", "offset": "point"},
    "resize_dart": {"panel": "name", "name": "name", "length": "number?", "width": "number?"},
    "add_seam": {"a": "side", "b": "side", "name": "name?", "ease": "number?",
                 "reverse": "flag"},
    "remove_seam": {"name": "name"},
    "set_seam_ease": {"name": "name", "ease": "number"},
}


class Edit(Revisioned):
    """``POST /api/edit``, ``/api/drag``, ``/api/drag/basis``: an editing tool and its
    arguments (lengths [m]), each checked for the kind the tool takes (:data:`EDIT_ARGS`):
    the tools themselves would apply ``"partner": "no"`` as true and ``"control": true`` as
    control point 1."""

    op: StrictStr
    args: dict[str, Any] = {}

    @field_validator("args")
    @classmethod
    def _no_label(cls, args):
        if "label" in args:  # the label is the studio's own description of the edit
            raise ValueError("'label' is not an argument of an editing tool")
        return args

    @model_validator(mode="after")
    def _kinds(self):
        kinds = EDIT_ARGS.get(self.op)
        if kinds is None:  # no such tool: refused by name where the tool is looked up
            return self
        for key, value in self.args.items():
            where = f"args.{key}"
            if key not in kinds:
                raise ValueError(f"{where}: {self.op} takes no such argument (it takes "
                                 f"{', '.join(kinds)})")
            kind = kinds[key]
            if not (value is None and kind.endswith("?")):
                _KINDS[kind.rstrip("?")](value, where)
        return self


def _message(exc: ValidationError) -> str:
    """``field: what is wrong`` for the first problem of a model check."""
    err = exc.errors()[0]
    where = ".".join(str(p) for p in err["loc"])
    text = err["msg"].removeprefix("Value error, ")
    if err["type"] == "missing":
        text = "missing"
    # a check of the whole body (no location) names the fields in its own message
    return f"{where}: {text}" if where else text


def parse_body(raw: bytes, model: type[BaseModel]) -> BaseModel:
    """The request body ``raw`` checked as ``model`` (an empty body is ``{}``); InputError
    or ValueError naming the field otherwise."""
    body = {}
    if raw:
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            raise InputError("not UTF-8 text", file="request body") from None
        body = parse_json_text(text, file="request body")
        if not isinstance(body, dict):
            raise InputError("expected a JSON object", file="request body")
    try:
        return model.model_validate(body)
    except ValidationError as exc:
        raise ValueError(_message(exc)) from None


def body(model: type[BaseModel]):
    """A FastAPI dependency: the request's JSON body checked as ``model``."""
    async def read(request: Request) -> BaseModel:
        raw = await read_capped(request, limits.json_body_bytes, "request body")
        if len(raw) <= INLINE_BODY:  # a drag's few hundred bytes: no thread hop per frame
            return parse_body(raw, model)
        return await in_worker(parse_body, raw, model)
    return read


def studio_of(request: Request) -> Studio:
    """A FastAPI dependency: the app's one :class:`~patternfit.studio.state.Studio`."""
    return request.app.state.studio


async def in_worker(fn, *args):
    """``fn(*args)`` in a worker thread, so the server keeps answering meanwhile. Past
    ``limits.request_seconds`` the client gets 503 (the work itself cannot be interrupted:
    it finishes in the background). Refusals raised by ``fn`` reach the app's handler."""
    try:
        with anyio.fail_after(limits.request_seconds):
            return await anyio.to_thread.run_sync(fn, *args, abandon_on_cancel=True)
    except TimeoutError:
        raise HTTPException(503, f"the request took longer than {limits.request_seconds:g} s; "
                                 "it finishes in the background (reload to see it)") from None
