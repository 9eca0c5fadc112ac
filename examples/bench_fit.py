#!/usr/bin/python3
"""Fit benchmark: issue 13's four rate-distortion targets, with error against run time.

For each case: ingest, fit at the target ratio within the time budget, then
print the PSNR-against-seconds curve from the fit log, the final whole-volume
and foreground PSNR of the saved asset, and peak memory against 3x the volume
as float32. Figures are printed, never asserted.

    /usr/bin/python3 examples/bench_fit.py [--quick] [OUT_DIR]

--quick divides every time budget by 10, to check the pipeline end to end.
Run from the project root after .ci/build.sh; needs ../shared/data.
"""
import csv
import json
import os
import sys

from benchlib import DATA, ROOT, baseline_rss_mib, run, volume_mib

# name, input, ingest flags, ratio, seconds, target dB, the reference at equal bytes
# (ZFP fixed-accuracy size-matched to gvr's asset, README "Rate-distortion against ZFP")
CASES = [
    ("ch2", "mri-colin27-aal/ch2.nii.gz", [], 10, 600, 41.0, "ZFP: 39.67 dB at 9.7:1"),
    ("ch2", "mri-colin27-aal/ch2.nii.gz", [], 40, 600, 35.0, "ZFP: 27.09 dB at 39.3:1"),
    ("ct-head", "ct-head-visible-human-png", [], 40, 900, 49.0, "ZFP: 50.89 dB at 47.2:1"),
    ("brainmaps54", "rgb-brainmaps54-cryosection", ["--spacing", "1,1,3.5"], 10, 600, 38.0,
     "ZFP: 41.4 dB at 10:1"),
]


def curve(log_path, points=10):
    with open(log_path) as log:
        rows = list(csv.DictReader(line for line in log if not line.startswith("#")))
    step = max(1, len(rows) // points)
    picked = rows[step - 1::step]
    if rows and picked[-1] is not rows[-1]:
        picked.append(rows[-1])
    return picked


def bench(name, source, ingest_flags, ratio, seconds, target_db, reference, out, baseline_mib):
    grid = os.path.join(out, name + ".vdb")
    if not os.path.exists(grid):
        run(["ingest", "-q", os.path.join(DATA, source), "-o", grid] + ingest_flags)
    float32_mib, _ = volume_mib(grid)
    stem = os.path.join(out, f"{name}-{ratio}")
    log = stem + ".csv"
    result = json.loads(run(["fit", "-q", grid, "-o", stem + ".gvr", "--ratio", str(ratio),
                             "--time", str(seconds), "--log", log, "--json"]))
    print(f"\n== {name}: {source}, ratio {ratio}, {seconds} s budget, target {target_db} dB ({reference})")
    print("   seconds   held-out PSNR (dB)")
    for row in curve(log):
        print(f"   {float(row['seconds']):7.1f}   {row['psnr_db']}")
    verdict = "met" if result["psnr_db"] >= target_db else f"missed by {target_db - result['psnr_db']:.2f} dB"
    print(f"   final (as saved): {result['psnr_db']:.2f} dB whole volume, {result['fg_psnr_db']:.2f} dB foreground, "
          f"{result['gaussians']} Gaussians, {result['ratio_vs_raw']:.2f}:1 vs raw, "
          f"{result['iterations']} iterations in {result['seconds']:.0f} s -> target {verdict}")
    memory = result["peak_rss_mib"]
    working = memory - baseline_mib
    print(f"   peak memory: {memory:.0f} MiB in all = {memory / float32_mib:.2f}x the float32 volume "
          f"({float32_mib:.0f} MiB); {working:.0f} MiB above gvr's {baseline_mib:.0f} MiB at start = "
          f"{working / float32_mib:.2f}x; target <= 3x")


def main():
    arguments = [a for a in sys.argv[1:] if a != "--quick"]
    quick = "--quick" in sys.argv[1:]
    out = arguments[0] if arguments else os.path.join(ROOT, "out", "bench-fit")
    os.makedirs(out, exist_ok=True)
    print(f"gvr fit benchmark; outputs in {out}" + (" (quick: budgets / 10)" if quick else ""))
    baseline = baseline_rss_mib()
    for name, source, flags, ratio, seconds, target, reference in CASES:
        bench(name, source, flags, ratio, max(10, seconds // 10) if quick else seconds, target, reference, out,
              baseline)


if __name__ == "__main__":
    main()
