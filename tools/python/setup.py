# SPDX-License-Identifier: MIT
"""Build the sfit Python package: a CPython extension compiled from the
library's own sources (../../lib/src, ../../lib/include, ../../port/host)
and the host library (../../tools/formats, ../../tools/lab: the C3D reader
and writer, the session, the label-swap check), with no copy. Needs
Debian 12's python3-dev, python3-numpy and python3-setuptools only (no
network).

    /usr/bin/python3 -m pip install --user --break-system-packages \\
        --no-build-isolation --no-deps ./tools/python
or, without pip, build in place and put tools/python on PYTHONPATH:
    cd tools/python && /usr/bin/python3 setup.py build_ext --inplace
"""
import glob
import os
import re

import numpy
from setuptools import Extension, setup

HERE = os.path.dirname(os.path.abspath(__file__))
os.chdir(HERE)  # setuptools wants paths relative to setup.py
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
LIB_SRC = os.path.join(ROOT, "lib", "src")
LIB_INC = os.path.join(ROOT, "lib", "include")
PORT = os.path.join(ROOT, "port")
PORT_HOST = os.path.join(PORT, "host")
FORMATS = os.path.join(ROOT, "tools", "formats")  # the host library (tools/README.md): bytes <-> structs
LAB = os.path.join(ROOT, "tools", "lab")  # and computations on loaded trajectories

if not os.path.isfile(os.path.join(LIB_INC, "sfit", "sfit.h")):
    raise SystemExit("sfit: lib/include not found at %s (build from a full sfit checkout)" % LIB_INC)


def _version():
    with open(os.path.join(LIB_INC, "sfit", "sfit.h"), encoding="utf-8") as f:
        text = f.read()
    parts = [re.search(r"#define SFIT_VERSION_%s (\d+)" % k, text).group(1)
             for k in ("MAJOR", "MINOR", "PATCH")]
    return ".".join(parts)


# Absolute paths: the objects of ../../lib/src go under build/temp.*/<abs path>,
# never next to the sources.
lib_sources = sorted(glob.glob(os.path.join(LIB_SRC, "*.c")))
# The host library the CLI links (tools/CMakeLists.txt, sfit_host): every
# source of tools/formats and tools/lab but the skeleton's (not bound; its
# page needs a header the CMake build generates).
host_sources = sorted(f for d in (FORMATS, LAB) for f in glob.glob(os.path.join(d, "*.c"))
                      if not os.path.basename(f).startswith("skel_"))
ext = Extension(
    "sfit._sfit",
    # the binding: every tools/python/src/py_*.c (py_module.c registers them)
    sources=sorted(glob.glob(os.path.join(HERE, "src", "py_*.c")))
    # the host library it binds: the C3D reader and writer, the session,
    # the label-swap check
    + host_sources
    + lib_sources,
    include_dirs=[LIB_INC, LIB_SRC, PORT, PORT_HOST, FORMATS, LAB, numpy.get_include()],
    # C99 like the library; -fno-math-errno as on target (sqrtf inline), no fast-math
    extra_compile_args=["-std=c99", "-O2", "-fno-math-errno", "-Wall", "-Wextra"],
    define_macros=[("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")],
    libraries=["m"],
)

setup(
    name="sfit",
    version=_version(),
    description="Sphere and circle fitting (GDKE/UGDK): the sfit C library for numpy",
    license="MIT",
    packages=["sfit"],
    package_data={"sfit": ["__init__.pyi", "py.typed"]},
    ext_modules=[ext],
    python_requires=">=3.9",
    install_requires=["numpy"],
    zip_safe=False,
)
