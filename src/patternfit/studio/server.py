"""Running the studio: uvicorn on 127.0.0.1, on a free port unless one is given."""

from __future__ import annotations

import errno
import socket
import threading
import webbrowser

from ..errors import InputError
from .app import create_app

#: the only address the studio binds to: the design session is not shared on the network
HOST = "127.0.0.1"


def bind(port: int | None) -> socket.socket:
    """A socket bound to ``port`` at 127.0.0.1 (None or 0: a free port), for the server to
    listen on; an :class:`~patternfit.errors.InputError` naming ``--port`` when the port
    cannot be had (another studio on it, a port reserved to the system)."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    if hasattr(socket, "SO_EXCLUSIVEADDRUSE"):
        # Windows: SO_REUSEADDR there lets a second server take a port another listens on
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_EXCLUSIVEADDRUSE, 1)
    else:
        # as uvicorn binds: a port left in TIME_WAIT by a studio just stopped can be taken
        # again at once, while one another server listens on stays refused
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((HOST, port or 0))
    except OSError as err:
        sock.close()
        why = "already in use (another studio?)" if err.errno == errno.EADDRINUSE else \
            f"cannot listen on it ({err.strerror or err})"
        raise InputError(f"{why}; choose another port, or --port 0 for a free one",
                         place=f"--port {port}") from None
    return sock


def serve(session_dir, *, port: int | None = None, browser: bool = True, announce=print):
    """Serve the studio over ``session_dir`` until interrupted; ``announce(url)`` is called
    once the address is known, and the browser opened on it unless ``browser`` is false.
    The port is bound first (:func:`bind`): a refused one announces, opens and creates
    nothing."""
    import uvicorn  # the server, needed only when the studio runs (not by create_app's users)

    sock = bind(port)
    try:
        app = create_app(session_dir)
        url = f"http://{HOST}:{sock.getsockname()[1]}/"
        announce(url)
        if browser:
            # opened a moment later, once the server listens
            threading.Timer(1.0, webbrowser.open, args=(url,)).start()
        server = uvicorn.Server(uvicorn.Config(app, log_level="warning"))
        try:
            # the socket bound above, so no other server can take the port in between
            server.run(sockets=[sock])
        except KeyboardInterrupt:
            pass  # Ctrl+C, re-raised by uvicorn once it shut down: the studio's normal end
        finally:
            app.state.studio.stop_drape()
            app.state.fabric_lab.stop()
            app.state.studio.flush()  # the last edit written
    finally:
        sock.close()
