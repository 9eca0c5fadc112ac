#!/usr/bin/python3
"""Fit at scale: the one scaling table of docs/benchmarks.md.

Fits each volume at 10:1 for --seconds (default 600) and prints one row per volume
and build: voxels, Gaussians, iterations, voxel samples a second, the held-out PSNR
at 60 s, 300 s and 600 s of the fit log, the saved asset's PSNR, and ZFP
(fixed-accuracy, `gvr baseline`) at the asset's bytes. With
--baseline OLD_GVR each volume is fitted by the old build and this one in turn, so
the two rows share the machine's state. Figures are printed, never asserted.

    /usr/bin/python3 examples/bench_scaling.py [--seconds S] [--baseline OLD_GVR]
        [--volume NAME=PATH ...] [OUT_DIR]

Default volumes: ch2 (7.1 M voxels), ct-head (61 M) and the chest CT (67 M) from
../shared/data; --volume adds any file gvr ingest reads (a 0.5 mm MRI, say).
"""
import argparse
import csv
import json
import os
import subprocess

from benchlib import DATA, GVR, ROOT, measured

CHECKPOINTS = (60, 300, 600)


def held_out_curve(log_path):
    """(seconds, held-out PSNR) rows of a fit log."""
    with open(log_path) as log:
        rows = list(csv.DictReader(line for line in log if not line.startswith("#")))
    return [(float(row["seconds"]), float(row["psnr_db"])) for row in rows if row["psnr_db"]]


def psnr_at(curve, seconds):
    """The last held-out PSNR logged by @seconds (None if the fit was shorter)."""
    if not curve or curve[-1][0] < 0.9 * seconds:
        return None
    before = [psnr for t, psnr in curve if t <= seconds]
    return before[-1] if before else None


def fit(gvr, grid, out, tag, seconds):
    asset, log = os.path.join(out, tag + ".gvr"), os.path.join(out, tag + ".csv")
    text, _, peak = measured(["fit", "-q", "--json", grid, "-o", asset, "--ratio", "10", "--time", str(seconds),
                              "--log", log], gvr)
    result = json.loads(text)
    result.update(curve=held_out_curve(log), asset=asset, peak_rss=peak)
    return result


def zfp_at(grid, nbytes, out):
    stream = os.path.join(out, "zfp.zfp")
    text = subprocess.run([GVR, "baseline", grid, "--method", "zfp-accuracy", "--target-bytes", str(nbytes),
                           "-o", os.path.join(out, "zfp-rec.vdb"), "--stream", stream, "--json", "-q"],
                          check=True, capture_output=True, text=True).stdout
    return json.loads(text)["psnr_db"]


def cell(value, digits=2):
    return "—" if value is None else f"{value:.{digits}f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default=os.path.join(ROOT, "out", "bench-scaling"))
    parser.add_argument("--seconds", type=float, default=600.0)
    parser.add_argument("--baseline", help="an older gvr to fit each volume with first")
    parser.add_argument("--volume", action="append", default=[], help="NAME=PATH, another volume")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    cases = [("ch2", os.path.join(DATA, "mri-colin27-aal", "ch2.nii.gz")),
             ("ct-head", os.path.join(DATA, "ct-head-visible-human-png")),
             ("chest", os.path.join(DATA, "ct-chest-ricord-512"))]
    cases += [tuple(v.split("=", 1)) for v in args.volume]
    builds = ([("before", args.baseline)] if args.baseline else []) + [("this build", GVR)]
    print("| volume | voxels | build | Gaussians | iterations | samples/s | "
          + " | ".join(f"{s} s" for s in CHECKPOINTS) + " | as saved | ratio | peak RSS | ZFP |")
    print("|---|---|---|---|---|---|" + "---|" * len(CHECKPOINTS) + "---|---|---|---|")
    for name, source in cases:
        out = os.path.join(args.out, name)
        os.makedirs(out, exist_ok=True)
        grid = os.path.join(out, name + ".vdb")
        subprocess.run([GVR, "ingest", "-q", source, "-o", grid], check=True, capture_output=True)
        for label, gvr in builds:
            r = fit(gvr, grid, out, label.replace(" ", "-"), args.seconds)
            nbytes = r["file_bytes"]
            zfp = zfp_at(grid, nbytes, out)
            dims = json.loads(subprocess.run([GVR, "info", "--json", grid], check=True, capture_output=True,
                                             text=True).stdout)["grids"][0]["metadata"]["gvr_dims"]
            psnrs = " | ".join(cell(psnr_at(r["curve"], s)) for s in CHECKPOINTS)
            print(f"| `{name}` | {dims[0] * dims[1] * dims[2] / 1e6:.1f} M | {label} | {r['gaussians']:,} | "
                  f"{r['iterations']:,} | {r['voxel_samples_per_second'] / 1e6:.2f} M | {psnrs} | "
                  f"{cell(r['psnr_db'])} | {r['ratio_vs_raw']:.2f}:1 | {r['peak_rss']:.0f} MiB | {cell(zfp)} |", flush=True)
    print(f"\nHeld-out PSNR (dB) of the fit log at each time of a {args.seconds:g} s fit at 10:1; 'as saved' is "
          "the asset's whole-volume PSNR; ZFP at the asset's bytes.")


if __name__ == "__main__":
    main()
