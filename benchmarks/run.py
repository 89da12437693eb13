"""Run every gridfield benchmark side by side in one command and write one markdown report.

Usage::

    python benchmarks/run.py                        # the full suite (9-12 minutes on 2 cores)
    python benchmarks/run.py --quick                # small sizes, few repeats (under a minute)
    python benchmarks/run.py --out benchmarks/RESULTS.md
    python benchmarks/run.py --sizes 1024 4096 --repeat 5 --only startup components end_to_end

Sections (``--only`` picks some; all by default):

``startup``
    ``gridfield --help`` wall time (median of 5 fresh processes) beside the bare interpreter's
    start-up, and the heavy modules (matplotlib, numba, scipy.sparse, shapely, skimage) that
    ``import gridfield`` and ``gridfield --help`` import, each with the chain of imports that pulled
    it in (from ``python -X importtime``) and the gridfield source line responsible.
``components``
    One process, one synthetic map per size (sizes up to 4096 of ``--sizes``): gridfield's
    brushfire against SciPy's ``distance_transform_edt`` / ``distance_transform_cdt`` and OpenCV's
    ``distanceTransform``; the potential + gradient build against the memory-streaming floor
    (allocating and writing its three float64 output arrays); the octile wavefront planner against
    scikit-image's ``MCP_Geometric``; the follower's steps per second.
``end_to_end``
    ``benchmarks/end_to_end.py``: ``plan`` on 1024^2, 4096^2, 8192^2 maps (each size in a fresh
    process): time against OpenCV ``DIST_C`` on the same map, peak memory.
``peers``
    ``benchmarks/peers.py``: Robotics Toolbox, python-motion-planning and the classic cell-by-cell
    potential, each as a ratio to gridfield's equivalent on the peer's own example map.
``areas``
    The per-area scripts (``benchmarks/brushfire.py``, ``potential.py``, ``follow.py``,
    ``navigation.py``, ``rasterize.py``, ``incremental.py``), each run through its ``main`` in a subprocess; their
    output is included verbatim. A script that does not exist is reported as missing.

Every time is a median of several runs (``--repeat``), and every ratio compares two things
measured in the same process on the same data. The report ends with the targets of the
benchmark issue and whether this run met them.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime as _dt
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
sys.path.insert(0, str(HERE))

import end_to_end  # noqa: E402
import peers  # noqa: E402
import startup  # noqa: E402
from end_to_end import Timing, timed  # noqa: E402

SECTIONS = ("startup", "components", "end_to_end", "peers", "areas")
AREA_SCRIPTS = ("brushfire", "potential", "follow", "navigation", "rasterize", "incremental")
HEAVY = ("matplotlib", "numba", "scipy.sparse", "shapely", "skimage")  # numba: must never come back at run time
HELP_TARGET_S = 0.5
E2E_TARGET_RATIO = 3.0
PLAN_FIRST_TARGET = 2.0  # first `gridfield plan maps/seed000.yaml --json` / the import floor
PLAN_WARM_TARGET = 1.5
DEMO_FIRST_TARGET = 1.3  # first `gridfield demo` / the second
PEER_TARGET_RATIO = 100.0
MEMORY_TARGET = 4 * 2**30


def log(msg: str) -> None:
    """Progress on stderr (the report goes to stdout / ``--out``)."""
    print(f"[run.py {time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


# ----------------------------------------------------------------------------------------------
# Machine facts
# ----------------------------------------------------------------------------------------------
def _version(module: str) -> str:
    try:
        from importlib.metadata import version

        return version(module)
    except Exception:
        return "not installed"


def _cpu_model() -> str:
    with contextlib.suppress(OSError):
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return platform.processor() or "unknown"


def _memory_total() -> str:
    with contextlib.suppress(OSError, ValueError, IndexError):
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal"):
                return f"{int(line.split()[1]) / 2**20:.1f} GiB"
    return "unknown"


def _git(*args: str) -> str:
    try:
        return subprocess.run(["git", *args], cwd=REPO, capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


def machine_facts() -> list[str]:
    """Bullet lines describing the machine and the software measured."""
    from gridfield.fields import _potential as _kernels_potential

    threads = _kernels_potential.get_num_threads()
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    commit = _git("rev-parse", "--short", "HEAD")
    dirty = " (with uncommitted changes)" if _git("status", "--porcelain", "--untracked-files=no") else ""
    blas = {k: v for k, v in os.environ.items() if k.startswith(("OPENBLAS_", "OMP_", "NUMBA_", "MKL_"))}
    return [
        f"- CPU: {_cpu_model()}, {os.cpu_count()} logical cores; memory {_memory_total()}; "
        f"{platform.system()} {platform.release()}",
        f"- load average (1, 5, 15 min) at start: {load}",
        f"- Python {platform.python_version()} ({sys.executable})",
        f"- gridfield {_version('gridfield')} at commit {commit or '?'}{dirty}",
        "- numpy {}, scipy {}, gridfield's kernels compiled ahead of time (Cython; OpenMP {} threads), "
        "scikit-image {}, opencv-python-headless {}, scikit-fmm {}".format(
            np.__version__, _version("scipy"), threads, _version("scikit-image"),
            _version("opencv-python-headless"), _version("scikit-fmm")),
        f"- peers: roboticstoolbox-python {_version('roboticstoolbox-python')}, "
        f"python-motion-planning {_version('python-motion-planning')}",
        f"- environment: {', '.join(f'{k}={v}' for k, v in sorted(blas.items())) or 'no OPENBLAS_/OMP_/NUMBA_ variables'}",
    ]


# ----------------------------------------------------------------------------------------------
# Start-up: gridfield --help and heavy imports
# ----------------------------------------------------------------------------------------------
_HELP_CODE = (
    "import contextlib, io\n"
    "from gridfield.cli import main\n"
    "with contextlib.redirect_stdout(io.StringIO()):\n"
    "    try:\n        main(['--help'])\n    except SystemExit:\n        pass\n"
)


def _gridfield_command() -> list[str]:
    """The installed ``gridfield`` console script beside this interpreter, else ``python -m gridfield``."""
    exe = Path(sys.executable).with_name("gridfield")
    if exe.exists():
        return [str(exe)]
    found = shutil.which("gridfield")
    if found and Path(found).resolve().parent == Path(sys.executable).resolve().parent:
        return [found]
    return [sys.executable, "-m", "gridfield"]


def _wall(cmd: Sequence[str], repeat: int) -> tuple[Timing, int]:
    times, rc = [], 0
    for _ in range(repeat):
        t0 = time.perf_counter()
        rc = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
        times.append(time.perf_counter() - t0)
    return Timing(statistics.median(times), min(times), max(times), len(times)), rc


@dataclass
class ImportRecord:
    """One module in a ``-X importtime`` listing."""

    name: str
    depth: int
    self_us: int
    cumulative_us: int


def parse_importtime(text: str) -> list[ImportRecord]:
    """Records of ``python -X importtime`` stderr, in the order printed (children before parents)."""
    out = []
    for line in text.splitlines():
        m = re.match(r"import time:\s+(\d+) \|\s+(\d+) \|( *)(\S+)", line)
        if m:
            out.append(ImportRecord(m.group(4), len(m.group(3)) // 2, int(m.group(1)), int(m.group(2))))
    return out


def import_chain(records: Sequence[ImportRecord], index: int) -> list[str]:
    """The chain of importers of ``records[index]``, outermost first, ending with the module itself."""
    chain = [records[index].name]
    depth = records[index].depth
    for r in records[index + 1:]:
        if r.depth < depth:
            chain.append(r.name)
            depth = r.depth
            if depth == 0:
                break
    return chain[::-1]


def _module_file(module: str) -> Path | None:
    rel = Path(*module.split("."))
    for cand in (REPO / rel.with_suffix(".py"), REPO / rel / "__init__.py"):
        if cand.exists():
            return cand
    return None


def _import_lines(path: Path, target: str) -> list[str]:
    """``file:line: text`` of the lines of ``path`` that import ``target`` (absolute or relative)."""
    last = target.split(".")[-1]
    top = target.split(".")[0]
    pats = [rf"^\s*import\s+{re.escape(target)}\b", rf"^\s*from\s+{re.escape(target)}\s+import\b",
            rf"^\s*from\s+{re.escape(top)}(\.\S+)?\s+import\s+.*\b{re.escape(last)}\b",
            rf"^\s*import\s+{re.escape(top)}\b"]
    if target.startswith("gridfield."):
        pats.append(rf"^\s*from\s+\.+(\w+\.)*{re.escape(last)}\s+import\b")
        pats.append(rf"^\s*from\s+\.+\s+import\s+.*\b{re.escape(last)}\b")
    hits = []
    for i, line in enumerate(path.read_text().splitlines(), 1):
        if any(re.search(p, line) for p in pats):
            hits.append(f"{path.relative_to(REPO)}:{i}: `{line.strip()}`")
    return hits


def _explain(records: Sequence[ImportRecord], index: int) -> dict[str, Any]:
    """Import chain of ``records[index]``, the innermost gridfield module in it and its import line."""
    chain = import_chain(records, index)
    culprit, lines = "", []
    for k in range(len(chain) - 1):  # every link made by a gridfield module: its import line
        if chain[k].startswith("gridfield"):
            culprit = chain[k]
            f = _module_file(chain[k])
            if f is not None:
                lines += _import_lines(f, chain[k + 1])
    root, root_lines = chain[0], []
    if root.startswith("gridfield.") and root != culprit:
        # imported at depth 0: from inside a function of a module loaded in this run, or of a CLI
        # sub-command module (loaded by importlib.import_module, which -X importtime does not list)
        files = {_module_file(r.name) for r in records if r.name.startswith("gridfield")}
        files |= set((REPO / "gridfield" / "cli").glob("*.py"))
        for f in sorted(f for f in files if f is not None):
            root_lines += _import_lines(f, root)
        if len(root_lines) > 4:
            root_lines = [*root_lines[:4], f"{len(root_lines) - 4} more"]
    return {"chain": chain, "culprit": culprit, "lines": lines, "root_lines": root_lines,
            "cumulative_ms": records[index].cumulative_us / 1e3}


def heavy_imports(code: str) -> dict[str, Any]:
    """Run ``code`` under ``python -X importtime``: the heavy modules it imports and who pulled them in,
    and the slowest third-party packages imported directly by gridfield modules."""
    proc = subprocess.run([sys.executable, "-X", "importtime", "-c", code], capture_output=True, text=True,
                          timeout=120)
    records = parse_importtime(proc.stderr)
    found: dict[str, Any] = {}
    for heavy in HEAVY:
        # records are printed children first: prefer the package's own line to its first submodule's
        hits = [i for i, r in enumerate(records) if r.name == heavy]
        hits = hits or [i for i, r in enumerate(records) if r.name.startswith(heavy + ".")]
        if hits:
            found[heavy] = _explain(records, hits[0])
    direct = []
    for i, r in enumerate(records):
        chain = import_chain(records, i)
        if not r.name.startswith("gridfield") and len(chain) > 1 and chain[-2].startswith("gridfield"):
            direct.append((r.cumulative_us, i))
    slow = [_explain(records, i) for _, i in sorted(direct, reverse=True)[:4]]
    return {"found": found, "slowest": slow, "returncode": proc.returncode}


def section_startup(results: dict[str, Any], repeat: int = 5, quick: bool = False) -> list[str]:
    """``gridfield --help`` timing, the heavy-import audit, and every command's first/warm time against
    the import floor (:mod:`startup`)."""
    cmd = _gridfield_command()
    t_help, rc = _wall([*cmd, "--help"], repeat)
    t_bare, _ = _wall([sys.executable, "-c", "pass"], repeat)
    t_import, _ = _wall([sys.executable, "-c", "import gridfield"], repeat)
    results["help"] = {"median": t_help.median, "rc": rc}
    lines = [
        "## Start-up",
        "",
        f"`{' '.join(Path(c).name if i == 0 else c for i, c in enumerate(cmd))} --help`, "
        f"{repeat} fresh processes each (exit code {rc}):",
        "",
        "| command | ms median (min-max) | n |",
        "|---|---|---|",
        f"| `gridfield --help` | **{t_help.ms}** | {t_help.n} |",
        f"| `python -c \"import gridfield\"` | {t_import.ms} | {t_import.n} |",
        f"| `python -c pass` (the interpreter alone) | {t_bare.ms} | {t_bare.n} |",
        "",
        f"Target `gridfield --help` < {HELP_TARGET_S * 1e3:.0f} ms: "
        f"**{'met' if t_help.median < HELP_TARGET_S else 'NOT met'}** ({t_help.median * 1e3:.0f} ms, of which "
        f"{t_bare.median * 1e3:.0f} ms is the interpreter's own start-up on this machine).",
        "",
        "Heavy modules imported (`python -X importtime`; chain = importer -> ... -> module):",
        "",
        "| run | heavy modules imported | chains and the gridfield lines responsible |",
        "|---|---|---|",
    ]
    audits = {"import gridfield": heavy_imports("import gridfield"), "gridfield --help": heavy_imports(_HELP_CODE)}
    results["heavy"] = {k: sorted(v["found"]) for k, v in audits.items()}
    for label, audit in audits.items():
        found = audit["found"]
        detail = []
        for name, info in found.items():
            where = "; ".join(info["lines"] + [f"(reached from {x})" for x in info["root_lines"]]) or "?"
            detail.append(f"**{name}** ({info['cumulative_ms']:.0f} ms): {' -> '.join(info['chain'])} — {where}")
        lines.append(f"| `{label}` | {', '.join(sorted(found)) or 'none'} | {'<br>'.join(detail) or '-'} |")
    lines += ["", "Slowest third-party imports made by gridfield modules during `gridfield --help` "
              "(cumulative ms, under -X importtime):", ""]
    for info in audits["gridfield --help"]["slowest"]:
        where = "; ".join(info["lines"] + [f"(reached from {x})" for x in info["root_lines"]]) or "?"
        lines.append(f"- {info['chain'][-1]} {info['cumulative_ms']:.0f} ms: {' -> '.join(info['chain'])} — {where}")
    lines.append("")
    floor, rows = startup.measure(repeat, not quick, ("plan (potential) --json",) if quick else None)
    results["commands"] = {"floor": floor, "rows": rows}
    lines += [f"Every command in fresh processes ({repeat} runs, `gridfield demo` 2; first = the first run of "
              "this benchmark, warm = median of the others; the kernels are compiled at install, so there is "
              f"nothing to compile or load from a cache). Floor: `python -c \"import numpy, scipy.ndimage, "
              f"shapely, yaml\"`, {floor:.2f} s (warm median).", "",
              "| command | first (s) | warm (s) | first / floor | warm / floor | first / warm |",
              "|---|---|---|---|---|---|"]
    for name, (first, warm) in rows.items():
        lines.append(f"| `gridfield {name}` | {first:.2f} | {warm:.2f} | {first / floor:.2f} | {warm / floor:.2f} "
                     f"| {first / warm:.2f} |")
    lines.append("")
    return lines


# ----------------------------------------------------------------------------------------------
# Components side by side
# ----------------------------------------------------------------------------------------------
@dataclass
class Line:
    group: str
    method: str
    size: int
    t: Timing | None
    ref: bool = False
    note: str = ""


def _safe(fn: Callable[[], Any]) -> tuple[Any, str]:
    try:
        return fn(), ""
    except Exception as e:
        return None, f"{type(e).__name__}: {e}".splitlines()[0][:160]


def components_for_size(n: int, repeat: int) -> list[Line]:
    """Every side-by-side measurement on the synthetic n x n map."""
    from scipy import ndimage

    from gridfield.distance.brushfire import brushfire
    from gridfield.fields.potential import build_field
    from gridfield.following.follower import follow

    gm = end_to_end.synthetic_map(n)
    occ = gm.occupied
    free = ~occ
    free8 = np.ascontiguousarray(free, np.uint8)
    out: list[Line] = []

    def add(group: str, method: str, fn: Callable[[], Any], *, ref: bool = False, warmup: int = 1,
            note: str = "") -> Any:
        log(f"components {n}: {group}: {method}")
        res, err = _safe(lambda: timed(fn, repeat, warmup=warmup, budget=30.0))
        if err:
            out.append(Line(group, method, n, None, ref, err))
            return None
        out.append(Line(group, method, n, res[0], ref, note))
        return res[1]

    g = "Euclidean distance map"
    add(g, "gridfield brushfire(metric='euclidean', compute_labels=False, compute_nearest=False): distance",
        lambda: brushfire(gm, metric="euclidean", compute_labels=False, compute_nearest=False), ref=True)
    add(g, "gridfield brushfire(metric='euclidean', compute_labels=False): + nearest obstacle",
        lambda: brushfire(gm, metric="euclidean", compute_labels=False))
    add(g, "gridfield brushfire(metric='euclidean'): + labels + GVD (what plan computes)",
        lambda: brushfire(gm, metric="euclidean"))
    add(g, "scipy.ndimage.distance_transform_edt: distance", lambda: ndimage.distance_transform_edt(free))
    add(g, "scipy.ndimage.distance_transform_edt(return_indices=True): + nearest",
        lambda: ndimage.distance_transform_edt(free, return_indices=True))
    try:
        import cv2

        add(g, "OpenCV distanceTransform(DIST_L2, DIST_MASK_PRECISE): distance (float32)",
            lambda: cv2.distanceTransform(free8, cv2.DIST_L2, cv2.DIST_MASK_PRECISE))
        add(g, "OpenCV distanceTransform(DIST_L2, 5): approximate distance (float32)",
            lambda: cv2.distanceTransform(free8, cv2.DIST_L2, 5))
    except ImportError:
        cv2 = None
        out.append(Line(g, "OpenCV", n, None, note="opencv-python-headless not installed"))

    g = "Chessboard distance map"
    add(g, "gridfield brushfire(connectivity=8, compute_labels=False, compute_nearest=False)",
        lambda: brushfire(gm, connectivity=8, compute_labels=False, compute_nearest=False), ref=True)
    add(g, "scipy.ndimage.distance_transform_cdt(metric='chessboard')",
        lambda: ndimage.distance_transform_cdt(free, metric="chessboard"))
    if cv2 is not None:
        add(g, "OpenCV distanceTransform(DIST_C, 3)", lambda: cv2.distanceTransform(free8, cv2.DIST_C, 3))

    g = "Potential + gradients"
    params = dict(end_to_end.PARAMS)
    dmap = brushfire(gm, metric="euclidean", compute_labels=False)
    goal = end_to_end.GOAL
    fld = add(g, "gridfield build_field(dmap=...): U, dU/dx, dU/dy (float64)",
              lambda: build_field(gm, goal, params, dmap=dmap), ref=True)

    def floor() -> list[np.ndarray]:
        arrays = [np.empty(occ.shape) for _ in range(3)]
        for a in arrays:
            a.fill(1.0)
        return arrays

    add(g, "floor: allocate and write three float64 arrays (np.empty + fill)", floor)
    pre = [np.empty(occ.shape) for _ in range(3)]

    def floor_warm(arrays: list[np.ndarray] = pre) -> None:
        for a in arrays:
            a.fill(1.0)

    add(g, "floor: write three preallocated float64 arrays (fill)", floor_warm)

    g = "Octile wavefront + path"
    gfplan = add(g, "gridfield plan('wavefront-octile')",
                 lambda: _plan("wavefront-octile", gm), ref=True)
    try:
        from skimage.graph import MCP_Geometric

        costs = np.where(occ, np.inf, 1.0)
        s_cell = (int(end_to_end.START[1] / gm.grid.resolution), int(end_to_end.START[0] / gm.grid.resolution))
        g_cell = (int(goal[1] / gm.grid.resolution), int(goal[0] / gm.grid.resolution))

        def mcp() -> Any:
            m = MCP_Geometric(costs)
            cum, _ = m.find_costs([g_cell])
            return cum, m.traceback(s_cell)

        res = add(g, "scikit-image MCP_Geometric: find_costs(goal) + traceback(start)", mcp)
        if res is not None and gfplan is not None:
            out[-1].note = (f"path cost {res[0][s_cell] * gm.grid.resolution:.3f} vs gridfield length "
                            f"{gfplan.length:.3f}")
    except ImportError:
        out.append(Line(g, "scikit-image MCP_Geometric", n, None, note="scikit-image not installed"))

    g = "Follower"
    if fld is not None:
        fparams = end_to_end.plan_params(n)
        paths: list[Any] = []

        def run_follow() -> None:
            paths.append(follow(fld, end_to_end.START, params=fparams))

        add(g, "gridfield follow(field, start): whole path", run_follow, ref=True)
        if paths:
            p = paths[-1]
            steps = np.median([q.seconds / max(q.iterations, 1) for q in paths])
            out[-1].note = (f"{p.status} after {p.iterations} steps; **{1 / steps:,.0f} steps/s** "
                            f"({steps * 1e6:.2f} us/step, follower's own clock)")
    return out


def _plan(name: str, gm: Any) -> Any:
    from gridfield.planners import plan

    return plan(name, gm, end_to_end.START, end_to_end.GOAL, {})


def section_components(sizes: Sequence[int], repeat: int, results: dict[str, Any]) -> list[str]:
    lines = [
        "## Components side by side",
        "",
        "Same process, same synthetic map per size (`end_to_end.synthetic_map`: 100 m x 100 m, 40 squares and "
        "discs, about 11 % occupied). `ratio` = time / the time of the group's row marked ★ at that size.",
        "",
        "| group | method | size | ms median (min-max) | n | ratio | notes |",
        "|---|---|---|---|---|---|---|",
    ]
    all_lines: list[Line] = []
    for n in sizes:
        all_lines += components_for_size(n, repeat)
    results["components"] = all_lines
    for x in all_lines:
        ref = next((r for r in all_lines if r.group == x.group and r.size == x.size and r.ref), None)
        if x.t is None:
            lines.append(f"| {x.group} | {x.method} | {x.size}^2 | failed | | | {x.note} |")
            continue
        ratio = f"{x.t.median / ref.t.median:.2f}" if ref is not None and ref.t is not None else "-"
        star = " ★" if x.ref else ""
        lines.append(f"| {x.group} | {x.method}{star} | {x.size}^2 | {x.t.ms} | {x.t.n} | {ratio} | {x.note} |")
    lines.append("")
    return lines


# ----------------------------------------------------------------------------------------------
# End to end, peers
# ----------------------------------------------------------------------------------------------
def section_end_to_end(sizes: Sequence[int], repeat: int, results: dict[str, Any]) -> list[str]:
    log(f"end_to_end: sizes {list(sizes)} (each in a fresh process), the classic field")
    res = end_to_end.measure(sizes, repeat, model="khatib")
    results["end_to_end"] = res
    log(f"end_to_end: sizes {list(sizes)}, the planner's default field")
    res_default = end_to_end.measure(sizes, repeat, model="default")
    results["end_to_end_default"] = res_default
    return [
        "## End-to-end `plan` (benchmarks/end_to_end.py)",
        "",
        "`plan(\"potential\", gridmap, (5, 5), (95, 95), {model: khatib, d_star: 2, q_star: 2, max_iterations: 4n})` "
        "on the synthetic "
        "100 m x 100 m map in memory (brushfire, potential, gradients, follower), each size in a fresh process. "
        "Time ratio: plan / OpenCV `DIST_C` on the same map in the same process (interleaved rounds). The "
        "brushfire `plan` computes holds the distance and nearest obstacle only (no wavefront steps, labels or "
        "GVD, which no potential reads); the full one is timed after the rounds, for context. The max of the "
        "plan column is its first round: memory this process has not touched lately costs several times more "
        "to write on this VM. Peak memory: the child's "
        "VmHWM (whole process: interpreter, libraries, map, plan; not ru_maxrss, which on Linux a child inherits "
        "from its parent's peak at fork); tracemalloc: the peak of what `plan` itself allocated (numpy "
        "allocations are traced).",
        "",
        end_to_end.table(res),
        "",
        "The same with the planner's default field (`--model default`: no `model`, so `nf1`, the complete field "
        "of issue 25: brushfire, clearance band, a weighted-A* fast march from the goal towards the start and "
        "its upwind gradient, then the follower). A heavier computation than the classic field's; the "
        "end-to-end targets above were set on the classic one and are not verdicts on this table.",
        "",
        end_to_end.table(res_default),
        "",
    ]


def section_peers(repeat: int, scale: float, results: dict[str, Any]) -> list[str]:
    log("peers")
    rows = peers.measure(repeat, scale)
    results["peers"] = rows
    return [
        "## Peers (benchmarks/peers.py)",
        "",
        "Each peer on its own example-sized map, gridfield's equivalent on the same map in the same process; "
        "ratio = peer median / gridfield median. How each pair is made comparable is in the docstring of "
        "benchmarks/peers.py" + (f" (maps shrunk by --scale {scale})" if scale != 1 else "") + ".",
        "",
        peers.table(rows),
        "",
    ]


# ----------------------------------------------------------------------------------------------
# Per-area scripts
# ----------------------------------------------------------------------------------------------
def _script_options(script: Path) -> str:
    try:
        return subprocess.run([sys.executable, str(script), "--help"], capture_output=True, text=True,
                              timeout=120).stdout
    except (OSError, subprocess.SubprocessError):
        return ""


#: Extra options of ``--quick`` runs for scripts whose defaults cover more than sizes and repeats.
QUICK_EXTRA = {
    "brushfire": ["--maps", "random", "--no-compile"],
    "navigation": ["--maps", "arena", "--skip", "harmonic"],
}


def area_arguments(help_text: str, *, quick: bool, repeat: int | None, name: str = "") -> list[str]:
    """Arguments for a per-area script: small sizes when quick; ``--repeat`` (default 3 in the full
    suite, so that all five scripts fit its time budget; 2 when quick)."""
    args: list[str] = []
    if quick:
        if re.search(r"--sizes\b", help_text):
            args += ["--sizes", "512"]
        elif re.search(r"--size\b", help_text):
            args += ["--size", "512"]
    if quick:
        extra = QUICK_EXTRA.get(name, [])
        if all(re.search(rf"{re.escape(x)}\b", help_text) for x in extra if x.startswith("--")):
            args += extra
    rep = repeat if repeat is not None else (2 if quick else 3)
    if rep is not None:
        for flag in ("--repeat", "--repeats"):
            if re.search(rf"{flag}\b", help_text):
                args += [flag, str(rep)]
                break
    return args


def section_areas(quick: bool, repeat: int | None, timeout: float, results: dict[str, Any],
                  scripts: Sequence[str] = AREA_SCRIPTS) -> list[str]:
    lines = ["## Per-area benchmarks", "",
             "Each script's `main`, run as `python benchmarks/<area>.py [args]` in its own process; output verbatim.", ""]
    status: dict[str, str] = {}
    for name in scripts:
        script = HERE / f"{name}.py"
        if not script.exists():
            status[name] = "missing"
            lines += [f"### {name}", "", f"**missing**: benchmarks/{name}.py does not exist yet.", ""]
            continue
        args = area_arguments(_script_options(script), quick=quick, repeat=repeat, name=name)
        log(f"areas: {name}.py {' '.join(args)}")
        t0 = time.perf_counter()
        try:
            proc = subprocess.run([sys.executable, str(script), *args], capture_output=True, text=True,
                                  timeout=timeout, cwd=REPO)
            wall = time.perf_counter() - t0
            ok = proc.returncode == 0
            status[name] = "ok" if ok else f"failed (exit {proc.returncode})"
            body = proc.stdout.strip() + ("" if ok else "\n" + "\n".join(proc.stderr.strip().splitlines()[-15:]))
        except subprocess.TimeoutExpired as e:
            wall = time.perf_counter() - t0
            status[name] = f"timed out after {timeout:.0f} s"
            out = e.stdout.decode() if isinstance(e.stdout, bytes) else (e.stdout or "")
            body = out.strip()
        lines += [f"### {name}", "", f"`python benchmarks/{name}.py {' '.join(args)}`: {status[name]}, "
                  f"{wall:.0f} s", "", "```", body or "(no output)", "```", ""]
    results["areas"] = status
    return lines


# ----------------------------------------------------------------------------------------------
# Targets
# ----------------------------------------------------------------------------------------------
def section_targets(results: dict[str, Any]) -> list[str]:
    rows = []
    e2e = {r["n"]: r for r in results.get("end_to_end", []) if "error" not in r}
    if 4096 in e2e and e2e[4096]["dist_c"]:
        r = e2e[4096]
        ratio = r["plan"]["median"] / r["dist_c"]["median"]
        rows.append(("end-to-end plan (classic field, model khatib) on 4096^2 within 3x OpenCV DIST_C", f"{ratio:.2f}x "
                     f"({r['plan']['median'] * 1e3:,.0f} ms vs {r['dist_c']['median'] * 1e3:,.0f} ms, "
                     f"medians of {r['plan']['n']})",
                     "met" if ratio <= E2E_TARGET_RATIO else "NOT met"))
    else:
        rows.append(("end-to-end plan (classic field, model khatib) on 4096^2 within 3x OpenCV DIST_C", "not measured in this run", "-"))
    if 8192 in e2e:
        r = e2e[8192]
        rows.append(("end-to-end plan (classic field, model khatib) on 8192^2 within 4 GiB peak memory",
                     f"{r['rss_peak'] / 2**30:.2f} GiB peak RSS (plan's own allocations "
                     f"{(r.get('traced_peak') or 0) / 2**30:.2f} GiB)",
                     "met" if r["rss_peak"] <= MEMORY_TARGET else "NOT met"))
    else:
        rows.append(("end-to-end plan (classic field, model khatib) on 8192^2 within 4 GiB peak memory", "not measured in this run", "-"))
    prs = results.get("peers")
    if prs is not None:
        measured = [p for p in prs if not p.context and p.status == "ok" and p.gf_time is not None]
        short = [p for p in measured if p.ratio < PEER_TARGET_RATIO]
        unmeasured = [p for p in prs if not p.context and p not in measured]
        verdict = "NOT met" if short else ("met" if measured and not unmeasured else "-")
        rows.append(("every peer ≥ 100x slower than gridfield's equivalent (all rows below)",
                     f"{len(measured) - len(short)} of {len(measured)} comparisons ≥ 100x"
                     + (f"; {len(unmeasured)} not measured" if unmeasured else ""), verdict))
        for p in prs:
            if p.context:
                continue
            if p.status == "ok" and p.gf_time is not None:
                rows.append((f"- {p.peer} vs gridfield {p.gridfield}", f"{p.ratio:,.0f}x",
                             "met" if p.ratio >= PEER_TARGET_RATIO else "NOT met"))
            else:
                rows.append((f"- {p.peer} vs gridfield {p.gridfield}", f"{p.status}: {p.note}", "-"))
    else:
        rows.append(("every peer ≥ 100x slower than gridfield's equivalent", "not measured in this run", "-"))
    cmds = results.get("commands")
    if cmds is not None:
        floor, crow = cmds["floor"], cmds["rows"]
        first, warm = crow["plan (potential) --json"]
        rows.append((f"first `gridfield plan maps/seed000.yaml --json` <= {PLAN_FIRST_TARGET}x the import floor",
                     f"{first / floor:.2f}x ({first:.2f} s vs {floor:.2f} s)",
                     "met" if first / floor <= PLAN_FIRST_TARGET else "NOT met"))
        rows.append((f"warm `gridfield plan maps/seed000.yaml --json` <= {PLAN_WARM_TARGET}x the import floor",
                     f"{warm / floor:.2f}x ({warm:.2f} s)", "met" if warm / floor <= PLAN_WARM_TARGET else "NOT met"))
        if "demo" in crow:
            first, warm = crow["demo"]
            rows.append((f"first `gridfield demo` within {DEMO_FIRST_TARGET}x of the second",
                         f"{first / warm:.2f}x ({first:.1f} s vs {warm:.1f} s)",
                         "met" if first / warm <= DEMO_FIRST_TARGET else "NOT met"))
    if "help" in results:
        h = results["help"]["median"]
        rows.append(("`gridfield --help` under 0.5 s", f"{h * 1e3:.0f} ms", "met" if h < HELP_TARGET_S else "NOT met"))
        heavy = results.get("heavy", {}).get("gridfield --help", [])
        rows.append(("no heavy imports at start-up (`gridfield --help`; part of the --help target)",
                     ", ".join(heavy) or "none",
                     "met" if not heavy else "NOT met"))
    out = ["## Targets", "", "| target | this run | verdict |", "|---|---|---|"]
    out += [f"| {a} | {b} | **{c}** |" for a, b, c in rows]
    return [*out, ""]


# ----------------------------------------------------------------------------------------------
def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes and few repeats (about a minute)")
    ap.add_argument("--sizes", type=int, nargs="+", help="map sizes (cells per side) for end_to_end; components "
                    "use those up to 4096 (default 1024 4096 8192; quick: 512 1024)")
    ap.add_argument("--repeat", type=int, help="timed runs per measurement (default 5; quick: 2)")
    ap.add_argument("--out", metavar="FILE", help="also write the markdown report to FILE")
    ap.add_argument("--startup-repeat", type=int, default=5, help="fresh processes per start-up timing (default 5)")
    ap.add_argument("--only", nargs="+", choices=SECTIONS, metavar="SECTION",
                    help=f"run only these sections ({', '.join(SECTIONS)})")
    ap.add_argument("--peer-scale", type=float, help="shrink the peers' maps (default 1; quick: 0.5)")
    ap.add_argument("--area-timeout", type=float, default=None, help="seconds per area script (default 480; quick 120)")
    args = ap.parse_args(argv)

    sizes = args.sizes or ([512, 1024] if args.quick else list(end_to_end.DEFAULT_SIZES))
    repeat = args.repeat or (2 if args.quick else 5)
    e2e_repeat = args.repeat or (2 if args.quick else 5)
    sections = args.only or list(SECTIONS)
    comp_sizes = [n for n in sizes if n <= 4096] or [min(sizes)]
    peer_scale = args.peer_scale or (0.5 if args.quick else 1.0)
    area_timeout = args.area_timeout or (120.0 if args.quick else 480.0)

    started = time.perf_counter()
    command = "python benchmarks/run.py" + ("" if argv is None and len(sys.argv) <= 1 else " " + " ".join(
        sys.argv[1:] if argv is None else argv))
    report = [
        "# gridfield benchmark results",
        "",
        f"Command: `{command}`  ",
        f"Date: {_dt.datetime.now(_dt.UTC).strftime('%Y-%m-%d %H:%M UTC')}",
        "",
        *machine_facts(),
        "",
    ]
    results: dict[str, Any] = {}
    body: list[str] = []
    if "startup" in sections:
        log("startup")
        body += section_startup(results, args.startup_repeat, quick=args.quick)
    if "end_to_end" in sections:  # first: children spawned by a small parent
        body += section_end_to_end(sizes, e2e_repeat, results)
    if "components" in sections:
        body += section_components(comp_sizes, repeat, results)
    if "peers" in sections:
        body += section_peers(args.repeat or (1 if args.quick else 3), peer_scale, results)
    if "areas" in sections:
        body += section_areas(args.quick, args.repeat, area_timeout, results)
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    report += section_targets(results) + body + [
        f"Finished in {time.perf_counter() - started:.0f} s; load average at the end: {load}.", ""]
    text = "\n".join(report)
    print(text)
    if args.out:
        Path(args.out).write_text(text)
        log(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
