"""Blender (the bpy module) for seamlit-io's FBX tests (tests/fbx.rs): writes the test
scenes as FBX with Blender's own exporter, and reads an FBX back with Blender's own importer
into JSON, the reference the tests compare seamlit's reading with.

    python3 blender.py write SCENE OUT.fbx   # SCENE: head_body, names, nothing
    python3 blender.py read IN.fbx OUT.json

The JSON: {"objects": [{"name", "type", "parent", "world": [16, row-major],
"positions": [[x, y, z], ...] (mesh vertices, world space), "triangles": N}]}, with every
position and matrix converted from Blender's +Z up to glTF's +Y up ((x, y, z) -> (x, z, -y)).
"""

import json
import math
import sys

import bpy
import bmesh  # after bpy, which makes it importable
from mathutils import Matrix

# Blender's +Z up to glTF's +Y up.
Z_UP_TO_Y_UP = Matrix(((1, 0, 0, 0), (0, 0, 1, 0), (0, -1, 0, 0), (0, 0, 0, 1)))


def empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def ring(radius, height, n, offset=0.0):
    return [
        (radius * math.cos(2 * math.pi * (k + offset) / n), radius * math.sin(2 * math.pi * (k + offset) / n), height)
        for k in range(n)
    ]


def mesh_object(name, rings, cap_bottom, cap_top, parent=None):
    """A smooth tube through `rings` (lists of equally many points), capped where asked."""
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    layers = [[bm.verts.new(p) for p in r] for r in rings]
    n = len(rings[0])
    for a, b in zip(layers, layers[1:]):
        for k in range(n):
            bm.faces.new((a[k], a[(k + 1) % n], b[(k + 1) % n], b[k]))
    # Caps as triangle fans around a centre vertex (tangents are exported for triangles and
    # quads only).
    for layer, cap, flip in ((layers[0], cap_bottom, True), (layers[-1], cap_top, False)):
        if cap:
            centre = bm.verts.new(tuple(sum(v.co[i] for v in layer) / n for i in range(3)))
            for k in range(n):
                a, b = layer[k], layer[(k + 1) % n]
                bm.faces.new((centre, b, a) if flip else (centre, a, b))
    for f in bm.faces:
        f.smooth = True
    bm.to_mesh(mesh)
    bm.free()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    obj.parent = parent
    return obj


def head_body():
    """A body (a tube capped below) and a head (capped above) that share the neck ring: the
    same 16 positions, each object's normals there computed from its own faces only."""
    n = 16
    neck = ring(0.08, 1.5, n)
    body = mesh_object("Body", [ring(0.25, 0.0, n), ring(0.3, 1.0, n), ring(0.12, 1.4, n), neck], True, False)
    head = mesh_object("Head", [neck, ring(0.12, 1.6, n), ring(0.11, 1.8, n), ring(0.05, 1.9, n)], False, True)
    head.parent = body


def names():
    """Objects named in Cyrillic, parented, rotated and scaled; one with two materials (two
    parts), two UV layers, vertex colours and tangents."""
    root = bpy.data.objects.new("Корень", None)
    bpy.context.scene.collection.objects.link(root)
    root.location = (0.5, -0.25, 0.1)
    root.rotation_euler = (0.0, 0.0, 0.3)
    torso = mesh_object("Тело", [ring(0.3, 0.0, 8), ring(0.3, 0.6, 8)], True, True, root)
    torso.scale = (1.0, 1.5, 1.0)
    arm = mesh_object("Рука.левая", [ring(0.05, 0.0, 6, 0.5), ring(0.05, 0.5, 6, 0.5)], True, True, torso)
    arm.location = (0.35, 0.0, 0.4)
    arm.rotation_euler = (0.0, math.radians(70), 0.0)
    mesh = torso.data
    for material_name, colour in (("Кожа", (0.8, 0.6, 0.5, 1.0)), ("Ткань", (0.2, 0.4, 0.9, 1.0))):
        material = bpy.data.materials.new(material_name)
        material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = colour
        mesh.materials.append(material)
    for i, polygon in enumerate(mesh.polygons):
        polygon.material_index = i % 2
    for layer in ("UVMap", "Второй"):
        uv = mesh.uv_layers.new(name=layer)
        for loop in mesh.loops:
            co = mesh.vertices[loop.vertex_index].co
            uv.data[loop.index].uv = (math.atan2(co.y, co.x) / (2 * math.pi) + 0.5, co.z + (0.25 if layer != "UVMap" else 0.0))
    colors = mesh.color_attributes.new("Col", "FLOAT_COLOR", "CORNER")
    for i, c in enumerate(colors.data):
        c.color = (i % 3 / 2, i % 5 / 4, 0.5, 1.0)


def nothing():
    """No mesh: an empty object only."""
    bpy.context.scene.collection.objects.link(bpy.data.objects.new("Пусто", None))


def write(scene, out):
    empty_scene()
    {"head_body": head_body, "names": names, "nothing": nothing}[scene]()
    bpy.context.view_layer.update()
    bpy.ops.export_scene.fbx(filepath=out, use_selection=False, use_tspace=scene == "names", bake_anim=False)


def read(path, out):
    empty_scene()
    bpy.ops.import_scene.fbx(filepath=path)
    bpy.context.view_layer.update()
    objects = []
    for obj in bpy.data.objects:
        world = Z_UP_TO_Y_UP @ obj.matrix_world
        entry = {
            "name": obj.name,
            "type": obj.type,
            "parent": obj.parent.name if obj.parent else None,
            "world": [x for row in world for x in row],
        }
        if obj.type == "MESH":
            mesh = obj.data
            mesh.calc_loop_triangles()
            entry["positions"] = [list(world @ v.co) for v in mesh.vertices]
            entry["triangles"] = len(mesh.loop_triangles)
        objects.append(entry)
    with open(out, "w", encoding="utf-8") as f:
        json.dump({"objects": objects}, f, ensure_ascii=False)


if __name__ == "__main__":
    command, *args = sys.argv[1:]
    {"write": write, "read": read}[command](*args)
