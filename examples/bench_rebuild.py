"""Stack rebuilds and orbits, this gvr against an older one, in one run.

Each case renders a turntable with `gvr render --orbit` through both binaries, in
turn, and reads their per-frame timings: the mean stack build, the mean composite
of frames that reuse a stack, and the frames per second over the whole orbit,
rebuilds included. The ratios are this build over the baseline.

    git worktree add /tmp/gvr-old 6f2d3d2
    cmake -S /tmp/gvr-old -B /tmp/gvr-old/build -G Ninja -DCMAKE_BUILD_TYPE=Release
    ninja -C /tmp/gvr-old/build gvr
    /usr/bin/python3 examples/bench_rebuild.py --baseline /tmp/gvr-old/build/cli/gvr \\
        out/bench-fit13/ct-head-40.gvr out/ct-chest.gvr:ct

A case is an input, optionally followed by :PRESET for --tf.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

from benchlib import GVR


def orbit(gvr, source, preset, frames, size):
    """Per-frame timings of one turntable: gvr render's --json frames."""
    with tempfile.TemporaryDirectory() as scratch:
        command = [gvr, "render", source, "-o", os.path.join(scratch, "f.png"), "--orbit", str(frames), "--size",
                   size, "-q", "--json"]
        if preset:
            command += ["--tf", preset]
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"{' '.join(command)} failed: {done.stderr.strip()}")
        return json.loads(done.stdout)["frames"]


def summary(frames):
    builds = [f["build_ms"] for f in frames if not f["reused"]]
    reused = [f["composite_ms"] + f["warp_ms"] for f in frames if f["reused"]]
    return {
        "builds": len(builds),
        "build_ms": sum(builds) / len(builds),
        "reused_frame_ms": sum(reused) / len(reused) if reused else None,
        "orbit_fps": len(frames) / (sum(f["total_ms"] for f in frames) / 1000.0),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("cases", nargs="+", help="INPUT or INPUT:PRESET")
    parser.add_argument("--baseline", required=True, help="the older gvr binary")
    parser.add_argument("--gvr", default=GVR, help="this gvr binary (default: %(default)s)")
    parser.add_argument("--frames", type=int, default=24, help="orbit frames per case (default: %(default)s)")
    parser.add_argument("--size", default="512x512", help="image size (default: %(default)s)")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()

    rows = []
    for case in args.cases:
        source, _, preset = case.partition(":")
        row = {"input": source, "tf": preset or "default"}
        for name, binary in (("baseline", args.baseline), ("current", args.gvr)):
            row[name] = summary(orbit(binary, source, preset, args.frames, args.size))
            print(f"{case}: {name} done", file=sys.stderr)
        row["build_speedup"] = row["baseline"]["build_ms"] / row["current"]["build_ms"]
        row["orbit_speedup"] = row["current"]["orbit_fps"] / row["baseline"]["orbit_fps"]
        rows.append(row)

    if args.json:
        print(json.dumps(rows, indent=2))
        return
    print(f"{args.frames}-frame orbits at {args.size}; baseline {args.baseline}, current {args.gvr}\n")
    print("| input | tf | build, baseline | build, current | speed-up | reused frame (composite + warp) | "
          "orbit FPS, baseline | orbit FPS, current |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        b, c = r["baseline"], r["current"]
        print(f"| {os.path.basename(r['input'])} | {r['tf']} | {b['build_ms']:.0f} ms | {c['build_ms']:.0f} ms | "
              f"{r['build_speedup']:.2f}x | {c['reused_frame_ms']:.1f} ms | {b['orbit_fps']:.2f} | "
              f"{c['orbit_fps']:.2f} |")


if __name__ == "__main__":
    main()
