"""What the benchmark scripts share: where gvr and the data are, and how to time
one gvr run and read its peak memory."""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GVR = os.path.join(ROOT, "build", "cli", "gvr")
DATA = os.path.join(ROOT, "..", "shared", "data")

# Runs one command in a fresh Python process so that its peak RSS is its own, not
# the largest of every child this script has started.
_MEASURE = ("import json, resource, subprocess, sys, time; start = time.monotonic(); "
            "done = subprocess.run(sys.argv[1:], capture_output=True, text=True); "
            "print(json.dumps({'seconds': time.monotonic() - start, 'code': done.returncode, 'out': done.stdout, "
            "'err': done.stderr, 'peak_rss_kib': resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss}))")


def run(arguments):
    """gvr's standard output; raises on a non-zero exit."""
    return subprocess.run([GVR] + arguments, check=True, capture_output=True, text=True).stdout


def measured(arguments, gvr=GVR):
    """Runs @gvr with @arguments: (standard output, wall seconds, peak RSS in MiB)."""
    probe = subprocess.run([sys.executable, "-c", _MEASURE, gvr] + arguments, capture_output=True, text=True,
                           check=True)
    result = json.loads(probe.stdout)
    if result["code"] != 0:
        raise RuntimeError(f"gvr {' '.join(arguments)} failed: {result['err']}")
    return result["out"], result["seconds"], result["peak_rss_kib"] / 1024


def baseline_rss_mib():
    """Peak RSS of gvr doing nothing: the shared libraries it maps at start."""
    return measured(["--version"])[2]


def volume_mib(grid_path):
    """The grid's source volume as dense float32, in MiB."""
    info = json.loads(run(["info", "--json", grid_path]))["grids"][0]
    dims = info["metadata"]["gvr_dims"]
    return dims[0] * dims[1] * dims[2] * info["metadata"]["gvr_channels"] * 4 / 2**20, dims
