#!/usr/bin/env bash
# Installs everything gvr needs to build, run and test, from Debian 12 packages. Run as root.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends \
  cmake ninja-build g++ pkg-config \
  libopenvdb-dev libboost-iostreams-dev libtbb-dev libblosc-dev zlib1g-dev libeigen3-dev \
  libopenimageio-dev libembree-dev libgtest-dev libnifti2-dev libgdcm-dev libcli11-dev \
  nlohmann-json3-dev libtomlplusplus-dev libzfp-dev libvolpack1-dev \
  mricron-data \
  python3 python3-openvdb python3-numpy python3-nibabel python3-skimage python3-pil python3-matplotlib \
  blender \
  > /dev/null
