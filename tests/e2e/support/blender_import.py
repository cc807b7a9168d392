# Run inside Blender: blender --background --factory-startup --python-exit-code 1 \
#   --python blender_import.py -- OUT.json FILE.glb ...
# Imports each .glb with Blender's own glTF importer into an empty scene (the frame rate set
# first from the file's scene extras, as a user script should) and writes what Blender made of
# it to OUT.json: vertices, smooth polygons, shape keys, actions, the scene's fps, the colour of
# vertex 0 and how far the vertices move between the first frame and the middle one.
import json
import struct
import sys

import numpy as np

# Debian's Blender 3.4.1 importer uses np.bool, removed in numpy 1.24: the one-line workaround.
if not hasattr(np, "bool"):
    np.bool = bool

import bpy  # noqa: E402


def gltf_json(path):
    with open(path, "rb") as handle:
        header = handle.read(20)
        length = struct.unpack_from("<I", header, 12)[0]
        return json.loads(handle.read(length))


def world_positions(obj):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    matrix = np.array(evaluated.matrix_world)
    coordinates = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", coordinates)
    evaluated.to_mesh_clear()
    points = coordinates.reshape(-1, 3)
    return points @ matrix[:3, :3].T + matrix[:3, 3]


def inspect(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    extras = gltf_json(path)["scenes"][0].get("extras", {})
    scene = bpy.context.scene
    if "fps" in extras:  # glTF keys animations in seconds; Blender converts at the scene's rate
        scene.render.fps = round(extras["fps"])
        scene.render.fps_base = round(extras["fps"]) / extras["fps"]
    bpy.ops.import_scene.gltf(filepath=path)
    meshes = [o for o in scene.objects if o.type == "MESH"]
    obj = meshes[0]
    mesh = obj.data
    keys = mesh.shape_keys.key_blocks if mesh.shape_keys else []
    colour = None
    if mesh.color_attributes:
        attribute = mesh.color_attributes[0]
        colour = list(attribute.data[0].color)[:3] if attribute.domain == "POINT" else None
        if colour is None:  # corner domain: the first corner of vertex 0
            for loop in mesh.loops:
                if loop.vertex_index == 0:
                    colour = list(attribute.data[loop.index].color)[:3]
                    break
    start, end = (int(v) for v in (bpy.data.actions[0].frame_range if bpy.data.actions else (1, 1)))
    scene.frame_set(start)
    first = world_positions(obj)
    scene.frame_set((start + end) // 2)
    middle = world_positions(obj)
    return {"file": path, "vertices": len(mesh.vertices), "polygons": len(mesh.polygons),
            "smooth_polygons": sum(1 for p in mesh.polygons if p.use_smooth),
            "shape_keys": max(0, len(keys) - 1), "actions": len(bpy.data.actions),
            "action_names": sorted(a.name for a in bpy.data.actions),
            "scene_fps": scene.render.fps / scene.render.fps_base, "extras_fps": extras.get("fps"),
            "frame_range": [start, end], "colour_vertex0": colour,
            "max_move_m": float(np.abs(middle - first).max()),
            "max_root_move_m": float(np.abs(middle.mean(axis=0) - first.mean(axis=0)).max())}


arguments = sys.argv[sys.argv.index("--") + 1:]
results = [inspect(path) for path in arguments[1:]]
with open(arguments[0], "w", encoding="utf-8") as handle:
    json.dump(results, handle, indent=1)
