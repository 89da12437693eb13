"""Fuzz every loader with random and mutated bytes of its format: a gridfield error or a result, never a
traceback of another kind, never a hang."""

from __future__ import annotations

import gc
import shutil
import signal
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gridfield.core.errors import MESSAGE_LIMIT, GridfieldError
from gridfield.core.grid import Grid, GridMap
from gridfield.core.limits import override
from gridfield.io import bundled_map, read, read_scen, write_bitmap, write_npz, write_ros_map

HANG_SECONDS = 20  # far above any loader's time on these tiny files; only a hang reaches it


def _small_map() -> GridMap:
    occ = np.zeros((6, 7), bool)
    occ[2:4, 3] = True
    return GridMap(Grid((6, 7), 0.5, origin=(-1.0, 2.0)), occ)


def _seeds(folder: Path) -> dict[str, tuple[str, bytes, Callable[[Path], Any]]]:
    """name -> (file name, valid bytes, loader)."""
    gm = _small_map()
    for suffix in (".png", ".bmp", ".pgm"):
        write_bitmap(folder / f"seed{suffix}", gm)
    write_ros_map(folder / "ros.yaml", gm, image_name="ros_image.pgm")
    write_npz(folder / "seed.npz", {"occupied": gm.occupied}, gm.grid)
    from gridfield.fields.potential import build_field
    from gridfield.io import save_field

    save_field(folder / "field.npz", build_field(gm, (2.0, 4.5)))
    shutil.copy(bundled_map("seed000.yaml"), folder / "seed000.yaml")
    scen = bundled_map("arena/arena.map.scen").read_bytes().splitlines(keepends=True)[:6]
    spec = b"output: rows.csv\nmaps:\n  - path: seed000.yaml\n    resolution: 0.5\n    random_pairs: {n: 2, seed: 1}\n" \
           b"planners: [wavefront]\nparams: {q_star: [1.0, 2.0]}\n"

    def load_field(p: Path) -> Any:
        from gridfield.io import load_field

        return load_field(p)

    def load_spec(p: Path) -> Any:
        from gridfield.sweep import load_spec

        return load_spec(p)

    return {
        "world": ("w.yaml", (folder / "seed000.yaml").read_bytes(), read),
        "ros_yaml": ("r.yaml", (folder / "ros.yaml").read_bytes().replace(b"ros_image.pgm", b"ros_image.pgm"), read),
        "ros_image": ("ros_image.pgm", (folder / "ros_image.pgm").read_bytes(), lambda p: read(folder / "ros.yaml")),
        "png": ("m.png", (folder / "seed.png").read_bytes(), read),
        "bmp": ("m.bmp", (folder / "seed.bmp").read_bytes(), read),
        "pgm_binary": ("m.pgm", (folder / "seed.pgm").read_bytes(), read),
        "pgm_ascii": ("a.pgm", b"P2\n# a comment\n4 3\n255\n0 255 255 0\n255 0 255 255\n9 9 9 9\n", read),
        "movingai": ("m.map", bundled_map("arena/arena.map").read_bytes(), read),
        "scen": ("s.scen", b"".join(scen), read_scen),
        "npz": ("m.npz", (folder / "seed.npz").read_bytes(), read),
        "field": ("f.npz", (folder / "field.npz").read_bytes(), load_field),
        "sweep_spec": ("spec.yaml", spec, load_spec),
    }


@st.composite
def _mutated(draw: st.DrawFn, seed: bytes) -> bytes:
    data = bytearray(seed)
    for _ in range(draw(st.integers(1, 6))):
        op = draw(st.sampled_from(["flip", "set", "insert", "delete", "truncate", "duplicate", "digits"]))
        pos = draw(st.integers(0, max(len(data) - 1, 0)))
        if op == "flip" and data:
            data[pos] ^= 1 << draw(st.integers(0, 7))
        elif op == "set" and data:
            data[pos] = draw(st.integers(0, 255))
        elif op == "insert":
            data[pos:pos] = draw(st.binary(min_size=1, max_size=16))
        elif op == "delete":
            del data[pos:pos + draw(st.integers(1, 64))]
        elif op == "truncate":
            del data[pos:]
        elif op == "duplicate":
            data[pos:pos] = data[pos:pos + draw(st.integers(1, 200))]
        elif op == "digits":  # big numbers where sizes and counts live
            data[pos:pos] = draw(st.sampled_from([b"99999999", b"-1", b"1e308", b"nan", b"0", b"65536", b"&a", b"*a"]))
    return bytes(data)


@pytest.fixture(scope="module")
def seeds(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, tuple[str, bytes, Callable[[Path], Any]]]]:
    folder = tmp_path_factory.mktemp("fuzz")
    return folder, _seeds(folder)


def _hang(signum: int, frame: Any) -> None:  # pragma: no cover - only on a hang
    raise TimeoutError(f"a loader ran for more than {HANG_SECONDS} s")


FORMATS = ["world", "ros_yaml", "ros_image", "png", "bmp", "pgm_binary", "pgm_ascii", "movingai", "scen", "npz",
           "field", "sweep_spec"]


@pytest.mark.parametrize("fmt", FORMATS)
@settings(max_examples=100, suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
          deadline=None)
@given(data=st.data())
def test_loaders_never_raise_anything_but_gridfield_errors(seeds, fmt: str, data: st.DataObject) -> None:
    folder, table = seeds
    name, seed, loader = table[fmt]
    raw = data.draw(st.one_of(st.binary(max_size=400), _mutated(seed)), label="bytes")
    path = folder / name
    original = path.read_bytes() if path.exists() else None
    path.write_bytes(raw)
    old = signal.signal(signal.SIGALRM, _hang)
    signal.alarm(HANG_SECONDS)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ResourceWarning)
            try:
                with override(10**6):  # a mutated header may ask for any size: the guard must answer
                    loader(path)
            except GridfieldError as e:
                assert len(str(e)) <= MESSAGE_LIMIT
            gc.collect(0)  # the young cycles an exception leaves (frames holding an open file)
        leaks = [w for w in caught if issubclass(w.category, ResourceWarning) and str(folder) in str(w.message)]
        assert not leaks, leaks[0].message  # a loader left a file open
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
        if original is not None:
            path.write_bytes(original)
