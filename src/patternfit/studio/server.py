"""Running the studio: uvicorn on 127.0.0.1, on a free port unless one is given."""

from __future__ import annotations

import socket
import threading
import webbrowser

from .app import create_app

#: the only address the studio binds to: the design session is not shared on the network
HOST = "127.0.0.1"


def free_port() -> int:
    """A TCP port nobody listens on at 127.0.0.1 right now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((HOST, 0))
        return s.getsockname()[1]


def serve(session_dir, *, port: int | None = None, browser: bool = True, announce=print):
    """Serve the studio over ``session_dir`` until interrupted; ``announce(url)`` is called
    once the address is known, and the browser opened on it unless ``browser`` is false."""
    import uvicorn  # the server, needed only when the studio runs (not by create_app's users)

    app = create_app(session_dir)
    port = port or free_port()
    url = f"http://{HOST}:{port}/"
    announce(url)
    if browser:
        # opened a moment later, once the server listens
        threading.Timer(1.0, webbrowser.open, args=(url,)).start()
    try:
        uvicorn.run(app, host=HOST, port=port, log_level="warning")
    finally:
        app.state.studio.stop_drape()
        app.state.fabric_lab.stop()
        app.state.studio.flush()  # the last edit written
