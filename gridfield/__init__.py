"""gridfield: grid-based robot path planning with brushfire distance maps and potential fields.

Pipeline (each stage one module, data flows one way)::

    io -> world / grid -> rasterize -> brushfire -> potential -> follow -> plot / compare

Heavy modules (matplotlib, scipy.ndimage, the compiled kernels) are imported only when used.
"""

from ._version import __version__
from .errors import GridfieldError, MapFormatError, ParameterError
from .grid import Grid, GridMap
from .path import Path

__all__ = ["Grid", "GridMap", "GridfieldError", "MapFormatError", "ParameterError", "Path", "__version__"]
