"""The suite reads only what the repository holds: its external maps are in tests/data/maps, each listed
in that folder's MANIFEST.md with its source, licence and sha256, and nothing under tests/, benchmarks/,
docs/ or .ci/ names the developers' own folder of maps beside the repository (a clone has none)."""

from __future__ import annotations

import gzip
import hashlib
import sys
from pathlib import Path

from mapdata import TEST_MAPS

REPO = Path(__file__).resolve().parents[1]


def _rows() -> dict[str, list[str]]:
    rows = {}
    for line in (TEST_MAPS / "MANIFEST.md").read_text().splitlines():
        cols = [c.strip() for c in line.split("|")][1:-1]
        if len(cols) == 9 and cols[0].startswith("`"):
            rows[cols[0].strip("`")] = cols
    return rows


def test_every_data_file_is_in_the_manifest_with_its_checksums():
    rows = _rows()
    files = {p.relative_to(TEST_MAPS).as_posix() for p in TEST_MAPS.rglob("*") if p.is_file()} - {"MANIFEST.md"}
    assert files == set(rows), (sorted(files - set(rows)), sorted(set(rows) - files))
    for name, cols in rows.items():
        data = (TEST_MAPS / name).read_bytes()
        assert cols[8].strip("`") == hashlib.sha256(data).hexdigest(), name
        assert cols[1] and cols[4], f"{name}: no source or licence"  # every file names where it came from
        if name.endswith(".gz"):  # the upstream checksum is that of the published (decompressed) bytes
            published = gzip.decompress(data)
            assert cols[7] == "gzip -9"
            assert cols[6].strip("`") == hashlib.sha256(published).hexdigest(), name
            assert int(cols[5]) == len(published), name
        elif cols[7] == "copied":
            assert cols[6].strip("`") == hashlib.sha256(data).hexdigest(), name


def test_the_test_data_stays_small():
    total = sum(p.stat().st_size for p in (REPO / "tests" / "data").rglob("*") if p.is_file())
    assert total < 4_000_000, f"tests/data holds {total / 1e6:.1f} MB"


def _outside_data():
    sys.path.insert(0, str(REPO / "tools"))
    try:
        import outside_data
    finally:
        sys.path.pop(0)
    return outside_data


def test_nothing_reads_the_shared_folder_beside_the_repository():
    """No file of tests/, benchmarks/, docs/ or .ci/ (nor the root conftest) names the developers' folder
    beside the repository (``tools/outside_data.py``): the suite, the benchmarks and the docs build must
    run on a clone alone."""
    tool = _outside_data()
    names = tool.tracked(REPO)
    assert "tests/test_data_manifest.py" in names and len(names) > 100  # the search sees the tree
    assert tool.offenders(REPO, names) == []


def test_the_search_finds_a_line_naming_the_folder():
    """The check can fail: the tool's own source names the folder (in its docstring and pattern)."""
    assert _outside_data().offenders(REPO, ["tools/outside_data.py"])
