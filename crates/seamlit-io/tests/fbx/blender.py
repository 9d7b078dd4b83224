"""Blender (the bpy module) for seamlit-io's FBX tests (tests/fbx.rs): writes the test
scenes as FBX with Blender's own exporter, and reads an FBX back with Blender's own importer
into JSON, the reference the tests compare seamlit's reading with.

    python3 blender.py write SCENE OUT.fbx   # SCENE: head_body, names, arm, shapes, textured, embedded, nothing
    python3 blender.py read IN.fbx OUT.json
    python3 blender.py pose IN.fbx OUT.json FRAME...

The JSON: {"objects": [{"name", "type", "parent", "world": [16, row-major],
"positions": [[x, y, z], ...] (mesh vertices, world space), "triangles": N}]}, with every
position and matrix converted from Blender's +Z up to glTF's +Y up ((x, y, z) -> (x, z, -y)).
"""

import json
import math
import os
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
    parts), two UV layers, vertex colours and tangents. Written +Z up."""
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


def arm():
    """A skinned, animated arm: a tube along +X (0 to 2) bound to a two-bone armature
    ("Плечо" the upper arm, "Предплечье" the forearm), weights blended over the elbow; over
    frames 0 to 24 the forearm bends 90 degrees and the upper arm 20. 24 frames a second."""
    scene = bpy.context.scene
    scene.render.fps = 24
    scene.frame_start, scene.frame_end = 0, 24
    data = bpy.data.armatures.new("Скелет")
    rig = bpy.data.objects.new("Скелет", data)
    scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    upper = data.edit_bones.new("Плечо")
    upper.head, upper.tail = (0, 0, 0), (1, 0, 0)
    lower = data.edit_bones.new("Предплечье")
    lower.head, lower.tail = (1, 0, 0), (2, 0, 0)
    lower.parent = upper
    lower.use_connect = True
    bpy.ops.object.mode_set(mode="OBJECT")
    n = 8
    rings = [[(x, 0.1 * math.cos(2 * math.pi * k / n), 0.1 * math.sin(2 * math.pi * k / n)) for k in range(n)] for x in (0.0, 0.5, 0.8, 1.0, 1.2, 1.5, 2.0)]
    mesh = mesh_object("Рука", rings, True, True)
    mesh.parent = rig
    groups = {name: mesh.vertex_groups.new(name=name) for name in ("Плечо", "Предплечье")}
    for v in mesh.data.vertices:
        t = min(max((v.co.x - 0.8) / 0.4, 0.0), 1.0)
        if t < 1.0:
            groups["Плечо"].add([v.index], 1.0 - t, "REPLACE")
        if t > 0.0:
            groups["Предплечье"].add([v.index], t, "REPLACE")
    modifier = mesh.modifiers.new("Armature", "ARMATURE")
    modifier.object = rig
    for frame, (a, b) in ((0, (0.0, 0.0)), (12, (10.0, 60.0)), (24, (20.0, 90.0))):
        for bone, angle in (("Плечо", a), ("Предплечье", b)):
            pose_bone = rig.pose.bones[bone]
            pose_bone.rotation_mode = "XYZ"
            pose_bone.rotation_euler = (0.0, 0.0, math.radians(angle))
            pose_bone.keyframe_insert("rotation_euler", frame=frame)
    # Exported at frame 0, where the pose is the rest pose (the exporter writes the current
    # frame's transforms besides the animation).
    scene.frame_set(0)


def shapes():
    """A grid with two shape keys ("Улыбка" lifts the middle, "Frown" pushes one edge down),
    the smile animated."""
    n = 6
    rings = [[(x / (n - 1), y / (n - 1), 0.0) for x in range(n)] for y in range(n)]
    mesh = bpy.data.meshes.new("Лицо")
    bm = bmesh.new()
    rows = [[bm.verts.new(p) for p in r] for r in rings]
    for a, b in zip(rows, rows[1:]):
        for k in range(n - 1):
            bm.faces.new((a[k], a[k + 1], b[k + 1], b[k]))
    bm.to_mesh(mesh)
    bm.free()
    face = bpy.data.objects.new("Лицо", mesh)
    bpy.context.scene.collection.objects.link(face)
    face.shape_key_add(name="Basis")
    smile = face.shape_key_add(name="Улыбка")
    frown = face.shape_key_add(name="Frown")
    for i, v in enumerate(mesh.vertices):
        x, y = v.co.x, v.co.y
        smile.data[i].co.z = 0.3 * math.sin(math.pi * x) * math.sin(math.pi * y)
        frown.data[i].co.z = -0.2 * (1.0 - y) if y < 0.3 else 0.0
    smile.value = 0.25
    # Animated: the smile from 0.25 at frame 0 to 1 at frame 10, 24 frames a second.
    scene = bpy.context.scene
    scene.render.fps = 24
    scene.frame_start, scene.frame_end = 0, 10
    smile.keyframe_insert("value", frame=0)
    smile.value = 1.0
    smile.keyframe_insert("value", frame=10)
    scene.frame_set(0)


def textured(out):
    """A quad whose material's base colour is a 4 x 4 PNG (red, green, blue, white rows),
    saved as texture.png beside the FBX."""
    mesh = bpy.data.meshes.new("Quad")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [], [(0, 1, 2, 3)])
    uv = mesh.uv_layers.new(name="UVMap")
    for loop, co in zip(mesh.loops, ((0, 0), (1, 0), (1, 1), (0, 1))):
        uv.data[loop.index].uv = co
    quad = bpy.data.objects.new("Quad", mesh)
    bpy.context.scene.collection.objects.link(quad)
    image = bpy.data.images.new("texture", 4, 4)
    rows = [(1, 0, 0, 1), (0, 1, 0, 1), (0, 0, 1, 1), (1, 1, 1, 1)]
    image.pixels = [c for row in rows for _ in range(4) for c in row]
    image.filepath_raw = os.path.join(os.path.dirname(out), "texture.png")
    image.file_format = "PNG"
    image.save()
    material = bpy.data.materials.new("Картинка")
    nodes = material.node_tree.nodes
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    material.node_tree.links.new(texture.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
    mesh.materials.append(material)


def nothing():
    """No mesh: an empty object only."""
    bpy.context.scene.collection.objects.link(bpy.data.objects.new("Пусто", None))


def write(scene, out):
    empty_scene()
    if scene in ("textured", "embedded"):
        textured(out)
    else:
        {"head_body": head_body, "names": names, "arm": arm, "shapes": shapes, "nothing": nothing}[scene]()
    bpy.context.view_layer.update()
    bpy.ops.export_scene.fbx(
        filepath=out,
        use_selection=False,
        use_tspace=scene == "names",
        bake_anim=scene in ("arm", "shapes"),
        bake_anim_use_all_actions=False,
        bake_anim_use_nla_strips=False,
        add_leaf_bones=False,
        # "embedded" puts the texture's bytes in the file; the others name it by path.
        path_mode="COPY" if scene == "embedded" else "RELATIVE",
        embed_textures=scene == "embedded",
        # The names scene is written +Z up (Blender's own axes), the others +Y up (the
        # exporter's default): the reader converts either.
        axis_forward="Y" if scene == "names" else "-Z",
        axis_up="Z" if scene == "names" else "Y",
    )


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
            if mesh.shape_keys:
                entry["shape_keys"] = [
                    {"name": key.name, "value": key.value, "positions": [list(world @ d.co) for d in key.data]}
                    for key in mesh.shape_keys.key_blocks[1:]
                ]
        objects.append(entry)
        if obj.type == "ARMATURE":
            # Bones are nodes in FBX (and in glTF), parts of one object in Blender.
            for bone in obj.data.bones:
                parent = bone.parent.name if bone.parent else obj.name
                objects.append({"name": bone.name, "type": "BONE", "parent": parent})
    with open(out, "w", encoding="utf-8") as f:
        json.dump({"objects": objects}, f, ensure_ascii=False)


def pose(path, out, *frames):
    """The evaluated (skinned, animated) world positions of every mesh at each frame, and the
    time in seconds each frame is at."""
    empty_scene()
    # No offset: the importer's default moves the animation one frame later.
    bpy.ops.import_scene.fbx(filepath=path, anim_offset=0.0)
    scene = bpy.context.scene
    poses = []
    for frame in frames:
        scene.frame_set(int(frame))
        depsgraph = bpy.context.evaluated_depsgraph_get()
        meshes = {}
        for obj in bpy.data.objects:
            if obj.type != "MESH":
                continue
            evaluated = obj.evaluated_get(depsgraph)
            world = Z_UP_TO_Y_UP @ evaluated.matrix_world
            mesh = evaluated.to_mesh()
            meshes[obj.name] = [list(world @ v.co) for v in mesh.vertices]
            evaluated.to_mesh_clear()
        fps = scene.render.fps / scene.render.fps_base
        poses.append({"frame": int(frame), "time": int(frame) / fps, "meshes": meshes})
    with open(out, "w", encoding="utf-8") as f:
        json.dump({"poses": poses}, f, ensure_ascii=False)


if __name__ == "__main__":
    command, *args = sys.argv[1:]
    {"write": write, "read": read, "pose": pose}[command](*args)
