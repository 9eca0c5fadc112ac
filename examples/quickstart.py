#!/usr/bin/python3
"""gvr from Python in one page: a NIfTI read with nibabel, fitted, exported,
evaluated and rendered, then plotted with matplotlib.

    /usr/bin/python3 examples/quickstart.py [VOLUME.nii.gz] [OUT_FOLDER]

Needs the gvr module: `bash examples/run-default.sh` installs it, or run with
PYTHONPATH=build/python after .ci/build.sh.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files, no window
import matplotlib.pyplot as plt
import nibabel
import numpy as np

import gvr

source = sys.argv[1] if len(sys.argv) > 1 else "/usr/share/mricron/templates/ch2.nii.gz"
out = sys.argv[2] if len(sys.argv) > 2 else "out"
os.makedirs(out, exist_ok=True)

# 1. A volume from nibabel: its scaling applied, its affine placing it in millimetres,
#    and the type the file stores kept for the ratio; values keep their units (HU stays HU).
#    (Volume.from_numpy takes any array, indexed [i, j, k] as nibabel gives them.)
image = nibabel.load(source)
volume = gvr.Volume.from_nibabel(image)
print(f"{source}: {volume.shape} voxels, {volume.metadata['source_type']}")


# 2. Fit Gaussians at 20:1 against the raw bytes, for 20 seconds.
def progress(state):
    if state["held_out_psnr_db"] is not None:
        print(f"\r  fitting: {100 * state['fraction']:3.0f} %, {state['held_out_psnr_db']:.2f} dB held-out",
              end="", flush=True)


asset = gvr.fit(volume, ratio=20, seconds=20, progress=progress)
asset.save(f"{out}/quickstart.gvr")
print(f"\n  {asset.count} Gaussians -> {out}/quickstart.gvr ({os.path.getsize(f'{out}/quickstart.gvr')} bytes)")

# 3. Export the field onto the source's grid, and write it as NIfTI with nibabel.
reconstruction = asset.export()
nibabel.save(nibabel.Nifti1Image(reconstruction.to_numpy(), reconstruction.affine),
             f"{out}/quickstart-reconstruction.nii.gz")

# 4. Evaluate: the keys of `gvr eval --json`.
quality = gvr.evaluate(volume, reconstruction)
print(f"  PSNR {quality['psnr']:.2f} dB, foreground {quality['fg_psnr']:.2f} dB, SSIM {quality['ssim']:.4f}")

# 5. Render a shear-warp view straight from the Gaussians, and plot it beside a
#    middle slice of the source and of the reconstruction.
view = gvr.render(asset, azimuth=30, elevation=15, size=(384, 384))
k = volume.shape[2] // 2
figure, axes = plt.subplots(1, 3, figsize=(12, 4))
for axis, (title, picture) in zip(axes, [("source", volume.to_numpy()[:, :, k].T),
                                         ("reconstruction", reconstruction.to_numpy()[:, :, k].T),
                                         ("shear-warp view", np.clip(view[..., :3], 0, 1))]):
    axis.imshow(picture, cmap="gray", origin="lower" if title != "shear-warp view" else "upper")
    axis.set_title(title)
    axis.axis("off")
figure.tight_layout()
figure.savefig(f"{out}/quickstart.png", dpi=100)
print(f"  plots -> {out}/quickstart.png")
