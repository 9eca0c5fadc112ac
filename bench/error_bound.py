#!/usr/bin/python3
"""gvr fit --max-error against error-bounded codecs at the same maximum error, one Markdown row a volume.

For each volume: the source as gvr reads it (gvr ingest to NIfTI, every voxel kept), the gvr+bound asset
(its ratio, the Gaussians' own ratio, the layer's encode seconds and the export's seconds, which decode
it), and, at the same bound, ZFP fixed-accuracy (gvr baseline), SZ3 ABS and SPERR PWE (built by
../shared/tools/codecs/build.sh; measuring tools, not dependencies). Every maximum error is read back
by nibabel in float64 against the source as read: the last columns are the largest over the four.
Ratios are raw source bytes over compressed bytes. Colour volumes are coded by SZ3 and SPERR channel by
channel (their bytes summed). Nothing is asserted; run it with nothing else on the machine.

Usage: bench/error_bound.py GVR DATA_DIR CODEC_DIR WORK_DIR [NAME ...]"""
import json, os, subprocess, sys, time
import nibabel as nib
import numpy as np

# name: source under DATA_DIR, bound in the source's units, the fit's seconds (the Gaussians at fit's
# default preview ratio under a bound), and gvr fit's further flags (paths under DATA_DIR)
VOLUMES = {
    "ch2": ("mri-colin27-aal/ch2.nii.gz", 4, 20, []),
    "ch2-lossless": ("mri-colin27-aal/ch2.nii.gz", 0.5, 20, []),
    "colin27-labels": ("mri-colin27-aal/ch2.nii.gz", 4, 20,
                       ["--label-volume", "mri-colin27-aal/aal.nii.gz", "--label-names", "mri-colin27-aal/aal.nii.txt",
                        "--labels", "all"]),
    "freesurfer-norm": ("mri-freesurfer-norm-aparc/norm.mgz", 4, 20, []),
    "ct-head": ("ct-head-visible-human-png", 4, 20, []),
    "chest": ("ct-chest-ricord-512", 1, 40, []),
    "gantry-tilt": ("ct-gantry-tilt-shear/shear.nii.gz", 8, 20, []),
    "brainmaps54": ("rgb-brainmaps54-cryosection", 4, 20, []),
    "frog": ("rgb-frog-cryosection/color_png", 4, 40, []),
    "ct-perfusion": ("rgb24-ct-perfusion/ct_perfusion.nii.gz", 4, 20, []),
    "asl": ("mri-4d-asl-float32/mpld_asl.nii.gz", 4, 20, []),
}


def fit_flags(data, flags):
    """gvr fit's further flags of a volume, its paths under @data."""
    return [os.path.join(data, f) if "/" in f else f for f in flags]


def run(*args):
    subprocess.run([str(a) for a in args], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def voxels(path):
    """The NIfTI's values in float64, shape (x, y, z, channels)."""
    data = np.asanyarray(nib.load(path).dataobj)
    if data.dtype.names:  # RGB24
        return np.stack([data[n].astype(np.float64) for n in data.dtype.names], axis=-1)
    data = nib.load(path).get_fdata(dtype=np.float64)
    return data.reshape(data.shape[:3] + (-1,))


def external(codec_dir, source, bound, work):
    """Bytes and maximum error of SZ3 ABS and SPERR PWE at @bound, channel by channel."""
    nx, ny, nz = source.shape[:3]
    sizes, worst = {"sz3": 0, "sperr": 0}, {"sz3": 0.0, "sperr": 0.0}
    for c in range(source.shape[3]):
        channel = source[..., c]
        np.asfortranarray(channel).T.astype(np.float32).tofile(f"{work}/in.raw")
        run(f"{codec_dir}/sz3", "-f", "-3", nx, ny, nz, "-M", "ABS", bound, "-i", f"{work}/in.raw",
            "-z", f"{work}/sz3.bin", "-o", f"{work}/sz3.raw")
        run(f"{codec_dir}/sperr3d", "c", f"{work}/in.raw", nx, ny, nz, "pwe", bound, f"{work}/sperr.bin")
        run(f"{codec_dir}/sperr3d", "d", f"{work}/sperr.bin", f"{work}/sperr.raw")
        for name in sizes:
            sizes[name] += os.path.getsize(f"{work}/{name}.bin")
            back = np.fromfile(f"{work}/{name}.raw", np.float32).reshape(channel.T.shape).T
            worst[name] = max(worst[name], float(np.abs(back.astype(np.float64) - channel).max()))
    return sizes, worst


def row(gvr, data, codec_dir, work, name):
    src, bound, seconds, flags = VOLUMES[name]
    src = os.path.join(data, src)
    ref, asset, export, zfp = (f"{work}/{name}{ext}" for ext in ("-asread.nii.gz", ".gvr", ".nii.gz", ".zfp"))
    run(gvr, "ingest", "-q", src, "--threshold", "-1e9", "-o", ref)
    fit = subprocess.run([gvr, "fit", "-q", src, "-o", asset, "--time", str(seconds), "--max-error", str(bound),
                          "--json", *fit_flags(data, flags)], check=True, capture_output=True, text=True)
    report = json.loads(fit.stdout)
    layer, raw = report["residual_layer"], report["raw_source_bytes"]
    start = time.perf_counter()
    run(gvr, "export", "-q", asset, "-o", export)
    export_seconds = time.perf_counter() - start
    run(gvr, "baseline", "-q", src, "--method", "zfp-accuracy", "--tolerance", bound, "--stream", zfp,
        "-o", f"{work}/{name}-zfp.vdb")
    source = voxels(ref)
    gvr_error = float(np.abs(voxels(export).reshape(source.shape) - source).max())
    sizes, worst = external(codec_dir, source, bound, work)
    largest = max(gvr_error, *worst.values())
    print(f"| {name} | {bound:g} | **{raw / report['file_bytes']:.2f}:1** | {raw / layer['gaussian_bytes']:.0f}:1 | "
          f"{raw / os.path.getsize(zfp):.2f}:1 | {raw / sizes['sz3']:.2f}:1 | {raw / sizes['sperr']:.2f}:1 | "
          f"{report['file_bytes'] / sizes['sz3']:.2f} | {layer['seconds']:.1f} s / {export_seconds:.1f} s | "
          f"{gvr_error:g} | {largest:g} |", flush=True)


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__.split("\n\n")[-1])
    gvr, data, codec_dir, work = (os.path.realpath(a) for a in sys.argv[1:5])
    os.makedirs(work, exist_ok=True)
    print("| volume | bound | gvr+bound | Gaussians | ZFP accuracy | SZ3 ABS | SPERR PWE | gvr / SZ3 bytes | "
          "layer encode / export | gvr max error | largest max error |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name in sys.argv[5:] or VOLUMES:
        row(gvr, data, codec_dir, work, name)


if __name__ == "__main__":
    main()
