#!/usr/bin/env bash
# Installs every Debian 12 package Holovox needs to build, test, benchmark and run.
# Idempotent: packages already present are skipped by apt. Works as root or through sudo.
set -euo pipefail

PACKAGES=(
  # toolchain
  build-essential cmake ninja-build ccache pkg-config git clang clang-format clang-tidy
  libclang-rt-14-dev time file dpkg-dev openssl bc strace
  # core
  libglm-dev libzstd-dev liblz4-dev libxxhash-dev libopenexr-dev libpng-dev zlib1g-dev
  libvtk9-dev
  # dicom
  libdcmtk-dev dcmtk libssl-dev libopenjp2-7-dev libsqlite3-dev sqlite3 nlohmann-json3-dev libcurl4-openssl-dev
  # render
  libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri mesa-utils
  # ui
  qt6-base-dev qt6-base-dev-tools libqt6opengl6-dev libqt6openglwidgets6 qt6-qpa-plugins
  xvfb xauth libxkbcommon-x11-0
  # distributed light-field views
  libopenmpi-dev openmpi-bin
  # tests, peers and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev openexr orthanc orthanc-dicomweb dcm2niix python3-pydicom python3-nibabel python3-vtk9 dicom3tools mricron-data teem-apps
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: run as root or install sudo" >&2; exit 1; }
  SUDO="sudo"
fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
# Debian's Orthanc package starts a system service on 4242/8042; Holovox runs its own instances.
if command -v systemctl >/dev/null && systemctl is-active --quiet orthanc 2>/dev/null; then
  $SUDO systemctl stop orthanc || true
fi
echo "install-deps: done"
