#!/usr/bin/env bash
# The project's test command (README "Install and the two commands"; CI runs exactly this
# through .ci/run). Needs root or sudo for apt-get (scripts/build_parallel_h5py.sh) and network
# access to PyPI and the Debian mirrors.
# From a fresh clone: creates .venv, installs the package with its test tools from PyPI
# (the `mpich` wheel provides mpiexec), lints, runs the serial tests, then the MPI tests,
# which run for real under `mpiexec -n 2`, then slurm/run_study.sbatch under a real SLURM.
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m venv .venv
.venv/bin/python -m pip install --quiet --upgrade pip
.venv/bin/python -m pip install --quiet -e '.[test]'
# The example plug-in package (a cone profile and a fatigue criterion registered through entry
# points): the conformance tests run it with the built-in plug-ins.
.venv/bin/python -m pip install --quiet -e examples/plugins
.venv/bin/ruff check engine tests benchmarks scripts
.venv/bin/ruff format --check engine tests benchmarks scripts
.venv/bin/python -m pytest tests --ignore=tests/mpi --ignore=tests/slurm -q
# The manual as one site (tests/test_docs.py builds it too, without writing pages).
.venv/bin/python -m sphinx -W --keep-going -n -b html docs build/site
# MPI tests: each test launches `mpiexec -n 2 python -m engine ...` (real ranks, real files,
# real signals), and the collective tests run the test module itself on two ranks.
.venv/bin/python -m pytest tests/mpi -q
# Second MPI run, for the collective (mpio) output strategy: an MPI-enabled h5py built from
# Debian's parallel HDF5 in .venv-mpio (idempotent; about 10 minutes on 2 cores the first
# time), with Debian's mpiexec matching that build. `auto` then writes collectively on 2
# ranks, so the whole MPI suite runs through the mpio writer, plus tests/mpi/test_mpio.py.
bash scripts/build_parallel_h5py.sh
ENGINE_MPIEXEC=mpiexec.mpich .venv-mpio/bin/python -m pytest tests/mpi -q
# SLURM phase: slurm/run_study.sbatch under a real single-node SLURM (slurm-wlm, munge) that
# tests/slurm starts as root in a temporary directory of its own (configuration, MUNGE key and
# socket, state, logs; free ports) and stops by PIDs at the end; the jobs run the engine from
# .venv-mpio (mpi4py on Debian's MPICH, which `srun --mpi=pmi2` connects). About 4 minutes.
# Without root the tests are skipped and say why. (On a machine run by systemd, installing
# munge also starts the system's munged; the tests do not use it.)
if [[ $(id -u) -eq 0 ]]; then
    missing=()
    for package in slurm-wlm munge; do
        dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
    done
    if ((${#missing[@]})); then
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
            -o DPkg::Lock::Timeout=600 "${missing[@]}" >/dev/null
    fi
fi
.venv/bin/python -m pytest tests/slurm -q -rs
