#!/usr/bin/env bash
# gvr fit --max-error on shared volumes, one Markdown row a volume: the whole
# asset's ratio and size, the Gaussians' own ratio, the voxels stored exactly, the
# largest error read back by nibabel from the NIfTI export (float64, against the
# source as read), the layer's encode time, and ZFP fixed-accuracy's ratio at the
# same tolerance (gvr baseline). The table of docs/benchmarks.md, "An error bound".
# Nothing is asserted; run it with nothing else on the machine.
#
# Usage: bench/error_bound.sh GVR DATA_DIR WORK_DIR
set -euo pipefail
if [ $# -ne 3 ]; then sed -n '9p' "$0" >&2; exit 2; fi
G=$(realpath "$1"); D=$(realpath "$2"); W=$3; mkdir -p "$W"; cd "$W"
row() {  # name source reference.nii.gz bound ratio seconds
    local name=$1 src=$2 ref=$3 E=$4 R=$5 T=$6
    $G fit -q "$src" -o $name.gvr --ratio $R --time $T --max-error $E --json > $name.json 2>/dev/null
    $G export -q $name.gvr -o $name.nii.gz >/dev/null 2>&1
    $G baseline -q "$src" --method zfp-accuracy --tolerance $E --stream $name.zfp -o $name-zfp.vdb >/dev/null 2>&1 || true
    /usr/bin/python3 - "$name" "$ref" "$E" <<'PY'
import json, os, sys
import nibabel as nb, numpy as np
name, ref, E = sys.argv[1], sys.argv[2], float(sys.argv[3])
j = json.load(open(name + ".json")); L = j["residual_layer"]
a = nb.load(ref).get_fdata(dtype=np.float64); b = nb.load(name + ".nii.gz").get_fdata(dtype=np.float64)
a = a.reshape(b.shape)
raw = j["raw_source_bytes"]; zfp = os.path.getsize(name + ".zfp") if os.path.exists(name + ".zfp") else 0
print(f"| {name} | {E:g} | {raw/j['file_bytes']:.2f}:1 ({j['file_bytes']/2**20:.2f} MiB) | "
      f"{raw/L['gaussian_bytes']:.1f}:1 | {L['exact_voxels']} | {np.abs(a-b).max():g} | "
      f"{L['seconds']:.1f} s | " + (f"{raw/zfp:.2f}:1 |" if zfp else "- |"), flush=True)
PY
}
$G ingest -q $D/ct-chest-ricord-512 --threshold -5000 -o chest-asread.nii.gz >/dev/null 2>&1
row ch2 $D/mri-colin27-aal/ch2.nii.gz $D/mri-colin27-aal/ch2.nii.gz 4 40 20
row ch2-lossless $D/mri-colin27-aal/ch2.nii.gz $D/mri-colin27-aal/ch2.nii.gz 0.5 40 20
row chest $D/ct-chest-ricord-512 chest-asread.nii.gz 1 40 40
