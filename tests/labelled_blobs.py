"""Two labelled blobs as NIfTI files, for the tests that need a fit by structure:
1 "Left" and 2 "Right" in a 32 x 20 x 16 volume, with an "ID NAME" list."""
import os

import nibabel
import numpy as np


def write_labelled_blobs(folder):
    """Writes blobs.nii, labels.nii and names.txt into folder; their paths."""
    i, j, k = np.meshgrid(np.arange(32), np.arange(20), np.arange(16), indexing="ij")
    left = (i - 9) ** 2 + (j - 10) ** 2 + (k - 8) ** 2
    right = (i - 23) ** 2 + (j - 10) ** 2 + (k - 8) ** 2
    image = (200 * np.exp(-left / 18) + 120 * np.exp(-right / 12)).astype(np.float32)
    labels = np.where(left < 36, 1, np.where(right < 25, 2, 0)).astype(np.int16)
    paths = [os.path.join(str(folder), name) for name in ("blobs.nii", "labels.nii", "names.txt")]
    nibabel.save(nibabel.Nifti1Image(image, np.eye(4)), paths[0])
    nibabel.save(nibabel.Nifti1Image(labels, np.eye(4)), paths[1])
    with open(paths[2], "w") as names:
        names.write("1 Left\n2 Right\n")
    return paths
