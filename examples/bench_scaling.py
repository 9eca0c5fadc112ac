#!/usr/bin/python3
"""Scaling benchmark: does the fit's cost grow with the work, and no faster?

Fits ch2 (7.1 M voxels), ch2 resampled x1.5 per axis (24 M voxels, made here with
scipy and never stored in the repository) and ct-head (61 M voxels) at 10:1, each
for the same seconds per million voxels, and prints for each: Gaussians, iterations
per second, voxel samples per second, and held-out PSNR at fixed seconds per
million voxels. If the cost grew with the work alone, the samples per second would
match and the PSNR curves would coincide. Figures are printed, never asserted.

    /usr/bin/python3 examples/bench_scaling.py [--seconds-per-mvoxel S] [OUT_DIR]

Default S = 5 (about 8 minutes on 2 cores). Run from the project root after
.ci/build.sh; needs ../shared/data.
"""
import csv
import json
import os
import sys

import nibabel
import numpy
from scipy import ndimage

from benchlib import DATA, ROOT, run, volume_mib


def resampled_ch2(out):
    """ch2 at 1.5x the samples per axis (cubic), with the voxel size shrunk to match."""
    path = os.path.join(out, "ch2-x1.5.nii.gz")
    if not os.path.exists(path):
        source = nibabel.load(os.path.join(DATA, "mri-colin27-aal", "ch2.nii.gz"))
        data = numpy.asarray(source.dataobj, dtype=numpy.float32)
        bigger = numpy.clip(ndimage.zoom(data, 1.5, order=3), 0, 255).round().astype(numpy.uint8)
        affine = source.affine.copy()
        affine[:3, :3] /= 1.5
        nibabel.save(nibabel.Nifti1Image(bigger, affine), path)
    return path


def held_out_curve(log_path):
    """(seconds, held-out PSNR) rows of a fit log, the amplitude solve's last row included."""
    with open(log_path) as log:
        rows = list(csv.DictReader(line for line in log if not line.startswith("#")))
    return [(float(row["seconds"]), float(row["psnr_db"])) for row in rows if row["psnr_db"]]


def psnr_at(curve, seconds):
    before = [psnr for t, psnr in curve if t <= seconds]
    return before[-1] if before else float("nan")


def bench(name, source, checkpoints, out):
    """Fits @source for checkpoints[-1] seconds per million voxels."""
    grid = os.path.join(out, name + ".vdb")
    run(["ingest", "-q", source, "-o", grid])
    dims = volume_mib(grid)[1]
    mvoxels = dims[0] * dims[1] * dims[2] / 1e6
    log = os.path.join(out, name + ".csv")
    fit = json.loads(run(["fit", "-q", "--json", grid, "-o", os.path.join(out, name + ".gvr"), "--ratio", "10",
                          "--time", f"{checkpoints[-1] * mvoxels:.1f}", "--log", log]))
    curve = held_out_curve(log)
    adam_seconds = curve[-2][0]  # the last row is the amplitude solve's
    return {
        "name": name, "mvoxels": mvoxels, "seconds": fit["seconds"], "gaussians": fit["gaussians"],
        "iterations_per_s": fit["iterations"] / adam_seconds,
        "samples_per_s": fit["voxel_samples_per_second"],
        "psnr": [psnr_at(curve, s * mvoxels) for s in checkpoints[:-1]] + [fit["psnr_db"]],
    }


def main():
    args = sys.argv[1:]
    seconds_per_mvoxel = 5.0
    if args[:1] == ["--seconds-per-mvoxel"]:
        seconds_per_mvoxel, args = float(args[1]), args[2:]
    out = args[0] if args else os.path.join(ROOT, "out", "bench-scaling")
    os.makedirs(out, exist_ok=True)
    checkpoints = [seconds_per_mvoxel * k / 5 for k in range(1, 6)]
    cases = [("ch2", os.path.join(DATA, "mri-colin27-aal", "ch2.nii.gz")),
             ("ch2-x1.5", resampled_ch2(out)),
             ("ct-head", os.path.join(DATA, "ct-head-visible-human-png"))]
    results = [bench(name, source, checkpoints, out) for name, source in cases]
    header = " | ".join(f"{s:g} s/Mvox" for s in checkpoints[:-1])
    print(f"| volume | voxels | budget | Gaussians | iterations/s | voxel samples/s | {header} | as saved |")
    print("|---|---|---|---|---|---|" + "---|" * len(checkpoints))
    for r in results:
        psnr = " | ".join(f"{p:.2f}" for p in r["psnr"])
        print(f"| `{r['name']}` | {r['mvoxels']:.1f} M | {r['seconds']:.0f} s | {r['gaussians']:,} | "
              f"{r['iterations_per_s']:.1f} | {r['samples_per_s'] / 1e3:.0f} k | {psnr} |")
    print("\nHeld-out PSNR (dB) at each budget in seconds per million voxels; the last column is the saved "
          "asset's whole-volume PSNR.")


if __name__ == "__main__":
    main()
