# The public names of gridfield.chunked, for editors and type checkers; at run time __init__.py loads
# each on first use (lazy_loader.attach_stub reads this file).

from ._cluster import connect as connect
from ._distance import BORDERS as BORDERS
from ._distance import METRICS as METRICS
from ._distance import distance as distance
from ._distance import scratch_dir as scratch_dir
from ._field import field as field
from ._gvd import gvd as gvd
from ._labels import labels as labels
from ._wavefront import nf1_octile_field as nf1_octile_field
from ._wavefront import wavefront as wavefront

__all__ = ["BORDERS", "METRICS", "connect", "distance", "field", "gvd", "labels", "nf1_octile_field", "scratch_dir",
           "wavefront"]
