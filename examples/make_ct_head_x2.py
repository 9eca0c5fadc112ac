"""Writes ct-head resampled x2 along each axis as a raw uint8 volume, for the
"Larger than one machine" runs: 1024 x 1024 x 468 voxels, about 490 M, made on
the fly from the shared PNG stack so that no large file is committed.

Usage: /usr/bin/python3 examples/make_ct_head_x2.py ../shared/data/ct-head-visible-human-png OUT.raw
Then:  gvr ingest OUT.raw --raw-dims 1024,1024,468 --raw-type uint8 --spacing 0.5,0.5,0.5 -o OUT.vdb

Slices are linearly interpolated in-plane and between neighbours and written one
at a time: the script holds the in-plane-doubled slices (about 1 GB as float32),
never the output volume.
"""
import os
import sys

import numpy as np
from PIL import Image


def slices(folder):
    names = sorted((n for n in os.listdir(folder) if n.endswith(".png")),
                   key=lambda n: int(n.split("-")[1].split(".")[0]))
    for name in names:
        yield np.asarray(Image.open(os.path.join(folder, name)).convert("L"), dtype=np.float32)


def doubled(a, axis):
    """Samples at the centres of the two halves of every voxel: a linear ramp
    between neighbours, the edge voxel repeated beyond the ends."""
    before = np.concatenate([np.take(a, [0], axis), np.take(a, range(a.shape[axis] - 1), axis)], axis)
    after = np.concatenate([np.take(a, range(1, a.shape[axis]), axis), np.take(a, [a.shape[axis] - 1], axis)], axis)
    out = np.empty(a.shape[:axis] + (2 * a.shape[axis],) + a.shape[axis + 1:], np.float32)
    index = [slice(None)] * a.ndim
    index[axis] = slice(0, None, 2)
    out[tuple(index)] = 0.75 * a + 0.25 * before
    index[axis] = slice(1, None, 2)
    out[tuple(index)] = 0.75 * a + 0.25 * after
    return out


def main():
    folder, output = sys.argv[1:3]
    planes = [doubled(doubled(s, 0), 1) for s in slices(folder)]  # 234 x 4 MB as float32
    with open(output + ".part", "wb") as out:
        for k, plane in enumerate(planes):
            below = planes[max(k - 1, 0)]
            above = planes[min(k + 1, len(planes) - 1)]
            for neighbour in (below, above):
                out.write(np.clip(np.rint(0.75 * plane + 0.25 * neighbour), 0, 255).astype(np.uint8).tobytes())
    os.replace(output + ".part", output)
    print(f"wrote {output}: 1024 x 1024 x {2 * len(planes)} uint8")


main()
