"""Writes a raw uint8 volume larger than this machine's memory that is mostly
empty: a sparse file of 4096 x 4096 x 2048 voxels (32 GiB, 128 GiB as float32)
holding four copies of a smaller raw volume, for the streamed-ingest run of the
"Larger than one machine" section. The empty space is left as holes, so the file
takes only the copies' bytes on disk.

Usage: /usr/bin/python3 examples/make_sparse_giant.py x2.raw 1024,1024,468 giant.raw
(x2.raw from examples/make_ct_head_x2.py). Then:
    gvr ingest giant.raw --raw-dims 4096,4096,2048 --raw-type uint8 -o giant.vdb
"""
import os
import sys

DIMS = (4096, 4096, 2048)
# Where each copy's first voxel goes: one per quadrant of the plane, at four depths.
OFFSETS = [(0, 0, 0), (2048, 0, 512), (0, 2048, 1024), (2048, 2048, 1536)]


def main():
    source, source_dims, output = sys.argv[1:4]
    nx, ny, nz = (int(d) for d in source_dims.split(","))
    if os.path.getsize(source) != nx * ny * nz:
        sys.exit(f"{source}: expected {nx * ny * nz} bytes of uint8 for {source_dims}")
    for ox, oy, oz in OFFSETS:
        if ox + nx > DIMS[0] or oy + ny > DIMS[1] or oz + nz > DIMS[2]:
            sys.exit(f"{source}: {source_dims} does not fit four times into {DIMS}")
    part = output + ".part"
    with open(source, "rb") as src, open(part, "wb") as out:
        out.truncate(DIMS[0] * DIMS[1] * DIMS[2])
        for k in range(nz):
            plane = src.read(nx * ny)
            for ox, oy, oz in OFFSETS:
                for j in range(ny):
                    at = ((oz + k) * DIMS[1] + oy + j) * DIMS[0] + ox
                    os.pwrite(out.fileno(), plane[j * nx:(j + 1) * nx], at)
    os.replace(part, output)
    print(f"wrote {output}: {DIMS[0]} x {DIMS[1]} x {DIMS[2]} uint8 with 4 copies of {source}")


if __name__ == "__main__":
    main()
