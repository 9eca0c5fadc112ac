#!/usr/bin/env bash
# How well `gvr fit --time S` keeps its budget on every shared volume: one line a
# fit, with the seconds after reading the input against S, the phases, the work
# done and the PSNR. Builds given side by side alternate, volume by volume. The
# table of docs/benchmarks.md, "The time budget". Nothing is asserted. Run it with
# nothing else on the machine.
#
# Usage: bench/time_budget.sh SECONDS RATIO DATA_DIR GVR [GVR...]
#   DATA_DIR: ../shared/data (each volume is ingested once, by the last GVR)
set -euo pipefail
if [ $# -lt 4 ]; then
    sed -n '8,9p' "$0" >&2
    exit 2
fi
seconds=$1 ratio=$2 data=$(realpath "$3")
shift 3
builds=()
for gvr in "$@"; do builds+=("$(realpath "$gvr")"); done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
volumes=(ct-chest-ricord-512 ct-head-visible-human-png ct-gantry-tilt-shear/shear.nii.gz
         mri-colin27-aal/ch2.nii.gz mri-freesurfer-norm-aparc/norm.mgz mri-4d-asl-float32/mpld_asl.nii.gz
         rgb24-ct-perfusion/ct_perfusion.nii.gz rgb-brainmaps54-cryosection rgb-frog-cryosection/color_png)
for volume in "${volumes[@]}"; do
    grid="$work/$(echo "$volume" | tr '/' '_').vdb"
    "${builds[-1]}" ingest -q "$data/$volume" -o "$grid" >/dev/null
    for gvr in "${builds[@]}"; do
        "$gvr" fit -q "$grid" -o "$work/fit.gvr" --ratio "$ratio" --time "$seconds" --json >"$work/fit.json" 2>/dev/null
        python3 - "$volume" "$gvr" "$seconds" "$work/fit.json" <<'PY'
import json, sys
volume, gvr, budget, path = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
fit = json.load(open(path))
phases = fit["phase_seconds"]
after = phases["total"] - phases["load"]
solve = fit["amplitude_solve"]
solved = "skipped" if solve.get("skipped") else "%d its" % solve["iterations"]
print(f"{volume} | {gvr} | {after:.1f} s ({100 * (after / budget - 1):+.1f} %) | fit {phases['fit']:.1f}, "
      f"write {phases['write']:.2f}, measure {phases['measure']:.1f} s | {fit['iterations']} its, "
      f"{fit['voxel_samples_per_second'] / 1e6:.2f} M samples/s | {fit['ratio_vs_raw']:.2f}:1 | "
      f"{fit['psnr_db']:.2f} dB | solve {solved}", flush=True)
PY
    done
done
