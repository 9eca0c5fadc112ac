#!/usr/bin/python3
"""Label benchmark: fit ten AAL structures of the Colin27 brain at 10:1 once, then
print per-structure quality and the render time of one structure against all ten.

    /usr/bin/python3 examples/bench_labels.py [--seconds S] [OUT_DIR]

Run from the project root after .ci/build.sh; needs ../shared/data. Figures are
printed, never asserted.
"""
import json
import os
import statistics
import sys

from benchlib import DATA, ROOT, run

STRUCTURES = ["Hippocampus_L", "Hippocampus_R", "Thalamus_L", "Thalamus_R", "Caudate_L", "Caudate_R",
              "Putamen_L", "Putamen_R", "Amygdala_L", "Amygdala_R"]


def render_ms(asset, out, extra, repeats=3):
    """Median single-frame time at 512x512: one stack build, composite and warp."""
    times = []
    for _ in range(repeats):
        frames = json.loads(run(["render", asset, "-o", os.path.join(out, "frame.png"), "--size", "512x512",
                                 "--tf", "mri", "-q", "--json"] + extra))["frames"]
        times.append(frames[0]["total_ms"])
    return statistics.median(times)


def main():
    arguments = sys.argv[1:]
    seconds = "120"
    if "--seconds" in arguments:
        at = arguments.index("--seconds")
        seconds = arguments[at + 1]
        del arguments[at:at + 2]
    out = arguments[0] if arguments else os.path.join(ROOT, "out", "bench-labels")
    os.makedirs(out, exist_ok=True)
    atlas = os.path.join(DATA, "mri-colin27-aal")
    grid, asset = os.path.join(out, "ch2-aal.vdb"), os.path.join(out, "ch2-aal.gvr")
    run(["ingest", "-q", os.path.join(atlas, "ch2.nii.gz"), "-o", grid, "--labels", os.path.join(atlas, "aal.nii.gz"),
         "--label-names", os.path.join(atlas, "aal.nii.txt")])
    fit = json.loads(run(["fit", "-q", grid, "-o", asset, "--labels", ",".join(STRUCTURES), "--ratio", "10",
                          "--time", seconds, "--json"]))
    quality = json.loads(run(["eval", grid, asset, "--labels", grid, "--json"]))["structures"]
    print(f"gvr label benchmark: ch2 + AAL, {len(STRUCTURES)} structures, --ratio 10 per structure, {seconds} s fit; "
          f"{fit['gaussians']} Gaussians, {fit['file_bytes']} bytes; outputs in {out}")
    print(f"{'structure':<16} {'voxels':>7} {'Gaussians':>9} {'PSNR dB':>8} {'SSIM':>7}")
    gaussians = {s["id"]: s["gaussians"] for s in fit["structures"]}
    for s in quality:
        print(f"{s['name']:<16} {s['voxels']:>7} {gaussians[s['id']]:>9} {s['psnr']:>8.2f} {s['ssim']:>7.4f}")
    everything = render_ms(asset, out, [])
    one = render_ms(asset, out, ["--show", "Hippocampus_L"])
    print(f"render 512x512 (median of 3 single frames, stack built each time): all {len(STRUCTURES)} structures "
          f"{everything:.1f} ms, Hippocampus_L alone {one:.1f} ms: {everything / one:.1f}x faster")


if __name__ == "__main__":
    main()
