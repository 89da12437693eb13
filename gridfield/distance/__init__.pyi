# The public names of gridfield.distance, for editors and type checkers; at run time __init__.py
# loads each on first use (lazy_loader.attach_stub reads this file).

from . import brushfire as brushfire
from . import incremental as incremental
from .brushfire import BORDER_LABEL as BORDER_LABEL
from .brushfire import METRICS as METRICS
from .brushfire import DistanceMap as DistanceMap
from .incremental import ID_MAX as ID_MAX
from .incremental import IncrementalBrushfire as IncrementalBrushfire
from .incremental import Window as Window

__all__ = [
    "BORDER_LABEL",
    "ID_MAX",
    "METRICS",
    "DistanceMap",
    "IncrementalBrushfire",
    "Window",
    "brushfire",
    "incremental",
]
