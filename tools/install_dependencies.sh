#!/usr/bin/env bash
# Installs the Debian 12 packages this project needs, skipping those already present.
# deal.II 9.4.1 pulls in Trilinos 13.2 (Amesos2, Epetra, Tpetra), SuiteSparse (CHOLMOD),
# METIS, p4est and Open MPI. libfclib-dev writes FCLIB problems (Output/Write FCLIB problem).
# OpenBLAS replaces the reference BLAS: CHOLMOD's supernodal
# factorization is about 8x faster with it. numdiff compares test output with tolerances.
set -euo pipefail

packages=(
  build-essential cmake ninja-build
  libdeal.ii-dev
  libtrilinos-amesos2-dev libtrilinos-amesos-dev
  libsuitesparse-dev libmetis-dev
  openmpi-bin libopenmpi-dev
  libopenblas0-pthread libopenblas-pthread-dev
  numdiff
  libfclib-dev
  python3 python3-numpy python3-matplotlib
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_dependencies: all packages present"
  exit 0
fi

echo "install_dependencies: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install_dependencies: done"
