"""Installs the extension that blender/build_extension.sh wrote into Blender as a user does
(Install from Disk: `bpy.ops.extensions.package_install_files`), enables it, and fixes the
seam between two objects with its operator. Runs in Blender as the `bpy` Python module
(pip install bpy==5.0.1, Python 3.11), in user folders of its own.

Usage: python3 blender/check_extension.py target/blender/seamlit_seams-VERSION.zip
Prints one line with the seam before and after; exits non-zero on any failure.
"""

import os
import shutil
import sys
import tempfile
from pathlib import Path

# Blender's user folders (where extensions and their wheels go) in a folder of their own,
# set before bpy starts.
USER = Path(tempfile.mkdtemp(prefix="seamlit-blender-"))
os.environ["BLENDER_USER_RESOURCES"] = str(USER)

import numpy as np  # noqa: E402

import bpy  # noqa: E402


def strip(name, profile, location=(0.0, 0.0, 0.0)):
    """A smooth-shaded strip of quads along x through the (x, z) points of `profile`, y from
    0 to 1: bent, so its shading is smooth across its middle."""
    corners = [(x, y, z) for x, z in profile for y in (0.0, 1.0)]
    faces = [(2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1) for i in range(len(profile) - 1)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(corners, [], faces)
    mesh.shade_smooth()
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    bpy.context.scene.collection.objects.link(obj)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.context.view_layer.update()  # matrix_world from the location
    return obj


def world_corners(obj):
    mesh = obj.data
    m = np.array(obj.matrix_world)
    co = np.array([mesh.vertices[loop.vertex_index].co for loop in mesh.loops])
    n = np.empty(len(mesh.loops) * 3, np.float32)
    mesh.corner_normals.foreach_get("vector", n)
    n = n.reshape(-1, 3) @ np.linalg.inv(m[:3, :3])
    return co @ m[:3, :3].T + m[:3, 3], n / np.linalg.norm(n, axis=1, keepdims=True)


def seam(a, b):
    """The largest angle (degrees) between the normals of a and b where they meet."""
    (pa, na), (pb, nb) = world_corners(a), world_corners(b)
    worst = 0.0
    for p, n in zip(pa, na):
        for q, m in zip(pb, nb):
            if np.allclose(p, q, atol=1e-5):
                worst = max(worst, float(np.degrees(np.arccos(np.clip(np.dot(n, m), -1, 1)))))
    return worst


def main(zip_path):
    zip_path = Path(zip_path).resolve()
    assert zip_path.is_file(), f"{zip_path} is missing: run blender/build_extension.sh"
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # The operator does not exist before the extension is installed.
    assert not hasattr(bpy.types, "OBJECT_OT_seamlit_fix_seams")
    result = bpy.ops.extensions.package_install_files(
        filepath=str(zip_path), repo="user_default", enable_on_install=True
    )
    assert result == {"FINISHED"}, result
    enabled = [a.module for a in bpy.context.preferences.addons]
    assert any(m.endswith("seamlit_seams") for m in enabled), enabled
    import seamlit

    assert Path(seamlit.__file__).resolve().is_relative_to(USER), (
        f"seamlit was imported from {seamlit.__file__}, not the extension's wheel"
    )
    # Two objects each smoothed on its own, meeting at x = 1 at 30 degrees: a seam.
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    flat = strip("flat", [(0.0, -0.1), (0.5, 0.0), (1.0, 0.0)])
    tilted = strip("tilted", [(0.0, 0.0), (c, s), (c + 0.5, s + 0.1)], location=(1, 0, 0))
    before = seam(flat, tilted)
    assert bpy.ops.object.seamlit_fix_seams(crease=180.0) == {"FINISHED"}
    after = seam(flat, tilted)
    assert before > 29.0 and after < 0.01, (before, after)
    print(
        f"check_extension: {zip_path.name} installed and enabled (seamlit from the wheel, "
        f"{Path(seamlit.__file__).parent}); seam {before:.2f} degrees before, {after:.2f} after"
    )


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    try:
        main(sys.argv[1])
    finally:
        shutil.rmtree(USER, ignore_errors=True)
