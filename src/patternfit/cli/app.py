"""The Typer application every command module registers on, and its one error boundary.

Exit status of every command: 0 done; 1 the result failed its checks (a drape or fit that
went wrong); 2 an input file or option was refused, or a path could not be read or written
(``error: <message>`` on standard error, naming it);
3 an internal error (one line; ``PATTERNFIT_DEBUG=1`` shows the traceback); 130 stopped by
Ctrl-C or SIGTERM (a drape's last state and a batch's rows kept; a correction stopped
writes nothing); 141 the reader of the output went away (``| head``).
"""

from __future__ import annotations

import inspect
import math
import os
import signal
import sys
import tempfile
import threading
import warnings
from pathlib import Path

import typer
from rich.console import Console
from rich.markup import escape
from typer.core import TyperGroup
from typer.exceptions import TyperException

from ..constants import limits
from ..errors import ctrl_c
from ..files import dumps_finite_json
from ..text import printable

#: set (to anything but empty) to get the traceback of an error instead of one line
DEBUG_ENV = "PATTERNFIT_DEBUG"

#: exit status of a command whose result failed its checks
CHECKS_FAILED = 1
#: exit status of a refused input or option
REFUSED = 2
#: exit status of an internal error
INTERNAL = 3
#: exit status after Ctrl-C or SIGTERM (128 + SIGINT, as a shell reports it)
INTERRUPTED = 130
#: exit status when the output's reader went away (128 + SIGPIPE, as a shell reports it)
BROKEN_PIPE = 141


def say_warning(text: str) -> None:
    """``warning: <text>`` in yellow, the text printed as it is (not read as markup; control
    characters shown, not sent to the terminal)."""
    console.print(f"[yellow]warning:[/] {escape(printable(text))}", highlight=False)


def _warning_printer():
    """A ``warnings.showwarning`` for one command: ``warning: <message>`` in yellow, each
    text once (a drape places its coarse and its fine mesh: the same placement warning
    came twice)."""
    shown: set[str] = set()

    def show(message, category, filename, lineno, file=None, line=None) -> None:
        text = str(message)
        if text not in shown:
            shown.add(text)
            say_warning(text)
    return show


class Group(TyperGroup):
    """A command group whose list shows each command's first help paragraph as one line.

    Typer's Rich help keeps the source line breaks of that paragraph in the list (a
    docstring wrapped at 92 characters showed as a ragged three-line entry)."""

    def get_command(self, ctx, name):
        command = super().get_command(ctx, name)
        if command is not None and not command.short_help and command.help:
            first = inspect.cleandoc(command.help).split("\n\n")[0]
            command.short_help = " ".join(first.split())
        return command


class _Boundary(Group):
    """The root command group. Every command (sub-groups included) runs inside
    :meth:`invoke`, so ``CliRunner`` and the console script share one error boundary."""

    def invoke(self, ctx):
        terminate = _stop_on_terminate()
        try:
            with warnings.catch_warnings():
                # a library warning (a placement replaced, a unit guessed) is one line to
                # the user, not Python's "file:line: Category: message"
                warnings.showwarning = _warning_printer()
                return super().invoke(ctx)
        except (typer.Exit, typer.Abort, TyperException):
            raise  # exits, usage errors: Typer prints these itself
        except BrokenPipeError:
            # the reader went away (``patternfit drape --help | head``): stop quietly, as
            # the shell's own commands do, not with "internal error"; the interpreter's
            # last flush of the closed pipe goes nowhere
            try:
                os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            except (OSError, ValueError):  # no file behind it (a test's runner)
                pass
            raise typer.Exit(BROKEN_PIPE) from None
        except (KeyboardInterrupt, Exception) as exc:
            if ctrl_c(exc):
                # the shell's status for SIGINT, not Click's "Aborted!" with status 1, which
                # scripts read as a result that failed its checks
                console.print("interrupted: stopped before the end; nothing more was "
                              "written", highlight=False)
                raise typer.Exit(INTERRUPTED) from None
            if os.environ.get(DEBUG_ENV) or not isinstance(exc, Exception):
                raise
            if isinstance(exc, OSError) and exc.filename is not None:
                # a path the system refused (a file named where a folder must be, a folder
                # where a file must be, /proc): the user's to change, not our error
                fail(f"{exc.filename}: {exc.strerror or exc}")
            if isinstance(exc, ValueError):
                # InputError (a file or option refused, naming it) and the argument checks
                # of the library functions, whose messages name the argument
                fail(str(exc))
            first = (str(exc).strip().splitlines() or [""])[0]
            fail(f"internal error: {type(exc).__name__}: {first} (rerun with {DEBUG_ENV}=1 "
                 "for the traceback)", INTERNAL)
        finally:
            terminate()


def _stop_on_terminate():
    """Make SIGTERM (``timeout``, ``kill``, a scheduler's stop) stop a command as Ctrl-C
    does, its last state kept and its messages out, instead of ending the process at once
    (a drape stopped by ``timeout`` left an empty log); returns what puts the previous
    handler back. Outside the main thread (where no handler can be set) nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        return lambda: None

    def stop(signum, frame):
        raise KeyboardInterrupt

    before = signal.signal(signal.SIGTERM, stop)
    return lambda: signal.signal(signal.SIGTERM, before)


app = typer.Typer(name="patternfit", cls=_Boundary, no_args_is_help=True, add_completion=False,
                  help="Virtual try-on for garment design: mesh, drape, evaluate the fit, "
                       "edit the pattern. Lengths in metres unless an option says otherwise.",
                  epilog="Exit status: 0 done, 1 the result failed its checks, 2 an input or "
                         "option was refused, 3 an internal error (PATTERNFIT_DEBUG=1 shows "
                         "its traceback), 130 stopped by Ctrl-C or SIGTERM (a drape's last "
                         "state and a batch's rows are kept; a correction stopped writes "
                         "nothing), 141 the output's reader went away.")

# A long path is printed whole on one line (soft wrap), not broken at the width, so that it
# can be copied; in a pipe or a CI log (no terminal, no COLUMNS) Rich assumes 80 columns and
# would squeeze the tables until names are cut ("female…"), so there the width is one that
# every table the commands print fits in
# emoji=False: a file named "coat:fire:v2.dxf" is printed as named, not with an emoji in it
def _console(stream, **options) -> Console:
    return Console(soft_wrap=True, emoji=False, **options,
                   width=None if stream.isatty() or os.environ.get("COLUMNS") else 200)


console = _console(sys.stderr, stderr=True)
# what a listing command answers (the garments, bodies, fabrics, seams, a fabric test's
# table) goes to standard output, so that it can be piped and kept (`patternfit fabrics |
# grep denim`, `> list.txt` wrote nothing); messages, progress and errors stay on stderr
listing = _console(sys.stdout)


def print_json(data) -> None:
    """Write ``data`` as JSON on standard output (for ``--json``); never ``NaN``."""
    sys.stdout.write(dumps_finite_json(data, indent=1) + "\n")


def fail(message: str, code: int = REFUSED) -> None:
    """Print an error in red on standard error and exit with ``code``; a control character
    the message quotes (a refused name, a file's name) is shown, not sent to the terminal."""
    console.print(f"[bold red]error:[/] {escape(printable(message))}", highlight=False)
    raise typer.Exit(code)


def folder_text(text: str | Path) -> Path:
    """Option parser of an output folder (:func:`folder_option`): refuses an empty name,
    which a path type reads as "." (the results went into the current folder unasked).
    The option's default arrives as the ``Path`` it is."""
    if isinstance(text, Path):
        return text
    if not text.strip():
        raise typer.BadParameter("empty; a folder to write into")
    return Path(text)


def output_folder(out: Path | None) -> Path | None:
    """Option callback refusing an output folder before any work is done: a file of that
    name, or a place where no folder can be made, failed only when the results were
    written, after the drape. Nothing is made here: a command refused later leaves none."""
    if out is None:
        return None
    if out.exists() and not out.is_dir():
        raise typer.BadParameter(f"{out} is a file, not a folder")
    above = out
    while not above.exists():
        above = above.parent
    if not above.is_dir():
        raise typer.BadParameter(f"cannot make the folder {out}: {above} is a file")
    try:  # a trial folder, not access(): root may write anywhere but /proc
        os.rmdir(tempfile.mkdtemp(prefix=".patternfit-", dir=above))
    except OSError as exc:
        raise typer.BadParameter(f"cannot make the folder {out}: {above} is not writable "
                                 f"({exc.strerror or exc})") from None
    return out


def finite(value):
    """Option callback refusing NaN and infinity, which Typer's float type accepts."""
    if value is not None and not math.isfinite(value):
        raise typer.BadParameter(f"expected a finite number, got {value}")
    return value


def between(low: float, high: float):
    """Option callback: :func:`finite`, then ``low <= value <= high`` (Typer's own range
    check runs first and called NaN "should be less than or equal to" the high end)."""
    def check(value):
        finite(value)
        if value is not None and not low <= value <= high:
            raise typer.BadParameter(f"expected {low:g} to {high:g}, got {value:g}")
        return value
    return check


def positive(value):
    """Option callback refusing a value that is not a finite number > 0."""
    finite(value)
    if value is not None and not value > 0:
        raise typer.BadParameter(f"expected a number > 0, got {value}")
    return value


#: help of every command's --size (a built-in garment's size, or a graded DXF's)
SIZE_HELP = ("Size: of a built-in garment (S–XL, default M) or of a graded DXF file (default "
             "its sample size).")


def folder_option(default, *names: str, help: str):
    """An option naming a folder the command writes into (``names`` its flags; none: from
    the parameter's name): refused before any work when empty (:func:`folder_text`), a
    file, or where no folder can be made (:func:`output_folder`)."""
    return typer.Option(default, *names, help=help, parser=folder_text,
                        callback=output_folder, metavar="DIR")


def triangles_option(default, help: str = "Target triangle count."):
    """The ``--triangles``/``-n`` option of every command that meshes: 1 to
    ``limits.triangles``, so that a typo cannot ask for more memory than the machine has."""
    return typer.Option(default, "--triangles", "-n", min=1, max=limits.triangles, help=help)


def verdict_options() -> dict:
    """The options of the fit verdict a drape or correction command takes, as keyword
    defaults (``--pressure-max``, ``--stretch-limit``, ``--style``); each None means the
    rule's own (``patternfit.fit.verdict_rules``)."""
    return {
        "pressure_max": typer.Option(None, "--pressure-max", callback=positive,
                                     help="Pressure above which a region is too tight "
                                          "\\[kPa] (default 2.0, Kawabata's daily-wear "
                                          "maximum)."),
        "stretch_limit": typer.Option(None, "--stretch-limit", callback=finite,
                                      help="Comfortable stretch of the fabric along a yarn "
                                           "(0.03 = 3%; default: the fabric's)."),
        "style": typer.Option(None, "--style", help="Garment type whose ease ranges apply: "
                              "skirt, trousers, coat, dress, shirt (default: the pattern's)."),
    }
