"""YAML files: the safe parser with its alias-bomb guard, and world YAML files.

PyYAML follows aliases while it builds a document, so a small file can expand to billions of values;
:func:`read_yaml` sizes the node graph first (:data:`YAML_EXPANDED_LIMIT`) and builds nothing larger.
ROS map YAML files are read through the same parser (:mod:`gridfield.io._ros`).
"""

from __future__ import annotations

from pathlib import Path as FsPath
from typing import Any

import yaml

from ..core.errors import MapFormatError, shorten
from ..geometry.world import World, world_from_dict
from ._common import PathLike, _check_file

#: A YAML document may expand (aliases followed) to at most this many values, and at most
#: this many times its own number of values: more is an alias bomb, refused before it is built.
YAML_EXPANDED_LIMIT = 10**6


def _check_yaml_size(p: FsPath, root: Any) -> None:
    """Refuse a YAML node graph whose aliases expand beyond :data:`YAML_EXPANDED_LIMIT` values."""
    sizes: dict[int, int] = {}
    order: list[Any] = []
    stack = [root]
    while stack:  # distinct nodes, depth first; children before parents in `order` reversed
        node = stack.pop()
        if id(node) in sizes:
            continue
        sizes[id(node)] = 0
        order.append(node)
        if isinstance(node, yaml.SequenceNode):
            stack.extend(node.value)
        elif isinstance(node, yaml.MappingNode):
            stack.extend(n for pair in node.value for n in pair)
    for node in reversed(order):
        if isinstance(node, yaml.SequenceNode):
            total = 1 + sum(sizes[id(n)] for n in node.value)
        elif isinstance(node, yaml.MappingNode):
            total = 1 + sum(sizes[id(n)] for pair in node.value for n in pair)
        else:
            total = 1
        sizes[id(node)] = total
    expanded = sizes[id(root)]
    if expanded > max(YAML_EXPANDED_LIMIT, 10 * len(order)) and expanded > len(order):
        raise MapFormatError(
            f"{p}: YAML aliases expand its {len(order)} values to {expanded:.3g}; refused (more than "
            f"{YAML_EXPANDED_LIMIT:g} values after expansion, an alias bomb?)"
        )


def read_yaml(path: PathLike) -> Any:
    """Parse a YAML file, raising :class:`MapFormatError` with the file and line on bad syntax.

    Aliases are followed only up to :data:`YAML_EXPANDED_LIMIT` values (an alias bomb is refused before
    it is built); an empty file is an error.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    object
        The document as PyYAML's safe loader builds it (dicts, lists, strings, numbers).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     f = pathlib.Path(d) / "a.yaml"
    ...     _ = f.write_text("bounds: [0, 0, 4, 3]\\nresolution: 0.5\\n")
    ...     read_yaml(f)
    {'bounds': [0, 0, 4, 3], 'resolution': 0.5}
    """
    p = _check_file(path)
    try:
        text = p.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise MapFormatError(f"{p}: not a text (UTF-8) YAML file") from None
    except OSError as e:
        raise MapFormatError(f"{p}: cannot read: {e.strerror}") from None
    try:
        loader = yaml.SafeLoader(text)
        try:
            node = loader.get_single_node()
            if node is not None:
                _check_yaml_size(p, node)
            data = loader.construct_document(node) if node is not None else None
        finally:
            loader.dispose()
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f" line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(e, "problem", None) or str(e).splitlines()[0]
        raise MapFormatError(f"{p}:{where}: invalid YAML: {shorten(problem)}") from None
    except RecursionError:
        raise MapFormatError(f"{p}: invalid YAML: nested too deeply") from None
    if data is None:
        raise MapFormatError(f"{p}: the file is empty")
    return data


def read_world(path: PathLike) -> World:
    """Read a world YAML file (see :func:`gridfield.geometry.world.world_from_dict` for the keys).

    Parameters
    ----------
    path : str or path-like
        A world YAML file (``bounds``, ``obstacles``, optional ``start``, ``goal``, ``robot``, ...).

    Returns
    -------
    World
        Its ``source`` is ``str(path)``.

    Examples
    --------
    >>> from gridfield.io import bundled_map
    >>> w = read_world(bundled_map("seed000.yaml"))
    >>> [ob.id for ob in w.obstacles], w.start, w.goal
    ([1, 2, 3], (1.0, 10.0), (22.0, 12.0))
    """
    data = read_yaml(path)
    return world_from_dict(data, source=str(path))
