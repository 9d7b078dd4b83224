"""seamlit for Blender: fix the normals of several mesh objects across their seams.

The operator reads each selected mesh object's corner normals (what Blender shows now:
smooth and sharp edges, existing custom normals), hands all objects to ``seamlit.fix`` as
one model (placed by their world matrices), and writes the result back as custom split
normals. With the default ``auto`` policy, only corners at positions that two or more
objects share change. Nothing else of the objects is touched.
"""

from __future__ import annotations

import numpy as np

import bpy
from bpy.props import EnumProperty, FloatProperty, StringProperty

MODES = [
    ("model", "Across Objects", "Smooth across all selected objects: the seams go"),
    ("object", "Per Object", "Smooth within each object only: the seams stay"),
    ("flat", "Flat", "Face normals"),
]
WEIGHTINGS = [
    ("angle", "Angle", "By the corner angle at the vertex"),
    ("area", "Area", "By face area"),
    ("angle-area", "Angle x Area", "By corner angle times face area"),
    ("uniform", "Uniform", "Every face once (the paper's plain average)"),
]
NORMALS = [
    ("auto", "Auto", "Keep the objects' normals; repair only the seams that smoothing each object alone made (hard edges and custom normals stay)"),
    ("smooth-shared", "Smooth shared", "As Auto, but average every shared position within the crease, hard edges between objects included"),
    ("keep", "Keep", "Keep every normal the objects have, seams included"),
    ("recompute", "Recompute", "Compute every normal from the faces"),
]


def corner_arrays(obj):
    """One seamlit object for a Blender mesh object: a vertex per distinct (vertex, corner
    normal) pair, so that sharp edges and custom normals survive; and for every loop of
    every loop triangle, the seamlit vertex of that corner."""
    mesh = obj.data
    mesh.calc_loop_triangles()
    co = np.empty(len(mesh.vertices) * 3, np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    loop_vertex = np.empty(len(mesh.loops), np.int64)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    corner_normals = np.empty(len(mesh.loops) * 3, np.float32)
    mesh.corner_normals.foreach_get("vector", corner_normals)
    corner_normals = corner_normals.reshape(-1, 3)
    tri_loops = np.empty(len(mesh.loop_triangles) * 3, np.int64)
    mesh.loop_triangles.foreach_get("loops", tri_loops)
    # A seamlit vertex per (Blender vertex, corner normal bits).
    keys = np.concatenate(
        [loop_vertex[:, None].view(np.int64), corner_normals.view(np.int32).astype(np.int64)], axis=1
    )
    unique, loop_to_vertex = np.unique(keys, axis=0, return_inverse=True)
    loop_to_vertex = loop_to_vertex.reshape(-1)
    first_loop = np.zeros(len(unique), np.int64)
    first_loop[loop_to_vertex[::-1]] = np.arange(len(loop_to_vertex))[::-1]
    arrays = {
        "name": obj.name,
        "positions": co[unique[:, 0]],
        "normals": corner_normals[first_loop],
        "triangles": loop_to_vertex[tri_loops].reshape(-1, 3).astype(np.uint32),
        "transform": np.array(obj.matrix_world, np.float32),
    }
    return arrays, tri_loops


def write_corner_normals(mesh, normals):
    """Sets a mesh's custom normals, one per corner. Blender 5 keeps them as they are, as a
    float corner attribute ("free" normals); older versions encode them relative to each
    corner's smooth fan (a few thousandths of a degree off)."""
    if bpy.app.version >= (5, 0, 0):
        existing = mesh.attributes.get("custom_normal")
        if existing is not None:
            mesh.attributes.remove(existing)
        attribute = mesh.attributes.new("custom_normal", "FLOAT_VECTOR", "CORNER")
        attribute.data.foreach_set("vector", normals.reshape(-1))
        mesh.update()
    else:
        mesh.normals_split_custom_set(normals.tolist())


def seam_angle(objects, normals_per_object):
    """The largest angle (degrees) between world-space normals that different objects give
    one world position; 0 where no position is shared."""
    seen = {}
    worst = 0.0
    for index, (o, normals) in enumerate(zip(objects, normals_per_object)):
        m = o["transform"].astype(np.float64)
        world = o["positions"] @ m[:3, :3].T + m[:3, 3]
        n = normals @ np.linalg.inv(m[:3, :3])
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        for p, v in zip(np.round(world, 5), n):
            key = tuple(p)
            first = seen.setdefault(key, (index, v))
            if first[0] != index:
                angle = np.degrees(np.arccos(np.clip(np.dot(first[1], v), -1.0, 1.0)))
                worst = max(worst, angle)
    return worst


class OBJECT_OT_seamlit_fix_seams(bpy.types.Operator):
    """Smooth the normals of the selected mesh objects across the seams where they meet,
    as custom split normals"""

    bl_idname = "object.seamlit_fix_seams"
    bl_label = "Fix Seams Across Objects"
    bl_options = {"REGISTER", "UNDO"}

    mode: EnumProperty(name="Mode", items=MODES, default="model")
    crease: FloatProperty(
        name="Crease Angle",
        description="Faces meeting at a sharper angle keep separate normals (180: smooth everything)",
        default=60.0,
        min=0.0,
        max=180.0,
    )
    weld_tolerance: StringProperty(
        name="Weld Tolerance",
        description="How close positions must be to be one: a distance, rel:FRACTION of the bounding-box diagonal, or exact",
        default="rel:1e-6",
    )
    weighting: EnumProperty(name="Weighting", items=WEIGHTINGS, default="angle")
    normals: EnumProperty(name="Normals", items=NORMALS, default="auto")

    @classmethod
    def poll(cls, context):
        return any(o.type == "MESH" for o in context.selected_objects)

    def execute(self, context):
        try:
            import seamlit
        except ImportError:
            self.report({"ERROR"}, "seamlit: the seamlit Python package is not installed (see the add-on's README)")
            return {"CANCELLED"}
        targets = [o for o in context.selected_objects if o.type == "MESH" and len(o.data.polygons)]
        if not targets:
            self.report({"WARNING"}, "seamlit: no mesh object with faces is selected")
            return {"CANCELLED"}
        objects, loops = zip(*(corner_arrays(o) for o in targets))
        before = seam_angle(objects, [o["normals"] for o in objects])
        try:
            fixed = seamlit.fix(
                objects,
                mode=self.mode,
                crease=self.crease,
                weld_tolerance=self.weld_tolerance,
                weighting=self.weighting,
                normals=self.normals,
                tangents="none",
            )
        except seamlit.SeamlitError as error:
            self.report({"ERROR"}, f"seamlit: {error}")
            return {"CANCELLED"}
        for obj, o, tri_loops, f in zip(targets, objects, loops, fixed):
            corner = np.empty((len(obj.data.loops), 3), np.float32)
            corner[tri_loops] = f["normals"][f["triangles"].reshape(-1)]
            write_corner_normals(obj.data, corner)
        after_objects = [dict(o, positions=o["positions"][f["remap"]]) for o, f in zip(objects, fixed)]
        after = seam_angle(after_objects, [f["normals"] for f in fixed])
        message = f"seamlit: {len(targets)} objects, seams {before:.2f}° before, {after:.2f}° after"
        # An INFO report is what the status bar shows after an operator.
        self.report({"INFO"}, message)
        return {"FINISHED"}


class VIEW3D_PT_seamlit(bpy.types.Panel):
    bl_label = "seamlit"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "seamlit"

    def draw(self, context):
        layout = self.layout
        layout.label(text=f"{sum(o.type == 'MESH' for o in context.selected_objects)} mesh objects selected")
        layout.operator(OBJECT_OT_seamlit_fix_seams.bl_idname)


def menu(self, context):
    self.layout.operator(OBJECT_OT_seamlit_fix_seams.bl_idname)


CLASSES = (OBJECT_OT_seamlit_fix_seams, VIEW3D_PT_seamlit)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.VIEW3D_MT_object.append(menu)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(menu)
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
