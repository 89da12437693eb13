"""Bad input, second list: each case is a one-line gridfield error (or a bound stated up front), bounded
memory, and unchanged answers on good input. Every test here fails on the code before the fix."""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import threading
import tracemalloc
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from gridfield.errors import GridfieldError, MapFormatError
from gridfield.io import bundled_map, read, read_bitmap, read_npz, read_ros_map, read_scen, read_yaml

ROOT = Path(__file__).resolve().parents[1]
ARENA = bundled_map("arena/arena.map")


def cli(*args: str, timeout: float = 60) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gridfield", *args], capture_output=True, text=True,
                          timeout=timeout, cwd=ROOT)


def one_line_error(r: subprocess.CompletedProcess[str]) -> str:
    assert r.returncode == 2, (r.returncode, r.stderr[-2000:])
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr[-2000:]
    return lines[0]


def peak_bytes(fn, *args, **kw) -> tuple[object, int]:
    """``fn(*args)`` (its result or the GridfieldError it raised) and the peak of traced allocations (numpy too)."""
    tracemalloc.start()
    try:
        try:
            out: object = fn(*args, **kw)
        except GridfieldError as e:
            out = e
        return out, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


# ----------------------------------------------------------------------------------------
# 1. .scen reading: one long field must not widen the whole table
# ----------------------------------------------------------------------------------------
LINE = "0\tarena.map\t49\t49\t1\t11\t1\t12\t1\n"


def test_scen_long_path_field_stays_small(tmp_path):
    # a valid file: every map field is a 3000-character relative path (basename arena.map); the old reader
    # made a 9-column table as wide as the longest field: 5000 x 9 x 3000 x 4 bytes = 540 MB
    f = tmp_path / "long.scen"
    longpath = "d/" * 1495 + "arena.map"
    f.write_text("version 1\n" + "".join(LINE.replace("arena.map", longpath) for _ in range(5000)))
    s, peak = peak_bytes(read_scen, f)
    assert isinstance(s, object) and len(s) == 5000 and str(s.map_name[0]) == "arena.map"  # type: ignore[arg-type, attr-defined]
    assert peak < 20e6, peak


def test_scen_one_long_field_is_refused_naming_the_line(tmp_path):
    f = tmp_path / "m.scen"
    f.write_text("version 1\n" + LINE * 3 + LINE.replace("\t1\n", "\t" + "1" * 20000 + "\n") + LINE)
    e, peak = peak_bytes(read_scen, f)
    assert isinstance(e, MapFormatError)
    assert "m.scen: line 5: the optimal field is 20000 characters long" in str(e)
    assert peak < 5e6, peak


def test_scen_one_huge_line_is_refused_with_bounded_memory(tmp_path):
    f = tmp_path / "m.scen"
    with open(f, "w") as fh:
        fh.write("version 1\n" + LINE)
        fh.write("0\t" + "x" * 30_000_000 + "\t49\t49\t1\t11\t1\t12\t1\n")
    e, peak = peak_bytes(read_scen, f)
    assert isinstance(e, MapFormatError) and "m.scen: line 3: longer than 65536 bytes" in str(e), e
    assert peak < 2e6, peak


def test_scen_many_short_lines_unchanged():
    s = read_scen(ARENA.with_name("arena.map.scen"))
    assert len(s) == 160 and s.map_name.dtype == np.dtype("<U9") and s.digits == 6


# ----------------------------------------------------------------------------------------
# 2. non-regular files are refused before they are opened
# ----------------------------------------------------------------------------------------
@contextlib.contextmanager
def fifo(path: Path) -> Iterator[Path]:
    """A FIFO at ``path``; a helper thread opens it for writing (and closes it) whenever a reader waits, so
    that the old code, which opened it, does not hang the test (it reads an empty file instead)."""
    os.mkfifo(path)
    stop = threading.Event()

    def unblock() -> None:
        while not stop.wait(0.05):
            try:
                fd = os.open(path, os.O_WRONLY | os.O_NONBLOCK)
            except OSError:
                continue  # no reader yet
            os.close(fd)

    t = threading.Thread(target=unblock, daemon=True)
    t.start()
    try:
        yield path
    finally:
        stop.set()
        t.join()


@pytest.mark.parametrize(("name", "reader"), [("s.scen", read_scen), ("m.map", read), ("w.yaml", read_yaml),
                                              ("w.yaml", read), ("a.npz", read_npz), ("a.png", read_bitmap),
                                              ("r.yaml", read_ros_map)])
def test_fifo_is_refused(tmp_path, name, reader):
    with fifo(tmp_path / name) as f, pytest.raises(MapFormatError, match=rf"{name}: is a FIFO \(named pipe\), "
                                                                         "expected a regular file"):
        reader(f)


def test_fifo_ros_image_is_refused(tmp_path):
    (tmp_path / "m.yaml").write_text("image: img.png\nresolution: 0.05\norigin: [0, 0, 0]\n")
    with fifo(tmp_path / "img.png"), pytest.raises(MapFormatError, match=r"m\.yaml: 'image': .*img\.png: is a FIFO"):
        read_ros_map(tmp_path / "m.yaml")


def test_fifo_sweep_spec_and_rows_file_are_refused(tmp_path):
    from gridfield.sweep import load_spec

    with fifo(tmp_path / "spec.yaml") as f, pytest.raises(MapFormatError, match=r"spec\.yaml: is a FIFO"):
        load_spec(f)
    spec = tmp_path / "ok.yaml"
    spec.write_text(f"maps: [{ARENA}]\nplanners: [wavefront-octile]\noutput: rows.csv\n"
                    "params: {}\n")
    with fifo(tmp_path / "rows.csv"), pytest.raises(GridfieldError, match=r"rows\.csv: the rows file exists and "
                                                                         "is not a regular file"):
        load_spec(spec)


def test_cli_fifo_scenario_is_one_line(tmp_path):
    with fifo(tmp_path / "s.scen") as f:
        line = one_line_error(cli("plan", str(ARENA), "--scenario", str(f), "--index", "0", timeout=30))
    assert "s.scen: is a FIFO (named pipe), expected a regular file" in line
