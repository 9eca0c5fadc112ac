#!/usr/bin/env bash
# Refactoring check: two gvr builds (say the commit before, copied aside, and this one)
# make the same bytes from the same fixed-iteration work. Runs every command on the
# shared Colin27 MRI and colour perfusion volumes: fits (full, A3, RGB, bounds over a grid and a source,
# by structure, in bricks), exports, renders (shear-warp stills, an orbit, segments, the
# ray marcher, structures hidden, a bounded asset, a grid), downsampling baselines,
# eval and probe, then compares each output (.vdb files past their header's random UUID).
# Usage: .ci/same-outputs.sh GVR_BEFORE GVR_AFTER [WORK]   (about 5 minutes on 2 cores)
set -euo pipefail
[ $# -ge 2 ] || { sed -n 2,8p "$0"; exit 2; }
data=$(cd "$(dirname "$0")/../../shared/data" && pwd)
work=${3:-$(mktemp -d)}

outputs() {
  local gvr=$1 out=$2 ch2=$data/mri-colin27-aal/ch2.nii.gz rgb=$data/rgb24-ct-perfusion/ct_perfusion.nii.gz
  mkdir -p "$out" && cd "$out"
  "$gvr" ingest "$ch2" -o ch2.vdb > /dev/null
  "$gvr" fit ch2.vdb -o a.gvr --iterations 40 -q > /dev/null
  "$gvr" fit ch2.vdb -o a3.gvr --iterations 20 --ablation A3 -q > /dev/null
  "$gvr" fit "$rgb" -o rgb.gvr --iterations 20 -q > /dev/null
  "$gvr" fit ch2.vdb -o bound.gvr --iterations 10 --max-error 1% -q > /dev/null
  "$gvr" fit "$ch2" -o bound-source.gvr --iterations 10 --max-error 2 -q > /dev/null
  "$gvr" fit "$ch2" -o lab.gvr --iterations 10 --labels all --label-volume "$data/mri-colin27-aal/aal.nii.gz" \
    --label-names "$data/mri-colin27-aal/aal.nii.txt" -q > /dev/null
  "$gvr" fit ch2.vdb -o bricks.gvr --iterations 10 --bricks 3 -q > /dev/null
  for asset in a rgb bound; do "$gvr" export $asset.gvr -o $asset.vdb > /dev/null; done
  "$gvr" render a.gvr -o a.png -q > /dev/null
  "$gvr" render a.gvr -o a-segments.png --azimuth 100 --elevation 40 --classify segments -q > /dev/null
  "$gvr" render a.gvr -o orbit.png --orbit 3 --size 128x96 -q > /dev/null
  "$gvr" render a.gvr -o marched.png --renderer raymarch --size 128x128 -q > /dev/null
  "$gvr" render rgb.gvr -o rgb.png -q > /dev/null
  "$gvr" render lab.gvr -o lab.png --hide 1,2 -q > /dev/null
  "$gvr" render bound.gvr -o bound.png -q > /dev/null
  "$gvr" render ch2.vdb -o grid.png -q > /dev/null
  for factor in 2 3; do
    "$gvr" baseline ch2.vdb --method downsample --factor $factor -o ds$factor.vdb --stream ds$factor-stream.vdb > /dev/null
  done
  "$gvr" baseline "$rgb" --method downsample --factor 2 -o rgb-ds2.vdb --stream rgb-ds2-stream.vdb > /dev/null
  "$gvr" eval a.vdb ch2.vdb --json | grep -v seconds > eval.json
  "$gvr" eval rgb.vdb "$rgb" --json | grep -v seconds > eval-rgb.json
  for asset in a bound; do "$gvr" probe $asset.gvr --index 60,70,50 --index 90.5,100.25,80 --json > probe-$asset.json; done
}

(outputs "$(realpath "$1")" "$work/before")
(outputs "$(realpath "$2")" "$work/after")
differ=0
for file in "$work"/before/*; do
  name=$(basename "$file")
  skip=0; [[ $name == *.vdb ]] && skip=60
  cmp -s -i $skip "$file" "$work/after/$name" || { echo "differs: $name"; differ=1; }
done
[ $differ = 0 ] && echo "same-outputs: all $(ls "$work/before" | wc -l) outputs byte-identical ($work)"
exit $differ
