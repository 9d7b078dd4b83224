"""The seamlit Python package: the fix on arrays, files in and out, errors, trimesh.

Run by crates/seamlit-py/tests/python.rs (part of `cargo test --workspace`), which puts the
freshly built extension on PYTHONPATH and names the command line binary in SEAMLIT_BIN.
"""

import json
import tempfile
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import seamlit

REPO = Path(os.environ.get("SEAMLIT_REPO", Path(__file__).resolve().parents[3]))
MODELS = REPO / "assets" / "models"


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def two_quads(angle_deg=30.0):
    """Two quads sharing the edge x = 1 (each object with its own copy of that edge's
    vertices), the second tilted by `angle_deg`: the paper's simplest seam."""
    a = np.radians(angle_deg)
    flat = np.array([[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]], np.float32)
    tilted = np.array(
        [[1, 0, 0], [1 + np.cos(a), np.sin(a), 0], [1 + np.cos(a), np.sin(a), 1], [1, 0, 1]],
        np.float32,
    )
    triangles = np.array([[0, 3, 2], [0, 2, 1]], np.uint32)
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    return [
        {"name": "flat", "positions": flat, "triangles": triangles, "uvs": uvs},
        {"name": "tilted", "positions": tilted, "triangles": triangles, "uvs": uvs},
    ]


def seam_angle(objects, fixed):
    """The largest angle (degrees) between the normals two objects give one position."""
    by_position = {}
    for o, f in zip(objects, fixed):
        positions = np.asarray(o["positions"])[f["remap"]]
        if "transform" in o:
            m = np.asarray(o["transform"], np.float64)
            positions = positions @ m[:3, :3].T + m[:3, 3]
        normals = f["normals"].astype(np.float64)
        if "transform" in o:
            normals = normals @ np.linalg.inv(m[:3, :3])
        normals = unit(normals)
        for p, n in zip(positions, normals):
            by_position.setdefault(tuple(np.round(p, 5)), []).append(n)
    worst = 0.0
    for normals in by_position.values():
        for n in normals[1:]:
            worst = max(worst, np.degrees(np.arccos(np.clip(np.dot(normals[0], n), -1, 1))))
    return worst


def test_two_quads_get_one_normal_on_their_shared_edge():
    objects = two_quads()
    fixed = seamlit.fix(objects, crease=180)
    assert seam_angle(objects, fixed) < 1e-3
    # The shared edge's normal is the average of the two faces' (uniform tilt: half way).
    expected = unit(np.array([-np.sin(np.radians(15.0)), np.cos(np.radians(15.0)), 0.0]))
    np.testing.assert_allclose(fixed[0]["normals"][1], expected, atol=1e-5)
    # Per object (the seam the paper starts from): the edge keeps two normals.
    per_object = seamlit.fix(objects, mode="object", crease=180)
    assert seam_angle(objects, per_object) > 29.0
    # Tangents: unit, orthogonal to the normal, handedness +-1.
    t = fixed[0]["tangents"]
    assert t.shape == (4, 4)
    np.testing.assert_allclose(np.linalg.norm(t[:, :3], axis=1), 1.0, atol=1e-5)
    np.testing.assert_allclose(np.sum(t[:, :3] * fixed[0]["normals"], axis=1), 0.0, atol=1e-5)
    assert set(np.abs(t[:, 3])) == {1.0}


def sphere(rings=24, segments=48):
    """A UV sphere: positions (n x 3), triangles, and each vertex's longitude segment."""
    positions, segment = [], []
    for i in range(rings + 1):
        theta = np.pi * i / rings
        for j in range(segments + 1):
            phi = 2 * np.pi * j / segments
            positions.append([np.sin(theta) * np.cos(phi), np.cos(theta), np.sin(theta) * np.sin(phi)])
            segment.append(j)
    triangles = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * (segments + 1) + j, (i + 1) * (segments + 1) + j
            triangles += [[a, b, a + 1], [a + 1, b, b + 1]]
    return np.array(positions, np.float32), np.array(triangles, np.uint32)


def split_by_faces(positions, triangles, parts):
    """The mesh as `parts` objects by triangle ranges, each with its own vertex copies."""
    objects = []
    for chunk in np.array_split(triangles, parts):
        used, inverse = np.unique(chunk, return_inverse=True)
        objects.append(
            {"positions": positions[used], "triangles": inverse.reshape(-1, 3).astype(np.uint32)}
        )
    return objects


def test_splitting_a_sphere_into_objects_changes_no_normal():
    positions, triangles = sphere()
    whole = seamlit.fix([{"positions": positions, "triangles": triangles}], crease=180)[0]
    whole_by_position = {}
    for p, n in zip(positions[whole["remap"]], whole["normals"]):
        whole_by_position.setdefault(tuple(np.round(p, 5)), n)
    objects = split_by_faces(positions, triangles, 5)
    fixed = seamlit.fix(objects, crease=180)
    for o, f in zip(objects, fixed):
        for p, n in zip(o["positions"][f["remap"]], f["normals"]):
            np.testing.assert_allclose(n, whole_by_position[tuple(np.round(p, 5))], atol=1e-5)
    assert seam_angle(objects, fixed) < 1e-3
    # Per object, the cut shows.
    assert seam_angle(objects, seamlit.fix(objects, mode="object", crease=180)) > 1.0


def test_a_transform_places_an_object_and_normals_stay_in_its_own_space():
    objects = two_quads()
    # The tilted quad given in its own frame, moved by +1 in y, then placed back by -1.
    moved = dict(objects[1])
    moved["positions"] = objects[1]["positions"] + np.array([0, 1, 0], np.float32)
    moved["transform"] = np.array(
        [[1, 0, 0, 0], [0, 1, 0, -1], [0, 0, 1, 0], [0, 0, 0, 1]], np.float32
    )
    fixed = seamlit.fix([objects[0], moved], crease=180)
    assert seam_angle([objects[0], moved], fixed) < 1e-3
    # Without the transform the quads do not meet: the edge keeps the flat quad's normal.
    apart = seamlit.fix([objects[0], dict(moved, transform=None)], crease=180)
    np.testing.assert_allclose(apart[0]["normals"][1], [0, 1, 0], atol=1e-6)


def test_a_crease_splits_vertices_and_the_remap_says_which():
    objects = two_quads(angle_deg=90.0)
    fixed = seamlit.fix(objects, crease=60)
    # A 90 degree fold over a 60 degree crease: no vertex shared, nothing to split.
    assert all(len(f["remap"]) == 4 for f in fixed)
    # An L inside one object: its corner vertices need two normals each.
    a = np.radians(90.0)
    positions = np.array(
        [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1], [1 + np.cos(a), np.sin(a), 0], [1 + np.cos(a), np.sin(a), 1]],
        np.float32,
    )
    triangles = np.array([[0, 3, 2], [0, 2, 1], [1, 2, 5], [1, 5, 4]], np.uint32)
    f = seamlit.fix([{"positions": positions, "triangles": triangles}], crease=60)[0]
    assert len(f["remap"]) == 8
    assert sorted(f["remap"][6:]) == [1, 2]
    assert f["triangles"].max() == 7


def test_authored_normals_are_kept_with_auto_and_replaced_with_recompute():
    objects = two_quads()
    weird = np.tile(unit(np.array([[0.2, 1.0, 0.1]], np.float32)), (4, 1)).astype(np.float32)
    objects[0]["normals"] = weird
    objects[1]["normals"] = weird
    auto = seamlit.fix(objects, crease=180)
    # Away from the seam (vertices 0 and 3 of the flat quad), auto keeps the file's normals.
    np.testing.assert_array_equal(auto[0]["normals"][[0, 3]], weird[[0, 3]])
    recompute = seamlit.fix(objects, crease=180, normals="recompute")
    np.testing.assert_allclose(recompute[0]["normals"][[0, 3]], [[0, 1, 0], [0, 1, 0]], atol=1e-6)


def test_bad_arrays_and_options_raise_one_line_errors():
    objects = two_quads()
    with pytest.raises(seamlit.SeamlitError, match=r"object 1: positions must have shape \(n, 3\)"):
        seamlit.fix([objects[0], dict(objects[1], positions=np.zeros((4, 2)))])
    with pytest.raises(seamlit.SeamlitError, match="refers to vertex 9"):
        seamlit.fix([dict(objects[0], triangles=np.array([[0, 1, 9]]))])
    with pytest.raises(seamlit.SeamlitError, match="uvs has 3 rows, positions 4"):
        seamlit.fix([dict(objects[0], uvs=np.zeros((3, 2)))])
    with pytest.raises(seamlit.SeamlitError, match="mode='smooth'"):
        seamlit.fix(objects, mode="smooth")
    with pytest.raises(seamlit.SeamlitError, match="is not a tolerance"):
        seamlit.fix(objects, weld_tolerance="close")
    with pytest.raises(seamlit.SeamlitError, match="non-finite position"):
        bad = objects[0]["positions"].copy()
        bad[2, 1] = np.nan
        seamlit.fix([dict(objects[0], positions=bad)])
    assert issubclass(seamlit.SeamlitError, ValueError)


def cli(*args):
    return subprocess.run(
        [os.environ["SEAMLIT_BIN"], *map(str, args)], capture_output=True, text=True
    )


def test_fix_file_writes_what_the_command_line_writes(tmp_path):
    for model, extension in [("groups.obj", "glb"), ("cornell_box/cornell_box.obj", "obj"), ("NormalTangentTest.glb", "glb")]:
        source = MODELS / model
        # The same file name in two folders: an OBJ names its material library after it.
        ours, theirs = tmp_path / "py" / f"out.{extension}", tmp_path / "cli" / f"out.{extension}"
        ours.parent.mkdir(exist_ok=True)
        theirs.parent.mkdir(exist_ok=True)
        result = seamlit.fix_file(source, ours, crease=45)
        run = cli("fix", source, "-o", theirs, "--crease", 45)
        assert run.returncode == 0, run.stderr
        assert ours.read_bytes() == theirs.read_bytes(), model
        assert result["output"] == str(ours)
        assert result["options"]["crease_angle_deg"] == 45
        assert result["report"]["objects"] == len(result["changes"]["objects"])


def test_fix_file_matches_skin_seams_and_says_what_the_command_line_says(tmp_path):
    # A neck whose two objects' skin weights differ: the command line gives the copies one set
    # of weights (--skin-seams match, its default), and so does fix_file: the same library call.
    source = MODELS / "usd" / "skinned_neck.usda"
    ours, theirs, kept = (tmp_path / d / "fixed.usda" for d in ("py", "cli", "keep"))
    for path in (ours, theirs, kept):
        path.parent.mkdir()
    result = seamlit.fix_file(source, ours)
    run = cli("fix", source, "-o", theirs)
    assert run.returncode == 0, run.stderr
    assert ours.read_bytes() == theirs.read_bytes()
    assert result["skin_seams_matched"] > 0, result["skin_seams_matched"]
    assert result["as_loaded"]["skin_seams"]["positions"] > 0
    assert result["fixed"]["skin_seams"]["positions"] == 0
    assert result["summary"].replace(str(ours), "OUT") == run.stdout.strip().replace(str(theirs), "OUT")
    # Left as authored on request, the weights are not written anew: other bytes.
    seamlit.fix_file(source, kept, skin_seams="keep")
    assert kept.read_bytes() != theirs.read_bytes()
    with pytest.raises(seamlit.SeamlitError, match="skin_seams"):
        seamlit.fix_file(source, tmp_path / "x.usda", skin_seams="weld")


def test_a_usd_stage_gets_a_layer_of_fixed_normals_as_from_the_command_line(tmp_path):
    source = MODELS / "usd" / "head_body.usda"
    # Outputs at the same depth: the layer names its input by the same relative path.
    ours, theirs = tmp_path / "py" / "fixed.usda", tmp_path / "cli" / "fixed.usda"
    ours.parent.mkdir()
    theirs.parent.mkdir()
    seamlit.fix_file(source, ours)
    run = cli("fix", source, "-o", theirs)
    assert run.returncode == 0, run.stderr
    assert ours.read_bytes() == theirs.read_bytes()
    assert b"subLayers" in ours.read_bytes()
    before = seamlit.inspect(source)["as_loaded"]["cross_object"]["max_normal_angle_deg"]
    # The layer sublayers the input, outside the layer's folder: read as USD resolves it,
    # refused where reading is confined to the layer's folder (asset_roots, the strict mode).
    with pytest.raises(seamlit.SeamlitError, match="--asset-root"):
        seamlit.inspect(ours, asset_roots=[ours.parent])
    reread = seamlit.inspect(ours)
    after = reread["as_loaded"]["cross_object"]["max_normal_angle_deg"]
    assert before > 20.0 and after < 0.01, (before, after)


def test_keep_compression_writes_what_the_command_line_writes(tmp_path):
    compressed = MODELS / "compressed"
    source = compressed / "teapot_mo.glb"
    ours, theirs, plain = tmp_path / "py.glb", tmp_path / "cli.glb", tmp_path / "plain.glb"
    seamlit.fix_file(source, ours, keep_compression=True)
    run = cli("fix", source, "-o", theirs, "--keep-compression")
    assert run.returncode == 0, run.stderr
    assert ours.read_bytes() == theirs.read_bytes()
    seamlit.fix_file(source, plain)
    assert b'"EXT_meshopt_compression"' in ours.read_bytes()
    assert b'"EXT_meshopt_compression"' not in plain.read_bytes()
    assert len(ours.read_bytes()) < len(plain.read_bytes())
    with pytest.raises(seamlit.SeamlitError, match="no Draco encoder"):
        seamlit.fix_file(compressed / "teapot_draco.glb", tmp_path / "d.glb", keep_compression=True)
    assert not (tmp_path / "d.glb").exists()


def test_inspect_reports_the_seam_before_and_after_and_writes_nothing(tmp_path):
    source = MODELS / "newell_teaset" / "teapot"
    report = seamlit.inspect(source, tessellation=4, normals="recompute", mode="object")
    assert report["as_loaded"]["objects"] == 32
    assert report["fixed"]["shared_positions"] > 0
    # Smoothed per object, the patches' seams stay; across the model they go.
    assert report["fixed"]["cross_object"]["max_normal_angle_deg"] > 1.0
    model = seamlit.inspect(source, tessellation=4, normals="recompute")
    assert model["fixed"]["cross_object"]["max_normal_angle_deg"] < 0.01
    run = cli("inspect", source, "--tessellation", 4, "--normals", "recompute", "--json")
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout)["model"] == model["fixed"]


def test_bad_files_raise_the_command_lines_message(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        seamlit.fix_file(tmp_path / "missing.obj", tmp_path / "out.glb")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    run = cli("fix", bad, "-o", tmp_path / "cli.glb")
    assert run.returncode == 2
    with pytest.raises(seamlit.SeamlitError) as error:
        seamlit.fix_file(bad, tmp_path / "out.glb")
    assert str(error.value) == run.stderr.strip().removeprefix("error: ")
    assert not (tmp_path / "out.glb").exists()


def test_fix_scene_fixes_a_trimesh_scene_in_place():
    import trimesh

    import seamlit.trimesh as st

    objects = two_quads()
    scene = trimesh.Scene()
    for o in objects:
        mesh = trimesh.Trimesh(o["positions"], o["triangles"], process=False)
        scene.add_geometry(mesh, geom_name=o["name"], node_name=o["name"])
    before = [scene.geometry[o["name"]].vertex_normals.copy() for o in objects]
    # One flat quad each: trimesh's normals are the faces', an authored hard edge that the
    # default keeps (issue 31); "smooth-shared" averages it, which shows the write-back.
    kept = st.fix_scene(scene, crease=180)
    assert kept == {"objects": 2, "copied": []}
    for o, b in zip(objects, before):
        np.testing.assert_allclose(scene.geometry[o["name"]].vertex_normals, b, atol=1e-6)
    result = st.fix_scene(scene, crease=180, normals="smooth-shared")
    assert result == {"objects": 2, "copied": []}
    after = [scene.geometry[o["name"]].vertex_normals for o in objects]
    # trimesh's own normals disagree on the shared edge; seamlit's agree.
    assert np.degrees(np.arccos(np.dot(before[0][1], before[1][0]))) > 10
    np.testing.assert_allclose(after[0][1], after[1][0], atol=1e-5)
    np.testing.assert_allclose(after[0][2], after[1][3], atol=1e-5)
    np.testing.assert_allclose(after[0][0], before[0][0], atol=1e-6)


def test_fix_bytes_stays_in_memory_and_writes_what_the_command_line_writes(tmp_path, monkeypatch):
    # No temporary folder for any self-contained model: read, fixed and written in memory.
    def no_folder(*args, **kwargs):
        raise AssertionError("fix_bytes made a temporary folder")

    monkeypatch.setattr(tempfile, "mkdtemp", no_folder)
    monkeypatch.setattr(tempfile, "TemporaryDirectory", no_folder)
    for name in ("fox/Fox.glb", "usd/head_body.usdz", "usd/others/Rigged/RiggedFigure.usdz",
                 "ufbx/blender_293_half_skinned_7400_binary.fbx"):
        source = MODELS / name
        out, result = seamlit.fix_bytes(source.read_bytes(), source.name)
        expected = tmp_path / (source.stem + ".glb")
        run = cli("fix", source, "-o", expected)
        assert run.returncode == 0, run.stderr
        assert out == expected.read_bytes(), name
        assert result["output"] == expected.name and result["input"] == source.name
        first = run.stdout.splitlines()[0].replace(str(expected), expected.name)
        assert result["summary"].splitlines()[0] == first, name
    with pytest.raises(seamlit.SeamlitError, match="^bad.glb"):
        seamlit.fix_bytes(b"glTF\x02\x00\x00\x00garbage", "bad.glb")
    with pytest.raises(seamlit.SeamlitError, match="^bad.usdz"):
        seamlit.fix_bytes(b"PK\x03\x04garbage", "bad.usdz")
