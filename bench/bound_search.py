#!/usr/bin/python3
"""gvr fit --ratio R --max-error auto: the bound the search reaches, its cost, and the bound checked.

For each volume of bench/error_bound.py, the whole asset asked to fit R: the ratio written, the bound
reached, how many layers the search encoded and the layer's seconds (the search included), and the
export's maximum error read back by nibabel in float64 against the source as read. Nothing is
asserted; run it with nothing else on the machine.

Usage: bench/bound_search.py GVR DATA_DIR WORK_DIR [NAME ...]"""
import json, os, subprocess, sys
import numpy as np

from error_bound import VOLUMES, fit_flags, run, voxels

# name: the ratio asked of the whole asset, near what error_bound.py's bound gives
RATIOS = {"ch2": 10, "colin27-labels": 10, "freesurfer-norm": 50, "ct-head": 80, "chest": 4, "gantry-tilt": 10,
          "brainmaps54": 20, "frog": 5, "ct-perfusion": 8, "asl": 11}


def row(gvr, data, work, name):
    src, _, seconds, flags = VOLUMES[name]
    src = os.path.join(data, src)
    ref, asset, export = (f"{work}/{name}{ext}" for ext in ("-asread.nii.gz", "-auto.gvr", "-auto.nii.gz"))
    run(gvr, "ingest", "-q", src, "--threshold", "-1e9", "-o", ref)
    fit = subprocess.run([gvr, "fit", "-q", src, "-o", asset, "--time", str(seconds), "--ratio", str(RATIOS[name]),
                          "--max-error", "auto", "--json", *fit_flags(data, flags)], check=True, capture_output=True,
                         text=True)
    report = json.loads(fit.stdout)
    layer = report["residual_layer"]
    run(gvr, "export", "-q", asset, "-o", export)
    source = voxels(ref)
    error = float(np.abs(voxels(export).reshape(source.shape) - source).max())
    print(f"| {name} | {RATIOS[name]}:1 | {report['ratio_vs_raw']:.2f}:1 | {layer['max_error']:g} | "
          f"{layer['encodes']} | {layer['seconds']:.1f} s | {error:g} |", flush=True)


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__.split("\n\n")[-1])
    gvr, data, work = (os.path.realpath(a) for a in sys.argv[1:4])
    os.makedirs(work, exist_ok=True)
    print("| volume | asked | written | bound reached | layers encoded | layer seconds | max error (nibabel) |")
    print("|---|---|---|---|---|---|---|")
    for name in sys.argv[4:] or RATIOS:
        row(gvr, data, work, name)


if __name__ == "__main__":
    main()
