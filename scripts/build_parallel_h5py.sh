#!/usr/bin/env bash
# Build an MPI-enabled h5py (parallel HDF5, `driver="mpio"`) in its own virtual environment,
# from Debian's parallel HDF5 and the package registries only. The default .venv is untouched.
#
#   bash scripts/build_parallel_h5py.sh            # -> .venv-mpio (idempotent: skips done work)
#   MPIO_VENV=/opt/venv-mpio bash scripts/build_parallel_h5py.sh
#
# Then run the engine with Debian's mpiexec, matching the MPI the build linked against:
#
#   mpiexec.mpich -n 2 .venv-mpio/bin/python -m engine study.toml --output-strategy mpio
#
# Route: Debian packages mpich, libmpich-dev, libhdf5-mpich-dev, pkg-config; mpi4py and h5py
# from PyPI *source* distributions compiled with mpicc.mpich (HDF5_MPI=ON,
# HDF5_PKGCONFIG_NAME=hdf5-mpich, --no-build-isolation, setuptools >= 77). CFLAGS "-O1 -g0"
# keeps the compile short (the Cython-generated C is large; -O2 -g takes several times longer);
# these are thin wrappers, so -O1 costs nothing measurable at run time. The project itself is
# installed editable with --no-deps, plus its pure-Python/wheel dependencies read from
# pyproject.toml *minus* mpich, mpi4py and h5py (the PyPI mpich wheel would shadow Debian's MPI).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
VENV=${MPIO_VENV:-$ROOT/.venv-mpio}
PYTHON=${PYTHON:-python3}
MPICC=${MPICC:-mpicc.mpich}
H5PY_SPEC=${H5PY_SPEC:-h5py}
MPI4PY_SPEC=${MPI4PY_SPEC:-mpi4py}
export CFLAGS=${CFLAGS:-"-O1 -g0"}
APT_PACKAGES=(mpich libmpich-dev libhdf5-mpich-dev pkg-config)

say() { printf '[build_parallel_h5py] %s\n' "$*"; }
start=$SECONDS

# 1. Debian packages (only what is missing).
missing=()
for package in "${APT_PACKAGES[@]}"; do
    dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
done
if ((${#missing[@]})); then
    say "installing Debian packages: ${missing[*]}"
    SUDO=""
    [[ $(id -u) -ne 0 ]] && SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
        "${missing[@]}" >/dev/null
fi
command -v "$MPICC" >/dev/null || { say "error: $MPICC not found"; exit 1; }
pkg-config --exists hdf5-mpich || { say "error: pkg-config cannot find hdf5-mpich"; exit 1; }

# 2. The virtual environment and build tools.
[[ -x $VENV/bin/python ]] || { say "creating $VENV"; "$PYTHON" -m venv "$VENV"; }
PY=$VENV/bin/python
have() { "$PY" -c "$1" >/dev/null 2>&1; }
if ! have 'import setuptools, sys; sys.exit(int(setuptools.__version__.split(".")[0]) < 77)'; then
    say "installing build tools"
    "$PY" -m pip install --quiet --upgrade pip "setuptools>=77" wheel "cython>=3,<4" pkgconfig
fi

# 3. Runtime dependencies of the project from pyproject.toml, except MPI and HDF5 bindings.
mapfile -t deps < <("$PY" - "$ROOT/pyproject.toml" <<'EOF'
import re, sys, tomllib
project = tomllib.load(open(sys.argv[1], "rb"))["project"]
requirements = project["dependencies"] + project.get("optional-dependencies", {}).get("test", [])
for requirement in requirements:
    name = re.split(r"[\s<>=!~;\[]", requirement, maxsplit=1)[0].lower()
    if name not in {"mpich", "mpi4py", "h5py"}:
        print(requirement)
EOF
)
if ! have 'import numpy, scipy, pyfftw, pandas, tqdm, matplotlib, pytest'; then
    say "installing dependencies: ${deps[*]}"
    "$PY" -m pip install --quiet "${deps[@]}"
fi

# 4. mpi4py from source against Debian's MPICH.
if ! have 'from mpi4py import MPI; import sys; sys.exit("MPICH" not in MPI.Get_library_version())'
then
    say "building mpi4py with $MPICC (CFLAGS=$CFLAGS)"
    t=$SECONDS
    MPICC=$MPICC "$PY" -m pip install --quiet --no-build-isolation --no-binary mpi4py \
        --no-cache-dir "$MPI4PY_SPEC"
    say "mpi4py built in $((SECONDS - t)) s"
fi

# 5. h5py from source against Debian's parallel HDF5.
if ! have 'import h5py, sys; sys.exit(not h5py.get_config().mpi)'; then
    say "building h5py with HDF5_MPI=ON against hdf5-mpich (CFLAGS=$CFLAGS)"
    t=$SECONDS
    CC=$MPICC HDF5_MPI=ON HDF5_PKGCONFIG_NAME=hdf5-mpich \
        "$PY" -m pip install --quiet --no-build-isolation --no-binary h5py --no-cache-dir \
        --force-reinstall --no-deps "$H5PY_SPEC"
    say "h5py built in $((SECONDS - t)) s"
fi

# 6. The project itself, editable, without letting pip pull the PyPI MPI wheels.
if ! have "import engine, sys; sys.exit(not engine.__file__.startswith('$ROOT/'))"; then
    say "installing the project (editable, --no-deps)"
    "$PY" -m pip install --quiet --no-build-isolation --no-deps -e "$ROOT"
fi

# 7. Check: MPI-enabled h5py, Debian's MPICH, nothing from the PyPI mpich wheel.
"$PY" - <<'EOF'
import h5py
from mpi4py import MPI
assert h5py.get_config().mpi, "h5py is not MPI-enabled"
print("[build_parallel_h5py] ok: h5py", h5py.__version__, "HDF5", h5py.version.hdf5_version,
      "mpi=True;", MPI.Get_library_version().splitlines()[0])
EOF
say "environment $VENV ready in $((SECONDS - start)) s; run with mpiexec.mpich"
