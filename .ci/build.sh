#!/usr/bin/env bash
# Configures and builds gvr in ./build (Release). Two jobs: OpenVDB units are memory-hungry.
# Arguments go to the configure step: .ci/run passes -DGVR_WERROR=ON.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" > /dev/null
cmake --build build -j 2
