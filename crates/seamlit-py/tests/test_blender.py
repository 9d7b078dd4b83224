"""The Blender add-on (blender/seamlit_seams), run headless with the `bpy` package (Blender
as a Python module): two objects sharing an edge, the operator, the custom normals read back.
"""

import os
import sys
from pathlib import Path

import numpy as np
import pytest

import bpy

REPO = Path(os.environ.get("SEAMLIT_REPO", Path(__file__).resolve().parents[3]))
sys.path.insert(0, str(REPO / "blender"))

import seamlit_seams  # noqa: E402


@pytest.fixture(scope="module", autouse=True)
def add_on():
    seamlit_seams.register()
    yield
    seamlit_seams.unregister()


def quad(name, corners, location=(0.0, 0.0, 0.0), faces=((0, 1, 2, 3),)):
    """A mesh object of quads with smooth shading, placed at `location`."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(c) for c in corners], [], [tuple(f) for f in faces])
    mesh.shade_smooth()
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    bpy.context.scene.collection.objects.link(obj)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.context.view_layer.update()  # matrix_world from the location
    return obj


def strip(name, profile, location=(0.0, 0.0, 0.0)):
    """A smooth-shaded strip of quads along x through the (x, z) points of `profile`, y from
    0 to 1: bent, so its shading is smooth across its middle (per-object smoothing)."""
    corners = [(x, y, z) for x, z in profile for y in (0.0, 1.0)]
    faces = [(2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1) for i in range(len(profile) - 1)]
    return quad(name, corners, location, faces)


def corner_normals(obj):
    n = np.empty(len(obj.data.loops) * 3, np.float32)
    obj.data.corner_normals.foreach_get("vector", n)
    return n.reshape(-1, 3)


def world_corners(obj):
    """Per loop: world position and world normal."""
    mesh = obj.data
    m = np.array(obj.matrix_world)
    co = np.array([mesh.vertices[l.vertex_index].co for l in mesh.loops])
    world = co @ m[:3, :3].T + m[:3, 3]
    n = corner_normals(obj) @ np.linalg.inv(m[:3, :3])
    return world, n / np.linalg.norm(n, axis=1, keepdims=True)


def seam(a, b):
    """The largest angle between normals of a and b at positions both have."""
    (pa, na), (pb, nb) = world_corners(a), world_corners(b)
    worst = 0.0
    for p, n in zip(pa, na):
        for q, m in zip(pb, nb):
            if np.allclose(p, q, atol=1e-5):
                worst = max(worst, np.degrees(np.arccos(np.clip(np.dot(n, m), -1, 1))))
    return worst


def scene():
    """Two objects each smoothed on its own, meeting at x = 1 at 30 degrees: a seam."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    flat = strip("flat", [(0.0, -0.1), (0.5, 0.0), (1.0, 0.0)])
    # The tilted strip is modelled around its own origin and placed by its object transform.
    tilted = strip("tilted", [(0.0, 0.0), (c, s), (c + 0.5, s + 0.1)], location=(1.0, 0.0, 0.0))
    return flat, tilted


def test_the_operator_closes_the_seam_and_keeps_every_other_corner(capfd):
    flat, tilted = scene()
    assert seam(flat, tilted) > 29.0
    before = {o.name: corner_normals(o).copy() for o in (flat, tilted)}
    uvs_before = len(flat.data.uv_layers)
    assert bpy.ops.object.seamlit_fix_seams(crease=180.0) == {"FINISHED"}
    assert seam(flat, tilted) < 0.01
    # Corners away from the shared edge (x = 1 of the flat strip, x = 0 of the tilted one)
    # keep their normals.
    for obj, x in ((flat, 1.0), (tilted, 1.0)):
        world, _ = world_corners(obj)
        away = ~np.isclose(world[:, 0], x, atol=1e-5)
        assert away.sum() == 6
        np.testing.assert_allclose(corner_normals(obj)[away], before[obj.name][away], atol=1e-6)
    # The objects stay separate, their vertices and UV layers untouched.
    assert len(flat.data.vertices) == 6 and len(tilted.data.vertices) == 6
    assert len(flat.data.uv_layers) == uvs_before
    out = capfd.readouterr()
    assert "seams 30.00° before, 0.00° after" in out.out + out.err


def test_a_hard_edge_between_flat_objects_stays_unless_asked():
    # One flat quad each: their normals are their faces', an authored hard edge (issue 31).
    bpy.ops.wm.read_factory_settings(use_empty=True)
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    flat = quad("flat", [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)])
    tilted = quad("tilted", [(0, 0, 0), (c, 0, s), (c, 1, s), (0, 1, 0)], location=(1.0, 0.0, 0.0))
    assert seam(flat, tilted) > 29.0
    assert bpy.ops.object.seamlit_fix_seams(crease=180.0) == {"FINISHED"}
    assert seam(flat, tilted) > 29.0
    assert bpy.ops.object.seamlit_fix_seams(crease=180.0, normals="smooth-shared") == {"FINISHED"}
    assert seam(flat, tilted) < 0.01


def test_per_object_mode_leaves_the_seam():
    flat, tilted = scene()
    assert bpy.ops.object.seamlit_fix_seams(mode="object", crease=180.0) == {"FINISHED"}
    assert seam(flat, tilted) > 29.0


def test_the_operator_registers_for_undo():
    # Blender snapshots the meshes an UNDO operator changes; `bpy.ops.ed.undo` itself needs
    # a window, which Blender as a Python module has not, so the flag is what is checked.
    assert "UNDO" in seamlit_seams.OBJECT_OT_seamlit_fix_seams.bl_options
    assert "REGISTER" in seamlit_seams.OBJECT_OT_seamlit_fix_seams.bl_options
