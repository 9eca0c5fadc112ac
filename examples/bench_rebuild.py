"""Stack builds and orbits: this gvr against a baseline (an older gvr, or the same
one with other flags), in one run.

Each case renders a turntable with `gvr render --orbit` through both, in turn, and
reads their per-frame timings: how many stacks were built and their mean build,
the mean composite plus warp of frames that reuse a stack, the frames per second
over the whole orbit, builds included, and the peak memory of the process.

    # axis stacks against view stacks, one binary:
    /usr/bin/python3 examples/bench_rebuild.py --baseline-flags="--stacks view" \\
        out/ct-head-40.gvr out/ct-chest-40.gvr:ct
    # against an older build:
    git worktree add /tmp/gvr-old 6f2d3d2
    cmake -S /tmp/gvr-old -B /tmp/gvr-old/build -G Ninja -DCMAKE_BUILD_TYPE=Release
    ninja -C /tmp/gvr-old/build gvr
    /usr/bin/python3 examples/bench_rebuild.py --baseline /tmp/gvr-old/build/cli/gvr out/ct-head-40.gvr

A case is an input, optionally followed by :PRESET for --tf.
"""
import argparse
import json
import os
import shlex
import sys
import tempfile

from benchlib import GVR, measured


def orbit(gvr, flags, source, preset, frames, size):
    """Per-frame timings of one turntable (gvr render's --json frames) and its peak RSS in MiB."""
    with tempfile.TemporaryDirectory() as scratch:
        arguments = ["render", source, "-o", os.path.join(scratch, "f.png"), "--orbit", str(frames), "--size", size,
                     "-q", "--json"] + flags
        if preset:
            arguments += ["--tf", preset]
        out, _, peak_mib = measured(arguments, gvr)
        return json.loads(out)["frames"], peak_mib


def summary(frames, peak_mib):
    builds = [f["build_ms"] for f in frames if not f["reused"]]
    reused = [f["composite_ms"] + f["warp_ms"] for f in frames if f["reused"]]
    return {
        "builds": len(builds),
        "build_ms": sum(builds) / len(builds),
        "reused_frame_ms": sum(reused) / len(reused) if reused else None,
        "orbit_fps": len(frames) / (sum(f["total_ms"] for f in frames) / 1000.0),
        "peak_rss_mib": peak_mib,
    }


def milliseconds(value):
    return "-" if value is None else f"{value:.1f} ms"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("cases", nargs="+", help="INPUT or INPUT:PRESET")
    parser.add_argument("--baseline", default=GVR, help="the baseline gvr binary (default: this one)")
    parser.add_argument("--baseline-flags", default="", help="extra gvr render flags for the baseline")
    parser.add_argument("--gvr", default=GVR, help="this gvr binary (default: %(default)s)")
    parser.add_argument("--flags", default="", help="extra gvr render flags for this gvr")
    parser.add_argument("--frames", type=int, default=24, help="orbit frames per case (default: %(default)s)")
    parser.add_argument("--size", default="512x512", help="image size (default: %(default)s)")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    if args.baseline == args.gvr and args.baseline_flags == args.flags:
        parser.error("the baseline is this gvr with the same flags: give --baseline or --baseline-flags")

    rows = []
    for case in args.cases:
        source, _, preset = case.partition(":")
        row = {"input": source, "tf": preset or "default"}
        for name, binary, flags in (("baseline", args.baseline, args.baseline_flags), ("current", args.gvr, args.flags)):
            row[name] = summary(*orbit(binary, shlex.split(flags), source, preset, args.frames, args.size))
            print(f"{case}: {name} done", file=sys.stderr)
        row["build_speedup"] = row["baseline"]["build_ms"] / row["current"]["build_ms"]
        row["orbit_speedup"] = row["current"]["orbit_fps"] / row["baseline"]["orbit_fps"]
        rows.append(row)

    if args.json:
        print(json.dumps(rows, indent=2))
        return
    print(f"{args.frames}-frame orbits at {args.size}; baseline {args.baseline} {args.baseline_flags}, "
          f"current {args.gvr} {args.flags}\n")
    print("| input | tf | stacks built | mean build | reused frame (composite + warp) | orbit FPS, builds included | "
          "peak RSS |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        b, c = r["baseline"], r["current"]
        print(f"| {os.path.basename(r['input'])} | {r['tf']} | {b['builds']} / {c['builds']} | "
              f"{b['build_ms']:.0f} / {c['build_ms']:.0f} ms | {milliseconds(b['reused_frame_ms'])} / "
              f"{milliseconds(c['reused_frame_ms'])} | {b['orbit_fps']:.2f} / {c['orbit_fps']:.2f} "
              f"({r['orbit_speedup']:.1f}x) | {b['peak_rss_mib']:.0f} / {c['peak_rss_mib']:.0f} MiB |")
    print("\nEach cell: baseline / current.")


if __name__ == "__main__":
    main()
