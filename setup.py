"""Build of gridfield's compiled kernels (Cython, ahead of time); the metadata is in pyproject.toml.

Adding a kernel module is one line: put ``gridfield/_kernels_NAME.pyx`` in the tree and its name in
``KERNELS`` below (``OPENMP`` too if it uses ``prange``). See "Building the kernels" in
benchmarks/README.md.
"""

from pathlib import Path

from Cython.Build import cythonize
from setuptools import Extension, setup

#: The compiled modules, gridfield/<name>.pyx each.
KERNELS = ["_kernels_anyangle", "_kernels_brushfire", "_kernels_chunked", "_kernels_eikonal", "_kernels_follow", "_kernels_incremental",
           "_kernels_navfn", "_kernels_navigation", "_kernels_polyanya", "_kernels_potential"]
#: Those with OpenMP loops (``prange``).
OPENMP = {"_kernels_potential"}

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
    return Extension(f"gridfield.{name}", [f"gridfield/{name}.pyx"], include_dirs=["gridfield"],
                     depends=[str(h) for h in sorted(Path("gridfield").glob("*.h")) + sorted(Path("gridfield").glob("*.pxd"))],
                     extra_compile_args=_CFLAGS + omp,
                     extra_link_args=omp, define_macros=[("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")])


setup(ext_modules=cythonize([_extension(n) for n in KERNELS], language_level=3,
                            compiler_directives={"boundscheck": False, "wraparound": False, "cdivision": True,
                                                 "initializedcheck": False}))
