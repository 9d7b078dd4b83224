"""Writes one model as FBX and as GLB with Blender (the bpy module), from one imported scene,
so that the two files hold the same objects, triangles, normals, UVs and materials (the same
normal map, so `seamlit fix` picks the same tangents for both): the inputs of benches/fbx.rs
and of BENCHMARKS.md's FBX-against-GLB timings.

    python3 fbx_inputs.py IN.glb OUT_DIR    # writes OUT_DIR/model.fbx and OUT_DIR/model.glb

Triangles of zero area (the teapot's poles) are deleted first: Blender drops them from one
export and not the other, and the two files would differ by them.
"""

import os
import sys

import bpy
import bmesh  # Blender's module, importable once bpy is

source, out = sys.argv[1:3]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=source)
removed = 0
for ob in bpy.context.scene.objects:
    if ob.type != "MESH":
        continue
    bm = bmesh.new()
    bm.from_mesh(ob.data)
    bad = [f for f in bm.faces if f.calc_area() <= 1e-12]
    removed += len(bad)
    bmesh.ops.delete(bm, geom=bad, context="FACES_ONLY")
    bm.to_mesh(ob.data)
    bm.free()
print(f"fbx_inputs.py: {removed} faces of zero area deleted")
bpy.ops.export_scene.fbx(filepath=os.path.join(out, "model.fbx"), bake_anim=False)
bpy.ops.export_scene.gltf(
    filepath=os.path.join(out, "model.glb"),
    export_format="GLB",
    export_normals=True,
    export_tangents=False,
    export_animations=False,
)
