#!/usr/bin/env python3
"""A small external codec for the tests of bench/ExternalCodec: it stands in for
SZ3 and SPERR, which CI does not build, and misbehaves on request.

    fake_codec.py c MODE IN.f32 NX NY NZ STEP OUT      compress
    fake_codec.py d MODE IN OUT.f32 NX NY NZ           decompress

MODE:
  quantise  round(value / STEP + dither) with zlib, the dither subtracted on the
            way back: an error of at most STEP / 2, and a size that grows as
            STEP shrinks even on integer data
  steps     quantise with STEP rounded down to a power of 4: sizes jump, so
            some targets lie between two sizes that no STEP separates
  first-x   keeps the first value of each row along NX and repeats it on the way
            back: exact only for data constant along the fastest axis, so a wrong
            axis order shows
  slow      quantise, after sleeping 0.4 s
  fail      exits 3 with a message        hang    sleeps for ever
  nothing   exits 0 and writes nothing    short   decompresses to half the size
  nan       decompresses to NaN
"""
import array
import math
import random
import struct
import sys
import time
import zlib


def read_floats(path):
    values = array.array("f")
    with open(path, "rb") as file:
        values.frombytes(file.read())
    return values


def dither(count):
    """The same offsets in [-0.5, 0.5) for compress and decompress."""
    generator = random.Random(1)
    return [generator.random() - 0.5 for _ in range(count)]


def write(path, data):
    with open(path, "wb") as file:
        file.write(data)


def compress(mode, source, nx, ny, nz, step, target):
    values = read_floats(source)
    if len(values) != nx * ny * nz:
        sys.exit(f"fake_codec: {source} holds {len(values)} values, not {nx} x {ny} x {nz}")
    if mode == "first-x":
        kept = array.array("f", (values[row * nx] for row in range(ny * nz)))
        write(target, zlib.compress(kept.tobytes()))
        return
    if mode == "slow":
        time.sleep(0.4)
    if mode == "steps":
        step = 4.0 ** math.floor(math.log(step, 4))
    codes = array.array("q", (round(v / step + d) for v, d in zip(values, dither(len(values)))))
    write(target, struct.pack("<d", step) + zlib.compress(codes.tobytes(), 9))


def decompress(mode, source, target, nx, ny, nz):
    with open(source, "rb") as file:
        data = file.read()
    if mode == "first-x":
        kept = array.array("f")
        kept.frombytes(zlib.decompress(data))
        write(target, array.array("f", (kept[i // nx] for i in range(nx * ny * nz))).tobytes())
        return
    step = struct.unpack("<d", data[:8])[0]
    codes = array.array("q")
    codes.frombytes(zlib.decompress(data[8:]))
    values = array.array("f", ((c - d) * step for c, d in zip(codes, dither(len(codes)))))
    if mode == "short":
        values = values[: len(values) // 2]
    if mode == "nan":
        values[len(values) // 3] = math.nan
    write(target, values.tobytes())


def main(argv):
    direction, mode = argv[1], argv[2]
    if mode == "fail":
        print("fake_codec: failing on purpose", file=sys.stderr)
        sys.exit(3)
    if mode == "hang":
        while True:
            time.sleep(60)
    if mode == "nothing":
        return
    if direction == "c":
        compress(mode, argv[3], int(argv[4]), int(argv[5]), int(argv[6]), float(argv[7]), argv[8])
    else:
        decompress(mode, argv[3], argv[4], int(argv[5]), int(argv[6]), int(argv[7]))


if __name__ == "__main__":
    main(sys.argv)
