#!/usr/bin/env python3
"""Writes a GLB's triangle meshes as an OpenUSD stage (.usdc or .usda, by the extension) with
Pixar's USD (usd-core): one Mesh prim per primitive under its node's world transform, points,
faces, `primvars:st` (V flipped to USD's up) and no normals, subdivisionScheme none.

    python3 bench/glb_to_usd.py IN.glb OUT.usdc

The USD benchmark's input (bench/usd.sh): the same model as the GLB, so that `seamlit fix` on
the two can be compared. Reads only what the demo teapot has: float positions and UVs,
unsigned indices, node matrices or TRS.
"""

import json
import struct
import sys

import numpy as np
from pxr import Gf, Sdf, Usd, UsdGeom, Vt

COMPONENTS = {5121: np.uint8, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def read_glb(path):
    data = open(path, "rb").read()
    magic, _, _ = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF":
        sys.exit(f"{path}: not a GLB")
    length, _ = struct.unpack_from("<II", data, 12)
    doc = json.loads(data[20 : 20 + length])
    blob = b""
    if 20 + length < len(data):
        blength, _ = struct.unpack_from("<II", data, 20 + length)
        blob = data[28 + length : 28 + length + blength]
    return doc, blob


def accessor(doc, blob, i):
    a = doc["accessors"][i]
    view = doc["bufferViews"][a["bufferView"]]
    dtype = np.dtype(COMPONENTS[a["componentType"]])
    width = WIDTH[a["type"]]
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    stride = view.get("byteStride", dtype.itemsize * width)
    rows = np.ndarray(
        (a["count"], width), dtype, blob, start, (stride, dtype.itemsize)
    )
    return rows.copy()


def local_matrix(node):
    if "matrix" in node:
        return Gf.Matrix4d(*node["matrix"])
    m = Gf.Matrix4d(1.0)
    s = node.get("scale", [1, 1, 1])
    r = node.get("rotation", [0, 0, 0, 1])
    t = node.get("translation", [0, 0, 0])
    m.SetScale(Gf.Vec3d(*s))
    rot = Gf.Matrix4d(1.0).SetRotate(Gf.Quatd(r[3], Gf.Vec3d(r[0], r[1], r[2])))
    m = m * rot
    m.SetTranslateOnly(Gf.Vec3d(*t))
    return m


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: glb_to_usd.py IN.glb OUT.usdc")
    doc, blob = read_glb(sys.argv[1])
    stage = Usd.Stage.CreateNew(sys.argv[2])
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    root = UsdGeom.Xform.Define(stage, "/Model")
    stage.SetDefaultPrim(root.GetPrim())
    count = 0
    scene = doc["scenes"][doc.get("scene", 0)]
    stack = [(n, Gf.Matrix4d(1.0)) for n in scene["nodes"]]
    while stack:
        n, parent = stack.pop()
        node = doc["nodes"][n]
        world = local_matrix(node) * parent
        stack.extend((c, world) for c in node.get("children", []))
        if "mesh" not in node:
            continue
        for p in doc["meshes"][node["mesh"]]["primitives"]:
            if p.get("mode", 4) != 4:
                continue
            points = accessor(doc, blob, p["attributes"]["POSITION"])
            if "indices" in p:
                indices = accessor(doc, blob, p["indices"]).reshape(-1).astype(np.int32)
            else:
                indices = np.arange(len(points), dtype=np.int32)
            mesh = UsdGeom.Mesh.Define(stage, f"/Model/mesh_{count}")
            count += 1
            mesh.AddTransformOp().Set(world)
            mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(points))
            mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(len(indices) // 3, 3, np.int32)))
            mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(indices))
            mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
            if "TEXCOORD_0" in p["attributes"]:
                uv = accessor(doc, blob, p["attributes"]["TEXCOORD_0"])
                uv[:, 1] = 1.0 - uv[:, 1]
                st = UsdGeom.PrimvarsAPI(mesh).CreatePrimvar(
                    "st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.vertex
                )
                st.Set(Vt.Vec2fArray.FromNumpy(uv))
    stage.GetRootLayer().Save()
    print(f"wrote {sys.argv[2]}: {count} meshes")


if __name__ == "__main__":
    main()
