#!/usr/bin/env bash
# Points against pre-integrated segments (`gvr render --classify`), one after the
# other: the table of docs/benchmarks.md, "Pre-integrated segments". Prints one line
# a row; nothing is asserted. Run it with nothing else on the machine.
#
# Usage: bench/classification_table.sh GVR CT_HEAD.vdb CHEST.vdb WORK_DIR
#   CT_HEAD.vdb: gvr ingest ../shared/data/ct-head-visible-human-png
#   CHEST.vdb:   gvr ingest ../shared/data/ct-chest-ricord-512
set -euo pipefail
if [ $# -ne 4 ]; then
    sed -n '6,8p' "$0" >&2
    exit 2
fi
gvr=$(realpath "$1") head=$(realpath "$2") chest=$(realpath "$3")
mkdir -p "$4" && cd "$4"
# Bands of the transfer function with steep edges: on ct-head's skin (8-bit values)
# and on the chest's lung and skin surfaces (HU).
echo '{"points": [[59, 1, 0.8, 0.6, 0], [60, 1, 0.8, 0.6, 0.6], [66, 1, 0.8, 0.6, 0.6], [67, 1, 0.8, 0.6, 0]]}' > band-head.json
echo '{"points": [[-521, 1, 0.7, 0.5, 0], [-520, 1, 0.7, 0.5, 0.6], [-490, 1, 0.7, 0.5, 0.6], [-489, 1, 0.7, 0.5, 0]]}' > band-chest.json

seen() { "$gvr" eval "$1" "$2" --json | python3 -c 'import json,sys; print("%.2f" % json.load(sys.stdin)["rendering"]["psnr"])'; }
# The mean build, and the median reused frame (composite and warp), of a --stats file.
times() {
    python3 - "$1" <<'PY'
import json, sys
frames = json.load(open(sys.argv[1]))["frames"]
builds = [f["build_ms"] for f in frames if not f["reused"]]
reused = sorted(f["composite_ms"] + f["warp_ms"] for f in frames if f["reused"])
print("build %.0f ms" % (sum(builds) / len(builds)) + ("; reused %.1f ms" % reused[len(reused) // 2] if reused else ""))
PY
}
# A still of each classification, scored against REFERENCE.
row() {  # NAME INPUT TF REFERENCE
    for classify in points segments; do
        "$gvr" render "$2" --tf "$3" --classify $classify -o "$1-$classify.exr" -q --stats "$1-$classify.json" >/dev/null
        echo "$1 $classify still: as seen $(seen "$4" "$1-$classify.exr") dB; $(times "$1-$classify.json")"
    done
}
# The anti-aliased ray marcher (4 x 4 rays a pixel, half a voxel a step) for presets;
# for bands, 2 x 2 rays a twentieth of a voxel a step, beside the former's own score.
for preset in "head $head mri" "bone $chest ct-bone" "ct $chest ct"; do
    set -- $preset
    "$gvr" render "$2" --tf "$3" --renderer raymarch --samples 4 -o "$1-ref.exr" -q >/dev/null
    row "$1" "$2" "$3" "$1-ref.exr"
done
for band in "hband $head band-head.json" "cband $chest band-chest.json"; do
    set -- $band
    "$gvr" render "$2" --tf "$3" --renderer raymarch --samples 2 --step 0.05 -o "$1-ref.exr" -q >/dev/null
    "$gvr" render "$2" --tf "$3" --renderer raymarch --samples 4 -o "$1-rm.exr" -q >/dev/null
    echo "$1 ray marcher, 4 x 4 rays at half a voxel: as seen $(seen "$1-ref.exr" "$1-rm.exr") dB"
    row "$1" "$2" "$3" "$1-ref.exr"
done
# Reused frames: orbits of 24 frames across the axes.
for orbit in "head $head mri" "ct $chest ct"; do
    set -- $orbit
    for classify in points segments; do
        "$gvr" render "$2" --tf "$3" --classify $classify --orbit 24 --stacks axes -o "orbit-$1-$classify.png" -q \
            --stats "orbit-$1-$classify.json" >/dev/null
        echo "orbit $1 $classify: $(times "orbit-$1-$classify.json")"
    done
done
