"""seamlit for trimesh: fix the normals of a ``trimesh.Scene`` across its geometries.

trimesh loads a multi-object file (glTF, OBJ with groups) as a ``Scene``: one ``Trimesh``
per geometry, placed by the scene graph. :func:`fix_scene` fixes all placed geometries
together, so their normals agree where they meet, and writes the result back into the scene.
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional

import numpy as np

from . import SeamlitError, fix

__all__ = ["fix_scene"]


def _objects(scene: Any, normals: Optional[str]) -> List[Dict[str, Any]]:
    objects = []
    for node in scene.graph.nodes_geometry:
        transform, name = scene.graph[node]
        mesh = scene.geometry[name]
        if not hasattr(mesh, "faces") or len(mesh.faces) == 0:
            continue
        uv = getattr(getattr(mesh, "visual", None), "uv", None)
        o: Dict[str, Any] = {
            "name": f"{node}",
            "positions": mesh.vertices,
            "triangles": mesh.faces,
            "transform": transform,
            "node": node,
            "geometry": name,
        }
        if uv is not None and len(uv) == len(mesh.vertices):
            o["uvs"] = uv
        if normals != "recompute":
            o["normals"] = mesh.vertex_normals
        objects.append(o)
    return objects


def _write(mesh: Any, result: Dict[str, Any]) -> None:
    """Puts a fix result into a mesh: split vertices duplicate every per-vertex array."""
    remap = result["remap"]
    count = len(mesh.vertices)
    if len(remap) != count or not np.array_equal(remap, np.arange(count)):
        visual = getattr(mesh, "visual", None)
        uv = getattr(visual, "uv", None)
        colors = None
        if getattr(visual, "kind", None) == "vertex":
            colors = np.asarray(visual.vertex_colors)[remap]
        attributes = {k: np.asarray(v)[remap] for k, v in mesh.vertex_attributes.items()}
        mesh.vertices = np.asarray(mesh.vertices)[remap]
        mesh.faces = result["triangles"]
        if uv is not None and len(uv) == count:
            visual.uv = np.asarray(uv)[remap]
        if colors is not None:
            mesh.visual.vertex_colors = colors
        for k, v in attributes.items():
            mesh.vertex_attributes[k] = v
    mesh.vertex_normals = result["normals"]
    if result["tangents"] is not None:
        mesh.vertex_attributes["tangents"] = result["tangents"]


def _same(a: Dict[str, Any], b: Dict[str, Any]) -> bool:
    return (
        np.array_equal(a["remap"], b["remap"])
        and np.array_equal(a["triangles"], b["triangles"])
        and np.allclose(a["normals"], b["normals"], atol=1e-5)
    )


def fix_scene(scene: Any, **options: Any) -> Dict[str, Any]:
    """Fix the normals (and tangents, for textured geometry) of every placed geometry of
    ``scene`` together, in place.

    ``options`` are those of :func:`seamlit.fix` (``mode``, ``crease``, ``weld_tolerance``,
    ``weighting``, ``tangents``, ``normals``). The meshes' ``vertex_normals`` are passed as
    their normals unless ``normals="recompute"``; with the default ``normals="auto"`` they
    are kept and repaired only where geometries meet. Tangents go to
    ``mesh.vertex_attributes["tangents"]``. Where a vertex needed two frames it is split:
    every per-vertex array (UVs, colours, vertex attributes) is duplicated with it.

    A geometry placed by several nodes whose placements got different normals is copied for
    the others (the copies are named in the result's ``copied``). Returns a dict with
    ``objects`` (how many placed geometries were fixed) and ``copied``.
    """
    if not hasattr(scene, "graph") or not hasattr(scene, "geometry"):
        raise SeamlitError("fix_scene needs a trimesh.Scene (trimesh.load(..., force='scene'))")
    objects = _objects(scene, options.get("normals"))
    results = fix(objects, **options)
    written: Dict[str, Dict[str, Any]] = {}
    copied = []
    for o, result in zip(objects, results):
        name = o["geometry"]
        if name not in written:
            _write(scene.geometry[name], result)
            written[name] = result
        elif not _same(written[name], result):
            copy_name = f"{name}_{o['node']}"
            mesh = scene.geometry[name].copy()
            _write(mesh, result)
            scene.add_geometry(mesh, geom_name=copy_name)
            scene.graph.update(o["node"], geometry=copy_name)
            copied.append(copy_name)
    return {"objects": len(objects), "copied": copied}
