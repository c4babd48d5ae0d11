"""The console entry point (``xodrlint = xodrlint.cli:main``): every failure ends in one
line and a documented exit code, only the invoked command is built, and the process
leaves without tearing the interpreter down."""

# No ``from __future__ import annotations``, as in :mod:`xodrlint.cli.commands`.
import contextlib
import errno
import os
import signal
import sys
from typing import Final, NoReturn

import typer

from xodrlint.cli.commands import app

#: Set to "0" to let the interpreter tear down normally (profilers, coverage, leak checks).
FAST_EXIT_ENV: Final = "XODRLINT_FAST_EXIT"


def _leave(code: object) -> NoReturn:
    """Exit without tearing the interpreter down: freeing a large map's tree and every
    module costs a pre-commit run tens of milliseconds and serves no one. Everything the
    run writes is flushed first; output files were already written and renamed."""
    status = code if isinstance(code, int) else (0 if code is None else 1)
    if not isinstance(code, int | None):
        print(code, file=sys.stderr)
    for stream in (sys.stdout, sys.stderr):
        if getattr(stream, "closed", False):
            # closed by the run itself (the language server's ``exit`` closes standard
            # output), which flushed it then: nothing is left to write or to fail
            continue
        try:
            stream.flush()
        except BrokenPipeError:  # its reader stopped early (| head): no error of the run
            pass
        except (OSError, ValueError):  # nothing more can be said there
            status = status or 1
    os._exit(status)


class Terminated(BaseException):
    """SIGTERM arrived (a CI job cancelled, a container stopped). Raised in the main
    thread like Ctrl-C's KeyboardInterrupt, so the same clean-up runs: workers are
    stopped and half-written reports removed. A BaseException: no ``except Exception``
    on the way may swallow it."""


def _terminate(signum: int, frame: object) -> None:
    raise Terminated


class ClosedStream(OSError):
    """Written to a standard stream the shell closed (``xodrlint check f >&-``)."""


class _Closed:
    """Stands in for a standard stream that was closed when the process started (Python
    then sets it to ``None``): a run that writes nothing there goes on; one that does
    ends in one line and exit 2, instead of an internal error."""

    def __init__(self, name: str) -> None:
        self.name = name

    def write(self, text: str) -> int:
        if not text:
            return 0
        raise ClosedStream(errno.EBADF, f"standard {self.name} is closed; use -o FILE")

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return False


def _invoked_alone(argv: list[str]) -> typer.Typer | None:
    """The command ``argv`` invokes, as an app of its own, or ``None`` (no command, a
    group such as ``schemas``, or an option first). Typer builds the click object of
    every command before it parses the line: a pre-commit run of ``check`` on a small
    map would pay 10 ms for the other commands' options."""
    if not argv or argv[0].startswith("-"):
        return None
    for info in app.registered_commands:
        callback = info.callback
        name = info.name or (callback.__name__.replace("_", "-") if callback else None)
        if name == argv[0]:
            alone = typer.Typer(
                add_completion=False,
                pretty_exceptions_enable=False,
                rich_markup_mode=None,
                context_settings={"help_option_names": ["-h", "--help"]},
            )
            alone.registered_commands = [info]
            return alone
    return None


def main() -> None:
    """Console entry point: every failure ends in one line and a documented exit code."""
    with contextlib.suppress(ValueError, OSError):  # not the main thread: no handler
        signal.signal(signal.SIGTERM, _terminate)
    if sys.stdout is None:
        sys.stdout = _Closed("output")
    if sys.stderr is None:
        sys.stderr = _Closed("error")
    # what a command need not free: it lives here until _leave exits without freeing
    # anything (a 20 MB map's tree took tens of milliseconds to free)
    keep_alive: list[object] = []
    try:
        alone = _invoked_alone(sys.argv[1:])
        if alone is not None:
            alone(args=sys.argv[2:], prog_name=f"xodrlint {sys.argv[1]}", obj=keep_alive)
        else:
            app(obj=keep_alive)
    except KeyboardInterrupt:
        typer.echo("xodrlint: interrupted", err=True)
        sys.exit(130)
    except SystemExit as done:
        if os.environ.get(FAST_EXIT_ENV, "1") != "0":
            _leave(done.code)
        raise
    except Terminated:
        typer.echo("xodrlint: terminated", err=True)
        _leave(143)
    except ClosedStream as error:
        typer.echo(f"xodrlint: {error.strerror}", err=True)
        if os.environ.get(FAST_EXIT_ENV, "1") != "0":
            _leave(2)
        sys.exit(2)
    except Exception as error:  # the last line of defence: exit 3, never a traceback
        if os.environ.get("XODRLINT_DEBUG"):
            raise
        typer.echo(
            f"xodrlint: internal error: {type(error).__name__}: {error} "
            "(set XODRLINT_DEBUG=1 for the traceback, and please report it)",
            err=True,
        )
        sys.exit(3)
