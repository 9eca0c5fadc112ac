"""gvr eval's SSIM and MS-SSIM match scikit-image on 2D images and 3D volumes.

Usage: metrics_vs_skimage.py GVR_EXECUTABLE SHARED_DATA_DIR WORK_DIR
(SHARED_DATA_DIR is unused: the images are synthesised here with a fixed seed.)
Runs with Debian's /usr/bin/python3 (numpy, scipy, scikit-image 0.19). Images are
written as 16-bit PNG by a small zlib writer below (no 16-bit RGB writer is installed),
and read back through `oiiotool --dumpdata` to make sure OpenImageIO, which gvr uses,
decodes exactly the samples written. (Not `oiiotool -d uint16 -o x.pnm`: OIIO 2.4.7
writes a 65535-maxval PNM whose samples are byte-swapped 8-bit values.)

Checks, with a fixed PSNR/SSIM peak P (--peak):
  - SSIM == skimage.metrics.structural_similarity(gaussian_weights=True, sigma=1.5,
    use_sample_covariance=False, data_range=P) (channel_axis=-1 for RGB), |diff| < 1e-5;
  - MS-SSIM == a reference written here (5 scales, weights 0.0448 0.2856 0.3001 0.2363
    0.1333; Gaussian stats sigma 1.5 truncate 3.5; cs at scales < M, SSIM at scale M;
    maps averaged over the interior after cropping 5 pixels like skimage; 2x2 average
    downsampling after dropping an odd last row/column; fewer scales, with the weights
    renormalised, when the smallest side at scale M would be < 11), |diff| < 1e-5, and
    ms_ssim_scales == the reference's scale count;
  - the reference's own single-scale SSIM equals skimage's to 1e-9;
  - identical inputs: psnr null (JSON has no infinity) beside mse 0, ssim == 1, ms_ssim == 1 (1e-9).
"""
import json
import os
import struct
import subprocess
import sys
import zlib

import nibabel
import numpy as np

import checks
from checks import check
from scipy import ndimage
from skimage.metrics import structural_similarity

WEIGHTS = np.array([0.0448, 0.2856, 0.3001, 0.2363, 0.1333])
SIGMA, TRUNCATE = 1.5, 3.5
WIN = 2 * int(TRUNCATE * SIGMA + 0.5) + 1  # 11, as skimage derives it
PAD = (WIN - 1) // 2  # 5
TOL = 1e-5  # the issue asks for 1e-3; gvr agrees to about 1e-8
PEAK = 1.0

# ---------------------------------------------------------------- image files

def write_png16(path, samples):
    """Write uint16 samples (H x W grey or H x W x 3 RGB) as a 16-bit PNG."""
    a = np.ascontiguousarray(np.asarray(samples, dtype=">u2"))
    height, width = a.shape[:2]
    colour_type = {2: 0, 3: 2}[a.ndim]  # 0 grey, 2 RGB
    raw = b"".join(b"\x00" + a[row].tobytes() for row in range(height))  # filter type 0 per row

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 16, colour_type, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        f.write(chunk(b"IEND", b""))


def read_back_with_oiio(png, shape):
    """Decode the PNG with OpenImageIO (`oiiotool --dumpdata`, which prints each pixel's
    integer samples) into a uint16 array of the given shape."""
    out = subprocess.run(["oiiotool", "--dumpdata", png], check=True, stdout=subprocess.PIPE, text=True).stdout
    a = np.zeros(shape, dtype=np.uint16)
    seen = 0
    for line in out.splitlines():
        line = line.strip()
        if not line.startswith("Pixel ("):
            continue
        coords, values = line[len("Pixel ("):].split("):", 1)
        x, y = (int(c) for c in coords.split(","))
        samples = [int(v) for v in values.split("(")[0].split()]
        a[y, x] = samples[0] if a.ndim == 2 else samples
        seen += 1
    assert seen == shape[0] * shape[1], f"oiiotool printed {seen} pixels"
    return a


# ---------------------------------------------------------------- test images

def smooth_image(rng, height, width):
    """Sum of a few Gaussian blobs and sinusoids, scaled into [0.05, 0.95]."""
    y, x = np.mgrid[0:height, 0:width].astype(np.float64)
    img = np.zeros((height, width))
    for _ in range(6):
        cy, cx = rng.uniform(0, height), rng.uniform(0, width)
        s = rng.uniform(0.05, 0.25) * min(height, width)
        img += rng.uniform(0.3, 1.0) * np.exp(-((y - cy) ** 2 + (x - cx) ** 2) / (2 * s * s))
    for _ in range(3):
        fy, fx = rng.uniform(0.02, 0.2, size=2)
        img += 0.25 * np.sin(2 * np.pi * (fy * y + fx * x) + rng.uniform(0, 2 * np.pi))
    img += 0.05 * ndimage.gaussian_filter(rng.standard_normal((height, width)), 1.0)  # some fine texture
    img -= img.min()
    return 0.05 + 0.9 * img / img.max()


def distort(rng, img):
    """Blur, contrast/brightness change and additive noise, clipped to [0, 1]."""
    blurred = ndimage.gaussian_filter(img, 1.2)
    out = 0.8 * blurred + 0.08 + rng.normal(0.0, 0.03, size=img.shape)
    return np.clip(out, 0.0, 1.0)


def to_u16(img):
    return np.round(np.clip(img, 0.0, 1.0) * 65535.0).astype(np.uint16)


def make_pair(rng, height, width, channels):
    if channels == 1:
        a = smooth_image(rng, height, width)
        b = distort(rng, a)
    else:
        a = np.stack([smooth_image(rng, height, width) for _ in range(channels)], axis=-1)
        b = np.stack([distort(rng, a[..., c]) for c in range(channels)], axis=-1)
    return to_u16(a), to_u16(b)


# ---------------------------------------------------------------- reference metrics

def _stats(x, y, peak):
    def f(v):
        return ndimage.gaussian_filter(v, sigma=SIGMA, truncate=TRUNCATE, mode="reflect")

    ux, uy = f(x), f(y)
    vx = f(x * x) - ux * ux  # population (not sample) covariance, as use_sample_covariance=False
    vy = f(y * y) - uy * uy
    vxy = f(x * y) - ux * uy
    c1, c2 = (0.01 * peak) ** 2, (0.03 * peak) ** 2
    cs = (2 * vxy + c2) / (vx + vy + c2)
    ssim_map = ((2 * ux * uy + c1) / (ux * ux + uy * uy + c1)) * cs

    def interior_mean(m):
        return float(m[tuple(slice(PAD, -PAD) for _ in m.shape)].mean())

    return interior_mean(ssim_map), interior_mean(cs)


def _downsample(x):
    """Averages pairs along every axis, after dropping an odd last sample."""
    x = x[tuple(slice(0, (n // 2) * 2) for n in x.shape)]
    for axis in range(x.ndim):
        even = np.take(x, range(0, x.shape[axis], 2), axis=axis)
        odd = np.take(x, range(1, x.shape[axis], 2), axis=axis)
        x = 0.5 * (even + odd)
    return x


def scale_count(*shape):
    m = 0
    side = min(shape)
    while m < len(WEIGHTS) and side >= WIN:
        m += 1
        side //= 2
    return m


def ms_ssim_grey(x, y, peak):
    m = scale_count(*x.shape)
    assert m >= 1, x.shape
    weights = WEIGHTS[:m] / WEIGHTS[:m].sum()
    value = 1.0
    single = None
    for j in range(m):
        s, cs = _stats(x, y, peak)
        if j == 0:
            single = s
        if j < m - 1:
            value *= max(cs, 0.0) ** weights[j]
            x, y = _downsample(x), _downsample(y)
        else:
            value *= max(s, 0.0) ** weights[j]
    return value, m, single


def reference(a, b, peak):
    """(ms_ssim, scales, own single-scale ssim) on float images, RGB per channel averaged."""
    if a.ndim == 2:
        return ms_ssim_grey(a, b, peak)
    results = [ms_ssim_grey(a[..., c], b[..., c], peak) for c in range(a.shape[2])]
    return (float(np.mean([r[0] for r in results])), results[0][1], float(np.mean([r[2] for r in results])))


def skimage_ssim(a, b, peak):
    kwargs = dict(gaussian_weights=True, sigma=SIGMA, use_sample_covariance=False, data_range=peak)
    if a.ndim == 3:
        kwargs["channel_axis"] = -1
    return float(structural_similarity(a, b, **kwargs))


# ---------------------------------------------------------------- gvr

def gvr_eval(gvr, ref, test, peak):
    args = [gvr, "eval", ref, test, "--json", "--peak", repr(peak)]
    result = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        print("command failed:", " ".join(args), result.stdout, result.stderr, sep="\n")
        raise RuntimeError(f"gvr eval exit code {result.returncode}")
    return json.loads(result.stdout)


def run_case(gvr, tmp, name, a16, b16):
    height, width = a16.shape[:2]
    channels = 1 if a16.ndim == 2 else a16.shape[2]
    print(f"== {name}: {width}x{height}, {channels} channel(s) ==")
    pa, pb = os.path.join(tmp, f"{name}_a.png"), os.path.join(tmp, f"{name}_b.png")
    write_png16(pa, a16)
    write_png16(pb, b16)
    check(f"{name} OpenImageIO decodes the written PNGs exactly",
          np.array_equal(read_back_with_oiio(pa, a16.shape), a16)
          and np.array_equal(read_back_with_oiio(pb, b16.shape), b16))
    a, b = a16.astype(np.float64) / 65535.0, b16.astype(np.float64) / 65535.0

    ref_ssim = skimage_ssim(a, b, PEAK)
    ref_ms, ref_scales, own_ssim = reference(a, b, PEAK)
    check(f"{name} reference single-scale SSIM == skimage (1e-9)", abs(own_ssim - ref_ssim) < 1e-9,
          f"own {own_ssim:.12f}, skimage {ref_ssim:.12f}, diff {abs(own_ssim - ref_ssim):.2e}")

    got = gvr_eval(gvr, pa, pb, PEAK)
    check(f"{name} gvr peak == --peak", abs(float(got["peak"]) - PEAK) < 1e-12, f"{got['peak']}")
    check(f"{name} SSIM: gvr vs skimage", abs(float(got["ssim"]) - ref_ssim) < TOL,
          f"gvr {float(got['ssim']):.6f}, skimage {ref_ssim:.6f}, diff {abs(float(got['ssim']) - ref_ssim):.2e}")
    check(f"{name} MS-SSIM scales: gvr vs reference", int(got["ms_ssim_scales"]) == ref_scales,
          f"gvr {got['ms_ssim_scales']}, reference {ref_scales}")
    check(f"{name} MS-SSIM: gvr vs reference", abs(float(got["ms_ssim"]) - ref_ms) < TOL,
          f"gvr {float(got['ms_ssim']):.6f}, reference {ref_ms:.6f}, diff {abs(float(got['ms_ssim']) - ref_ms):.2e}")
    mse = float(np.mean((a - b) ** 2))
    check(f"{name} MSE: gvr vs numpy (sanity)", abs(float(got["mse"]) - mse) <= 1e-6 * max(mse, 1e-12) + 1e-12,
          f"gvr {float(got['mse']):.8g}, numpy {mse:.8g}")

    same = gvr_eval(gvr, pa, pa, PEAK)
    check(f"{name} identical inputs: psnr null, mse 0", same["psnr"] is None and same["mse"] == 0, f"{same['psnr']!r}")
    check(f"{name} identical inputs: ssim == 1 and ms_ssim == 1",
          abs(float(same["ssim"]) - 1.0) < 1e-9 and abs(float(same["ms_ssim"]) - 1.0) < 1e-9,
          f"ssim {same['ssim']!r}, ms_ssim {same['ms_ssim']!r}, scales {same['ms_ssim_scales']}")
    return ref_scales


def smooth_volume(rng, shape):
    """Gaussian blobs and fine texture in 3D, scaled into [0.05, 0.95]."""
    axes = np.meshgrid(*[np.arange(n, dtype=np.float64) for n in shape], indexing="ij")
    vol = np.zeros(shape)
    for _ in range(6):
        centre = [rng.uniform(0, n) for n in shape]
        s = rng.uniform(0.1, 0.3) * min(shape)
        vol += rng.uniform(0.3, 1.0) * np.exp(-sum((a - c) ** 2 for a, c in zip(axes, centre)) / (2 * s * s))
    vol += 0.05 * ndimage.gaussian_filter(rng.standard_normal(shape), 1.0)
    vol -= vol.min()
    return 0.05 + 0.9 * vol / vol.max()


def run_volume_case(gvr, tmp, rng, name, shape, expected_scales):
    """A 3D pair as float32 NIfTI: every axis is smoothed and downsampled."""
    print(f"== {name}: {'x'.join(map(str, shape))} ==")
    a = smooth_volume(rng, shape).astype(np.float32)
    b = distort(rng, a.astype(np.float64)).astype(np.float32)
    pa, pb = os.path.join(tmp, f"{name}_a.nii"), os.path.join(tmp, f"{name}_b.nii")
    nibabel.save(nibabel.Nifti1Image(a, np.eye(4)), pa)
    nibabel.save(nibabel.Nifti1Image(b, np.eye(4)), pb)
    a, b = a.astype(np.float64), b.astype(np.float64)
    ref_ssim = float(structural_similarity(a, b, gaussian_weights=True, sigma=SIGMA, use_sample_covariance=False,
                                           data_range=PEAK))
    ref_ms, ref_scales, own_ssim = ms_ssim_grey(a, b, PEAK)
    check(f"{name} reference single-scale SSIM == skimage (1e-9)", abs(own_ssim - ref_ssim) < 1e-9,
          f"own {own_ssim:.12f}, skimage {ref_ssim:.12f}")
    check(f"{name} test design: reference uses {expected_scales} scale(s)", ref_scales == expected_scales,
          f"{ref_scales}")
    got = gvr_eval(gvr, pa, pb, PEAK)
    check(f"{name} SSIM: gvr vs skimage", abs(float(got["ssim"]) - ref_ssim) < TOL,
          f"gvr {float(got['ssim']):.6f}, skimage {ref_ssim:.6f}, diff {abs(float(got['ssim']) - ref_ssim):.2e}")
    check(f"{name} MS-SSIM scales: gvr vs reference", int(got["ms_ssim_scales"]) == ref_scales,
          f"gvr {got['ms_ssim_scales']}, reference {ref_scales}")
    check(f"{name} MS-SSIM: gvr vs reference", abs(float(got["ms_ssim"]) - ref_ms) < TOL,
          f"gvr {float(got['ms_ssim']):.6f}, reference {ref_ms:.6f}, diff {abs(float(got['ms_ssim']) - ref_ms):.2e}")


def all_cases(gvr, shared, scratch):
    rng = np.random.RandomState(20240611)
    cases = [
        ("grey_256x240", 240, 256, 1, 5),  # 240 >> 4 = 15 >= 11: 5 scales
        ("rgb_200x180", 180, 200, 3, 5),   # 180 -> 90, 45, 22, 11: 5 scales, the last exactly 11
        ("grey_64x64", 64, 64, 1, 3),      # 64, 32, 16 (8 < 11): 3 scales, weights renormalised
        ("grey_52x40", 40, 52, 1, 2),      # 40, 20 (10 < 11): 2 scales
    ]
    for name, height, width, channels, expected_scales in cases:
        a16, b16 = make_pair(rng, height, width, channels)
        scales = run_case(gvr, scratch, name, a16, b16)
        check(f"{name} test design: reference uses {expected_scales} scale(s)", scales == expected_scales,
              f"{scales}")
    run_volume_case(gvr, scratch, rng, "volume_52x48x44", (52, 48, 44), 3)  # 44, 22, 11


if __name__ == "__main__":
    sys.exit(checks.run(all_cases, __doc__))
