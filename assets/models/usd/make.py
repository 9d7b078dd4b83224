"""Writes the USD test stages of this folder with Pixar's USD (pip install usd-core; import pxr).

    python3 assets/models/usd/make.py assets/models/usd

Every stage is our own (the project's licence). What each is for: README.md.
"""

import math
import os
import shutil
import struct
import sys
import zlib

from pxr import Gf, Sdf, Usd, UsdGeom, UsdShade, UsdSkel, UsdUtils, Vt


def stage_at(path, up="Y", meters=1.0):
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z if up == "Z" else UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, meters)
    return stage


def sphere_rings(segments, rings):
    """The points of a UV sphere of radius 1, ring 0 the north pole, ring `rings` the south."""
    points = []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments):
            phi = 2 * math.pi * s / segments
            points.append((math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi)))
    return points


def band(segments, first_ring, last_ring):
    """Quads between rings `first_ring` and `last_ring` of a sphere, counter-clockwise seen
    from outside; returns (point indices used, in order, and faces as lists of those)."""
    used = list(range(first_ring * segments, (last_ring + 1) * segments))
    remap = {p: i for i, p in enumerate(used)}
    faces = []
    for r in range(first_ring, last_ring):
        for s in range(segments):
            a = r * segments + s
            b = r * segments + (s + 1) % segments
            c = (r + 1) * segments + (s + 1) % segments
            d = (r + 1) * segments + s
            faces.append([remap[a], remap[d], remap[c], remap[b]])
    return used, faces


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def unit(a):
    n = math.sqrt(dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


def smooth_normals(points, faces):
    """Per point: the corner-angle weighted average of its faces' normals (its own mesh's
    faces only: what per-mesh smoothing gives, and what opens the seam)."""
    sums = [(0.0, 0.0, 0.0)] * len(points)
    for face in faces:
        n = unit(cross(sub(points[face[1]], points[face[0]]), sub(points[face[2]], points[face[0]])))
        for k, p in enumerate(face):
            e1 = unit(sub(points[face[(k + 1) % len(face)]], points[p]))
            e2 = unit(sub(points[face[k - 1]], points[p]))
            angle = math.acos(max(-1.0, min(1.0, dot(e1, e2))))
            sums[p] = tuple(sums[p][i] + n[i] * angle for i in range(3))
    return [unit(s) for s in sums]


def flat(points, faces):
    return [unit(cross(sub(points[f[1]], points[f[0]]), sub(points[f[2]], points[f[0]]))) for f in faces]


def png(path, rgb):
    """A 2 x 2 PNG of one colour, written without any imaging library."""
    raw = b"".join(b"\x00" + bytes(rgb) * 2 for _ in range(2))
    chunk = lambda kind, data: struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    with open(path, "wb") as out:
        out.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 2, 0, 0, 0)))
        out.write(chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def preview_material(stage, path, color, texture=None, metallic=0.0, roughness=0.5):
    material = UsdShade.Material.Define(stage, path)
    shader = UsdShade.Shader.Define(stage, path + "/Surface")
    shader.CreateIdAttr("UsdPreviewSurface")
    shader.CreateInput("metallic", Sdf.ValueTypeNames.Float).Set(metallic)
    shader.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(roughness)
    diffuse = shader.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f)
    diffuse.Set(Gf.Vec3f(*color))
    if texture:
        reader = UsdShade.Shader.Define(stage, path + "/St")
        reader.CreateIdAttr("UsdPrimvarReader_float2")
        reader.CreateInput("varname", Sdf.ValueTypeNames.String).Set("st")
        image = UsdShade.Shader.Define(stage, path + "/Texture")
        image.CreateIdAttr("UsdUVTexture")
        image.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(texture)
        image.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(reader.ConnectableAPI(), "result")
        image.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
        diffuse.ConnectToSource(image.ConnectableAPI(), "rgb")
    material.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    return material


def mesh(stage, path, points, faces, scheme="none"):
    m = UsdGeom.Mesh.Define(stage, path)
    m.CreatePointsAttr([Gf.Vec3f(*p) for p in points])
    m.CreateFaceVertexCountsAttr([len(f) for f in faces])
    m.CreateFaceVertexIndicesAttr([i for f in faces for i in f])
    if scheme is not None:
        m.CreateSubdivisionSchemeAttr(scheme)
    lo = [min(p[i] for p in points) for i in range(3)]
    hi = [max(p[i] for p in points) for i in range(3)]
    m.CreateExtentAttr([Gf.Vec3f(*lo), Gf.Vec3f(*hi)])
    return m


def indexed_normals_mesh(stage, path, points, faces):
    """A mesh smoothed on its own, its normals an indexed faceVarying `primvars:normals` (one
    value a point, indexed by the corners)."""
    m = mesh(stage, path, points, faces)
    n = UsdGeom.PrimvarsAPI(m).CreatePrimvar("normals", Sdf.ValueTypeNames.Normal3fArray, UsdGeom.Tokens.faceVarying)
    n.Set([Gf.Vec3f(*v) for v in smooth_normals(points, faces)])
    n.SetIndices(Vt.IntArray([i for f in faces for i in f]))
    return m


def vertex_normals_mesh(stage, path, points, faces):
    """A mesh smoothed on its own, its normals a plain vertex `normals` attribute."""
    m = mesh(stage, path, points, faces)
    m.CreateNormalsAttr([Gf.Vec3f(*v) for v in smooth_normals(points, faces)])
    m.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    return m


def head_body(folder):
    """Head and body: the upper and lower halves of a sphere, each smoothed on its own, sharing
    the equator. The head sits under a translated Xform, its points moved down to match; its
    normals are indexed faceVarying `primvars:normals`, its UVs indexed faceVarying
    `primvars:st`; the body's are a plain vertex `normals` attribute and vertex UVs."""
    segments, rings = 16, 8
    points = sphere_rings(segments, rings)
    stage = stage_at(os.path.join(folder, "head_body.usda"))
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    png(os.path.join(folder, "skin.png"), (200, 150, 120))
    head_material = preview_material(stage, "/World/Looks/Skin", (1, 1, 1), texture="./skin.png", roughness=0.6)
    body_material = preview_material(stage, "/World/Looks/Cloth", (0.2, 0.3, 0.7), metallic=0.25, roughness=0.8)

    used, faces = band(segments, 1, rings // 2)
    head_points = [(points[p][0], points[p][1] - 0.5, points[p][2]) for p in used]
    normals = smooth_normals(head_points, faces)
    pivot = UsdGeom.Xform.Define(stage, "/World/HeadPivot")
    pivot.AddTranslateOp().Set(Gf.Vec3d(0, 0.5, 0))
    head = mesh(stage, "/World/HeadPivot/Head", head_points, faces)
    corners = [i for f in faces for i in f]
    primvars = UsdGeom.PrimvarsAPI(head)
    n = primvars.CreatePrimvar("normals", Sdf.ValueTypeNames.Normal3fArray, UsdGeom.Tokens.faceVarying)
    n.Set([Gf.Vec3f(*v) for v in normals])
    n.SetIndices(Vt.IntArray(corners))
    st = primvars.CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.faceVarying)
    st.Set([Gf.Vec2f((p[0] + 1) / 2, (p[1] + 1.5) / 2) for p in head_points])
    st.SetIndices(Vt.IntArray(corners))
    UsdShade.MaterialBindingAPI.Apply(head.GetPrim()).Bind(head_material)

    used, faces = band(segments, rings // 2, rings - 1)
    body_points = [points[p] for p in used]
    body = vertex_normals_mesh(stage, "/World/Body", body_points, faces)
    st = UsdGeom.PrimvarsAPI(body).CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.vertex)
    st.Set([Gf.Vec2f((p[0] + 1) / 2, (p[1] + 1) / 2) for p in body_points])
    UsdShade.MaterialBindingAPI.Apply(body.GetPrim()).Bind(body_material)
    stage.GetRootLayer().Save()
    stage.GetRootLayer().Export(os.path.join(folder, "head_body.usdc"))
    # The package: the layer and its texture, the layer first (its root).
    UsdUtils.CreateNewUsdzPackage(os.path.join(folder, "head_body.usda"), os.path.join(folder, "head_body.usdz"))


def box(lo, hi):
    """The 8 corners and 6 outward quads of an axis-aligned box."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    points = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [1, 2, 6, 5], [0, 4, 7, 3]]
    return points, faces


def faceted(folder):
    """Two boxes stacked, sharing the square where they meet, with authored hard edges: flat
    faceVarying `primvars:normals` (one value per face corner, not indexed) on the lower, and
    indexed ones (a value per face) on the upper."""
    stage = stage_at(os.path.join(folder, "faceted.usda"))
    root = UsdGeom.Xform.Define(stage, "/Blocks")
    stage.SetDefaultPrim(root.GetPrim())
    points, faces = box((-1, 0, -1), (1, 1, 1))
    lower = mesh(stage, "/Blocks/Lower", points, faces)
    n = UsdGeom.PrimvarsAPI(lower).CreatePrimvar("normals", Sdf.ValueTypeNames.Normal3fArray, UsdGeom.Tokens.faceVarying)
    n.Set([Gf.Vec3f(*f) for f in flat(points, faces) for _ in range(4)])
    points, faces = box((-1, 1, -1), (1, 2, 1))
    upper = mesh(stage, "/Blocks/Upper", points, faces)
    n = UsdGeom.PrimvarsAPI(upper).CreatePrimvar("normals", Sdf.ValueTypeNames.Normal3fArray, UsdGeom.Tokens.faceVarying)
    n.Set([Gf.Vec3f(*f) for f in flat(points, faces)])
    n.SetIndices(Vt.IntArray([k for k in range(6) for _ in range(4)]))
    stage.GetRootLayer().Save()


def z_up(folder):
    """A Z-up stage in centimetres with every kind of xformOp: translate, rotateXYZ, scale,
    orient, transform, an inverted op, `!resetXformStack!`, a mirroring scale, and a
    left-handed mesh. No normals: seamlit computes them."""
    stage = stage_at(os.path.join(folder, "z_up_cm.usda"), up="Z", meters=0.01)
    root = UsdGeom.Xform.Define(stage, "/Root")
    stage.SetDefaultPrim(root.GetPrim())
    xf = UsdGeom.Xformable(root)
    xf.AddTranslateOp().Set(Gf.Vec3d(10, 20, 30))
    xf.AddRotateXYZOp().Set(Gf.Vec3f(10, 20, 30))
    xf.AddScaleOp().Set(Gf.Vec3f(2, 3, 4))
    points, faces = box((0, 0, 0), (10, 10, 10))
    a = mesh(stage, "/Root/A", points, faces)
    UsdGeom.Xformable(a).AddOrientOp().Set(Gf.Quatf(0.9238795, 0, 0.3826834, 0))
    b = UsdGeom.Xform.Define(stage, "/Root/B")
    UsdGeom.Xformable(b).AddTransformOp().Set(Gf.Matrix4d(1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 5, 6, 7, 1))
    t = UsdGeom.Xformable(b).AddTranslateOp(opSuffix="pivot")
    t.Set(Gf.Vec3d(1, 2, 3))
    UsdGeom.Xformable(b).AddTranslateOp(opSuffix="pivot", isInverseOp=True)
    mesh(stage, "/Root/B/Mesh", points, faces)
    c = mesh(stage, "/Root/Reset", points, faces)
    UsdGeom.Xformable(c).SetResetXformStack(True)
    UsdGeom.Xformable(c).AddTranslateOp().Set(Gf.Vec3d(-50, 0, 0))
    d = mesh(stage, "/Root/Mirrored", points, faces)
    UsdGeom.Xformable(d).AddScaleOp().Set(Gf.Vec3f(-1, 1, 1))
    e = mesh(stage, "/Root/LeftHanded", points, [list(reversed(f)) for f in faces])
    e.CreateOrientationAttr(UsdGeom.Tokens.leftHanded)
    UsdGeom.Xformable(e).AddRotateZOp().Set(45.0)
    UsdGeom.Xformable(e).AddRotateYOp().Set(-30.0)
    UsdGeom.Xformable(e).AddRotateXOp().Set(15.0)
    stage.GetRootLayer().Save()


def catmull(folder):
    """A subdivision surface (subdivisionScheme left at its default, catmullClark) that
    carries normals, which renderers ignore, beside a polygonal box sharing a face with it."""
    stage = stage_at(os.path.join(folder, "subdivision.usda"))
    root = UsdGeom.Xform.Define(stage, "/Model")
    stage.SetDefaultPrim(root.GetPrim())
    points, faces = box((-1, 0, -1), (1, 1, 1))
    smooth = mesh(stage, "/Model/Smooth", points, faces, scheme=None)
    smooth.CreateNormalsAttr([Gf.Vec3f(*unit(p)) for p in points])
    points, faces = box((-1, 1, -1), (1, 2, 1))
    mesh(stage, "/Model/Polygonal", points, faces)
    stage.GetRootLayer().Save()


def layered(folder):
    """A shot: `shot.usda` sublayers `base.usda` (which defines the world and a mesh) and
    references `prop.usda` (another mesh, which shares an edge with the base's), the prop
    moved by the reference's prim and overridden (a new name for its material-less mesh's
    display colour) in the shot."""
    os.makedirs(os.path.join(folder, "layered"), exist_ok=True)
    points, faces = box((0, 0, 0), (1, 1, 1))
    prop = stage_at(os.path.join(folder, "layered", "prop.usda"))
    p = UsdGeom.Xform.Define(prop, "/Prop")
    prop.SetDefaultPrim(p.GetPrim())
    mesh(prop, "/Prop/Geom", points, faces)
    prop.GetRootLayer().Save()
    base = stage_at(os.path.join(folder, "layered", "base.usda"))
    w = UsdGeom.Xform.Define(base, "/World")
    base.SetDefaultPrim(w.GetPrim())
    mesh(base, "/World/Ground", *box((-1, -1, 0), (0, 0, 1)))
    base.GetRootLayer().Save()
    shot = stage_at(os.path.join(folder, "layered", "shot.usda"))
    shot.GetRootLayer().subLayerPaths.append("./base.usda")
    holder = UsdGeom.Xform.Define(shot, "/World/Holder")
    holder.GetPrim().GetReferences().AddReference("./prop.usda")
    UsdGeom.Xformable(holder).AddTranslateOp().Set(Gf.Vec3d(-1, -1, 0))
    shot.SetDefaultPrim(shot.GetPrimAtPath("/World"))
    shot.GetRootLayer().Save()


def instanced(folder):
    """One prototype mesh used by two instanceable prims (internal references)."""
    stage = stage_at(os.path.join(folder, "instanced.usda"))
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    proto = UsdGeom.Xform.Define(stage, "/Prototypes/Crate")
    stage.GetPrimAtPath("/Prototypes").SetSpecifier(Sdf.SpecifierClass)
    mesh(stage, "/Prototypes/Crate/Geom", *box((0, 0, 0), (1, 1, 1)))
    for k, name in enumerate(["One", "Two"]):
        inst = UsdGeom.Xform.Define(stage, "/World/" + name)
        inst.GetPrim().GetReferences().AddInternalReference("/Prototypes/Crate")
        inst.GetPrim().SetInstanceable(True)
        UsdGeom.Xformable(inst).AddTranslateOp().Set(Gf.Vec3d(2 * k, 0, 0))
    stage.GetRootLayer().Save()


def instanced_seams(folder):
    """The head and body of `head_body` (each smoothed on its own, 22.5 degrees apart at the
    equator) as one prototype, `class "Prototypes"`'s Character, drawn by three instanceable
    prims that reference it inside the stage, each moved and the third turned; a cap outside
    the instances closes the first one's body at its lowest ring, smoothed on its own. And
    two instances of a part from another layer (`instanced_part.usda`, referenced), whose
    prototype's opinions come from that layer only."""
    segments, rings = 16, 8
    points = sphere_rings(segments, rings)
    part = stage_at(os.path.join(folder, "instanced_part.usda"))
    root = UsdGeom.Xform.Define(part, "/Part")
    part.SetDefaultPrim(root.GetPrim())
    lower, faces = box((0, 0, 0), (1, 1, 1))
    mesh(part, "/Part/Lower", lower, faces)
    upper, faces = box((0, 1, 0), (1, 2, 1))
    mesh(part, "/Part/Upper", upper, faces)
    part.GetRootLayer().Save()

    stage = stage_at(os.path.join(folder, "instanced_seams.usda"))
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    UsdGeom.Xform.Define(stage, "/Prototypes/Character")
    stage.GetPrimAtPath("/Prototypes").SetSpecifier(Sdf.SpecifierClass)
    used, faces = band(segments, 1, rings // 2)
    head_points = [points[p] for p in used]
    indexed_normals_mesh(stage, "/Prototypes/Character/Head", head_points, faces)
    used, faces = band(segments, rings // 2, rings - 1)
    body_points = [points[p] for p in used]
    body = vertex_normals_mesh(stage, "/Prototypes/Character/Body", body_points, faces)
    places = [("One", (0, 0, 0), 0), ("Two", (3, 0, 0), 0), ("Three", (-3, 0, 0), 90)]
    for name, at, turn in places:
        inst = UsdGeom.Xform.Define(stage, "/World/" + name)
        inst.GetPrim().GetReferences().AddInternalReference("/Prototypes/Character")
        inst.GetPrim().SetInstanceable(True)
        UsdGeom.Xformable(inst).AddTranslateOp().Set(Gf.Vec3d(*at))
        if turn:
            UsdGeom.Xformable(inst).AddRotateYOp().Set(float(turn))
    # The cap: the first instance's lowest ring and the south pole, fanned.
    ring = [points[(rings - 1) * segments + s] for s in range(segments)]
    cap_points = ring + [points[rings * segments]]
    cap_faces = [[s, segments, (s + 1) % segments] for s in range(segments)]
    cap_faces = [[f[0], f[2], f[1]] if dot(cross(sub(cap_points[f[1]], cap_points[f[0]]), sub(cap_points[f[2]], cap_points[f[0]])), (0, -1, 0)) < 0 else f for f in cap_faces]
    vertex_normals_mesh(stage, "/World/Cap", cap_points, cap_faces)
    for k, name in enumerate(["PartA", "PartB"]):
        inst = UsdGeom.Xform.Define(stage, "/World/" + name)
        inst.GetPrim().GetReferences().AddReference("./instanced_part.usda")
        inst.GetPrim().SetInstanceable(True)
        UsdGeom.Xformable(inst).AddTranslateOp().Set(Gf.Vec3d(2 * k, 0, 4))
    stage.GetRootLayer().Save()


def instanced_source(folder):
    """The head of `head_body` drawn at /World/Original, beside the body (outside it, sharing
    the equator), and two instances elsewhere that reference /World/Original inside the
    stage: the prototype's source is itself a drawn mesh, so what is written on it the
    instances compose."""
    segments, rings = 16, 8
    points = sphere_rings(segments, rings)
    stage = stage_at(os.path.join(folder, "instanced_source.usda"))
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    UsdGeom.Xform.Define(stage, "/World/Original")
    used, faces = band(segments, 1, rings // 2)
    head_points = [points[p] for p in used]
    indexed_normals_mesh(stage, "/World/Original/Head", head_points, faces)
    used, faces = band(segments, rings // 2, rings - 1)
    body_points = [points[p] for p in used]
    body = vertex_normals_mesh(stage, "/World/Body", body_points, faces)
    for k, name in enumerate(["One", "Two"]):
        inst = UsdGeom.Xform.Define(stage, "/World/" + name)
        inst.GetPrim().GetReferences().AddInternalReference("/World/Original")
        inst.GetPrim().SetInstanceable(True)
        UsdGeom.Xformable(inst).AddTranslateOp().Set(Gf.Vec3d(0, 0, 3 * (k + 1)))
    stage.GetRootLayer().Save()


def teapots_polygonal(folder):
    """The usd-wg teapots (`others/intent-vfx`, 494 instances of one teapot, catmullClark),
    sublayered, with the teapot's class turned polygonal (`subdivisionScheme = "none"` in
    an `over` of `/_class_/teapot`, which every instance inherits), so that fix writes
    normals on it."""
    layer = Sdf.Layer.CreateNew(os.path.join(folder, "teapots_polygonal.usda"))
    layer.subLayerPaths.append("./others/intent-vfx/scenes/teapotScene_layout.usd")
    layer.defaultPrim = "Scene"
    body = Sdf.CreatePrimInLayer(layer, "/_class_/teapot/geo/default/Body")
    scheme = Sdf.AttributeSpec(body, "subdivisionScheme", Sdf.ValueTypeNames.Token, variability=Sdf.VariabilityUniform)
    scheme.default = "none"
    layer.Save()


def time_sampled(folder):
    """Two heads and bodies as in `head_body` (each smoothed on its own, 22.5 degrees apart at
    the equator), the second pair beside the first: the first body's points time-sampled
    (frames 1 and 2, the second moved down by 0.25), the second head's `primvars:normals`
    time-sampled (frames 1 and 2, the same values)."""
    segments, rings = 16, 8
    points = sphere_rings(segments, rings)
    stage = stage_at(os.path.join(folder, "time_sampled.usda"))
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    stage.SetStartTimeCode(1)
    stage.SetEndTimeCode(2)
    for k in (1, 2):
        dx = 3.0 * (k - 1)
        used, faces = band(segments, 1, rings // 2)
        head_points = [(points[p][0] + dx, points[p][1], points[p][2]) for p in used]
        head = mesh(stage, "/World/Head%d" % k, head_points, faces)
        n = UsdGeom.PrimvarsAPI(head).CreatePrimvar("normals", Sdf.ValueTypeNames.Normal3fArray, UsdGeom.Tokens.faceVarying)
        values = [Gf.Vec3f(*v) for v in smooth_normals(head_points, faces)]
        if k == 2:
            n.Set(values, 1)
            n.Set(values, 2)
        else:
            n.Set(values)
        n.SetIndices(Vt.IntArray([i for f in faces for i in f]))
        used, faces = band(segments, rings // 2, rings - 1)
        body_points = [(points[p][0] + dx, points[p][1], points[p][2]) for p in used]
        body = vertex_normals_mesh(stage, "/World/Body%d" % k, body_points, faces)
        if k == 1:
            moved = [Gf.Vec3f(p[0], p[1] - 0.25, p[2]) for p in body_points]
            body.GetPointsAttr().Set([Gf.Vec3f(*p) for p in body_points], 1)
            body.GetPointsAttr().Set(moved, 2)
    stage.GetRootLayer().Save()


def skinned_neck(folder):
    """A head and a body bound to one skeleton (Hips, Chest, Neck) under a translated SkelRoot,
    sharing the equator as `head_body` does, with skin influences that differ there. The
    `skel:skeleton` binding is on the SkelRoot (inherited); the skeleton has a transform of
    its own; the meshes sit under an Xform whose translation skinning ignores. The head is
    rigid: its own `skel:joints` (the neck alone), constant influences of one element, its
    points moved down by 0.5 and `geomBindTransform` moving them back up. The body uses the
    skeleton's joint order, two influences per point, vertex interpolation: its equator 0.6
    chest and 0.4 neck, where the head is all neck (a gap once the neck turns)."""
    segments, rings = 16, 8
    points = sphere_rings(segments, rings)
    stage = stage_at(os.path.join(folder, "skinned_neck.usda"))
    root = UsdSkel.Root.Define(stage, "/Character")
    stage.SetDefaultPrim(root.GetPrim())
    root.AddTranslateOp().Set(Gf.Vec3d(0, 1, 0))
    skeleton = UsdSkel.Skeleton.Define(stage, "/Character/Skeleton")
    skeleton.AddTranslateOp().Set(Gf.Vec3d(0.25, 0, 0))
    skeleton.CreateJointsAttr(["Hips", "Hips/Chest", "Hips/Chest/Neck"])
    at = lambda y: Gf.Matrix4d(1).SetTranslate(Gf.Vec3d(0, y, 0))
    skeleton.CreateBindTransformsAttr([at(-1), at(-0.5), at(0)])
    skeleton.CreateRestTransformsAttr([at(-1), at(0.5), at(0.5)])
    binding = UsdSkel.BindingAPI.Apply(root.GetPrim())
    binding.CreateSkeletonRel().SetTargets([skeleton.GetPath()])
    geom = UsdGeom.Xform.Define(stage, "/Character/Geom")
    geom.AddTranslateOp().Set(Gf.Vec3d(7, 7, 7))

    used, faces = band(segments, 1, rings // 2)
    head_points = [(points[p][0], points[p][1] - 0.5, points[p][2]) for p in used]
    head = indexed_normals_mesh(stage, "/Character/Geom/Head", head_points, faces)
    skin = UsdSkel.BindingAPI.Apply(head.GetPrim())
    skin.CreateJointsAttr(["Hips/Chest/Neck"])
    skin.CreateJointIndicesPrimvar(True, 1).Set([0])
    skin.CreateJointWeightsPrimvar(True, 1).Set([1.0])
    skin.CreateGeomBindTransformAttr(at(0.5))

    used, faces = band(segments, rings // 2, rings - 1)
    body_points = [points[p] for p in used]
    body = vertex_normals_mesh(stage, "/Character/Geom/Body", body_points, faces)
    # Per ring from the equator down: (joint, weight) pairs in the skeleton's order.
    by_ring = [[(1, 0.6), (2, 0.4)], [(1, 1.0), (0, 0.0)], [(0, 0.5), (1, 0.5)], [(0, 1.0), (0, 0.0)]]
    influences = [by_ring[p // segments - rings // 2] for p in used]
    skin = UsdSkel.BindingAPI.Apply(body.GetPrim())
    skin.CreateJointIndicesPrimvar(False, 2).Set([j for pairs in influences for j, _ in pairs])
    skin.CreateJointWeightsPrimvar(False, 2).Set([w for pairs in influences for _, w in pairs])
    stage.GetRootLayer().Save()


def subsets(folder):
    """One mesh, a 2 x 1 x 1 box cut at x = 0 into its left and right halves (five faces
    each), bound to a grey material, whose two `materialBind` GeomSubsets (a partition) bind
    the left half red and the right half blue; and `subsets_bad.usda`, the same mesh whose
    subsets cannot all be used: indices past the faces, a face in two subsets, a subset of
    points, a binding on a subset of another family."""
    xs, ys, zs = (-1, 0, 1), (0, 1), (-0.5, 0.5)
    points = [(x, y, z) for x in xs for y in ys for z in zs]
    at = {p: i for i, p in enumerate(points)}
    def quad(*corners):
        return [at[c] for c in corners]
    faces = []
    for a, b in ((-1, 0), (0, 1)):
        faces += [
            quad((a, 0, 0.5), (b, 0, 0.5), (b, 1, 0.5), (a, 1, 0.5)),  # front
            quad((b, 0, -0.5), (a, 0, -0.5), (a, 1, -0.5), (b, 1, -0.5)),  # back
            quad((a, 1, 0.5), (b, 1, 0.5), (b, 1, -0.5), (a, 1, -0.5)),  # top
            quad((a, 0, -0.5), (b, 0, -0.5), (b, 0, 0.5), (a, 0, 0.5)),  # bottom
        ]
    faces.append(quad((-1, 0, -0.5), (-1, 0, 0.5), (-1, 1, 0.5), (-1, 1, -0.5)))  # left end
    faces.append(quad((1, 0, 0.5), (1, 0, -0.5), (1, 1, -0.5), (1, 1, 0.5)))  # right end
    left, right = [0, 1, 2, 3, 8], [4, 5, 6, 7, 9]
    for name, bad in (("subsets.usda", False), ("subsets_bad.usda", True)):
        stage = stage_at(os.path.join(folder, name))
        root = UsdGeom.Xform.Define(stage, "/Model")
        stage.SetDefaultPrim(root.GetPrim())
        grey = preview_material(stage, "/Model/Materials/Grey", (0.5, 0.5, 0.5))
        red = preview_material(stage, "/Model/Materials/Red", (0.8, 0.02, 0.02))
        blue = preview_material(stage, "/Model/Materials/Blue", (0.02, 0.02, 0.8))
        m = mesh(stage, "/Model/Box", points, faces)
        UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(grey)
        if not bad:
            for subset_name, indices, material in (("Left", left, red), ("Right", right, blue)):
                subset = UsdGeom.Subset.CreateGeomSubset(
                    m, subset_name, UsdGeom.Tokens.face, Vt.IntArray(indices),
                    UsdShade.Tokens.materialBind, UsdGeom.Tokens.partition)
                UsdShade.MaterialBindingAPI.Apply(subset.GetPrim()).Bind(material)
        else:
            for subset_name, element, indices, family, material in (
                ("Left", UsdGeom.Tokens.face, left + [10, 40], UsdShade.Tokens.materialBind, red),
                ("Right", UsdGeom.Tokens.face, right + [8], UsdShade.Tokens.materialBind, blue),
                ("Points", UsdGeom.Tokens.point, [0, 1], UsdShade.Tokens.materialBind, blue),
                ("Other", UsdGeom.Tokens.face, right, "parts", red),
            ):
                subset = UsdGeom.Subset.CreateGeomSubset(
                    m, subset_name, element, Vt.IntArray(indices), family)
                UsdShade.MaterialBindingAPI.Apply(subset.GetPrim()).Bind(material)
        stage.GetRootLayer().Save()


def main():
    folder = sys.argv[1]
    head_body(folder)
    faceted(folder)
    z_up(folder)
    catmull(folder)
    layered(folder)
    instanced(folder)
    instanced_seams(folder)
    instanced_source(folder)
    teapots_polygonal(folder)
    time_sampled(folder)
    skinned_neck(folder)
    subsets(folder)


if __name__ == "__main__":
    main()
