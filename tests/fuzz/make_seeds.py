"""Writes the fuzzers' seed corpora: small valid files of every format gvr reads.

usage: make_seeds.py GVR SHARED_DATA OUT

OUT/<format>/ gets the seeds of each fuzz target in tests/fuzz. Volumes are small
(a few hundred voxels) so that the fuzzer mutates headers and data alike. VDB grids
and assets come from GVR itself; DICOM seeds are real slices from the shared data.
"""
import json
import pathlib
import shutil
import struct
import subprocess
import sys
import zlib

import nibabel
import numpy
from PIL import Image


def small_volume(dtype, shape=(6, 5, 4), offset=0):
    values = numpy.arange(numpy.prod(shape), dtype=numpy.float64).reshape(shape)
    return (values * 7 % 251 + offset).astype(dtype)


def write_nifti(folder):
    affine = numpy.diag([0.9, 1.1, 2.5, 1.0])
    for name, dtype, offset in [("uint8", numpy.uint8, 0), ("int16-hu", numpy.int16, -1024),
                                ("float32", numpy.float32, -0.5)]:
        nibabel.save(nibabel.Nifti1Image(small_volume(dtype, offset=offset), affine), folder / f"{name}.nii")
    rgb = numpy.zeros((4, 3, 2), dtype=[("R", "u1"), ("G", "u1"), ("B", "u1")])
    rgb["R"] = small_volume(numpy.uint8, (4, 3, 2))
    nibabel.save(nibabel.Nifti1Image(rgb, affine), folder / "rgb24.nii")


def write_mgh(folder):
    for name, dtype in [("uint8", numpy.uint8), ("float32", numpy.float32), ("int16", numpy.int16)]:
        nibabel.save(nibabel.MGHImage(small_volume(dtype), numpy.eye(4)), folder / f"{name}.mgh")


def metaimage(header, data):
    lines = [f"{key} = {value}" for key, value in header.items()]
    return ("\n".join(lines) + "\nElementDataFile = LOCAL\n").encode() + data


def write_metaimage(folder):
    volume = small_volume(numpy.int16, offset=-1000)
    header = {"ObjectType": "Image", "NDims": 3, "DimSize": "6 5 4", "ElementType": "MET_SHORT",
              "ElementSpacing": "1 1 2.5", "BinaryData": "True", "BinaryDataByteOrderMSB": "False"}
    raw = volume.transpose(2, 1, 0).tobytes()
    (folder / "short.mha").write_bytes(metaimage(header, raw))
    packed = zlib.compress(raw)
    compressed = dict(header, CompressedData="True", CompressedDataSize=len(packed))
    (folder / "short-zlib.mha").write_bytes(metaimage(compressed, packed))
    rgb = dict(header, ElementType="MET_UCHAR", ElementNumberOfChannels=3)
    (folder / "rgb.mha").write_bytes(metaimage(rgb, small_volume(numpy.uint8, (6, 5, 12)).tobytes()))


def write_raw(folder):
    # The fuzz target reads the layout from the first 16 bytes (see fuzz_input.cpp).
    for name, type_index, channels, bytes_per_sample in [("uint8", 0, 1, 1), ("int16", 3, 1, 2),
                                                         ("float32", 6, 1, 4), ("rgb", 0, 3, 1)]:
        dims = (5, 4, 3)
        layout = struct.pack("<HHHBBBB", dims[0] - 1, dims[1] - 1, dims[2] - 1, type_index,
                             0 if channels == 1 else 1, 0, 16) + bytes(6)
        data = bytes((7 * k) % 251 for k in range(5 * 4 * 3 * channels * bytes_per_sample))
        (folder / f"{name}.raw").write_bytes(layout + data)


def write_images(folder):
    grey = Image.fromarray(small_volume(numpy.uint8, (12, 10))[:, :])
    grey.save(folder / "grey.png")
    Image.fromarray(small_volume(numpy.uint16, (12, 10)) * 200).save(folder / "grey16.png")
    rgb = Image.fromarray(small_volume(numpy.uint8, (12, 10, 3)), "RGB")
    rgb.save(folder / "rgb.png")
    rgb.save(folder / "rgb.jpg", quality=90)
    grey.save(folder / "grey.tif")
    rgb.save(folder / "rgb.bmp")


def write_dicom(folder, shared):
    # Real slices: JPEG-lossless CT (16-bit HU), the smallest file of the series.
    series = sorted((shared / "ct-chest-ricord-512").glob("*.dcm"), key=lambda p: p.stat().st_size)
    shutil.copy(series[0], folder / "jpeg-lossless.dcm")


def write_vdb_and_assets(gvr, vdb_folder, asset_folder, work):
    for name in ["uint8", "int16-hu"]:
        source = work / "nifti" / f"{name}.nii"
        grid = vdb_folder / f"{name}.vdb"
        subprocess.run([gvr, "ingest", str(source), "-o", str(grid)], check=True, stdout=subprocess.DEVNULL)
        # Format 2, and format 3 with a residual layer; the asset target appends the
        # CRC-32 itself, so its seeds leave it off.
        for kind, bound in [("", []), ("-bounded", ["--max-error", "2"])]:
            asset = work / f"{name}{kind}.gvr"
            subprocess.run([gvr, "fit", str(grid), "-o", str(asset), "--gaussians", "12", "--iterations", "3", *bound],
                           check=True, stdout=subprocess.DEVNULL)
            (asset_folder / f"{name}{kind}.gvr-body").write_bytes(asset.read_bytes()[:-4])
    subprocess.run([gvr, "ingest", str(work / "nifti" / "rgb24.nii"), "-o", str(vdb_folder / "rgb.vdb")],
                   check=True, stdout=subprocess.DEVNULL)


def write_json_inputs(folders, examples):
    tf = {"points": [[-1000, 0, 0, 0, 0], [300, 1, 0.9, 0.8, 0.05], [3000, 1, 1, 1, 0.6]]}
    (folders["tf"] / "ct.json").write_text(json.dumps(tf))
    (folders["tf"] / "one.json").write_text('{"points": [[0.5, 1, 1, 1, 1]]}')
    (folders["labelstyle"] / "styles.json").write_text(
        json.dumps({"Hippocampus_L": {"color": [1, 0, 0], "opacity": 0.5}, "17": {"opacity": 0}}))
    for manifest in sorted(examples.glob("bench-*.json")):
        shutil.copy(manifest, folders["manifest"] / manifest.name)
    # The results target puts the header before its input when the first byte is not
    # a multiple of 4: these are rows (measured, failed, quoted), each after such a byte.
    rows = ["ch2,10,gvr,ok,,17204,40.1,160.4,0.8,31.2,29.5,0.91,0.95,33.1,0.93,12.5,0.3,410,25,,runs/ch2/r10/gvr/fit.csv,"
            "runs/ch2/r10/gvr/view_0000.png,work/ch2/truth_0000.png",
            'ct-head,20,zfp-rate,failed,"ingest: cannot read, ""x""",,,,,,,,,,,,,,,,,,']
    for index, row in enumerate(rows):
        (folders["results"] / f"rows-{index}.csv").write_bytes(b"\x01" + (row + "\n").encode())


def main():
    gvr, shared, out = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
    folders = {name: out / name for name in ["nifti", "metaimage", "mgh", "raw", "dicom", "image", "vdb", "asset",
                                               "tf", "labelstyle", "manifest", "results"]}
    for folder in folders.values():
        folder.mkdir(parents=True, exist_ok=True)
    write_nifti(folders["nifti"])
    write_mgh(folders["mgh"])
    write_metaimage(folders["metaimage"])
    write_raw(folders["raw"])
    write_images(folders["image"])
    write_dicom(folders["dicom"], shared)
    write_json_inputs(folders, pathlib.Path(__file__).resolve().parent.parent.parent / "examples")
    work = out / "work"
    work.mkdir(exist_ok=True)
    for name in ["nifti", "mgh"]:
        shutil.copytree(folders[name], work / name, dirs_exist_ok=True)
    write_vdb_and_assets(gvr, folders["vdb"], folders["asset"], work)
    v1 = pathlib.Path(__file__).resolve().parent.parent / "data" / "asset-v1-blobs.gvr"
    (folders["asset"] / "v1-blobs.gvr-body").write_bytes(v1.read_bytes()[:-4])
    shutil.rmtree(work)
    for name, folder in folders.items():
        print(f"{name}: {len(list(folder.iterdir()))} seeds in {folder}")


if __name__ == "__main__":
    main()
