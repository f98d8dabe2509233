"""``patternfit studio``: the design loop in the browser."""

from __future__ import annotations

from pathlib import Path

import typer

from .app import app, console, fail, folder_text

# patternfit.api and the stage modules are imported inside the commands, when they run:
# `patternfit --help` should not wait for them (see commands.py)


@app.command()
def studio(
    port: int = typer.Option(None, "--port",
                             help="TCP port on 127.0.0.1 (default, or 0: a free one)."),
    no_browser: bool = typer.Option(False, "--no-browser", help="Do not open a browser."),
    session: Path = typer.Option(Path("patternfit-session"), "--session",
                                 help="Session folder: created, or continued if it holds one.",
                                 parser=folder_text, metavar="DIR"),
):
    """Start the studio web app on 127.0.0.1 over a design session folder and print its
    address; stop it with Ctrl+C (the session is saved after every change)."""
    if port is not None and not 0 <= port <= 65535:
        fail("--port: expected 0..65535 (0: a free one)")
    try:
        from ..studio import serve
    except ImportError as err:  # pragma: no cover - fastapi/uvicorn are dependencies
        fail(f"the studio needs fastapi and uvicorn ({err})")
    serve(session, port=port, browser=not no_browser,
          announce=lambda url: console.print(f"patternfit studio on [bold]{url}[/] "
                                             f"(session: {session})", highlight=False))
