#!/usr/bin/python3
"""Fit engine benchmark: voxel-loss samples per second, and how their cost grows
with the Gaussian count, against a baseline gvr measured in the same run.

Each row is one `gvr fit --gaussians M --min-samples 0 --solve-iterations 0` for a
fixed time. Samples per second come from the fit log: (iterations between its
first and last rows) x batch / (seconds between them), so initialisation and the
final measurement are left out for both engines alike; the held-out evaluation
every --log-every iterations stays in. Figures are printed, never asserted.

    /usr/bin/python3 examples/bench_fit_engine.py [--baseline PATH_TO_OLD_GVR] [OUT_DIR]

Two parts:
  throughput  ct-head at 155,000 Gaussians, each engine at its default batch, 60 s,
              and the block engine on every row of its blocks
  scaling     ch2 at 10k, 40k, 100k and 400k Gaussians, a fixed batch of 2,097,152
              voxels a step, 40 s: seconds per million samples, O(M) pass included
Run from the project root after .ci/build.sh, with nothing else running; needs
../shared/data. About 14 minutes with a baseline.
"""
import csv
import json
import os
import sys

from benchlib import DATA, GVR, ROOT, measured

# The per-sample engine's default batch (commit 3b6779c); the block engine's is 524,288.
BASELINE_BATCH = 32768
BLOCK_BATCH = 524288
SCALING_BATCH = 2097152


def log_rate(log_path, batch):
    """(iterations a second, voxel samples a second) between the log's first and last rows."""
    with open(log_path) as log:
        rows = [r for r in csv.DictReader(line for line in log if not line.startswith("#"))]
    first, last = rows[0], rows[-1]
    iterations = int(last["iteration"]) - int(first["iteration"])
    seconds = float(last["seconds"]) - float(first["seconds"])
    return iterations / seconds, iterations * batch / seconds


def fit(gvr, grid, gaussians, seconds, batch, log, log_every, extra=()):
    arguments = ["fit", "-q", "--json", grid, "-o", log[:-4] + ".gvr", "--gaussians", str(gaussians),
                 "--min-samples", "0", "--solve-iterations", "0", "--time", str(seconds), "--batch", str(batch),
                 "--log", log, "--log-every", str(log_every)] + list(extra)
    out, _, peak = measured(arguments, gvr)
    result = json.loads(out)
    per_iteration, per_second = log_rate(log, batch)
    return {"iterations_per_s": per_iteration, "samples_per_s": per_second, "psnr": result["psnr_db"],
            "share": result.get("mean_gradient_share"), "peak_mib": peak}


def ingest(name, source, out):
    grid = os.path.join(out, name + ".vdb")
    if not os.path.exists(grid):
        measured(["ingest", "-q", os.path.join(DATA, source), "-o", grid])
    return grid


def engines(baseline):
    yield "block engine", GVR, BLOCK_BATCH, ()
    if baseline:
        yield "baseline", baseline, BASELINE_BATCH, ()


def main():
    arguments = sys.argv[1:]
    baseline = None
    if "--baseline" in arguments:
        at = arguments.index("--baseline")
        baseline = arguments[at + 1]
        del arguments[at:at + 2]
    out = arguments[0] if arguments else os.path.join(ROOT, "out", "bench-fit-engine")
    os.makedirs(out, exist_ok=True)
    ct_head = ingest("ct-head", "ct-head-visible-human-png", out)
    ch2 = ingest("ch2", "mri-colin27-aal/ch2.nii.gz", out)

    print("Throughput: ct-head (61.3 M voxels), 155,000 Gaussians, 60 s, each engine at its default batch\n")
    print("| engine | batch | iterations/s | voxel samples/s | share with a gradient | PSNR as saved |")
    print("|---|---|---|---|---|---|")
    rates = {}
    # The kernel on every row of its blocks: the fastest per sample, though not the best per second of fit.
    every_row = ("block engine, every row", GVR, 2 * BLOCK_BATCH, ("--row-stride", "1"))
    for name, gvr, batch, extra in list(engines(baseline)) + [every_row]:
        r = fit(gvr, ct_head, 155000, 60, batch, os.path.join(out, f"ct-head-{name[-3:]}.csv"), 10, extra)
        rates[name] = r["samples_per_s"]
        share = f"{r['share']:.2f}" if r["share"] is not None else "-"
        print(f"| {name} | {batch} | {r['iterations_per_s']:.2f} | {r['samples_per_s'] / 1e6:.2f} M | "
              f"{share} | {r['psnr']:.2f} dB |", flush=True)
    if baseline:
        for name in ("block engine", "block engine, every row"):
            print(f"\n{name} / baseline: {rates[name] / rates['baseline']:.1f}x the voxel samples a second")

    print(f"\nScaling: ch2 (7.1 M voxels), a fixed batch of {SCALING_BATCH:,} voxels a step, 40 s\n")
    print("| engine | Gaussians | voxel samples/s | seconds per million samples | against 10k |")
    print("|---|---|---|---|---|")
    for name, gvr, _, _ in engines(baseline):
        first = None
        for gaussians in (10000, 40000, 100000, 400000):
            r = fit(gvr, ch2, gaussians, 40, SCALING_BATCH, os.path.join(out, f"ch2-{name[0]}-{gaussians}.csv"), 2)
            cost = 1e6 / r["samples_per_s"]
            first = first or cost
            print(f"| {name} | {gaussians:,} | {r['samples_per_s'] / 1e6:.2f} M | {cost:.3f} s | {cost / first:.2f}x |",
                  flush=True)


if __name__ == "__main__":
    main()
