#!/usr/bin/env bash
# The main job (the README's first command): install, build, then run the pipeline
# on the embedded default volume, Debian's Colin27 T1 MRI, and say where each output is.
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/install-deps.sh
bash .ci/build.sh

input=/usr/share/mricron/templates/ch2.nii.gz
mkdir -p out
echo "== gvr info $input"
build/cli/gvr info "$input"
echo "== gvr ingest $input -o out/ch2.vdb"
build/cli/gvr ingest "$input" -o out/ch2.vdb
echo
echo "Outputs:"
echo "  sparse grid: $(pwd)/out/ch2.vdb   (open in Blender or Houdini; 'build/cli/gvr info out/ch2.vdb')"
