"""The Typer application every command module registers on."""

from __future__ import annotations

import json
import sys

import typer
from rich.console import Console

app = typer.Typer(name="patternfit", no_args_is_help=True, add_completion=False,
                  help="Virtual try-on for garment design: mesh, drape, evaluate the fit, "
                       "edit the pattern. Lengths in metres unless an option says otherwise.")

console = Console(stderr=True)


def print_json(data) -> None:
    """Write ``data`` as JSON on standard output (for ``--json``)."""
    sys.stdout.write(json.dumps(data, indent=1) + "\n")


def fail(message: str, code: int = 2) -> None:
    """Print an error in red on standard error and exit with ``code``."""
    console.print(f"[bold red]error:[/] {message}", highlight=False, soft_wrap=True)
    raise typer.Exit(code)
