"""The ``gridfield`` command line.

Each sub-command lives in its own module ``gridfield/cli/<name>.py`` exposing
``add_parser(subparsers)`` and ``run(args) -> int``; heavy imports happen inside ``run`` so
that ``gridfield --help`` stays fast. Bad input (any :class:`~gridfield.core.errors.GridfieldError`,
a missing file) becomes one line on stderr and exit code 2; a warning is one line on stderr.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from types import ModuleType
from typing import NoReturn

from .._version import __version__

__all__ = ["COMMANDS", "main"]

#: Sub-command modules, in the order ``--help`` lists them.
COMMANDS = ("demo", "info", "brushfire", "costmap", "field", "plan", "compare", "explore", "sweep")


class _Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line on stderr (and exit code 2), like every other error."""

    def error(self, message: str) -> NoReturn:
        from ..core.errors import cap_message

        message = " ".join(cap_message(message).split())  # a huge or multi-line value stays one short line
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")

    def parse_known_args(self, args: Sequence[str] | None = None,  # type: ignore[override]
                         namespace: argparse.Namespace | None = None) -> tuple[argparse.Namespace, list[str]]:
        """argparse's, plus a "did you mean" for a misspelt option of the chosen sub-command (``--planer``)."""
        ns, extras = super().parse_known_args(args, namespace)
        sub = self._sub_parser(ns)
        if extras and sub is not None and self.prog == "gridfield":
            sub.error(_unrecognized(extras, sub))
        return ns, extras

    def _sub_parser(self, ns: argparse.Namespace) -> argparse.ArgumentParser | None:
        for action in self._actions:
            if isinstance(action, argparse._SubParsersAction):
                return action.choices.get(getattr(ns, "command", None) or "")
        return None


def _unrecognized(extras: Sequence[str], parser: argparse.ArgumentParser) -> str:
    """``unrecognized arguments: --planer (did you mean --planner?)``: the closest option of ``parser``.

    Examples
    --------
    >>> p = argparse.ArgumentParser(prog="x"); _ = p.add_argument("--planner")
    >>> _unrecognized(["--planer", "fmm"], p)
    'unrecognized arguments: --planer fmm (did you mean --planner?)'

    A planner parameter without a flag of its own is given with ``--param``:

    >>> _ = p.add_argument("--param")
    >>> _unrecognized(["--model", "khatib"], p)
    'unrecognized arguments: --model khatib (did you mean --param model=khatib?)'
    """
    import difflib

    options = [o for a in parser._actions for o in a.option_strings if o.startswith("--")]
    registry = _registry_names() if "--param" in options else ()
    hints = []
    for i, word in enumerate(extras):
        if word.startswith("--"):
            flag = word.split("=", 1)[0]
            key = flag[2:].replace("-", "_")
            if key in registry and flag not in options:  # a parameter without a flag of its own: --param
                value = word.split("=", 1)[1] if "=" in word else (
                    extras[i + 1] if i + 1 < len(extras) and not extras[i + 1].startswith("--") else "VALUE")
                hints.append((flag, f"--param {key}={value}"))
                continue
            close = difflib.get_close_matches(flag, options, n=1, cutoff=0.6)
            if close:
                hints.append((flag, close[0]))
    text = "unrecognized arguments: " + " ".join(extras)
    if len(hints) == 1:
        return text + f" (did you mean {hints[0][1]}?)"
    return text + (" (" + "; ".join(f"{w}: did you mean {c}?" for w, c in hints) + ")" if hints else "")


def _registry_names() -> tuple[str, ...]:
    """Every planner parameter's registry name (``model``, ``clearance_band``, ...)."""
    from ..core.params import GROUPS, names

    return names(*GROUPS)


def _command(name: str) -> ModuleType:
    """The module of one command of :data:`COMMANDS` (one import statement each: tools see every arrow)."""
    if name == "demo":
        from . import demo

        return demo
    if name == "info":
        from . import info

        return info
    if name == "brushfire":
        from . import brushfire

        return brushfire
    if name == "costmap":
        from . import costmap

        return costmap
    if name == "field":
        from . import field

        return field
    if name == "plan":
        from . import plan

        return plan
    if name == "compare":
        from . import compare

        return compare
    if name == "explore":
        from . import explore

        return explore
    if name == "sweep":
        from . import sweep

        return sweep
    raise ValueError(f"no command {name!r}")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="gridfield",
        description="Grid-based path planning with brushfire distance maps and potential fields.",
    )
    parser.add_argument("--version", action="version", version=f"gridfield {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS:
        module = _command(name)
        p = module.add_parser(sub)
        p.set_defaults(_run=module.run)
    return parser


def _job(args: argparse.Namespace) -> tuple[str, int]:
    """The size guard's job for this command (see :func:`gridfield.core.limits.job`): its name and workers."""
    import os

    name = str(args.command)
    planner = getattr(args, "planner", None)
    if name in ("plan", "field") and isinstance(planner, str):
        name = f"{name}:{planner}"
    workers = 1
    if name == "sweep" and getattr(args, "scheduler", None) is None:
        workers = getattr(args, "workers", None) or os.cpu_count() or 1
    return name, workers


def main(argv: Sequence[str] | None = None) -> int:
    from ..core.errors import GridfieldError

    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as e:  # --help, --version (0) or a usage error (2, already printed)
        return int(e.code or 0)
    if not getattr(args, "_run", None):
        parser.print_help()
        return 2
    import warnings

    from ..core.limits import job, out_of_memory, override, progress, user_limit

    def one_line_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                         file: object = None, line: str | None = None) -> None:
        print(f"gridfield {args.command}: warning: {message}", file=sys.stderr)

    job_name, workers = _job(args)
    try:
        # a long search's progress line, on a terminal; sweeps and compare --batch show their own bar
        own_bar = args.command == "sweep" or getattr(args, "batch", None) is not None
        shown = False if getattr(args, "no_progress", False) or own_bar else None
        with warnings.catch_warnings(), override(getattr(args, "max_cells", None)), job(job_name, workers=workers), \
                progress(shown):
            user_limit()  # an empty or junk GRIDFIELD_MAX_CELLS is refused up front, as --max-cells is
            warnings.showwarning = one_line_warning  # e.g. star-nav's "kappa is too small": one line, no source
            try:
                code = int(args._run(args) or 0)
            except MemoryError as e:  # numpy's _ArrayMemoryError too: one line naming what was being built
                raise out_of_memory(e) from None
        sys.stdout.flush()  # a closed pipe (`gridfield plan --json | head -c 100`) shows here, not at exit
        return code
    except BrokenPipeError:
        # The reader went away: stop quietly, as Unix tools do (and keep Python from complaining at exit).
        import os

        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
        return 141  # 128 + SIGPIPE
    except GridfieldError as e:
        from ..io import redact  # a URL's credentials are never shown

        print(f"gridfield {args.command}: error: {redact(e)}", file=sys.stderr)
        return 2
    except (FileNotFoundError, IsADirectoryError, PermissionError) as e:
        from ..io import redact

        print(f"gridfield {args.command}: error: {redact(e.strerror or e)}: {redact(e.filename)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"gridfield {args.command}: interrupted", file=sys.stderr)
        return 130
