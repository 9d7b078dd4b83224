"""Writes one model as FBX and as GLB with Blender (the bpy module), from one imported scene,
so that the two files hold the same objects, triangles, normals and UVs: the inputs of
benches/fbx.rs.

    python3 fbx_inputs.py IN.glb OUT_DIR    # writes OUT_DIR/model.fbx and OUT_DIR/model.glb
"""

import os
import sys

import bpy

source, out = sys.argv[1:3]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=source)
bpy.ops.export_scene.fbx(filepath=os.path.join(out, "model.fbx"), bake_anim=False)
bpy.ops.export_scene.gltf(
    filepath=os.path.join(out, "model.glb"),
    export_format="GLB",
    export_normals=True,
    export_tangents=False,
    export_animations=False,
    export_materials="NONE",
)
