#!/usr/bin/env bash
# Installs the Debian 12 packages BoneMachining builds, tests and runs with.
# Idempotent and non-interactive: packages already present are skipped by apt.
set -euo pipefail
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
PKGS=(
  build-essential cmake ninja-build pkg-config git
  paraview paraview-dev python3-paraview libqt5opengl5-dev
  libinsighttoolkit5-dev libgdcm-dev libgdcm-tools libdcmtk-dev dicom3tools
  orthanc orthanc-dicomweb libcurl4-gnutls-dev python3-distributed
  libeigen3-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo
  qtbase5-dev libqt5charts5-dev libqt5svg5-dev qttools5-dev
  libopenmpi-dev libglew-dev libhdf5-openmpi-dev libhdf5-dev
  xvfb xauth xdotool imagemagick
  invesalius-examples
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup-debian: all ${#PKGS[@]} packages present"
  exit 0
fi
echo "setup-debian: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
