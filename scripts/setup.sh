#!/usr/bin/env bash
# Installs what warpmesh needs from Debian packages, if missing.  Idempotent:
# a second run installs nothing and needs no network.
set -euo pipefail

need=()
have_pkg() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
# The Python module and its tests (WARPMESH_PYTHON, scripts/build.sh): pybind11,
# the interpreter's headers, numpy, pytest, meshio (to_meshio), and dask's
# distributed scheduler (examples/batch_dask.py and its test).
# libhdf5-dev: the XDMF writer's .h5 heavy data (serial HDF5, warpmesh::io).
# libgmp-dev: the 3D checker warpmesh-check-bcc (exact arithmetic on
# 300-500-bit numbers).
for pkg in cmake g++ make libboost-dev libboost-test-dev libpng-dev zlib1g-dev libtiff-dev libhdf5-dev libgmp-dev pkg-config python3 \
           pybind11-dev python3-dev python3-numpy python3-pytest python3-meshio python3-distributed; do
  have_pkg "$pkg" || need+=("$pkg")
done
# The real-client tests (tests/python/, run by ctest with /usr/bin/python3):
# pytest and numpy; meshio (its XDMF reader imports h5py even for inline XML);
# gmsh's command line and Python API (also what dolfinx.io.gmshio uses);
# FEniCSx 0.5 for the round trips and the Poisson convergence test; CalculiX
# (an Abaqus-format solver) for the .inp; VTK's own Python reader for the binary
# and zlib .vtu (python3-vtk9); zarr for the chunked volumes of the dask
# partitioned run (examples/dask_partitioned3d.py).
for pkg in python3-pytest python3-numpy python3-meshio python3-h5py gmsh python3-gmsh python3-dolfinx calculix-ccx python3-vtk9 \
           python3-zarr; do
  have_pkg "$pkg" || need+=("$pkg")
done
# libgomp ships with g++ (OpenMP); Boost.Interval and Boost.Multiprecision are
# header-only parts of libboost-dev.

if ((${#need[@]})); then
  echo "setup: installing ${need[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}"
else
  echo "setup: all dependencies present"
fi
