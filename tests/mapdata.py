"""Where the suite's externally authored maps are: ``tests/data/maps`` (its ``MANIFEST.md`` names each
file's source, licence and sha256), and how a test reads one's bytes as published.

Text maps, scenario lists and PGM images are stored gzip-compressed there; gridfield's readers take them
as they are (``.map.gz``, ``.scen.gz``, ``.pgm.gz``); :func:`raw` gives the bytes a test's own,
independent decoder needs.
"""

from __future__ import annotations

import gzip
import io
from pathlib import Path

#: The suite's copy of externally authored maps (Moving AI, ROS, loader and polygon fixtures).
TEST_MAPS = Path(__file__).resolve().parent / "data" / "maps"
MOVINGAI = TEST_MAPS / "movingai"
ROS_MAPS = TEST_MAPS / "ros_maps"


def raw(path: Path) -> bytes:
    """The file's bytes as published: decompressed when its name ends in ``.gz``.

    >>> raw(MOVINGAI / "arena" / "arena.map.gz")[:12]
    b'type octile\\n'
    """
    data = Path(path).read_bytes()
    return gzip.decompress(data) if Path(path).suffix == ".gz" else data


def image(path: Path):
    """The image opened by Pillow (an independent decoder), from its bytes as published."""
    from PIL import Image

    return Image.open(io.BytesIO(raw(path)))


def movingai_pairs(root: Path = TEST_MAPS) -> list[tuple[Path, Path]]:
    """(map, scenarios) of every Moving AI folder under ``root / "movingai"``, sorted by folder."""
    pairs = []
    for d in sorted(p for p in (root / "movingai").iterdir() if p.is_dir()):
        maps, scens = sorted(d.glob("*.map.gz")), sorted(d.glob("*.scen.gz"))
        assert len(maps) == 1 and len(scens) == 1, d
        pairs.append((maps[0], scens[0]))
    return pairs
