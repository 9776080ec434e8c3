#!/usr/bin/env bash
# Installs softflow's build and run dependencies from Debian 12 packages.
# Idempotent; needs root (or sudo).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  petsc-dev            # PETSc 3.18 with MPI, MUMPS, hypre
  libhypre-dev         # hypre's headers: the velocity block is stored in its format
  libopenblas0-serial  # optimized BLAS/LAPACK: ~4x faster MUMPS than reference BLAS
  libgmsh-dev gmsh     # gmsh C++ API (meshing)
  libeigen3-dev libhdf5-dev
  libhdf5-openmpi-dev  # HDF5 checkpoints: the build PETSc links
  libcli11-dev libtoml11-dev nlohmann-json3-dev libfmt-dev libspdlog-dev
  libgtest-dev libbenchmark-dev
  openmpi-bin          # mpirun for the MPI tests
  python3 python3-numpy python3-matplotlib  # plots in docs/validation
  python3-scipy        # scripts/theory (Roscoe, tested: theory_roscoe_particle), bench/schur_spectrum.py
)

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
