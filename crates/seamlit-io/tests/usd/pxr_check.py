"""Pixar's USD (pip install usd-core; import pxr) as the oracle of the USD tests (tests/usd.rs).

    pxr_check.py points STAGE OUT.json        world-space points of every drawn mesh, +Y up
    pxr_check.py compare INPUT OUTPUT OUT.json every prim, property and stage metadata compared;
                                              normals properties listed apart, as
                                              `PRIM PROPERTY: STATE -> STATE`
    pxr_check.py validate STAGE OUT.json      UsdValidation's errors
    pxr_check.py seam STAGE OUT.json          the largest angle between normals of different
                                              meshes at shared positions, world space
    pxr_check.py seams STAGE OUT.json         `seam` per pair of meshes: "MESH MESH" -> degrees
    pxr_check.py normals STAGE [PRIM ...] OUT.json
                                              per drawn mesh (or PRIM named): its
                                              faceVertexIndices and the normal a renderer uses
                                              at each face corner; the number of prototypes
    pxr_check.py package USDZ OUT.json        the package's files (name, data offset, whether
                                              stored uncompressed, sizes) and its root layer
                                              (usd-core 26 has no UsdUtils.ComplianceChecker:
                                              `validate` runs its usdz validators)
    pxr_check.py layer LAYER OUT.json         the layer alone as Sdf exports it to text
    pxr_check.py skinned STAGE OUT.json [JOINT DEGREES | bind]
                                              world-space points of every skinned mesh as
                                              UsdSkel skins them, at the rest pose with JOINT
                                              turned DEGREES about Z (or at the bind pose:
                                              every skinning matrix the identity); and at the
                                              bind pose the largest angle between normals of
                                              different meshes at shared positions (`seam` for
                                              skinned meshes)

Each writes JSON to OUT.json. Nothing here uses seamlit.
"""

import json
import math
import sys

from pxr import Gf, Sdf, Usd, UsdGeom, UsdSkel, UsdValidation, Vt

NORMAL_PROPERTIES = ("primvars:normals", "primvars:normals:indices", "normals")


def drawn_meshes(stage):
    """The meshes a renderer draws, instance proxies included, in traversal order."""
    predicate = Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)
    cache = UsdGeom.XformCache(Usd.TimeCode.Default())
    for prim in Usd.PrimRange.Stage(stage, predicate):
        if not prim.IsA(UsdGeom.Mesh):
            continue
        imageable = UsdGeom.Imageable(prim)
        if imageable.ComputeVisibility() == UsdGeom.Tokens.invisible:
            continue
        if imageable.ComputePurpose() in (UsdGeom.Tokens.guide, UsdGeom.Tokens.proxy):
            continue
        yield prim, cache.GetLocalToWorldTransform(prim)


def up(stage):
    """The map to +Y up: (x, y, z) to (x, z, -y) for a Z-up stage."""
    if UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z:
        return lambda p: [p[0], p[2], -p[1]]
    return lambda p: [p[0], p[1], p[2]]


def points(stage_path, out):
    stage = Usd.Stage.Open(stage_path)
    to_y = up(stage)
    result = {}
    for prim, world in drawn_meshes(stage):
        pts = UsdGeom.Mesh(prim).GetPointsAttr().Get() or []
        result[str(prim.GetPath())] = [to_y(world.Transform(Gf.Vec3d(p))) for p in pts]
    json.dump(result, open(out, "w"))


def plain(value):
    """A value as JSON-comparable data."""
    if value is None:
        return None
    if isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, Sdf.AssetPath):
        return ["asset", value.path]
    if isinstance(value, Sdf.Path):
        return str(value)
    if isinstance(value, dict):
        return {k: plain(v) for k, v in sorted(value.items())}
    if hasattr(value, "__len__") and not isinstance(value, str):
        return [plain(v) for v in value]
    return str(value)


def describe(stage):
    """Per prim: type, specifier, metadata, and per property its metadata, value, time
    samples and targets. Plus the stage's own metadata (the root layer's)."""
    out = {"<stage>": {k: plain(v) for k, v in stage.GetPseudoRoot().GetAllMetadata().items() if k not in ("subLayers", "subLayerOffsets")}}
    for prim in Usd.PrimRange.Stage(stage, Usd.TraverseInstanceProxies(Usd.PrimAllPrimsPredicate)):
        entry = {
            "<type>": str(prim.GetTypeName()),
            "<specifier>": str(prim.GetSpecifier()),
            "<metadata>": {k: plain(v) for k, v in prim.GetAllMetadata().items()},
        }
        for prop in prim.GetProperties():
            record = {"metadata": {k: plain(v) for k, v in prop.GetAllMetadata().items()}}
            if isinstance(prop, Usd.Attribute):
                record["value"] = plain(prop.Get())
                record["samples"] = {str(t): plain(prop.Get(t)) for t in prop.GetTimeSamples()}
                record["connections"] = [str(p) for p in prop.GetConnections()]
            else:
                record["targets"] = [str(p) for p in prop.GetTargets()]
            entry[prop.GetName()] = record
        out[str(prim.GetPath())] = entry
    return out


def state(record):
    """A normals property as `absent`, `blocked` (no value) or `valued`."""
    if record is None:
        return "absent"
    return "blocked" if record.get("value") is None else "valued"


def compare(input_path, output_path, out):
    a = describe(Usd.Stage.Open(input_path))
    b = describe(Usd.Stage.Open(output_path))
    differences, normals = [], []
    for path in sorted(set(a) | set(b)):
        if path not in a or path not in b:
            differences.append(f"{path}: only in the {'output' if path in b else 'input'}")
            continue
        for key in sorted(set(a[path]) | set(b[path])):
            left, right = a[path].get(key), b[path].get(key)
            if left == right:
                continue
            if key in NORMAL_PROPERTIES:
                normals.append(f"{path} {key}: {state(left)} -> {state(right)}")
            else:
                differences.append(f"{path} {key}: {json.dumps(left)[:200]} -> {json.dumps(right)[:200]}")
    json.dump({"differences": differences, "normals": normals}, open(out, "w"), indent=1)


def validate(stage_path, out):
    stage = Usd.Stage.Open(stage_path)
    validators = UsdValidation.ValidationRegistry().GetOrLoadAllValidators()
    errors = UsdValidation.ValidationContext(validators).Validate(stage)
    found = sorted({e.GetName() for e in errors if e.GetType() == UsdValidation.ValidationErrorType.Error})
    json.dump(found, open(out, "w"))


def corner_normals(mesh):
    """Per face corner: the normal a renderer uses (primvars:normals, else normals), None for
    a mesh without normals."""
    counts = mesh.GetFaceVertexCountsAttr().Get() or []
    indices = mesh.GetFaceVertexIndicesAttr().Get() or []
    primvar = UsdGeom.PrimvarsAPI(mesh).GetPrimvar("normals")
    if primvar and primvar.HasValue():
        values, interpolation = primvar.ComputeFlattened(), primvar.GetInterpolation()
    elif mesh.GetNormalsAttr().HasValue():
        values, interpolation = mesh.GetNormalsAttr().Get(), mesh.GetNormalsInterpolation()
    else:
        return None
    result, corner = [], 0
    for face, n in enumerate(counts):
        for _ in range(n):
            element = {"faceVarying": corner, "uniform": face, "constant": 0}.get(interpolation, indices[corner])
            result.append(values[element])
            corner += 1
    return result


def drawn_corners(stage):
    """Every corner of the drawn meshes with normals: (mesh, world position, world unit
    normal)."""
    for prim, world in drawn_meshes(stage):
        mesh = UsdGeom.Mesh(prim)
        normals = corner_normals(mesh)
        if normals is None:
            continue
        pts = mesh.GetPointsAttr().Get()
        normal_matrix = world.GetInverse().GetTranspose()
        for c, p in enumerate(mesh.GetFaceVertexIndicesAttr().Get()):
            n = normal_matrix.TransformDir(Gf.Vec3d(normals[c])).GetNormalized()
            yield str(prim.GetPath()), world.Transform(Gf.Vec3d(pts[p])), n


def seam_pairs(corners):
    """Every pair of `corners` ((mesh, position, unit normal)) of two different meshes at one
    position, as (mesh, other mesh, the angle between their normals in degrees). One position
    is seamlit's weld: points within 1e-6 of the corners' bounding-box diagonal (its default
    `--weld-tolerance rel:1e-6`). Rounding to a fixed grid instead (it was 1e-4) joins
    distinct vertices closer than the grid: BrainStem.usdz's fixed output showed five "seams"
    over 5 degrees that way, each between two different vertices 16 to 60 micrometres apart
    (BENCHMARKS.md)."""
    corners = list(corners)
    if not corners:
        return
    low = [min(p[i] for _, p, _ in corners) for i in range(3)]
    high = [max(p[i] for _, p, _ in corners) for i in range(3)]
    tolerance = max(1e-6 * math.dist(low, high), 1e-12)
    cells = {}
    for k, (_, p, _) in enumerate(corners):
        cells.setdefault(tuple(math.floor(x / tolerance) for x in p), []).append(k)
    # Union-find over the points within the tolerance of each other (neighbouring cells).
    parent = list(range(len(corners)))

    def root(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    offsets = [(x, y, z) for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1)]
    for cell, members in cells.items():
        for offset in offsets:
            near = cells.get(tuple(c + o for c, o in zip(cell, offset)), ())
            for a in members:
                for b in near:
                    if a < b and math.dist(corners[a][1], corners[b][1]) <= tolerance:
                        parent[root(a)] = root(b)
    groups = {}
    for k, (mesh, _, n) in enumerate(corners):
        groups.setdefault(root(k), []).append((mesh, n))
    for group in groups.values():
        for i in range(len(group)):
            for j in range(i + 1, len(group)):
                if group[i][0] == group[j][0]:
                    continue
                d = max(-1.0, min(1.0, Gf.Dot(group[i][1], group[j][1])))
                yield group[i][0], group[j][0], math.degrees(math.acos(d))


def largest_seam(corners):
    """`seam`'s figures of `corners`: the largest angle and the number of pairs."""
    largest, pairs = 0.0, 0
    for _, _, degrees in seam_pairs(corners):
        pairs += 1
        largest = max(largest, degrees)
    return {"largest_degrees": largest, "pairs": pairs}


def seam(stage_path, out):
    json.dump(largest_seam(drawn_corners(Usd.Stage.Open(stage_path))), open(out, "w"))


def seams(stage_path, out):
    result = {}
    for a, b, degrees in seam_pairs(drawn_corners(Usd.Stage.Open(stage_path))):
        pair = " ".join(sorted([a, b]))
        result[pair] = max(result.get(pair, 0.0), degrees)
    json.dump(result, open(out, "w"))


def normals(stage_path, *rest):
    """`normals STAGE [PRIM ...] OUT`: of every drawn mesh, or of the PRIMs named; and the
    stage's number of instancing prototypes, as "<prototypes>"."""
    out, named = rest[-1], rest[:-1]
    stage = Usd.Stage.Open(stage_path)
    result = {"<prototypes>": len(stage.GetPrototypes())}
    meshes = [(stage.GetPrimAtPath(p), None) for p in named] if named else drawn_meshes(stage)
    for prim, _ in meshes:
        mesh = UsdGeom.Mesh(prim)
        values = corner_normals(mesh)
        result[str(prim.GetPath())] = {
            "indices": list(mesh.GetFaceVertexIndicesAttr().Get() or []),
            "normals": None if values is None else [[n[0], n[1], n[2]] for n in values],
        }
    json.dump(result, open(out, "w"))


def package(usdz_path, out):
    zf = Sdf.ZipFile.Open(usdz_path)
    files = []
    for name in zf.GetFileNames():
        info = zf.GetFileInfo(name)
        files.append({"name": name, "offset": info.dataOffset, "stored": info.compressionMethod == 0,
                      "size": info.size, "uncompressed": info.uncompressedSize})
    stage = Usd.Stage.Open(usdz_path)
    json.dump({"files": files, "root": stage.GetRootLayer().identifier}, open(out, "w"), indent=1)


def layer(layer_path, out):
    json.dump({"text": Sdf.Layer.FindOrOpen(layer_path).ExportToString()}, open(out, "w"))


def skinned(stage_path, out, joint=None, degrees="0"):
    """Per skinned mesh: its points skinned by pxr (`UsdSkelSkinningQuery.ComputeSkinnedPoints`,
    in the skeleton's space, then the skeleton's local-to-world), at the skeleton's rest pose
    with `joint` (a joint path) turned `degrees` about its Z axis, or with `joint` "bind" at
    the bind pose. And the seam at the bind pose: normals moved as the points are
    (`geomBindTransform`, then the skeleton's local-to-world), compared as `seam` compares
    them."""
    stage = Usd.Stage.Open(stage_path)
    to_y = up(stage)
    time = Usd.TimeCode.Default()
    cache = UsdSkel.Cache()
    result, corners = {}, []
    for root in Usd.PrimRange.Stage(stage, Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)):
        if not root.IsA(UsdSkel.Root):
            continue
        cache.Populate(UsdSkel.Root(root), Usd.TraverseInstanceProxies())
        for binding in cache.ComputeSkelBindings(UsdSkel.Root(root), Usd.TraverseInstanceProxies()):
            skel = cache.GetSkelQuery(binding.GetSkeleton())
            locals_ = skel.ComputeJointLocalTransforms(time, True)
            joints = [str(j) for j in skel.GetJointOrder()]
            if joint not in (None, "bind"):
                k = joints.index(joint)
                turn = Gf.Matrix4d(1).SetRotate(Gf.Rotation(Gf.Vec3d(0, 0, 1), float(degrees)))
                locals_[k] = turn * locals_[k]
            xforms = UsdSkel.ConcatJointTransforms(skel.GetTopology(), locals_)
            binds = skel.GetSkeleton().GetBindTransformsAttr().Get()
            skinning = Vt.Matrix4dArray([binds[i].GetInverse() * xforms[i] for i in range(len(xforms))])
            if joint == "bind":
                skinning = Vt.Matrix4dArray([Gf.Matrix4d(1)] * len(xforms))
            skel_world = UsdGeom.Xformable(binding.GetSkeleton().GetPrim()).ComputeLocalToWorldTransform(time)
            for query in binding.GetSkinningTargets():
                prim = query.GetPrim()
                mesh = UsdGeom.Mesh(prim)
                pts = Vt.Vec3fArray(mesh.GetPointsAttr().Get())
                query.ComputeSkinnedPoints(skinning, pts, time)
                result[str(prim.GetPath())] = [to_y(skel_world.Transform(Gf.Vec3d(p))) for p in pts]
                normals = corner_normals(mesh)
                if normals is None:
                    continue
                rest = query.GetGeomBindTransform(time) * skel_world
                normal_matrix = rest.GetInverse().GetTranspose()
                rest_points = mesh.GetPointsAttr().Get()
                for c, p in enumerate(mesh.GetFaceVertexIndicesAttr().Get()):
                    n = normal_matrix.TransformDir(Gf.Vec3d(normals[c])).GetNormalized()
                    corners.append((str(prim.GetPath()), rest.Transform(Gf.Vec3d(rest_points[p])), n))
    json.dump({"points": result, "seam": largest_seam(corners)}, open(out, "w"))


if __name__ == "__main__":
    command, args = sys.argv[1], sys.argv[2:]
    {"points": points, "compare": compare, "validate": validate, "seam": seam, "seams": seams, "normals": normals,
     "package": package, "layer": layer, "skinned": skinned}[command](*args)
