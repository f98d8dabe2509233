"""patternfit studio: the interactive design loop in the browser (``patternfit studio``).

:func:`create_app` builds the FastAPI app over one design session folder; :func:`serve`
runs it on 127.0.0.1.
"""

from .app import create_app
from .server import serve

__all__ = ["create_app", "serve"]
