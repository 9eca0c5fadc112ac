#!/usr/bin/env python3
"""The README's render table: for each input and transfer function, what a person
waits for and what they see, measured with `gvr render` and `gvr eval`.

Usage: python3 bench/render_table.py [--gvr GVR] [--baseline OLD_GVR] [--orbit N]
                                     [--size WxH] [--supersample S | --view] [--work DIR] NAME=INPUT:TF ...

Each NAME=INPUT:TF is a row: INPUT any file `gvr render` takes, TF a preset or a
transfer function file. For each row and each binary (the baseline first, when
given, then GVR, one after the other so that both meet the same machine):
- an orbit of N frames (`--orbit N --json`, default 120): the first frame (set-up
  included, `first_frame_ms`), the mean stack build, the mean reused frame, and the
  orbit's frames per second with its builds;
- a still at azimuth 30, elevation 15, scored by `gvr eval` ("as seen" PSNR)
  against the anti-aliased ray marcher (`--samples 4`) on the same input, beside
  the one-ray ray marcher's own score, the figure to reach; and the same view drawn
  from an axis stack (`--stacks axes`), as the orbit draws it.
--supersample passes S to every shear-warp render (`gvr view` draws with 1).
--view measures what `gvr view` shows: its moving frames (axis stacks at one sample a
pixel: the orbit, and the still's view drawn so), and what it draws once the view
rests (`--still-supersample`: the axis stack at `gvr render`'s own supersampling,
its build and its PSNR; a binary without a still keeps the moving frame).
Prints a Markdown table, and the same figures as JSON to WORK/render_table.json.
Nothing is asserted: run it with nothing else on the machine.
"""
import argparse
import json
import os
import subprocess
import sys

AZIMUTH, ELEVATION = "30", "15"


def run_json(command):
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"render_table: {' '.join(command)} failed: {done.stderr.strip()}")
    return json.loads(done.stdout)


def render(gvr, source, tf, output, size, *extra):
    return run_json([gvr, "render", source, "-o", output, "--tf", tf, "--size", size, "--json", "-q", *extra])


def seen_psnr(gvr, reference, test):
    return run_json([gvr, "eval", reference, test, "--json"])["rendering"]["psnr"]


def has_still(gvr):
    """Whether this gvr's window draws a still once the view rests (since 2026-11-29)."""
    done = subprocess.run([gvr, "view", "--help"], capture_output=True, text=True)
    return "--still-supersample" in done.stdout


def orbit_figures(gvr, source, tf, size, frames, folder, *extra):
    report = render(gvr, source, tf, os.path.join(folder, "orbit.png"), size, "--orbit", str(frames), *extra)
    stats = report["frames"]
    builds = [f["build_ms"] for f in stats if not f["reused"]]
    reused = [f["total_ms"] for f in stats if f["reused"]]
    return {
        "first_frame_ms": report["first_frame_ms"],
        "builds": len(builds),
        "build_ms": sum(builds) / len(builds) if builds else None,
        "reused_ms": sum(reused) / len(reused) if reused else None,
        "orbit_fps": len(stats) * 1000.0 / sum(f["total_ms"] for f in stats),
    }


def measure_row(args, name, source, tf):
    folder = os.path.join(args.work, name)
    os.makedirs(folder, exist_ok=True)
    view = ["--azimuth", AZIMUTH, "--elevation", ELEVATION]
    reference = os.path.join(folder, "antialiased.exr")
    one_ray = os.path.join(folder, "one-ray.exr")
    render(args.gvr, source, tf, reference, args.size, *view, "--renderer", "raymarch", "--samples", "4")
    render(args.gvr, source, tf, one_ray, args.size, *view, "--renderer", "raymarch")
    row = {"name": name, "input": source, "tf": tf, "one_ray_psnr": seen_psnr(args.gvr, reference, one_ray)}
    binaries = ([("baseline", args.baseline)] if args.baseline else []) + [("gvr", args.gvr)]
    supersample = "1" if args.view else args.supersample
    shear_warp = ["--supersample", supersample] if supersample else []
    for label, gvr in binaries:
        figures = orbit_figures(gvr, source, tf, args.size, args.orbit, folder, *shear_warp)
        # The same view as an orbit draws it: from an axis stack.
        orbit_frame = os.path.join(folder, f"{label}-axes.exr")
        render(gvr, source, tf, orbit_frame, args.size, *view, *shear_warp, "--stacks", "axes")
        figures["orbit_frame_psnr"] = seen_psnr(args.gvr, reference, orbit_frame)
        still = os.path.join(folder, f"{label}.exr")
        if args.view:
            figures["still_build_ms"] = None
            if has_still(gvr):
                report = render(gvr, source, tf, still, args.size, *view, "--stacks", "axes")
                figures["still_build_ms"] = report["frames"][0]["build_ms"]
            else:
                still = orbit_frame
        else:
            # What drew the still (gvr render reports it since 2026-11-28; older binaries do not).
            figures["still_settings"] = render(gvr, source, tf, still, args.size, *view, *shear_warp).get("settings")
        figures["psnr"] = seen_psnr(args.gvr, reference, still)
        row[label] = figures
    return row


def cell(value, digits):
    return "—" if value is None else f"{value:,.{digits}f}"


def print_table(rows, baseline, view):
    labels = (["baseline"] if baseline else []) + ["gvr"]
    if view:
        print("| input | transfer function | binary | first frame ms | stack build ms | moving frame ms "
              "| orbit FPS, builds included | moving frame's PSNR dB | at rest: the still's build ms "
              "| at rest: PSNR dB against 4x4 rays | one ray's PSNR dB |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
    else:
        print("| input | transfer function | binary | first frame ms | stack build ms | reused frame ms "
              "| orbit FPS, builds included | PSNR dB against 4x4 rays | orbit frame's PSNR dB | one ray's PSNR dB |")
        print("|---|---|---|---|---|---|---|---|---|---|")
    for row in rows:
        for label in labels:
            f = row[label]
            common = (f"| {row['name']} | {row['tf']} | {label} | {cell(f['first_frame_ms'], 0)} | "
                      f"{cell(f['build_ms'], 0)} ({f['builds']}) | {cell(f['reused_ms'], 1)} | {cell(f['orbit_fps'], 1)} | ")
            if view:
                print(common + f"{cell(f['orbit_frame_psnr'], 2)} | {cell(f['still_build_ms'], 0)} | "
                      f"{cell(f['psnr'], 2)} | {cell(row['one_ray_psnr'], 2)} |")
            else:
                print(common + f"{cell(f['psnr'], 2)} | {cell(f['orbit_frame_psnr'], 2)} | {cell(row['one_ray_psnr'], 2)} |")


def parse_row(text):
    name, _, rest = text.partition("=")
    source, _, tf = rest.rpartition(":")
    if not name or not source or not tf:
        sys.exit(f"render_table: '{text}' is not NAME=INPUT:TF")
    return name, source, tf


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("rows", nargs="+", help="NAME=INPUT:TF")
    parser.add_argument("--gvr", default="build/cli/gvr")
    parser.add_argument("--baseline", help="an older gvr to measure side by side")
    parser.add_argument("--orbit", type=int, default=120)
    parser.add_argument("--size", default="512x512")
    parser.add_argument("--supersample", help="passed to gvr render's shear-warp (default: its own)")
    parser.add_argument("--view", action="store_true", help="gvr view's moving frames and its still at rest")
    parser.add_argument("--work", default="out/render-table")
    args = parser.parse_args()
    if args.view and args.supersample:
        sys.exit("render_table: --view draws the moving frames at 1 and the still at gvr render's own; no --supersample")
    rows = [measure_row(args, *parse_row(text)) for text in args.rows]
    with open(os.path.join(args.work, "render_table.json"), "w") as out:
        json.dump(rows, out, indent=2)
    print_table(rows, args.baseline, args.view)


if __name__ == "__main__":
    main()
