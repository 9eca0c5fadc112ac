#!/usr/bin/env python3
"""gvr render against VTK's CPU ray caster, what 3D Slicer and ParaView fall back to
without a GPU (vtkFixedPointVolumeRayCastMapper, Debian's python3-vtk9).

Usage: xvfb-run -a python3 bench/vtk_render.py [--gvr GVR] [--frames N] [--size S]
                                              [--work DIR] NAME=VOLUME:INPUT:TF ...

Each NAME=VOLUME:INPUT:TF is a row. VOLUME is a NIfTI file (for example `gvr ingest
SCAN -o scan.nii.gz`, the voxels gvr fitted) that VTK renders; INPUT is what `gvr
render` draws (an asset, a .vdb grid or the same NIfTI); TF is a preset or a
transfer function file, or empty for gvr's preset for the data. Both renderers get:
- the same transfer-function points (`gvr render --save-tf`), opacity per voxel
  (VTK's scalar opacity unit distance is the smallest voxel edge);
- one sample per voxel along a ray (gvr's slice spacing 1; VTK's sample distance
  the smallest voxel edge), one ray per pixel for VTK, no shading;
- an orthographic camera on gvr's orbit (azimuth about +z from 30 degrees,
  elevation 15), in gvr's world (the NIfTI's affine as VTK's user matrix), framed
  as gvr frames a volume (its box with a 2 % margin);
- the machine's threads (gvr's TBB, VTK's multithreader), one renderer at a time.
Per row: VTK's first frame and mean frame; gvr's first frame (set-up included), its
stack builds, its mean reused frame and the orbit's frames per second; and the
ratios the issue asks for (gvr's reused frame over VTK's frame, gvr's orbit rate
over VTK's). VTK's first frame is written to WORK/NAME/vtk.png, to check by eye
that both draw the same thing. Prints a Markdown table, and the figures as JSON to
WORK/vtk_render.json. Nothing is asserted: run it with nothing else on the machine.
VTK needs an X display for its window even off screen: hence xvfb-run.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

import nibabel
import numpy as np
import vtk
from vtk.util import numpy_support

AZIMUTH, ELEVATION = 30.0, 15.0  # gvr render's defaults: its orbit starts there


def gvr_orbit(gvr, source, tf, size, frames, folder):
    """gvr render's orbit (axis stacks, as an orbit takes them) and the transfer function it used."""
    tf_file = os.path.join(folder, "tf.json")
    chosen = ["--tf", tf] if tf else []  # else the preset for the data
    done = subprocess.run([gvr, "render", source, "-o", os.path.join(folder, "gvr.png"), *chosen,
                           "--size", f"{size}x{size}", "--orbit", str(frames),
                           "--azimuth", str(AZIMUTH), "--elevation", str(ELEVATION),
                           "--save-tf", tf_file, "--json", "-q"], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"vtk_render: gvr render {source} failed: {done.stderr.strip()}")
    report = json.loads(done.stdout)
    stats = report["frames"]
    builds = [f["build_ms"] for f in stats if not f["reused"]]
    reused = [f["total_ms"] for f in stats if f["reused"]]
    with open(tf_file) as file:
        points = json.load(file)["points"]
    return points, {
        "first_frame_ms": report["first_frame_ms"],
        "builds": len(builds),
        "build_ms": sum(builds) / len(builds) if builds else None,
        "reused_ms": sum(reused) / len(reused) if reused else None,
        # Set-up included, as VTK's first frame includes its own.
        "orbit_fps": len(stats) * 1000.0 / (report["first_frame_ms"] + sum(f["total_ms"] for f in stats[1:])),
    }


def image_data(path):
    """The NIfTI's voxels in its stored integer type where its values are integers
    (as Slicer hands a CT to VTK), else float32, with its voxel spacing; and the
    affine that places the voxels in gvr's world (the file's sform)."""
    image = nibabel.load(path)
    values = np.asanyarray(image.dataobj)
    if values.ndim != 3:
        sys.exit(f"vtk_render: {path}: a 3D grey volume is needed, not shape {values.shape}")
    if values.dtype.kind == "f" and np.array_equal(values, np.round(values)) and \
            -32768 <= values.min() and values.max() <= 32767:
        values = values.astype(np.int16)
    elif values.dtype.kind == "f":
        values = values.astype(np.float32)
    data = vtk.vtkImageData()
    data.SetDimensions(*values.shape)
    spacing = np.linalg.norm(image.affine[:3, :3], axis=0)
    data.SetSpacing(*spacing)
    flat = np.ascontiguousarray(values.transpose(2, 1, 0)).ravel()  # VTK runs x fastest
    data.GetPointData().SetScalars(numpy_support.numpy_to_vtk(flat, deep=True))
    return data, image.affine


def placement(affine, spacing):
    """The volume's user matrix: from VTK's spaced voxels to the world (the affine's
    rotation, flips and shift), so that the views are gvr's."""
    matrix = np.array(affine, dtype=float)
    matrix[:3, :3] = matrix[:3, :3] / spacing
    user = vtk.vtkMatrix4x4()
    for i in range(4):
        for j in range(4):
            user.SetElement(i, j, matrix[i, j])
    return user


def world_corners(affine, dims):
    """The world corners of the voxel cells, as gvr's worldCorners()."""
    index = np.array([[x, y, z, 1.0] for x in (-0.5, dims[0] - 0.5) for y in (-0.5, dims[1] - 0.5)
                      for z in (-0.5, dims[2] - 0.5)])
    return (index @ np.array(affine, dtype=float).T)[:, :3]


def volume_property(points, voxel_mm):
    colour, opacity = vtk.vtkColorTransferFunction(), vtk.vtkPiecewiseFunction()
    for value, r, g, b, a in points:
        colour.AddRGBPoint(value, r, g, b)
        opacity.AddPoint(value, a)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(voxel_mm)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    return prop


def place_camera(camera, corners, azimuth_deg):
    """gvr's camera (render/Camera.cpp makeCamera) on the box of @a corners."""
    az, el = math.radians(azimuth_deg), math.radians(ELEVATION)
    direction = -np.array([math.cos(el) * math.sin(az), math.cos(el) * math.cos(az), math.sin(el)])
    right = np.cross(direction, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, direction)
    centre = corners.mean(axis=0)
    half = max(np.abs((corners - centre) @ right).max(), np.abs((corners - centre) @ up).max())
    camera.ParallelProjectionOn()
    camera.SetFocalPoint(*centre)
    camera.SetPosition(*(centre - direction * 4.0 * half))
    camera.SetViewUp(*up)
    camera.SetParallelScale(1.02 * half)
    camera.SetClippingRange(0.1 * half, 8.0 * half)


def vtk_orbit(volume_path, points, size, frames, folder):
    data, affine = image_data(volume_path)
    voxel_mm = min(data.GetSpacing())
    mapper = vtk.vtkFixedPointVolumeRayCastMapper()
    mapper.SetInputData(data)
    mapper.AutoAdjustSampleDistancesOff()
    mapper.SetSampleDistance(voxel_mm)
    mapper.SetImageSampleDistance(1.0)
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(volume_property(points, voxel_mm))
    volume.SetUserMatrix(placement(affine, np.array(data.GetSpacing())))
    renderer = vtk.vtkRenderer()
    renderer.AddVolume(volume)
    renderer.SetBackground(0, 0, 0)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(size, size)
    window.AddRenderer(renderer)
    corners = world_corners(affine, data.GetDimensions())
    times = []
    for f in range(frames):
        place_camera(renderer.GetActiveCamera(), corners, AZIMUTH + 360.0 * f / frames)
        start = time.perf_counter()
        window.Render()
        times.append((time.perf_counter() - start) * 1000.0)
        if f == 0:
            capture = vtk.vtkWindowToImageFilter()
            capture.SetInput(window)
            writer = vtk.vtkPNGWriter()
            writer.SetFileName(os.path.join(folder, "vtk.png"))
            writer.SetInputConnection(capture.GetOutputPort())
            writer.Write()
    return {"threads": mapper.GetNumberOfThreads(), "first_frame_ms": times[0],
            "frame_ms": sum(times[1:]) / max(len(times) - 1, 1),
            "orbit_fps": len(times) * 1000.0 / sum(times)}


def ratio(a, b):
    return a / b if a and b else None


def measure_row(args, name, volume, source, tf):
    folder = os.path.join(args.work, name)
    os.makedirs(folder, exist_ok=True)
    points, ours = gvr_orbit(args.gvr, source, tf, args.size, args.frames, folder)
    theirs = vtk_orbit(volume, points, args.size, args.frames, folder)
    return {"name": name, "volume": volume, "input": source, "tf": tf, "size": args.size,
            "frames": args.frames, "gvr": ours, "vtk": theirs,
            "reused_over_vtk": ratio(theirs["frame_ms"], ours["reused_ms"]),
            "orbit_over_vtk": ratio(ours["orbit_fps"], theirs["orbit_fps"])}


def cell(value, digits=1, unit=""):
    return "-" if value is None else f"{value:.{digits}f}{unit}"


def print_table(rows):
    print("| row | VTK first / mean frame | gvr first frame, builds x mean build | gvr reused frame | "
          "orbit FPS, gvr / VTK | gvr over VTK: reused frame, orbit |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        g, v = r["gvr"], r["vtk"]
        print(f"| {r['name']} | {cell(v['first_frame_ms'], 0)} / {cell(v['frame_ms'], 0)} ms | "
              f"{cell(g['first_frame_ms'], 0)} ms, {g['builds']} x {cell(g['build_ms'], 0)} ms | "
              f"{cell(g['reused_ms'], 0)} ms | {cell(g['orbit_fps'], 2)} / {cell(v['orbit_fps'], 2)} | "
              f"**{cell(r['reused_over_vtk'], 2, 'x')}**, **{cell(r['orbit_over_vtk'], 2, 'x')}** |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--gvr", default="build/cli/gvr")
    parser.add_argument("--frames", type=int, default=120, help="orbit frames (default 120)")
    parser.add_argument("--size", type=int, default=512, help="image side in pixels (default 512)")
    parser.add_argument("--work", default="/tmp/vtk_render")
    parser.add_argument("rows", nargs="+", metavar="NAME=VOLUME:INPUT:TF")
    args = parser.parse_args()
    if args.frames < 2:
        sys.exit("vtk_render: --frames must be at least 2")
    rows = []
    for spec in args.rows:
        name, _, rest = spec.partition("=")
        parts = rest.split(":")
        if not name or len(parts) != 3:
            sys.exit(f"vtk_render: {spec}: expected NAME=VOLUME:INPUT:TF")
        rows.append(measure_row(args, name, *parts))
    print_table(rows)
    with open(os.path.join(args.work, "vtk_render.json"), "w") as file:
        json.dump(rows, file, indent=2)


if __name__ == "__main__":
    main()
