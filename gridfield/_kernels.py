"""The one loader of the compiled kernels (``gridfield/_kernels_*.pyx``, built by ``setup.py``).

Every module that runs a kernel lazily gets it from :func:`kernels` (imported on first use, then
the same module object), so importing gridfield costs no extension import and a missing build is
one clear error naming the module and how to build it.

Examples
--------
>>> kernels("navfn") is kernels("navfn")
True
>>> kernels("nothing")
Traceback (most recent call last):
...
ValueError: no compiled kernel module 'nothing'; the kernels are: anyangle, brushfire, chunked, eikonal, follow, incremental, navfn, navigation, polyanya, potential
"""

from __future__ import annotations

import functools
import importlib
from types import ModuleType

__all__ = ["KERNEL_MODULES", "kernels"]

#: The kernel modules, ``gridfield._kernels_<name>``.
KERNEL_MODULES: tuple[str, ...] = ("anyangle", "brushfire", "chunked", "eikonal", "follow", "incremental", "navfn",
                                   "navigation", "polyanya", "potential")


@functools.cache
def kernels(name: str) -> ModuleType:
    """The compiled kernel module ``gridfield._kernels_<name>``, imported on first use.

    Parameters
    ----------
    name : str
        One of :data:`KERNEL_MODULES`.

    Returns
    -------
    module
        The extension module (the same object on every call).

    Raises
    ------
    ValueError
        For a name that is no kernel module.
    ImportError
        When the extension is not built (the message says how to build it).

    Examples
    --------
    >>> hasattr(kernels("follow"), "_force_many")
    True
    """
    if name not in KERNEL_MODULES:
        raise ValueError(f"no compiled kernel module {name!r}; the kernels are: {', '.join(KERNEL_MODULES)}")
    try:
        return importlib.import_module(f"{__package__}._kernels_{name}")
    except ImportError as e:
        raise ImportError(f"the compiled kernels gridfield._kernels_{name} are not built ({e}); build them with "
                          "`python setup.py build_ext --inplace` (or `pip install -e .`)") from e
