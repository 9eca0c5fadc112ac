#!/usr/bin/python3
"""Export and evaluation benchmark: the Export/evaluate issue's two targets.

Fits ct-head-visible-human-png (512 x 512 x 234) at 40:1, then times
  - gvr export of the asset back onto the source grid (target: under 30 s, peak
    memory at most 2x the dense float32 grid), and at twice the resolution;
  - gvr eval of the source against the export, SSIM and MS-SSIM included
    (target: under 20 s).
Peak memory is reported in all and above gvr's own footprint at start (its
shared libraries). Figures are printed, never asserted.

    /usr/bin/python3 examples/bench_export_eval.py [--fit-seconds S] [OUT_DIR]

Run from the project root after .ci/build.sh; needs ../shared/data.
"""
import argparse
import json
import os

from benchlib import DATA, ROOT, baseline_rss_mib, measured, run, volume_mib


def memory_line(peak_mib, baseline_mib, float32_mib, target):
    working = peak_mib - baseline_mib
    return (f"peak {peak_mib:.0f} MiB in all = {peak_mib / float32_mib:.2f}x the float32 grid ({float32_mib:.0f} MiB); "
            f"{working:.0f} MiB above gvr at start = {working / float32_mib:.2f}x; target <= {target}x")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default=os.path.join(ROOT, "out", "bench-export-eval"))
    parser.add_argument("--fit-seconds", type=int, default=120, help="fit budget for the asset (default 120)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    grid, asset = os.path.join(args.out, "ct-head.vdb"), os.path.join(args.out, "ct-head.gvr")
    exported, fine = os.path.join(args.out, "ct-head-export.vdb"), os.path.join(args.out, "ct-head-2x.vdb")
    print(f"gvr export/eval benchmark; outputs in {args.out}")
    run(["ingest", "-q", os.path.join(DATA, "ct-head-visible-human-png"), "-o", grid])
    float32_mib, dims = volume_mib(grid)
    fit = json.loads(run(["fit", "-q", grid, "-o", asset, "--ratio", "40", "--time", str(args.fit_seconds), "--json"]))
    print(f"asset: {fit['gaussians']} Gaussians at {fit['ratio_vs_raw']:.1f}:1, {fit['psnr_db']:.2f} dB after a "
          f"{fit['seconds']:.0f} s fit")
    baseline = baseline_rss_mib()

    out, seconds, peak = measured(["export", "-q", asset, "-o", exported, "--json"])
    active = sum(g["active_voxels"] for g in json.loads(out)["grids"])
    print(f"\nexport onto the source grid ({dims[0]}x{dims[1]}x{dims[2]}, {active} active voxels): "
          f"{seconds:.2f} s; target < 30 s -> {'met' if seconds < 30 else 'missed'}")
    print("   " + memory_line(peak, baseline, float32_mib, 2))

    out, seconds, peak = measured(["export", "-q", asset, "-o", fine, "--resolution", str(2 * max(dims)), "--json"])
    fine_dims = json.loads(out)["dims"]
    print(f"export at twice the resolution ({fine_dims[0]}x{fine_dims[1]}x{fine_dims[2]}): {seconds:.2f} s, "
          f"peak {peak:.0f} MiB")

    out, seconds, peak = measured(["eval", "--json", grid, exported])
    metrics = json.loads(out)
    print(f"\neval of two {dims[0]}x{dims[1]}x{dims[2]} volumes: {seconds:.2f} s; target < 20 s -> "
          f"{'met' if seconds < 20 else 'missed'}")
    print(f"   PSNR {metrics['psnr']:.2f} dB, foreground {metrics['fg_psnr']:.2f} dB, SSIM {metrics['ssim']:.4f}, "
          f"MS-SSIM {metrics['ms_ssim']:.4f} ({metrics['ms_ssim_scales']} scales), peak {metrics['peak']}")
    print("   " + memory_line(peak, baseline, float32_mib, "(no target)"))


if __name__ == "__main__":
    main()
