"""Maps larger than one machine: the brushfire and its fields on ``dask.array`` chunks (issue 27).

Every function takes and returns lazy ``dask.array`` arrays; nothing is computed until the caller asks
(``.compute()``, ``.to_zarr()``, ``dask.compute``), on whatever scheduler is active (a
``distributed.Client`` for a cluster). The per-block work runs gridfield's compiled kernels, and the results
are bit-identical to the in-memory functions on the whole array. Dask is imported lazily (the ``[dask]``
extra): importing this package does not import it.

- :func:`distance`: the Euclidean, chessboard or taxicab distance with the nearest obstacle (exact for any
  distance: a rechunk between the column and the row pass), or saturated with a halo only.
- :func:`scratch_dir`: a directory (or an object store's URL prefix, for workers that share no disk) for
  the temporary store between :func:`distance`'s and :func:`gvd`'s passes (``scratch=``), removed on exit,
  also on error.
- :func:`field`: the classic (khatib) potential and its gradient chunk by chunk, from the nearest cells.
- :func:`gvd`: the Euclidean distance, the label of each cell's nearest obstacle and the GVD (two gathers
  along the separable passes, then a one-cell halo).
- :func:`labels`: the 8-connected obstacle components across chunks, numbered as the in-memory labels.
- :func:`wavefront`: the grid navigation function (octile or unit), exact, by rounds of tile-wise Dijkstra
  with boundary exchange until no chunk changes (it computes: each round is persisted and compared).
- :func:`nf1_octile_field`: the complete model nf1 with the octile wavefront as its potential, and its gradient.
- :func:`connect`: a ``distributed.Client``, or one clear error when the scheduler cannot be reached.

Its names load on first use (``lazy_loader``; ``__init__.pyi`` lists them), so that the compiled kernel
beside the modules (``_chunked.pyx``) and the modules themselves import nothing of this ``__init__``.
"""

import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach_stub(__name__, __file__)
