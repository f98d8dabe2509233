"""The studio's requests by topic, each an ``APIRouter``: the session (options, state, new,
uploads, undo/redo), editing (geometry, edits, live drags), draping (drape, correction,
progress, the draped garment, exports), fabrics (editing and testing a fabric) and seams
(suggestions for the seam tool)."""

from .drape import router as drape
from .editing import router as editing
from .fabric import router as fabric
from .seams import router as seams
from .session import router as session

ROUTERS = (session, editing, drape, fabric, seams)
