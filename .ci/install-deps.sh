#!/usr/bin/env bash
# Installs everything gvr needs to build, test, run its main job and its benchmarks:
# the Debian 12 packages below, and nothing else. Run as root. .ci/deps-audit reads
# this list and fails CI when the build or the tests use a file from a package
# outside its dependency closure.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
packages=(
  # Toolchain and the tools CI itself runs.
  cmake
  ninja-build
  g++
  pkg-config
  strace
  # The man page, made from gvr --help at build time.
  help2man
  # Loads the completion that cmake --install puts in share/bash-completion/completions
  # when an interactive bash starts; the completion test sources it directly.
  bash-completion
  # The layout check (tests/code_format.sh): every C++ file as .clang-format lays it out.
  clang-format
  # The sanitizer build and the libFuzzer targets (.ci/sanitize.sh).
  clang
  libclang-rt-14-dev
  # With clang, zfp's CMake config requires OpenMP for C (libomp), and CMake takes
  # llvm-ar, llvm-ranlib and ld.lld for its archiver, ranlib and linker entries.
  libomp-14-dev
  llvm
  lld

  # Libraries the build links.
  libopenvdb-dev
  # FindOpenVDB.cmake needs Boost iostreams although nothing declares it.
  libboost-iostreams-dev
  libtbb-dev
  libblosc-dev
  zlib1g-dev
  libeigen3-dev
  libopenimageio-dev
  # OpenImageIOTargets.cmake refuses to load unless /usr/bin/iconvert and the other tools exist.
  openimageio-tools
  libembree-dev
  libgtest-dev
  # GTestConfig.cmake includes GMockTargets.cmake.
  libgmock-dev
  libnifti2-dev
  libgdcm-dev
  libcli11-dev
  nlohmann-json3-dev
  libtomlplusplus-dev
  libzfp-dev
  libzstd-dev
  libvolpack1-dev
  # The gvr Python module (python/).
  pybind11-dev
  python3-pybind11
  python3-dev
  # gvr view: the window, its HUD text and font.
  libsdl2-dev
  libsdl2-ttf-dev
  fonts-dejavu-core
  # Bricked fitting across processes (gvr fit --bricks under mpirun).
  libopenmpi-dev
  openmpi-bin

  # The embedded default volume (Colin27 T1 MRI).
  mricron-data

  # Test clients and benchmark reports.
  python3
  python3-openvdb
  python3-numpy
  python3-nibabel
  python3-skimage
  python3-pil
  python3-matplotlib
  python3-pytest
  blender
  # bench/vtk_render.py: VTK's CPU ray caster, what 3D Slicer and ParaView fall back to without a GPU.
  python3-vtk9
  # gvr view's test drives the window on a virtual display.
  xvfb
  xauth
  xdotool
)
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${packages[@]}" > /dev/null
