"""Export opens in real clients: pyopenvdb, nibabel and Blender read what gvr export
writes, and agree with gvr's own evaluation of the Gaussian field (gvr probe) and
with the source's geometry.

Usage: export_clients.py GVR_EXECUTABLE SHARED_DATA_DIR WORK_DIR
Runs with Debian's /usr/bin/python3 (numpy, nibabel, pyopenvdb, PIL) and needs
/usr/bin/blender (Debian 3.4, Cycles CPU). A temporary folder is made under WORK_DIR
and removed at the end.

Grey case (ch2.nii.gz): ingest, a small fit, export to .vdb and .nii.gz, then
  - pyopenvdb: grid names, fog-volume class, gvr_dims, index->world against nibabel's
    affine, stored values against gvr probe (active and inactive voxels);
  - nibabel: the NIfTI's shape, affine and data against the source and the VDB;
  - Blender: grid list, grid transform, object bounds, and a tiny Cycles render whose
    silhouette must lie inside the source's world box.
RGB case (brainmaps54 cryosection): ingest, a small fit, export --names houdini
(pyopenvdb: Cd + density, values against probe) and export with default names
(Blender: color + density, transform and bounds).

Note on Blender's bounds: Blender 3.4 computes a volume object's bound_box from the
grid's *leaf-node* bounding box (openvdb evalLeafBoundingBox, 8^3-aligned), mapped with
the grid transform at voxel-centre coordinates. So its box starts at the centre of the
first leaf voxel and ends at the centre of the last voxel of the last leaf: it is not
the active-voxel box and overshoots the source's box by up to 7 voxels per side. The
test therefore checks bound_box exactly against the leaf box of the exported grid, and
checks that it contains the source's voxel-centre box and overshoots it by less than
one leaf (8 voxels). The exact per-voxel geometry is checked through the grid's
matrix_object (Blender's index->object transform) against the nibabel affine.
"""
import json
import os
import subprocess
import sys
import textwrap
import time

import nibabel
import numpy as np

import checks
from checks import check
import pyopenvdb as vdb

BLENDER = "/usr/bin/blender"
LEAF = 8  # openvdb leaf node edge, in voxels

def run(args, **kwargs):
    started = time.time()
    result = subprocess.run([str(a) for a in args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, **kwargs)
    if result.returncode != 0:
        print("command failed:", " ".join(str(a) for a in args))
        print(result.stdout[-4000:])
        print(result.stderr[-4000:])
        raise RuntimeError(f"exit code {result.returncode}")
    print(f"  ran {os.path.basename(str(args[0]))} {args[1] if len(args) > 1 else ''} "
          f"in {time.time() - started:.1f} s", flush=True)
    return result.stdout


def probe(gvr, asset, indices):
    args = [gvr, "probe", asset, "--json"]
    for ijk in indices:
        args += ["--index", ",".join(str(int(c)) for c in ijk)]
    points = json.loads(run(args))["points"]
    assert len(points) == len(indices)
    for point, ijk in zip(points, indices):
        assert [int(round(c)) for c in point["index"]] == [int(c) for c in ijk], point
    return points


def rel_close(a, b, rel=1e-4, floor=1e-6):
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return bool(np.all(np.abs(a - b) <= rel * np.maximum(np.abs(b), floor) + floor))


def world_box(affine, dims, corners):
    """Axis-aligned world box of the voxel centres (corners=False: index 0..dims-1) or
    of the voxel corners (corners=True: index -0.5..dims-0.5)."""
    lo = np.full(3, -0.5 if corners else 0.0)
    hi = np.array(dims, dtype=np.float64) - (0.5 if corners else 1.0)
    pts = np.array([[x, y, z, 1.0] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    world = (affine @ pts.T).T[:, :3]
    return world.min(axis=0), world.max(axis=0)


def transform_matrix(grid):
    """The grid's index->world map as a 4x4 affine, through indexToWorld only."""
    origin = np.array(grid.transform.indexToWorld((0, 0, 0)))
    m = np.eye(4)
    m[:3, 3] = origin
    for axis in range(3):
        unit = [0, 0, 0]
        unit[axis] = 1
        m[:3, axis] = np.array(grid.transform.indexToWorld(tuple(unit))) - origin
    return m


BLENDER_SCRIPT = textwrap.dedent(r'''
    import bpy, json, math, sys
    from mathutils import Vector
    argv = sys.argv[sys.argv.index("--") + 1:]
    vdb_path, png_path, do_render = argv[0], argv[1], argv[2] == "1"
    scene = bpy.context.scene
    for o in list(bpy.data.objects):  # factory scene: cube, light, camera
        bpy.data.objects.remove(o, do_unlink=True)
    before = set(bpy.data.objects)
    bpy.ops.object.volume_import(filepath=vdb_path)
    new = [o for o in bpy.data.objects if o not in before]
    if len(new) != 1 or new[0].type != 'VOLUME':
        raise RuntimeError("volume_import created %r" % (new,))
    obj = new[0]
    obj.data.grids.load()
    grids = [[g.name, g.data_type, g.channels, [list(r) for r in g.matrix_object]] for g in obj.data.grids]
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    corners = [evaluated.matrix_world @ Vector(c) for c in evaluated.bound_box]
    lo = [min(c[i] for c in corners) for i in range(3)]
    hi = [max(c[i] for c in corners) for i in range(3)]
    result = {"object": obj.name, "grids": grids, "bbox_min": lo, "bbox_max": hi,
              "matrix_world": [list(r) for r in obj.matrix_world]}
    if do_render:
        centre = Vector([(a + b) / 2 for a, b in zip(lo, hi)])
        mat = bpy.data.materials.new("gvr_density")
        mat.use_nodes = True
        nodes = mat.node_tree.nodes
        for n in list(nodes):
            nodes.remove(n)
        output = nodes.new("ShaderNodeOutputMaterial")
        volume = nodes.new("ShaderNodeVolumePrincipled")
        volume.inputs["Density Attribute"].default_value = "density"
        volume.inputs["Density"].default_value = 2e-4  # values up to ~250 -> 0.05 per mm
        volume.inputs["Color"].default_value = (0.05, 0.05, 0.05, 1.0)  # mostly absorbing
        mat.node_tree.links.new(volume.outputs["Volume"], output.inputs["Volume"])
        obj.data.materials.append(mat)
        extent = max(h - l for l, h in zip(lo, hi))
        cam_data = bpy.data.cameras.new("gvr_cam")
        cam_data.type = 'ORTHO'
        cam_data.ortho_scale = 1.25 * extent
        cam_data.clip_start = 0.1
        cam_data.clip_end = 10.0 * extent + 1000.0
        cam = bpy.data.objects.new("gvr_cam", cam_data)
        scene.collection.objects.link(cam)
        # Looks along +Y: image right = world +X, image up = world +Z.
        cam.location = centre + Vector((0.0, -(2.0 * extent + 100.0), 0.0))
        cam.rotation_euler = (math.pi / 2, 0.0, 0.0)
        scene.camera = cam
        world = bpy.data.worlds.new("gvr_world")
        world.use_nodes = True
        world.node_tree.nodes["Background"].inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
        scene.world = world
        scene.render.engine = 'CYCLES'
        scene.cycles.device = 'CPU'
        scene.cycles.samples = 8
        scene.cycles.use_denoising = False
        scene.render.resolution_x = 48
        scene.render.resolution_y = 48
        scene.render.resolution_percentage = 100
        scene.view_settings.view_transform = 'Standard'
        scene.render.image_settings.file_format = 'PNG'
        scene.render.image_settings.color_mode = 'RGB'
        scene.render.filepath = png_path
        bpy.ops.render.render(write_still=True)
        result.update({"png": png_path, "camera_location": list(cam.location),
                       "ortho_scale": cam_data.ortho_scale, "resolution": [48, 48]})
    print("GVR_BLENDER_JSON " + json.dumps(result))
''')


def blender(tmp, vdb_path, png_path=None):
    script = os.path.join(tmp, "blender_client.py")
    with open(script, "w") as f:
        f.write(BLENDER_SCRIPT)
    out = run([BLENDER, "-b", "--factory-startup", "--python-exit-code", "1", "--python", script, "--",
               vdb_path, png_path or "", "1" if png_path else "0"])
    lines = [l for l in out.splitlines() if l.startswith("GVR_BLENDER_JSON ")]
    if len(lines) != 1:
        print(out[-4000:])
        raise RuntimeError("Blender printed no result line")
    return json.loads(lines[0][len("GVR_BLENDER_JSON "):])


def check_blender_geometry(label, result, grid, expected_index_to_world, dims):
    """Blender's grid transform and bounds against the expected index->world affine."""
    for name, _, _, matrix in result["grids"]:
        check(f"{label} Blender grid '{name}' matrix_object == source index->world",
              np.allclose(np.array(matrix), expected_index_to_world, atol=1e-4),
              f"max diff {np.abs(np.array(matrix) - expected_index_to_world).max():.2e}")
    check(f"{label} Blender object matrix_world is identity",
          np.allclose(np.array(result["matrix_world"]), np.eye(4), atol=1e-6))
    got_lo, got_hi = np.array(result["bbox_min"]), np.array(result["bbox_max"])
    # What Blender 3.4 reports: the leaf-node box, at voxel-centre coordinates.
    leaf_lo, leaf_hi = grid.evalLeafBoundingBox()
    leaf_world = np.array([expected_index_to_world @ np.array([x, y, z, 1.0])
                           for x in (leaf_lo[0], leaf_hi[0]) for y in (leaf_lo[1], leaf_hi[1])
                           for z in (leaf_lo[2], leaf_hi[2])])[:, :3]
    check(f"{label} Blender bound_box == leaf box of the VDB (voxel centres) mapped by the source affine",
          np.allclose(got_lo, leaf_world.min(0), atol=1e-3) and np.allclose(got_hi, leaf_world.max(0), atol=1e-3),
          f"blender {got_lo.round(3).tolist()}..{got_hi.round(3).tolist()}, "
          f"leaf box {leaf_world.min(0).round(3).tolist()}..{leaf_world.max(0).round(3).tolist()}")
    src_lo, src_hi = world_box(expected_index_to_world, dims, corners=False)
    voxel = np.abs(expected_index_to_world[:3, :3]).sum(axis=1)  # world extent of one voxel step per axis
    over_lo, over_hi = src_lo - got_lo, got_hi - src_hi
    check(f"{label} Blender bound_box contains the source's voxel-centre box and overshoots it by < 1 leaf",
          bool(np.all(over_lo >= -1e-3) and np.all(over_hi >= -1e-3)
               and np.all(over_lo < LEAF * voxel) and np.all(over_hi < LEAF * voxel)),
          f"source centres {src_lo.round(3).tolist()}..{src_hi.round(3).tolist()}, "
          f"overshoot low {over_lo.round(3).tolist()} high {over_hi.round(3).tolist()} mm")
    within_voxel = bool(np.all(np.abs(over_lo) <= voxel + 1e-3) and np.all(np.abs(over_hi) <= voxel + 1e-3))
    print(f"INFO {label} Blender bound_box within one voxel of the source's box on every side: {within_voxel} "
          f"(not required: Blender reports leaf-node bounds)")


def read_png(path):
    from PIL import Image
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"), dtype=np.float64) / 255.0


def grey_case(gvr, shared, tmp):
    print("== grey: mri-colin27-aal/ch2.nii.gz ==")
    source = os.path.join(shared, "mri-colin27-aal", "ch2.nii.gz")
    src = nibabel.load(source)
    src_shape, src_affine = tuple(src.shape[:3]), src.affine
    ingested = os.path.join(tmp, "ch2.vdb")
    asset = os.path.join(tmp, "ch2.gvr")
    exported = os.path.join(tmp, "ch2_export.vdb")
    run([gvr, "ingest", source, "-o", ingested, "-q"])
    fit = json.loads(run([gvr, "fit", ingested, "-o", asset, "--gaussians", 3000, "--iterations", 60,
                          "--seed", 1, "-q", "--json"]))
    print(f"  fit: {fit['gaussians']} Gaussians, psnr {fit['psnr_db']:.2f} dB")
    nifti_path = os.path.join(tmp, "ch2_export.nii.gz")
    export = json.loads(run([gvr, "export", asset, "-o", exported, "-o", nifti_path, "--json", "-q"]))
    written = [output["path"] for output in export["outputs"]]
    check("grey export reports the NIfTI next to the VDB",
          os.path.isfile(nifti_path) and written == [exported, nifti_path], f"outputs = {written}")
    threshold = float(export["threshold"])

    # --- pyopenvdb ---
    grids, file_meta = vdb.readAll(exported)
    names = [g.name for g in grids]
    check("grey VDB grid names are exactly ['density']", names == ["density"], f"{names}")
    grid = grids[0]
    check("grey VDB 'density' is a FloatGrid", isinstance(grid, vdb.FloatGrid), type(grid).__name__)
    check("grey VDB 'density' grid class is fog volume", grid.gridClass == vdb.GridClass.FOG_VOLUME,
          f"{grid.gridClass}")
    dims = tuple(int(d) for d in grid.metadata.get("gvr_dims", ()))
    check("grey VDB gvr_dims == source shape", dims == src_shape, f"{dims} vs {src_shape}")
    index_to_world = transform_matrix(grid)
    test_ijk = [(0, 0, 0), (180, 216, 180), (90, 108, 90), (17, 201, 3), (150, 5, 99)]
    worst_mm = 0.0
    for ijk in test_ijk:
        got = np.array(grid.transform.indexToWorld(ijk))
        want = (src_affine @ np.array([*ijk, 1.0]))[:3]
        worst_mm = max(worst_mm, float(np.abs(got - want).max()))
    check("grey VDB indexToWorld == nibabel affine of the source (5 voxels)", worst_mm < 1e-4,
          f"worst {worst_mm:.2e} mm")
    check("grey VDB transform (as a matrix) == nibabel affine", np.allclose(index_to_world, src_affine, atol=1e-4))

    dense = np.zeros(src_shape, dtype=np.float32)
    grid.copyToArray(dense, ijk=(0, 0, 0))
    accessor = grid.getConstAccessor()
    # In-brain voxels with a clearly non-zero value, chosen deterministically.
    rng = np.random.RandomState(1234)
    candidates = np.argwhere(dense > 0.3 * float(dense.max()))
    check("grey VDB has clearly non-zero voxels", len(candidates) > 1000, f"{len(candidates)} voxels > 30% of max")
    picked = [tuple(int(c) for c in candidates[i]) for i in rng.choice(len(candidates), 6, replace=False)]
    edge = np.argwhere((dense > threshold) & (dense < 0.05 * float(dense.max())))  # faint active voxel
    if len(edge):
        picked.append(tuple(int(c) for c in edge[rng.randint(len(edge))]))
    corner = (0, 0, 0)
    picked.append(corner)
    points = probe(gvr, asset, picked)
    for ijk, point in zip(picked, points):
        value, active = accessor.probeValue(ijk)
        expected = float(point["value"][0])
        world_ok = np.allclose(point["world_mm"], (src_affine @ np.array([*ijk, 1.0]))[:3], atol=1e-4)
        if expected > threshold:
            ok = active and rel_close(value, expected)
        else:  # gvr leaves voxels at or below the threshold inactive, holding the background
            ok = (not active) and value == grid.background
        check(f"grey VDB voxel {ijk} == gvr probe", ok and world_ok,
              f"vdb {value:.6g} (active {active}), probe {expected:.6g} ({point['gaussians']} Gaussians), "
              f"probe world {point['world_mm']}")
    c_value, c_active = accessor.probeValue(corner)
    check(f"grey corner voxel {corner} is inactive background", (not c_active) and c_value == grid.background,
          f"value {c_value}, active {c_active}, background {grid.background}")

    # --- nibabel ---
    out = nibabel.load(nifti_path)
    check("grey NIfTI shape == source shape", tuple(out.shape) == src_shape, f"{out.shape} vs {src_shape}")
    check("grey NIfTI affine == source affine", np.allclose(out.affine, src_affine, atol=1e-4),
          f"max diff {np.abs(out.affine - src_affine).max():.2e}")
    sform, sform_code = out.header.get_sform(coded=True)
    check("grey NIfTI has an sform equal to the source affine",
          sform is not None and sform_code > 0 and np.allclose(sform, src_affine, atol=1e-4), f"code {sform_code}")
    check("grey NIfTI keeps the source's datatype and sform code",
          out.get_data_dtype() == src.get_data_dtype() and sform_code == src.header.get_sform(coded=True)[1],
          f"{out.get_data_dtype()} code {sform_code}, source {src.get_data_dtype()}")
    # ch2 stores uint8 with no scaling: the reconstruction is rounded and clamped into it.
    nii = np.asanyarray(out.get_fdata(dtype=np.float32))
    stored = np.clip(np.round(dense), 0, 255)
    for ijk in picked:
        check(f"grey NIfTI voxel {ijk} == VDB value rounded into uint8", nii[ijk] == stored[ijk],
              f"nifti {nii[ijk]:.6g}, vdb {dense[ijk]:.6g}")
    check("grey NIfTI == VDB densified (inactive -> background), rounded into uint8, at every voxel",
          np.array_equal(nii, stored), f"max diff {np.abs(nii - stored).max():.3g}")

    # --- Blender ---
    png = os.path.join(tmp, "ch2_render.png")
    result = blender(tmp, exported, png)
    print(f"  blender: {json.dumps({k: result[k] for k in ('grids', 'bbox_min', 'bbox_max', 'png')})[:400]}")
    bnames = [g[0] for g in result["grids"]]
    check("grey Blender grid names include 'density'", "density" in bnames, f"{bnames}")
    check("grey Blender 'density' is FLOAT", any(g[0] == "density" and g[1] == "FLOAT" for g in result["grids"]))
    check_blender_geometry("grey", result, grid, src_affine, src_shape)

    image = read_png(png)
    background = np.ones(3)  # white world, Standard view transform
    darkness = np.abs(image - background).max(axis=2)
    covered = darkness > 0.1
    corner_px = darkness[[0, 0, -1, -1], [0, -1, 0, -1]]
    check("grey render corners show the background", bool(np.all(corner_px < 0.02)),
          f"corner darkness {corner_px.round(3).tolist()}")
    check("grey render is not empty (> 10% pixels differ from the background by > 0.1)",
          covered.mean() > 0.10, f"{100 * covered.mean():.1f}% covered, max darkness {darkness.max():.2f}")
    # Where the covered pixels are: ortho camera looking along +Y, right = +X, up = +Z.
    h, w = darkness.shape
    scale = result["ortho_scale"]
    cam = np.array(result["camera_location"])
    vs, us = np.nonzero(covered)
    xs = cam[0] + ((us + 0.5) / w - 0.5) * scale
    zs = cam[2] + (0.5 - (vs + 0.5) / h) * scale
    lo, hi = world_box(src_affine, src_shape, corners=True)
    margin = 2.0 * scale / w  # the pixel filter spreads the edge by ~1-2 pixels
    inside = (xs >= lo[0] - margin) & (xs <= hi[0] + margin) & (zs >= lo[2] - margin) & (zs <= hi[2] + margin)
    check("grey render silhouette lies inside the source's world box (x, z)", bool(inside.all()),
          f"covered x {xs.min():.1f}..{xs.max():.1f}, z {zs.min():.1f}..{zs.max():.1f} mm; "
          f"source x {lo[0]:.1f}..{hi[0]:.1f}, z {lo[2]:.1f}..{hi[2]:.1f} mm, margin {margin:.1f}")
    check("grey render silhouette spans most of the head (> 50% of the source's x and z extent)",
          (xs.max() - xs.min()) > 0.5 * (hi[0] - lo[0]) and (zs.max() - zs.min()) > 0.5 * (hi[2] - lo[2]))


def rgb_case(gvr, shared, tmp):
    print("== RGB: rgb-brainmaps54-cryosection (spacing 1,1,3.5) ==")
    source = os.path.join(shared, "rgb-brainmaps54-cryosection")
    ingested = os.path.join(tmp, "rgb.vdb")
    asset = os.path.join(tmp, "rgb.gvr")
    houdini = os.path.join(tmp, "rgb_houdini.vdb")
    default = os.path.join(tmp, "rgb_blender.vdb")
    run([gvr, "ingest", source, "-o", ingested, "--spacing", "1,1,3.5", "-q"])
    fit = json.loads(run([gvr, "fit", ingested, "-o", asset, "--gaussians", 3000, "--iterations", 60,
                          "--seed", 1, "-q", "--json"]))
    print(f"  fit: {fit['gaussians']} Gaussians, psnr {fit['psnr_db']:.2f} dB")
    export = json.loads(run([gvr, "export", asset, "-o", houdini, "--names", "houdini", "--json", "-q"]))
    threshold = float(export["threshold"])

    grids, _ = vdb.readAll(houdini)
    by_name = {g.name: g for g in grids}
    check("RGB houdini VDB grid names are exactly {'Cd', 'density'}", sorted(by_name) == ["Cd", "density"],
          f"{[g.name for g in grids]}")
    cd, density = by_name["Cd"], by_name["density"]
    check("RGB houdini 'Cd' is vec3s", isinstance(cd, vdb.Vec3SGrid) and cd.valueTypeName == "vec3s",
          f"{type(cd).__name__} {cd.valueTypeName}")
    check("RGB houdini 'density' is float fog volume",
          isinstance(density, vdb.FloatGrid) and density.gridClass == vdb.GridClass.FOG_VOLUME,
          f"{type(density).__name__} {density.gridClass}")
    dims = tuple(int(d) for d in cd.metadata.get("gvr_dims", ()))
    check("RGB gvr_dims == stack dims (512, 304, 57)", dims == (512, 304, 57), f"{dims}")
    expected_affine = np.diag([1.0, 1.0, 3.5, 1.0])  # image stack: origin 0, spacing from --spacing
    check("RGB 'Cd' and 'density' transforms == diag(1, 1, 3.5)",
          np.allclose(transform_matrix(cd), expected_affine, atol=1e-6)
          and np.allclose(transform_matrix(density), expected_affine, atol=1e-6))

    rng = np.random.RandomState(99)
    # Enough voxels that some lie on each side of the surround: a fit makes most of
    # the paper the surround itself, where the density is 0.
    picked = [tuple(int(rng.randint(n)) for n in dims) for _ in range(48)]
    picked += [(256, 152, 28), (0, 0, 0), (dims[0] - 1, dims[1] - 1, dims[2] - 1)]
    points = probe(gvr, asset, picked)
    cd_acc, den_acc = cd.getConstAccessor(), density.getConstAccessor()
    lum, dens = [], []
    for ijk, point in zip(picked, points):
        value, active = cd_acc.probeValue(ijk)
        d_value, d_active = den_acc.probeValue(ijk)
        expected = np.array(point["value"], dtype=np.float64)
        l_expected = 0.2126 * expected[0] + 0.7152 * expected[1] + 0.0722 * expected[2]
        world_ok = np.allclose(point["world_mm"], (expected_affine @ np.array([*ijk, 1.0]))[:3], atol=1e-4)
        if l_expected > threshold:
            ok = active and d_active and rel_close(value, expected)
        else:
            ok = (not active) and (not d_active)
        check(f"RGB Cd voxel {ijk} == gvr probe", ok and world_ok,
              f"vdb {np.round(value, 4).tolist()} (active {active}), probe {np.round(expected, 4).tolist()}, "
              f"density {d_value:.5g}")
        if active and d_value > 1e-3:
            lum.append(0.2126 * value[0] + 0.7152 * value[1] + 0.0722 * value[2])
            dens.append(d_value)
    # density = |luminance(Cd) - b| / scale, b the luminance around the specimen: a line on
    # each side of b, with opposite slopes.
    if check("RGB enough voxels with density > 0 to test density vs luminance", len(dens) >= 3, f"{len(dens)}"):
        lum, dens = np.array(lum), np.array(dens)
        pivot = lum[np.argmin(dens)]
        slopes = []
        for side in (lum < pivot, lum > pivot):
            if side.sum() < 3:
                continue
            a = np.column_stack([lum[side], np.ones(side.sum())])
            coef, *_ = np.linalg.lstsq(a, dens[side], rcond=None)
            residual = float(np.abs(a @ coef - dens[side]).max())
            check("RGB density is affine in the luminance on one side of the surround", residual < 1e-4 * dens.max(),
                  f"density = {coef[0]:.5f} * lum + {coef[1]:.4f}, max residual {residual:.2e}")
            slopes.append(coef[0])
        if len(slopes) == 2:
            check("RGB density slopes are opposite: distance from the surround", abs(slopes[0] + slopes[1]) < 1e-3 * abs(slopes[1]),
                  f"{slopes}")
        check("RGB density fits on at least one side", len(slopes) >= 1, f"{len(slopes)}")

    run([gvr, "export", asset, "-o", default, "-q"])
    result = blender(tmp, default)
    print(f"  blender: {json.dumps({k: result[k] for k in ('grids', 'bbox_min', 'bbox_max')})[:400]}")
    types = {g[0]: g[1] for g in result["grids"]}
    check("RGB Blender grids are 'color' (VECTOR_FLOAT) and 'density' (FLOAT)",
          types == {"color": "VECTOR_FLOAT", "density": "FLOAT"}, f"{types}")
    grids_default = {g.name: g for g in vdb.readAll(default)[0]}
    check("RGB default-name VDB grid names are exactly {'color', 'density'}",
          sorted(grids_default) == ["color", "density"], f"{sorted(grids_default)}")
    check_blender_geometry("RGB", result, grids_default["color"], expected_affine, dims)


def both_cases(gvr, shared, scratch):
    grey_case(gvr, shared, scratch)
    rgb_case(gvr, shared, scratch)


if __name__ == "__main__":
    sys.exit(checks.run(both_cases, __doc__))
