"""gvr view as a person uses it: a window on a virtual display, driven by xdotool
(real X input events), checked through the screenshots it saves.

Usage: xvfb-run -a -s "-screen 0 1280x1024x24" python3 view_xvfb.py GVR SHARED_DATA WORK

- A fixed view's screenshot matches `gvr render` at the same camera within one
  8-bit level on average: it is the still the window draws once the view rests,
  which comes after the coarse and the refined images.
- A drag to the right turns the azimuth by 0.4 degrees a pixel: the screenshot
  then matches `gvr render` at the new azimuth.
- The wheel zooms in (more pixels covered), `]` raises the opacity, `t` moves to
  the next preset, and the number keys hide structures as `gvr render --hide` does.
- A missing file, a missing display and a still's sampling out of range are
  one-line errors with exit code 2.
"""
import json
import os
import subprocess
import sys
import time

import numpy as np
from PIL import Image

from labelled_blobs import write_labelled_blobs

GVR, SHARED, WORK = sys.argv[1:4]
CH2 = "/usr/share/mricron/templates/ch2.nii.gz"
SIZE = "200x160"


def gvr(*args):
    return subprocess.run([GVR, *args], check=True, capture_output=True, text=True).stdout


def xdotool(*args):
    return subprocess.run(["xdotool", *args], check=True, capture_output=True, text=True).stdout.strip()


def pixels(path):
    return np.asarray(Image.open(path).convert("RGBA"), dtype=np.float64)


def mean_level_difference(a, b):
    return np.abs(pixels(a) - pixels(b)).mean()


def coverage(path):
    return (pixels(path)[..., 3] > 0).mean()


class Window:
    """One `gvr view` process and its window."""

    def __init__(self, *args):
        self.folder = os.path.join(WORK, "shots-%d" % time.monotonic_ns())
        self.process = subprocess.Popen([GVR, "view", *args, "--size", SIZE, "--screenshots", self.folder, "--json"],
                                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.id = xdotool("search", "--sync", "--onlyvisible", "--name", "gvr view").split()[0]
        # No window manager gives focus on a virtual display: take it, and make sure.
        deadline = time.monotonic() + 30
        while xdotool("getwindowfocus") != self.id:
            assert time.monotonic() < deadline, "the window never got the keyboard focus"
            xdotool("windowfocus", self.id)
            time.sleep(0.1)
        time.sleep(0.5)  # SDL sees the focus arrive before the first key
        self.shots = 0

    def key(self, name):
        xdotool("key", "--delay", "50", name)

    def drag(self, dx, dy):
        xdotool("mousemove", "--window", self.id, "100", "80", "mousedown", "1", "mousemove_relative", "--",
                str(dx), str(dy), "mouseup", "1")

    def wheel_up(self):
        xdotool("mousemove", "--window", self.id, "100", "80", "click", "4")

    def screenshot(self):
        self.key("s")
        self.shots += 1
        path = os.path.join(self.folder, "gvr-view-%04d.png" % self.shots)
        deadline = time.monotonic() + 60
        while not os.path.exists(path):
            assert time.monotonic() < deadline, "no screenshot " + path
            time.sleep(0.05)
        time.sleep(0.2)  # written atomically; the rename is the last step
        return path

    def close(self):
        self.key("q")
        out, err = self.process.communicate(timeout=60)
        assert self.process.returncode == 0, err
        return json.loads(out)


def render(source, name, *args):
    """What a screenshot (the view at rest) shows: gvr render at the window's size and
    stacks (axes; gvr render's own supersampling, the still's)."""
    path = os.path.join(WORK, name)
    gvr("render", source, "-o", path, "--size", SIZE, "--stacks", "axes", "-q", *args)
    return path


def check(condition, message):
    print(("ok   " if condition else "FAIL ") + message)
    return condition


def main():
    os.makedirs(WORK, exist_ok=True)
    asset = os.path.join(WORK, "ch2.gvr")
    gvr("fit", "-q", CH2, "-o", asset, "--ratio", "40", "--iterations", "30")
    passed = True

    window = Window(asset, "--azimuth", "30", "--elevation", "15", "--tf", "mri")
    start = window.screenshot()
    window.drag(50, 0)  # 20 degrees of azimuth
    turned = window.screenshot()
    window.wheel_up()
    zoomed = window.screenshot()
    window.key("r")
    window.key("bracketright")
    denser = window.screenshot()
    window.key("bracketleft")  # back to x1.00
    window.key("t")  # mri -> ct (rgb needs colour data)
    ct = window.screenshot()
    summary = window.close()

    at30 = render(asset, "at30.png", "--azimuth", "30", "--elevation", "15", "--tf", "mri")
    at50 = render(asset, "at50.png", "--azimuth", "50", "--elevation", "15", "--tf", "mri")
    ct30 = render(asset, "ct30.png", "--azimuth", "30", "--elevation", "15", "--tf", "ct")
    d = mean_level_difference(start, at30)
    passed &= check(d <= 1.0, f"fixed view = gvr render: {d:.3f} levels on average")
    d50, d30 = mean_level_difference(turned, at50), mean_level_difference(turned, at30)
    passed &= check(d50 <= 1.0 and d50 < d30, f"drag right = azimuth 50: {d50:.3f} levels (to azimuth 30: {d30:.3f})")
    passed &= check(coverage(zoomed) > coverage(turned) * 1.1,
                    f"wheel zooms in: {coverage(turned):.3f} -> {coverage(zoomed):.3f} of the pixels covered")
    alpha = lambda path: pixels(path)[..., 3].mean()
    passed &= check(alpha(denser) > alpha(start) + 1.0, f"] raises the opacity: {alpha(start):.2f} -> {alpha(denser):.2f}")
    d = mean_level_difference(ct, ct30)
    passed &= check(d <= 1.0, f"t cycles to ct, as gvr render --tf ct: {d:.3f} levels")
    passed &= check(summary["frames"] > 5 and summary["stacks_built"] >= 4 and len(summary["screenshots"]) == 5,
                    f"summary: {summary['frames']} frames, {summary['stacks_built']} stacks built, "
                    f"{summary['stale_frames']} stale, {len(summary['screenshots'])} screenshots")
    setup = summary["setup_seconds"]
    passed &= check(set(setup) == {"read", "classify", "window", "total"}
                    and summary["first_image_ms"] >= 1000 * setup["total"],
                    f"first image after {summary['first_image_ms']:.0f} ms, set-up {1000 * setup['total']:.0f} ms")
    passed &= check(summary["refined_image_ms"] > summary["first_image_ms"],
                    f"the coarse image first, the refined one after {summary['refined_image_ms']:.0f} ms")
    passed &= check(summary["still_image_ms"] > summary["refined_image_ms"],
                    f"the still once the view rests, after {summary['still_image_ms']:.0f} ms")

    passed &= check_structures()
    passed &= check_bad_input(asset)
    return passed


def check_structures():
    """Two labelled blobs: key 2 hides the second, as render --hide does."""
    blobs, labels, names = write_labelled_blobs(WORK)
    tf = os.path.join(WORK, "tf.json")
    with open(tf, "w") as out:
        json.dump({"points": [[5, 1, 0.8, 0.6, 0], [200, 1, 1, 1, 0.5]]}, out)
    asset = os.path.join(WORK, "blobs.gvr")
    gvr("fit", "-q", blobs, "-o", asset, "--labels", "all", "--label-volume", labels, "--label-names", names,
        "--iterations", "20")
    window = Window(asset, "--tf", tf)
    both = window.screenshot()
    window.key("2")
    left_only = window.screenshot()
    window.close()
    ok = check(mean_level_difference(both, render(asset, "both.png", "--tf", tf)) <= 1.0, "labelled asset = gvr render")
    d = mean_level_difference(left_only, render(asset, "left.png", "--tf", tf, "--hide", "Right"))
    return check(d <= 1.0 and coverage(left_only) < coverage(both), f"key 2 hides Right, as --hide Right: {d:.3f} levels") and ok


def check_bad_input(asset):
    missing = subprocess.run([GVR, "view", os.path.join(WORK, "missing.gvr")], capture_output=True, text=True)
    ok = check(missing.returncode == 2 and missing.stderr.count("\n") == 1 and "missing.gvr" in missing.stderr,
               "a missing file: exit 2, " + missing.stderr.strip())
    still = subprocess.run([GVR, "view", asset, "--still-supersample", "7"], capture_output=True, text=True)
    ok &= check(still.returncode == 2 and still.stderr.count("\n") == 1 and "--still-supersample" in still.stderr,
                "a still's sampling out of range: exit 2, " + still.stderr.strip())
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    headless = subprocess.run([GVR, "view", asset], capture_output=True, text=True, env=env)
    return check(headless.returncode == 2 and headless.stderr.count("\n") == 1 and "display" in headless.stderr,
                 "no display: exit 2, " + headless.stderr.strip()) and ok


if __name__ == "__main__":
    sys.exit(0 if main() else 1)
