"""An export with --dcc renders in Blender as gvr renders it: the same silhouette.

Usage: blender_silhouettes.py GVR_EXECUTABLE SHARED_DATA_DIR WORK_DIR [IMAGE_DIR]
Runs with Debian's /usr/bin/python3 (numpy, PIL) and /usr/bin/blender (3.4, Cycles
CPU). For the chest CT (HU, its default ct preset), ch2 (MRI, mri preset) and the
brainmaps54 cryosection (colour, rgb preset): ingest,
a small fit, `gvr export --dcc`, then examples/blender/render.py with the framing of
`gvr info --json` of the export, against `gvr render` of the asset at the same
azimuth, elevation and size. The silhouettes (alpha at least 0.3) must overlap with
an intersection over union of at least 0.8, and the mean luminance of the pixels
both cover must agree within 15 %; the chest is also drawn with ct-bone. With IMAGE_DIR, the two pictures of
each volume are written there side by side (Blender left, gvr right), as the README
shows them: then from one-minute fits at 20:1, at 256 pixels and 64 samples, and the
chest with its lungs kept (the default threshold) through the ct-bone preset, so that
the pictures show anatomy rather than the few Gaussians of the quick check.
"""
import os
import subprocess
import sys

import numpy as np
from PIL import Image

import checks
from checks import check

BLENDER = "/usr/bin/blender"
SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "blender", "render.py")
VIEW = ["--azimuth", "30", "--elevation", "15"]
MIN_IOU = 0.8
MAX_BRIGHTNESS_GAP = 0.15


def run(args):
    result = subprocess.run([str(a) for a in args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        print(result.stdout[-3000:], result.stderr[-3000:])
        raise RuntimeError(f"{os.path.basename(str(args[0]))} exited with {result.returncode}")
    return result.stdout


def silhouette(png):
    return np.asarray(Image.open(png).convert("RGBA"))[..., 3] >= 0.3 * 255


def mean_luminance(png, covered):
    """Mean Rec. 709 luminance of the straight RGB on @a covered pixels, in 0..1."""
    rgb = np.asarray(Image.open(png).convert("RGBA"))[..., :3].astype(np.float64) / 255
    return float((rgb @ np.array([0.2126, 0.7152, 0.0722]))[covered].mean())


def side_by_side(left, right, out):
    a, b = Image.open(left).convert("RGBA"), Image.open(right).convert("RGBA")
    canvas = Image.new("RGBA", (a.width + b.width, max(a.height, b.height)), (0, 0, 0, 255))
    canvas.paste(a, (0, 0), a)
    canvas.paste(b, (a.width, 0), b)
    canvas.convert("RGB").save(out)


def compare(gvr, name, source, ingest_flags, fit_flags, export_flags, scratch, size, image_dir, samples="16", tf=()):
    grid, asset = os.path.join(scratch, name + ".vdb"), os.path.join(scratch, name + ".gvr")
    dcc, info = os.path.join(scratch, name + "-dcc.vdb"), os.path.join(scratch, name + "-dcc.json")
    blender_png, gvr_png = os.path.join(scratch, name + "-blender.png"), os.path.join(scratch, name + "-gvr.png")
    run([gvr, "ingest", "-q", source, "-o", grid] + ingest_flags)
    run([gvr, "fit", "-q", grid, "-o", asset] + fit_flags)
    run([gvr, "export", "-q", asset, "-o", dcc, "--dcc"] + list(tf) + export_flags)
    with open(info, "w") as file:
        file.write(run([gvr, "info", "--json", dcc]))
    run([BLENDER, "-b", "--factory-startup", "--python-exit-code", "1", "-P", SCRIPT, "--", dcc, blender_png,
         "--frame", info, "--size", size, "--samples", samples] + VIEW)
    run([gvr, "render", "-q", asset, "-o", gvr_png, "--size", f"{size}x{size}"] + list(tf) + VIEW)
    a, b = silhouette(blender_png), silhouette(gvr_png)
    iou = (a & b).sum() / max((a | b).sum(), 1)
    check(f"{name}: Blender's silhouette of the --dcc export matches gvr render's (IoU >= {MIN_IOU})",
          iou >= MIN_IOU and b.sum() > 0.05 * b.size,
          f"IoU {iou:.3f}, {a.sum()} and {b.sum()} of {a.size} pixels")
    # A scattering material once rendered half as bright as gvr (0.25 against 0.48 on an MRI).
    covered = a & b
    ours, theirs = mean_luminance(gvr_png, covered), mean_luminance(blender_png, covered)
    check(f"{name}: Blender is as bright as gvr render on the pixels both cover (within {MAX_BRIGHTNESS_GAP:.0%})",
          covered.any() and abs(theirs / ours - 1.0) <= MAX_BRIGHTNESS_GAP,
          f"mean luminance {theirs:.3f} in Blender, {ours:.3f} in gvr render")
    if image_dir:
        side_by_side(blender_png, gvr_png, os.path.join(image_dir, name + "-blender-vs-gvr.png"))


def refuses_a_millimetre_export(gvr, scratch):
    """A plain export (millimetres, physical density) rendered as a fog box filling the frame."""
    plain, png = os.path.join(scratch, "ch2-plain.vdb"), os.path.join(scratch, "ch2-plain.png")
    run([gvr, "export", "-q", os.path.join(scratch, "ch2.gvr"), "-o", plain])
    done = subprocess.run([BLENDER, "-b", "--factory-startup", "--python-exit-code", "1", "-P", SCRIPT, "--",
                           plain, png, "--size", "16", "--samples", "1"], capture_output=True, text=True)
    check("render.py refuses an export without --dcc, naming the flag",
          done.returncode != 0 and "gvr export --dcc" in done.stdout + done.stderr and not os.path.exists(png),
          f"exit {done.returncode}")


def quick_fit(gaussians, iterations):
    return ["--gaussians", gaussians, "--iterations", iterations, "--solve-iterations", "0", "--seed", "1"]


def both_volumes(gvr, shared, scratch):
    image_dir = os.path.abspath(sys.argv[4]) if len(sys.argv) > 4 else None
    ch2 = os.path.join(shared, "mri-colin27-aal", "ch2.nii.gz")
    chest = os.path.join(shared, "ct-chest-ricord-512")
    brainmaps = os.path.join(shared, "rgb-brainmaps54-cryosection")
    if not image_dir:
        compare(gvr, "ch2", ch2, [], quick_fit("3000", "60"), [], scratch, "64", None)
        compare(gvr, "chest", chest, ["--threshold", "-500"], quick_fit("6000", "40"), ["--resolution", "128"],
                scratch, "64", None)
        # Bone is thin: at 128 voxels across, the export lost a third of its silhouette.
        compare(gvr, "chest-bone", chest, ["--threshold", "-500"], quick_fit("6000", "40"), ["--resolution", "256"],
                scratch, "64", None, tf=("--tf", "ct-bone"))
        # Its blue embedding medium once exported as a fog box around the section (alpha 0.68).
        compare(gvr, "brainmaps54", brainmaps, [], quick_fit("4000", "40"), [], scratch, "64", None)
        refuses_a_millimetre_export(gvr, scratch)
        return
    minute = ["--ratio", "20", "--time", "60", "--seed", "1"]
    compare(gvr, "ch2", ch2, [], minute, [], scratch, "256", image_dir, samples="64")
    compare(gvr, "chest", chest, [], minute, ["--resolution", "256"], scratch, "256", image_dir, samples="64",
            tf=("--tf", "ct-bone"))


if __name__ == "__main__":
    sys.exit(checks.run(both_volumes, __doc__))
