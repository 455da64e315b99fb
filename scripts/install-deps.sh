#!/usr/bin/env bash
# Installs everything wirefem needs on Debian 12 (bookworm). Safe to re-run:
# apt-get skips what is already installed.
set -euo pipefail
packages=(
  cmake g++ make pkg-config
  libdeal.ii-dev          # deal.II 9.4 with Trilinos, MPI, CGAL, GSL, UMFPACK, SUNDIALS
  libcgal-dev libeigen3-dev libgsl-dev
  libsuitesparse-dev      # KLU for the rod FEM's linear solves
  libcairo2-dev           # final.png / final.svg
  libcli11-dev nlohmann-json3-dev libfmt-dev
  libgtest-dev libbenchmark-dev
  openmpi-bin             # mpirun for parameter sweeps
  numdiff python3 python3-numpy python3-scipy python3-matplotlib python3-pil
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
