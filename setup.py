"""Build of gridfield's compiled kernels (Cython, ahead of time); the metadata is in pyproject.toml.

Each kernel lives beside the module that calls it (``gridfield/distance/_brushfire.pyx`` next to
``gridfield/distance/brushfire.py``, as scikit-image keeps ``_skeletonize_cy.pyx`` beside its caller).
Adding one is a line in ``KERNELS`` below (its dotted module name; ``OPENMP`` too if it uses ``prange``).
See "Building the kernels" in benchmarks/README.md.
"""

from pathlib import Path

from Cython.Build import cythonize
from setuptools import Extension, setup

#: The compiled modules, by dotted name: gridfield/<path>.pyx each.
KERNELS = [
    "gridfield.distance._brushfire", "gridfield.distance._chamfer", "gridfield.distance._edt",
    "gridfield.distance._incremental", "gridfield.distance._incremental3", "gridfield.distance._edt3",
    "gridfield.chunked._chunked",
    "gridfield.fields._potential", "gridfield.fields._navfn", "gridfield.fields._navigation",
    "gridfield.fields._navigation3", "gridfield.fields._voxelpath",
    "gridfield.fields._laplace", "gridfield.fields._eikonal", "gridfield.fields._samplers",
    "gridfield.exact._anyangle", "gridfield.exact._occlusion", "gridfield.exact._astar",
    "gridfield.exact._polyanya", "gridfield.following._taut",
]
#: Those with OpenMP loops (``prange``).
OPENMP = {"gridfield.fields._potential"}

# -O3 vectorizes the branch-free loops; no -ffast-math and no contraction into FMA, so that the
# results are bit-identical to the reference arithmetic; -fno-math-errno and -fno-trapping-math (no
# errno, no FP traps: neither changes a result) let sqrt and selects between divisions vectorize.
# setuptools puts Python's own CFLAGS first (sysconfig: -DNDEBUG -g -fwrapv -O3 -Wall here), for a
# wheel (pip wheel ., build isolation) as for build_ext --inplace: what is measured is what ships.
# No -march: a wheel must run on any x86-64; the hot row loops pick their ISA at load time instead
# (target_clones in _potential_rows.h and _brushfire_rows.h).
_CFLAGS = ["-O3", "-ffp-contract=off", "-fno-math-errno", "-fno-trapping-math"]


def _extension(name: str) -> Extension:
    omp = ["-fopenmp"] if name in OPENMP else []
    source = Path(*name.split(".")).with_suffix(".pyx")
    here = source.parent
    # the C row loops: _brushfire_rows.h (the distance transforms) and _potential_rows.h (the potential's rows,
    # also run by the incremental and chunked kernels on their windows and blocks)
    headers = [Path("gridfield/distance"), Path("gridfield/fields")]
    return Extension(name, [str(source)], include_dirs=[str(here), *map(str, headers)],
                     depends=[str(h) for d in headers for h in sorted(d.glob("*.h"))] + [str(p) for p in sorted(here.glob("*.pxd"))],
                     extra_compile_args=_CFLAGS + omp,
                     extra_link_args=omp, define_macros=[("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")])


setup(ext_modules=cythonize([_extension(n) for n in KERNELS], language_level=3,
                            compiler_directives={"boundscheck": False, "wraparound": False, "cdivision": True,
                                                 "initializedcheck": False}))
