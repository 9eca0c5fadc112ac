"""Render a gvr export in headless Blender (Cycles) with a volume material.

    gvr export ASSET.gvr -o scan.vdb --dcc
    gvr info --json scan.vdb > scan.json          # optional: frame as gvr render does
    blender -b --factory-startup -P examples/blender/render.py -- scan.vdb scan.png \
        [--frame scan.json] [--azimuth 30] [--elevation 15] [--size 256] [--samples 16]

The export must come from `gvr export --dcc`: a "density" grid in 0..1 (the
transfer function's opacity per voxel), a "color" grid in 0..1, and one unit a
metre. The material emits and absorbs as gvr composites (extinction per metre
-ln(1 - density) / voxel size, emission its colour times that), so the picture
is as bright as `gvr render`'s. The camera is orthographic and orbits the volume's centre as `gvr render`'s
does: azimuth about the superior axis (+z), 0 looking from anterior (+y), and
elevation towards superior. With --frame (the JSON of `gvr info --json` on the
export) the view is framed on the source's whole box, exactly as `gvr render`
frames it; without, on the grid's bounds. The background is transparent, so the
PNG's alpha is the volume's silhouette.
"""

import argparse
import json
import math
import sys

import bpy
from mathutils import Matrix, Vector

MAX_DCC_VOXEL_M = 0.05  # no scanner's voxel is 5 cm; a millimetre export's are 1000 times a DCC one's


def arguments():
    parser = argparse.ArgumentParser(prog="render.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("vdb", help="export from gvr export --dcc")
    parser.add_argument("png", help="image to write (RGBA)")
    parser.add_argument("--frame", help="gvr info --json of the export: frame the source's box as gvr render does")
    parser.add_argument("--azimuth", type=float, default=30.0, help="degrees about +z; 0 looks from +y")
    parser.add_argument("--elevation", type=float, default=15.0, help="degrees towards +z")
    parser.add_argument("--size", type=int, default=256, help="image width and height in pixels")
    parser.add_argument("--samples", type=int, default=16, help="Cycles samples per pixel")
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    return parser.parse_args(argv)


def import_volume(path):
    for obj in list(bpy.data.objects):  # the factory scene's cube, light and camera
        bpy.data.objects.remove(obj, do_unlink=True)
    bpy.ops.object.volume_import(filepath=path)
    volume = next(obj for obj in bpy.data.objects if obj.type == 'VOLUME')
    volume.data.grids.load()
    names = [grid.name for grid in volume.data.grids]
    if "density" not in names:
        raise SystemExit(f"{path}: no 'density' grid (grids: {names}); export with gvr export --dcc")
    # A plain export is in millimetres, its density the physical value: a scan
    # hundreds of metres across, drawn as a fog box around the camera.
    if voxel_size(volume) > MAX_DCC_VOXEL_M:
        raise SystemExit(f"{path}: voxels of {voxel_size(volume):g} units, so not a --dcc export (one unit a metre); "
                         "export with gvr export --dcc")
    return volume


def voxel_size(volume):
    """Length of the density grid's first index axis, in metres."""
    grid = next(grid for grid in volume.data.grids if grid.name == "density")
    return Vector(grid.matrix_object.col[0][:3]).length


def source_corners(info_path):
    """The world corners of the source's voxel cells, as gvr render's worldCorners()."""
    with open(info_path) as file:
        grid = json.load(file)["grids"][0]
    affine = Matrix(grid["affine"])
    dims = grid["metadata"]["gvr_dims"]
    return [(affine @ Vector((i - 0.5, j - 0.5, k - 0.5, 1.0))).to_3d()
            for i in (0, dims[0]) for j in (0, dims[1]) for k in (0, dims[2])]


def bound_corners(volume):
    evaluated = volume.evaluated_get(bpy.context.evaluated_depsgraph_get())
    return [evaluated.matrix_world @ Vector(corner) for corner in evaluated.bound_box]


def add_material(volume):
    """Emission and absorption, as gvr composites: each voxel's density is the
    transfer function's opacity over one voxel, so the medium's extinction per metre
    is -ln(1 - density) / voxel size, and it emits its colour in proportion. (A
    Principled Volume scatters the world's light instead, and its self-shadowing
    rendered the chest and an MRI about half as bright as gvr render.)"""
    material = bpy.data.materials.new("gvr_volume")
    material.use_nodes = True
    tree = material.node_tree
    nodes, links = tree.nodes, tree.links
    for node in list(nodes):
        nodes.remove(node)

    def operate(operation, a, b):
        node = nodes.new("ShaderNodeMath")
        node.operation = operation
        for socket, value in zip(node.inputs, (a, b)):
            if isinstance(value, (int, float)):
                socket.default_value = value
            else:
                links.new(value, socket)
        return node.outputs["Value"]

    density = nodes.new("ShaderNodeAttribute")
    density.attribute_name = "density"
    colour = nodes.new("ShaderNodeAttribute")
    colour.attribute_name = "color"
    # An opacity of 1 is an infinite extinction: 0.999 is opaque within a voxel.
    clear = operate("SUBTRACT", 1.0, operate("MINIMUM", density.outputs["Fac"], 0.999))
    extinction = operate("MULTIPLY", operate("LOGARITHM", clear, math.e), -1.0 / voxel_size(volume))
    absorption = nodes.new("ShaderNodeVolumeAbsorption")
    absorption.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    links.new(extinction, absorption.inputs["Density"])
    emission = nodes.new("ShaderNodeEmission")
    links.new(colour.outputs["Color"], emission.inputs["Color"])
    links.new(extinction, emission.inputs["Strength"])
    both = nodes.new("ShaderNodeAddShader")
    links.new(absorption.outputs["Volume"], both.inputs[0])
    links.new(emission.outputs["Emission"], both.inputs[1])
    output = nodes.new("ShaderNodeOutputMaterial")
    links.new(both.outputs["Shader"], output.inputs["Volume"])
    volume.data.materials.append(material)


def add_camera(corners, azimuth, elevation):
    """gvr's OrthoCamera in Blender: same direction, up, centre and 2 % margin."""
    az, el = math.radians(azimuth), math.radians(elevation)
    direction = -Vector((math.cos(el) * math.sin(az), math.cos(el) * math.cos(az), math.sin(el)))
    right = direction.cross(Vector((0.0, 0.0, 1.0)))
    if right.length < 1e-9:
        right = Vector((-math.cos(az), math.sin(az), 0.0))
    right.normalize()
    up = right.cross(direction).normalized()
    centre = sum(corners, Vector((0.0, 0.0, 0.0))) / len(corners)
    half_right = max(abs((corner - centre).dot(right)) for corner in corners)
    half_up = max(abs((corner - centre).dot(up)) for corner in corners)
    extent = 2.0 * max(half_right, half_up)
    data = bpy.data.cameras.new("gvr_camera")
    data.type = 'ORTHO'
    data.ortho_scale = 1.02 * extent
    data.clip_start = 1e-4
    data.clip_end = 100.0 * extent + 10.0
    camera = bpy.data.objects.new("gvr_camera", data)
    bpy.context.scene.collection.objects.link(camera)
    # A Blender camera looks along its local -z with +y up.
    camera.matrix_world = Matrix((
        (right.x, up.x, -direction.x, centre.x - direction.x * 10.0 * extent),
        (right.y, up.y, -direction.y, centre.y - direction.y * 10.0 * extent),
        (right.z, up.z, -direction.z, centre.z - direction.z * 10.0 * extent),
        (0.0, 0.0, 0.0, 1.0)))
    bpy.context.scene.camera = camera


def set_up_render(png, size, samples):
    scene = bpy.context.scene
    world = bpy.data.worlds.new("gvr_world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    scene.world = world
    scene.render.engine = 'CYCLES'
    scene.cycles.device = 'CPU'
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.render.film_transparent = True
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    # gvr writes its colours as they are, with no display transform: Standard's sRGB
    # curve made every picture brighter than gvr render's (0.65 against 0.39 on ch2).
    scene.view_settings.view_transform = 'Raw'
    scene.render.image_settings.file_format = 'PNG'
    scene.render.image_settings.color_mode = 'RGBA'
    scene.render.filepath = png


def main():
    args = arguments()
    volume = import_volume(args.vdb)
    add_material(volume)
    corners = source_corners(args.frame) if args.frame else bound_corners(volume)
    add_camera(corners, args.azimuth, args.elevation)
    set_up_render(args.png, args.size, args.samples)
    bpy.ops.render.render(write_still=True)
    print(f"wrote {args.png}")


main()
