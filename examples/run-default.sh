#!/usr/bin/env bash
# The main job (the README's first command): install, build, then run the pipeline
# on the embedded default volume, Debian's Colin27 T1 MRI, and say where each output is.
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/install-deps.sh
bash .ci/build.sh
# gvr, its library (find_package(gvr)) and the Python module (import gvr) under /usr/local.
cmake --install build > /dev/null

input=/usr/share/mricron/templates/ch2.nii.gz
gvr=build/cli/gvr
mkdir -p out
echo "== gvr ingest $input -o out/ch2.vdb"
$gvr ingest "$input" -o out/ch2.vdb
echo
echo "== gvr fit out/ch2.vdb -o out/ch2.gvr --ratio 10 --time 60 --log out/ch2-fit.csv"
$gvr fit out/ch2.vdb -o out/ch2.gvr --ratio 10 --time 60 --log out/ch2-fit.csv
echo
echo "== gvr info out/ch2.gvr"
$gvr info out/ch2.gvr
echo
echo "== gvr export out/ch2.gvr -o out/ch2-reconstruction.vdb -o out/ch2-reconstruction.nii.gz"
$gvr export out/ch2.gvr -o out/ch2-reconstruction.vdb -o out/ch2-reconstruction.nii.gz
echo
echo "== gvr eval out/ch2.vdb out/ch2-reconstruction.vdb"
$gvr eval out/ch2.vdb out/ch2-reconstruction.vdb
echo
echo "== gvr render out/ch2.gvr -o out/ch2-render.png --stats out/ch2-render.json"
$gvr render out/ch2.gvr -o out/ch2-render.png --stats out/ch2-render.json
echo
echo "Outputs:"
echo "  sparse grid:         $(pwd)/out/ch2.vdb                  (Blender/Houdini; gvr info out/ch2.vdb)"
echo "  Gaussian asset:      $(pwd)/out/ch2.gvr                  (gvr info out/ch2.gvr)"
echo "  error against time:  $(pwd)/out/ch2-fit.csv"
echo "  reconstruction:      $(pwd)/out/ch2-reconstruction.vdb   (open in Blender or Houdini)"
echo "  reconstruction NIfTI: $(pwd)/out/ch2-reconstruction.nii.gz"
echo "  rendered view:       $(pwd)/out/ch2-render.png           (shear-warp from the Gaussians)"
echo "  render timings:      $(pwd)/out/ch2-render.json"
echo "Installed: /usr/local/bin/gvr, find_package(gvr) from /usr/local/lib/cmake/gvr, and"
echo "  /usr/bin/python3 -c 'import gvr' (examples/quickstart.py is the same pipeline from Python)"
echo "Look around (on a desktop, or under xvfb-run): gvr view $(pwd)/out/ch2.gvr"
