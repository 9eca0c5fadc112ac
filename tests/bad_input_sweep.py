"""Bad input, class by class, the way a careless or hostile user would give it.

usage: bad_input_sweep.py GVR SHARED_DATA WORK_DIR [--json]

Every case must end as the README's Errors section promises: exit code 2, exactly
one line on stderr starting "gvr: error:", no output file, and every input file
unchanged. Damage that a format cannot detect (a flipped byte in uncompressed
samples or in a VDB, which carry no checksum) may also give exit 0, and a header
that only lacks a voxel size gives exit 0 with a warning; never a crash or a hang. Prints a table of cases tried and handled per
class, and fails if any case is not handled.
"""
import collections
import gzip
import hashlib
import json
import os
import pathlib
import re
import struct
import subprocess
import sys
import time
import zlib

import nibabel
import numpy

import checks

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent / "fuzz"))
import make_seeds  # noqa: E402  (small valid files of every format)

TIMEOUT_SECONDS = 120
Case = collections.namedtuple("Case", "kind name args inputs outputs may_succeed")
cases = []


def case(kind, name, args, inputs=(), outputs=("out.vdb",), may_succeed=False):
    cases.append(Case(kind, name, [str(a) for a in args], [pathlib.Path(p) for p in inputs], outputs, may_succeed))


def cut(source, target, keep):
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_bytes(source.read_bytes()[:keep])
    return target


def flipped(source, target, offset):
    data = bytearray(source.read_bytes())
    data[offset] ^= 0x5A
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_bytes(bytes(data))
    return target


def patched(source, target, offset, fmt, value):
    data = bytearray(source.read_bytes())
    struct.pack_into(fmt, data, offset, value)
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_bytes(bytes(data))
    return target


def fractions(count):
    return [(k + 0.5) / count for k in range(count)]


def truncated_files(work, shared, seeds):
    sources = {
        "nii.gz": shared / "mri-colin27-aal/ch2.nii.gz",
        "nii": seeds / "nifti/int16-hu.nii",
        "mgz": shared / "mri-freesurfer-norm-aparc/norm.mgz",
        "mgh": seeds / "mgh/float32.mgh",
        "mha": seeds / "metaimage/short.mha",
        "mha-zlib": seeds / "metaimage/short-zlib.mha",
    }
    for label, source in sources.items():
        size = source.stat().st_size
        for f in fractions(8):
            target = cut(source, work / f"cut-{label}-{f:.3f}" / source.name, int(size * f))
            case("truncated file", f"{label} cut at {f:.0%}", ["ingest", target, "-o", "out.vdb"], [target])
    slices = {
        "png": sorted((shared / "ct-head-visible-human-png").glob("*.png"))[0],
        "jpeg": seeds / "image/rgb.jpg",
        "dicom": sorted((shared / "ct-chest-ricord-512").glob("*.dcm"), key=lambda p: p.stat().st_size)[0],
    }
    for label, source in slices.items():
        size = source.stat().st_size
        keeps = [int(size * f) for f in fractions(8)]
        if label == "dicom":  # inside the file meta information and the dataset header
            keeps += [130, 200, 400, 700, 1000, 1400, 2000, 2800]
        for keep in keeps:
            folder = work / f"cut-{label}-{keep}"
            target = cut(source, folder / source.name, keep)
            case("truncated file", f"{label} slice cut at {keep} bytes", ["ingest", folder, "-o", "out.vdb"], [target])


def truncated_tiff_pages(work):
    """A multi-page TIFF cut short: libtiff ends its page chain quietly at the cut."""
    from PIL import Image
    rng = numpy.random.default_rng(5)
    pages = [Image.fromarray(rng.integers(0, 255, (48, 40), dtype=numpy.uint8)) for _ in range(5)]
    whole = work / "pages.tif"
    pages[0].save(whole, save_all=True, append_images=pages[1:])
    size = whole.stat().st_size
    for f in fractions(8):
        target = cut(whole, work / f"cut-tiff-{f:.3f}" / whole.name, int(size * f))
        case("truncated file", f"5-page TIFF cut at {f:.0%}", ["ingest", target, "-o", "out.vdb"], [target])


def bench_inputs(work, gvr, grid):
    """A manifest and a results folder are inputs: names that would be paths, repeated
    keys, views too large, bytes that are not UTF-8, and rows no bench wrote."""
    manifests = {
        "a volume named ..": {"volumes": [{"name": "..", "input": str(grid)}]},
        "a volume named a/b": {"volumes": [{"name": "a/b", "input": str(grid)}]},
        "a codec named ../x": {"codecs": {"../x": {}}, "volumes": [{"input": str(grid)}]},
        "a volume name of 300 characters": {"volumes": [{"name": "x" * 300, "input": str(grid)}]},
        "render size 100000x100000": {"render": {"size": "100000x100000"}, "volumes": [{"input": str(grid)}]},
        "the ratio 8 twice": {"ratios": [8, 8.0], "volumes": [{"input": str(grid)}]},
    }
    for label, manifest in manifests.items():
        target = work / f"bench-{len(cases)}.json"
        target.write_text(json.dumps(manifest))
        case("bench input", f"manifest with {label}", ["bench", target, "-o", "bench-out"], [target], ["bench-out"])
    repeated = work / "bench-repeated-key.json"
    repeated.write_text('{"ratios": [10], "ratios": [20], "volumes": [{"input": "%s"}]}' % grid)
    not_utf8 = work / "bench-not-utf8.json"
    not_utf8.write_bytes(b'{"volumes": [{"name": "ch\xff", "input": "%s"}]}' % str(grid).encode())
    for label, target in [("a key twice", repeated), ("bytes that are not UTF-8", not_utf8)]:
        case("bench input", f"manifest with {label}", ["bench", target, "-o", "bench-out"], [target], ["bench-out"])
    manifest = work / "bench-resumed.json"
    manifest.write_text(json.dumps({"methods": ["vdb-half"], "render": {"size": "16x16", "views": 1},
                                    "volumes": [{"name": "grid", "input": str(grid)}]}))
    real = work / "results-real"
    subprocess.run([gvr, "bench", str(manifest), "-o", str(real)], check=True, capture_output=True)
    header = (real / "results.csv").read_text().splitlines(keepends=True)[0]
    for label, row in [("a row still running", "grid,,vdb-half,running,,10"),
                       ("a measured row whose bytes are words", "grid,,vdb-half,ok,,many"),
                       ("a row of a method no one named", "grid,,secret,ok,,10")]:
        folder = work / f"results-{len(cases)}"
        folder.mkdir()
        (folder / "results.csv").write_text(header + row + "," * (header.count(",") - row.count(",")) + "\n")
        case("bench input", f"--resume of a results folder with {label}",
             ["bench", manifest, "-o", folder, "--resume"], [manifest, folder / "results.csv"], ())
    linked = work / "results-linked"
    linked.mkdir()
    (linked / "results.csv").write_text(header)
    notes = work / "notes.txt"
    notes.write_text("a user's notes")
    (linked / "bench_report.py").symlink_to(notes)
    case("bench input", "--resume of a results folder whose report script links to a user's file",
         ["bench", manifest, "-o", linked, "--resume"], [manifest, notes], ())


def corrupt_compressed(work, shared, seeds):
    sources = {
        "nii.gz": shared / "mri-colin27-aal/ch2.nii.gz",
        "mgz": shared / "mri-freesurfer-norm-aparc/norm.mgz",
        "mha-zlib": seeds / "metaimage/short-zlib.mha",
        "png": sorted((shared / "ct-head-visible-human-png").glob("*.png"))[0],
    }
    for label, source in sources.items():
        size = source.stat().st_size
        start = source.read_bytes().index(b"LOCAL\n") + 8 if label == "mha-zlib" else 64
        for f in fractions(6):
            offset = start + int((size - start - 16) * f)
            folder = work / f"flip-{label}-{offset}"
            target = flipped(source, folder / source.name, offset)
            where = folder if label == "png" else target
            case("corrupt compressed data", f"{label} byte {offset} flipped", ["ingest", where, "-o", "out.vdb"], [target])


def nifti_float(work, name, values):
    path = work / name
    nibabel.save(nibabel.Nifti1Image(values.astype(numpy.float32), numpy.diag([1.0, 1.0, 2.0, 1.0])), path)
    return path


def absurd_headers(work, seeds):
    nii = seeds / "nifti/uint8.nii"
    for dims in [(1600, 1600, 1600), (32767, 32767, 32767), (-5, 4, 4), (0, 4, 4)]:
        data = bytearray(nii.read_bytes())
        struct.pack_into("<3h", data, 42, *dims)
        target = work / f"dims-{dims[0]}-{dims[1]}.nii"
        target.write_bytes(bytes(data))
        case("absurd dimensions", f"NIfTI claiming {dims}", ["ingest", target, "-o", "out.vdb"], [target])
        packed = work / f"dims-{dims[0]}-{dims[1]}.nii.gz"
        packed.write_bytes(gzip.compress(bytes(data)))
        case("absurd dimensions", f"NIfTI .gz claiming {dims}", ["ingest", packed, "-o", "out.vdb"], [packed])
    mgh = seeds / "mgh/uint8.mgh"
    for dims in [(30000, 30000, 30000), (-1, 5, 4)]:
        data = bytearray(mgh.read_bytes())
        struct.pack_into(">3i", data, 4, *dims)
        target = work / f"dims-{dims[0]}.mgh"
        target.write_bytes(bytes(data))
        case("absurd dimensions", f"MGH claiming {dims}", ["ingest", target, "-o", "out.vdb"], [target])
    many = nibabel.load(seeds / "nifti/uint8.nii")
    for _ in range(100000):  # nifticlib's list of extensions grows by copying: minutes, before
        many.header.extensions.append(nibabel.nifti1.Nifti1Extension(0, b"gvr-test"))
    target = work / "extensions.nii"
    nibabel.save(many, target)
    case("absurd dimensions", "NIfTI with 100,000 header extensions", ["ingest", target, "-o", "out.vdb"], [target])
    mha = seeds / "metaimage/short.mha"
    target = work / "dims-huge.mha"
    target.write_bytes(mha.read_bytes().replace(b"DimSize = 6 5 4", b"DimSize = 100000 100000 100000"))
    case("absurd dimensions", "MetaImage claiming 1e5 cubed", ["ingest", target, "-o", "out.vdb"], [target])
    png = seeds / "image/grey.png"
    for side in [30000, 65535]:
        data = bytearray(png.read_bytes())
        struct.pack_into(">II", data, 16, side, side)
        struct.pack_into(">I", data, 29, zlib.crc32(bytes(data[12:29])))
        folder = work / f"png-{side}"
        folder.mkdir()
        for k in range(3):
            (folder / f"{k}.png").write_bytes(bytes(data))
        case("absurd dimensions", f"three PNGs claiming {side} squared", ["ingest", folder, "-o", "out.vdb"], [folder / "0.png"])
    raw = work / "small.raw"
    raw.write_bytes(bytes(64))
    case("absurd dimensions", "raw file with --raw-dims 100000 cubed",
         ["ingest", raw, "-o", "out.vdb", "--raw-dims", "100000,100000,100000", "--raw-type", "uint8"], [raw])
    case("absurd dimensions", "raw file larger than its dims claim nothing of",
         ["ingest", raw, "-o", "out.vdb", "--raw-dims", "4,4,8", "--raw-type", "float32"], [raw])


def bad_values(work):
    values = numpy.arange(60, dtype=numpy.float32).reshape(5, 4, 3)
    for label, bad in [("NaN", numpy.nan), ("Inf", numpy.inf), ("-Inf", -numpy.inf)]:
        v = values.copy()
        v[2, 1, 1] = bad
        target = nifti_float(work, f"value-{label}.nii", v)
        case("NaN/Inf values", f"NIfTI float with one {label}", ["ingest", target, "-o", "out.vdb"], [target])
    target = work / "value-nan.mha"
    header = {"ObjectType": "Image", "NDims": 3, "DimSize": "2 2 2", "ElementType": "MET_FLOAT",
              "BinaryData": "True", "BinaryDataByteOrderMSB": "False"}
    target.write_bytes(make_seeds.metaimage(header, numpy.array([1, 2, numpy.nan, 4, 5, 6, 7, 8], numpy.float32).tobytes()))
    case("NaN/Inf values", "MetaImage float with a NaN", ["ingest", target, "-o", "out.vdb"], [target])


def unsupported_and_inconsistent_headers(work, seeds):
    nii = seeds / "nifti/float32.nii"
    for datatype, bitpix, label in [(32, 64, "complex64"), (1536, 128, "float128"), (2304, 32, "RGBA32"),
                                    (1792, 128, "complex128"), (77, 8, "unknown type 77")]:
        data = bytearray(nii.read_bytes())
        struct.pack_into("<hh", data, 70, datatype, bitpix)
        target = work / f"type-{datatype}.nii"
        target.write_bytes(bytes(data))
        case("unsupported type", f"NIfTI datatype {label}", ["ingest", target, "-o", "out.vdb"], [target])
    mgh = seeds / "mgh/uint8.mgh"
    target = patched(mgh, work / "type-99.mgh", 20, ">i", 99)
    case("unsupported type", "MGH type 99", ["ingest", target, "-o", "out.vdb"], [target])
    mha = seeds / "metaimage/short.mha"
    target = work / "type-string.mha"
    target.write_bytes(mha.read_bytes().replace(b"MET_SHORT", b"MET_STRING"))
    case("unsupported type", "MetaImage MET_STRING", ["ingest", target, "-o", "out.vdb"], [target])
    for offset, label in [(1e12, "1e12"), (-100.0, "-100"), (float("nan"), "NaN"), (352.5, "352.5")]:
        target = patched(nii, work / f"voxoffset-{label}.nii", 108, "<f", offset)
        case("inconsistent header", f"NIfTI vox_offset {label}", ["ingest", target, "-o", "out.vdb"], [target])
    data = bytearray(nii.read_bytes())
    struct.pack_into("<h", data, 254, 1)  # sform_code: scanner
    struct.pack_into("<4f", data, 280, 1.0, 0.0, 0.0, float("inf"))
    target = work / "sform-inf.nii"
    target.write_bytes(bytes(data))
    case("inconsistent header", "NIfTI sform with an Inf offset", ["ingest", target, "-o", "out.vdb"], [target])
    for pixdim, label in [((0.0, 1.0, 1.0), "0"), ((float("nan"), 1.0, 1.0), "NaN")]:
        data = bytearray(nii.read_bytes())
        struct.pack_into("<h", data, 252, 0)  # qform_code 0: pixdim alone gives the spacing
        struct.pack_into("<h", data, 254, 0)
        struct.pack_into("<3f", data, 80, *pixdim)
        target = work / f"pixdim-{label}.nii"
        target.write_bytes(bytes(data))
        case("inconsistent header", f"NIfTI pixdim {label}", ["ingest", target, "-o", "out.vdb"], [target],
             may_succeed="gvr: warning: pixdim[1] is")
    for volume in ["-1", "5"]:
        case("inconsistent header", f"MGH --volume {volume} of 1", ["ingest", mgh, "-o", "out.vdb", "--volume", volume], [mgh])


def path_escapes(work, seeds):
    (work / "escape").mkdir()
    raw = seeds / "metaimage/short.mha"
    header = raw.read_bytes().split(b"ElementDataFile")[0]
    for label, name in [("relative ../", "../../../../../../etc/passwd"), ("absolute", "/etc/passwd")]:
        target = work / "escape" / f"{label.split()[0]}.mhd"
        target.write_bytes(header.replace(b"DimSize = 6 5 4", b"DimSize = 4 4 2") + f"ElementDataFile = {name}\n".encode())
        case("data file outside the header's folder", f"MetaImage ElementDataFile {label}",
             ["ingest", target, "-o", "out.vdb"], [target])


def gvr_files(work, gvr, seeds):
    grid, asset = work / "small.vdb", work / "small.gvr"
    subprocess.run([gvr, "ingest", seeds / "nifti/int16-hu.nii", "-o", grid], check=True, capture_output=True)
    subprocess.run([gvr, "fit", grid, "-o", asset, "--gaussians", "40", "--iterations", "5"], check=True,
                   capture_output=True)
    return grid, asset


def with_header(asset, change):
    """The asset's bytes after change(body, header) edits them, with the CRC made right again."""
    data = asset.read_bytes()
    header_length = struct.unpack_from("<I", data, 12)[0]
    header = json.loads(data[16:16 + header_length])
    body = bytearray(data[:-4])
    change(body, header)
    text = json.dumps(header).encode()
    rebuilt = bytearray(body[:12]) + struct.pack("<I", len(text)) + text + body[16 + header_length:]
    return bytes(rebuilt + struct.pack("<I", zlib.crc32(bytes(rebuilt))))


def damaged_layers(work, gvr, grid):
    """A residual layer (format 3) cut short, or whose header lies with a valid CRC: every reader refuses it."""
    asset = work / "bounded.gvr"
    subprocess.run([gvr, "fit", grid, "-o", asset, "--gaussians", "40", "--iterations", "5", "--max-error", "3"],
                   check=True, capture_output=True)
    size, layer_start = asset.stat().st_size, size_without_layer(asset)
    for f in fractions(6):
        target = cut(asset, work / f"layer-cut-{f:.2f}.gvr", layer_start + int((size - layer_start) * f))
        case("damaged asset", f"residual layer cut at {f:.0%}", ["export", target, "-o", "out.vdb"], [target])
    readers = [("export", ["-o", "out.vdb"], ["out.vdb"]), ("probe", ["--index", "1,1,1"], []),
               ("render", ["-o", "out.png"], ["out.png"])]
    for label, key, value in [("bound -1", "bound", -1.0), ("bound NaN", "bound", float("nan")),
                              ("slope 0", "slope", 0.0), ("slab_slices 0", "slab_slices", 0),
                              ("exact_voxels 2^40", "exact_voxels", 1 << 40),
                              ("section_bytes + 1", "section_bytes", None), ("domain 'fixed'", "domain", "fixed")]:
        def change(body, header, key=key, value=value):
            header["residual"][key] = header["residual"][key] + 1 if value is None else value
        target = work / ("layer-" + "".join(c if c.isalnum() else "-" for c in label) + ".gvr")
        target.write_bytes(with_header(asset, change))
        for command, flags, outputs in readers:
            case("damaged asset", f"{command} of a residual layer with a valid CRC but {label}",
                 [command, target, *flags], [target], outputs)


def size_without_layer(asset):
    """Where the residual section starts: the file's end less its section and the CRC."""
    data = asset.read_bytes()
    header = json.loads(data[16:16 + struct.unpack_from("<I", data, 12)[0]])
    return len(data) - 4 - header["residual"]["section_bytes"]


def damaged_assets(work, asset):
    size = asset.stat().st_size
    for f in fractions(10):
        target = cut(asset, work / f"asset-cut-{f:.2f}.gvr", int(size * f))
        case("damaged asset", f"asset cut at {f:.0%}", ["export", target, "-o", "out.vdb"], [target])
    for f in fractions(12):
        offset = min(size - 1, int(size * f))
        target = flipped(asset, work / f"asset-flip-{offset}.gvr", offset)
        case("damaged asset", f"asset byte {offset} flipped", ["render", target, "-o", "out.png"], [target], ["out.png"])
    for label, change in [("version 99", lambda d, h: struct.pack_into("<I", d, 8, 99)),
                          ("count + 1", lambda d, h: h.update(count=h["count"] + 1)),
                          ("cutoff 0", lambda d, h: h.update(cutoff_sigmas=0.0)),
                          ("singular transform", lambda d, h: h.update(world_from_index=[0.0] * 16)),
                          ("value_scale 1e308", lambda d, h: h.update(value_scale=1e308)),
                          ("a projective transform", lambda d, h: h.update(
                              world_from_index=[1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1])),
                          ("w = 0", lambda d, h: h.update(world_from_index=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0])),
                          ("an offset of 1e300 mm", lambda d, h: h.update(
                              world_from_index=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1e300, 0, 0, 1])),
                          ("a count of 16.7 million", lambda d, h: h.update(count=1 << 24))]:
        target = work / f"asset-{label.replace(' ', '-')}.gvr"
        target.write_bytes(with_header(asset, change))
        case("damaged asset", f"asset with a valid CRC but {label}", ["export", target, "-o", "out.vdb"], [target])
        case("damaged asset", f"rendering an asset with a valid CRC but {label}", ["render", target, "-o", "out.png"],
             [target], ["out.png"])
    deep = work / "asset-deep.gvr"
    text = b"[" * 100000 + b"]" * 100000
    deep.write_bytes(asset.read_bytes()[:12] + struct.pack("<I", len(text)) + text + b"\0" * 8)
    case("damaged asset", "asset header nested 100,000 deep", ["info", deep], [deep], ())


def damaged_grids(work, grid):
    size = grid.stat().st_size
    for f in fractions(8):
        target = cut(grid, work / f"grid-cut-{f:.3f}.vdb", int(size * f))
        case("damaged VDB", f"VDB cut at {f:.0%}", ["fit", target, "-o", "out.gvr", "--gaussians", "8", "--iterations", "2"],
             [target], ["out.gvr"])
    for f in fractions(8):
        offset = int(size * f)
        target = flipped(grid, work / f"grid-flip-{offset}.vdb", offset)
        case("damaged VDB (no checksum)", f"VDB byte {offset} flipped", ["info", target], [target], (), may_succeed=True)


def outputs_and_flags(work, grid, asset):
    fifo = work / "fifo"
    os.mkfifo(fifo)
    (work / "a-folder").mkdir()
    for label, args, inputs in [
        ("ingest -o equal to its input", ["ingest", grid, "-o", grid], [grid]),
        ("fit -o equal to its input", ["fit", grid, "-o", grid, "--iterations", "2"], [grid]),
        ("export -o equal to its input", ["export", asset, "-o", asset], [asset]),
        ("-o a FIFO", ["export", asset, "-o", fifo], [asset]),
        ("-o /dev/null", ["export", asset, "-o", "/dev/null"], [asset]),
        ("-o a folder", ["export", asset, "-o", work / "a-folder"], [asset]),
        ("-o in a missing folder", ["export", asset, "-o", work / "missing/out.vdb"], [asset]),
        ("render --stats in a missing folder", ["render", asset, "-o", "out.png", "--stats", work / "missing/s.json"], [asset]),
        ("fit --log in a missing folder", ["fit", grid, "-o", "out.gvr", "--log", work / "missing/log.csv"], [grid]),
    ]:
        case("unsafe output", label, args, inputs, ["out.png", "out.gvr", "out.vdb"])
    fit = ["fit", grid, "-o", "out.gvr"]
    for flag in ["--iterations", "--threads", "--gaussians", "--seed", "--refresh-every", "--batch", "--held-out",
                 "--slice-pixels", "--prune-every", "--log-every"]:
        case("flag out of range", f"fit {flag} -1", fit + [flag, "-1"], [grid], ["out.gvr"])
    for flag in ["--mc-lambda", "--slice-max", "--slice-gamma", "--slice-beta", "--lr", "--cutoff", "--ratio", "--time"]:
        case("flag out of range", f"fit {flag} nan", fit + [flag, "nan"], [grid], ["out.gvr"])
    case("flag out of range", "fit --gaussians 0", fit + ["--gaussians", "0"], [grid], ["out.gvr"])
    case("flag out of range", "fit --threads 100000", fit + ["--threads", "100000"], [grid], ["out.gvr"])
    render = ["render", asset, "-o", "out.png"]
    for args in [["--renderer", "raymarch", "--step", "1e-9"], ["--slice-spacing", "1e-9"], ["--size", "0x0"],
                 ["--size", "100000x100000"], ["--renderer", "raymarch", "--samples", "0"],
                 ["--renderer", "raymarch", "--samples", "99"], ["--samples", "4"]]:
        case("flag out of range", "render " + " ".join(args), render + args, [asset], ["out.png"])
    for args in [["--resolution", "5000"], ["--voxel-size", "1e-6"]]:
        case("flag out of range", "export " + " ".join(args), ["export", asset, "-o", "out.vdb"] + args, [asset])


def legitimate_extremes(work, grid, asset):
    """Valid data at the ends of the float range, and files whose values gvr must refuse to trust."""
    rng = numpy.random.default_rng(3)
    for scale in [1e-36, 1e-40, 3e38]:
        values = (rng.random((12, 10, 8)) * scale).astype(numpy.float32)
        target = nifti_float(work, f"scale-{scale:g}.nii", values)
        for tf in ["mri", "ct-bone"]:
            case("legitimate extremes", f"render float data of scale {scale:g} with --tf {tf}",
                 ["render", target, "-o", "out.png", "--tf", tf], [target], ["out.png"], may_succeed=True)
    for label, spacing in [("1e6 x 1 x 1 mm", [1e6, 1, 1]), ("1e-6 x 1 x 1 mm", [1e-6, 1, 1])]:
        values = (rng.random((12, 12, 12)) * 1000).astype(numpy.float32)
        target = work / f"voxels-{spacing[0]:g}.nii"
        nibabel.save(nibabel.Nifti1Image(values, numpy.diag(spacing + [1])), target)
        for renderer in ["shear-warp", "raymarch"]:
            case("legitimate extremes", f"render {renderer} of 12^3 voxels of {label}",
                 ["render", target, "-o", "out.png", "--renderer", renderer], [target], ["out.png"], may_succeed=True)
    for label, points in [("points at +-1e308", [[-1e308, 0, 0, 0, 0], [1e308, 1, 1, 1, 1]]),
                          ("points 1e-300 apart", [[0, 0, 0, 0, 0], [1e-300, 1, 1, 1, 1]])]:
        tf = work / f"tf-{label.replace(' ', '-')}.json"
        tf.write_text(json.dumps({"points": points}))
        case("legitimate extremes", f"render with a transfer function of {label}",
             ["render", asset, "-o", "out.png", "--tf", tf], [asset, tf], ["out.png"], may_succeed=True)
    import pyopenvdb
    for label, value in [("a NaN voxel", float("nan")), ("an Inf voxel", float("inf"))]:
        nan = pyopenvdb.FloatGrid()
        nan.name = "density"
        accessor = nan.getAccessor()
        for ijk in [(0, 0, 0), (3, 2, 1), (5, 5, 5)]:
            accessor.setValueOn(ijk, 1.0)
        accessor.setValueOn((3, 3, 3), value)
        target = work / f"grid-{label.replace(' ', '-')}.vdb"
        pyopenvdb.write(str(target), grids=[nan])
        for command in [["render", target, "-o", "out.png"], ["fit", target, "-o", "out.gvr", "--iterations", "2"],
                        ["eval", target, target], ["export", asset, "-o", "out.vdb", "--like", target]]:
            case("non-finite grid", f"{command[0]} of a .vdb with {label}", command, [target], ["out.png", "out.gvr", "out.vdb"])
    case("flag out of range", "baseline downsample --factor 2147483647",
         ["baseline", grid, "--method", "downsample", "--factor", "2147483647", "-o", "out.vdb", "--stream", "s.vdb"], [grid],
         ["out.vdb", "s.vdb"])
    for label, args in [("--time 1e30", ["--time", "1e30"]), ("--iterations 2^64-1", ["--iterations", str(2**64 - 1)])]:
        case("flag out of range", f"fit {label}", ["fit", grid, "-o", "out.gvr"] + args, [grid], ["out.gvr"])
    for command in [["export", asset, "-o", "out.vdb", "--threshold", "nan"], ["eval", grid, asset, "--threshold", "nan"]]:
        case("flag out of range", f"{command[0]} --threshold nan", command, [grid, asset])


def inputs_kept(work, grid, asset):
    """Inputs that are not regular files, and outputs that are files an input reads."""
    for name in ["pipe.nii.gz", "pipe.vdb", "pipe.json"]:
        os.mkfifo(work / name)
    for label, args in [("ingest of a FIFO", ["ingest", work / "pipe.nii.gz", "-o", "out.vdb"]),
                        ("eval against a FIFO", ["eval", grid, work / "pipe.vdb"]),
                        ("render --tf a FIFO", ["render", asset, "-o", "out.png", "--tf", work / "pipe.json"]),
                        ("bench of /dev/zero", ["bench", "/dev/zero", "-o", work / "bench-out"])]:
        case("input not a regular file", label, args, [grid, asset], ["out.vdb", "out.png"])
    mhd = work / "vol.mhd"
    mhd.write_text("ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\nElementDataFile = data.vdb\n")
    (work / "data.vdb").write_bytes(bytes(range(64)))
    tf = work / "tf.json"
    tf.write_text(json.dumps({"points": [[0, 0, 0, 0, 0], [100, 1, 1, 1, 0.5]]}))
    for label, args, inputs in [
        ("ingest -o the MetaImage's data file", ["ingest", mhd, "-o", work / "data.vdb"], [work / "data.vdb"]),
        ("render --save-tf the input", ["render", grid, "-o", "out.png", "--save-tf", grid], [grid]),
        ("render --stats the transfer function", ["render", grid, "-o", "out.png", "--tf", tf, "--stats", tf], [tf]),
    ]:
        case("input destroyed", label, args, inputs, ["out.png"])


LIBRARY_SPELLING = re.compile(r"`[a-z][a-z0-9_]*(=[^`]*)?`")


def run_case(gvr, work, c):
    folder = work / "runs" / f"{len(list((work / 'runs').iterdir()))}"
    folder.mkdir()
    before = {p: hashlib.sha256(p.read_bytes()).hexdigest() for p in c.inputs if p.is_file()}
    try:
        run = subprocess.run([gvr] + c.args + ["--quiet"] * (c.args[0] in ("ingest", "fit", "export", "render")),
                             cwd=folder, capture_output=True, text=True, errors="replace", timeout=TIMEOUT_SECONDS)
    except subprocess.TimeoutExpired:
        return f"no exit within {TIMEOUT_SECONDS} s"
    lines = run.stderr.splitlines()
    changed = [str(p) for p, digest in before.items() if hashlib.sha256(p.read_bytes()).hexdigest() != digest]
    if changed:
        return f"changed its input {changed[0]}"
    if run.returncode == 0 and c.may_succeed:
        if isinstance(c.may_succeed, str) and c.may_succeed not in run.stderr:
            return f"exit 0 without the warning '{c.may_succeed}': {run.stderr.strip()[-300:]}"
        return None
    if run.returncode != 2:
        return f"exit {run.returncode}: {run.stderr.strip()[-300:]}"
    if len(lines) != 1 or not lines[0].startswith("gvr: error: "):
        return f"{len(lines)} lines on stderr: {run.stderr.strip()[-300:]}"
    if LIBRARY_SPELLING.search(run.stderr):  # the library's `key`, which gvr must say as --key
        return f"a setting in the library's spelling: {run.stderr.strip()[-300:]}"
    left = [name for name in c.outputs if (folder / name).exists()]
    if left or [p for p in folder.iterdir() if p.name.startswith(".gvr-")]:
        return f"left an output behind: {left}"
    return None


def body(gvr, shared, scratch):
    work, shared = pathlib.Path(scratch), pathlib.Path(shared)
    seeds = work / "seeds"
    subprocess.run([sys.executable, make_seeds.__file__, gvr, shared, seeds], check=True, capture_output=True)
    (work / "runs").mkdir()
    grid, asset = gvr_files(work, gvr, seeds)
    truncated_files(work, shared, seeds)
    truncated_tiff_pages(work)
    corrupt_compressed(work, shared, seeds)
    absurd_headers(work, seeds)
    bad_values(work)
    unsupported_and_inconsistent_headers(work, seeds)
    path_escapes(work, seeds)
    damaged_assets(work, asset)
    damaged_layers(work, gvr, grid)
    damaged_grids(work, grid)
    outputs_and_flags(work, grid, asset)
    legitimate_extremes(work, grid, asset)
    inputs_kept(work, grid, asset)
    bench_inputs(work, gvr, grid)
    tally = collections.OrderedDict()
    seconds = []
    for c in cases:
        started = time.time()
        problem = run_case(gvr, work, c)
        seconds.append((time.time() - started, c.name))
        tried, handled = tally.get(c.kind, (0, 0))
        tally[c.kind] = (tried + 1, handled + (problem is None))
        if problem:
            checks.check(f"{c.kind}: {c.name}", False, problem)
    print("\n| class | cases | handled |\n|---|---|---|")
    for kind, (tried, handled) in tally.items():
        print(f"| {kind} | {tried} | {handled} |")
    print("slowest cases: " + "; ".join(f"{name} {t:.1f} s" for t, name in sorted(seconds)[-4:]))
    total = sum(t for t, _ in tally.values()), sum(h for _, h in tally.values())
    print(f"| all | {total[0]} | {total[1]} |")
    checks.check("every bad input handled as the README promises", total[0] == total[1], f"{total[1]} of {total[0]}")


if __name__ == "__main__":
    sys.exit(checks.run(body, __doc__))
