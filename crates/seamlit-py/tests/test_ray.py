"""seamlit.ray on a real Ray cluster (``ray.cluster_utils.Cluster``: nodes of one CPU each on
this machine) and a real S3-compatible store (moto's server on 127.0.0.1, started here and
stopped after): a tree of the repository's own models fixed from a folder and from s3://,
compared byte for byte with ``seamlit fix DIR -o DIR``; the report checked against
``seamlit inspect --json``; workers and a node killed mid-run.

Needs ``ray[data]==2.60.0``, ``pyarrow`` and ``moto[server]`` (.ci/run installs them)."""

from __future__ import annotations

import hashlib
import json
import os
import random
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

try:
    import boto3
    import pyarrow.parquet as pq
    import ray
    from ray.cluster_utils import Cluster
except ImportError as e:  # a failure that says what to install, never a skip
    raise ImportError(
        f"the seamlit.ray tests need ray, pyarrow and moto: pip install 'ray[data]==2.60.0' pyarrow 'moto[server]>=5.2.5' ({e})"
    ) from e

from importlib.metadata import version as _version

# Earlier moto servers answer a multipart upload's completion with a root element Arrow takes
# for an error: every output over one part would fail for the server's sake, not seamlit's.
if tuple(int("0" + "".join(c for c in p if c.isdigit())) for p in _version("moto").split(".")[:3]) < (5, 2, 5):
    raise ImportError(f"the seamlit.ray tests need moto 5.2.5 or later (found {_version('moto')}): pip install 'moto[server]>=5.2.5'")

import seamlit
import seamlit.ray

REPO = Path(os.environ.get("SEAMLIT_REPO", Path(__file__).resolve().parents[3]))
MODELS = REPO / "assets" / "models"
BIN = os.environ["SEAMLIT_BIN"]


def cli(*args):
    return subprocess.run([BIN, *map(str, args)], capture_output=True, text=True)


def vrm_of(glb: bytes) -> bytes:
    """The GLB as a VRM 1.0 avatar (the VRMC_vrm extension added to its JSON chunk)."""
    length = struct.unpack_from("<I", glb, 12)[0]
    document = json.loads(glb[20 : 20 + length])
    rest = glb[20 + length :]
    document.setdefault("extensionsUsed", []).append("VRMC_vrm")
    document.setdefault("extensions", {})["VRMC_vrm"] = {
        "specVersion": "1.0",
        "meta": {"name": "fox"},
        "humanoid": {"humanBones": {"hips": {"node": 0}}},
    }
    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + rest
    return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body


def make_tree(root: Path) -> None:
    """The repository's models in subfolders, every kind seamlit reads, and one corrupted
    file."""
    copy = lambda src, dst: (dst.parent.mkdir(parents=True, exist_ok=True), shutil.copy(src, dst))
    shutil.copytree(MODELS / "clearcoat_test", root / "gltf" / "clearcoat")
    shutil.copytree(MODELS / "cornell_box", root / "obj" / "cornell_box")
    for name in ("blender_272_cube_7400_binary.fbx", "maya_parented_cubes_7500_ascii.fbx", "blender_293_half_skinned_7400_binary.fbx"):
        copy(MODELS / "ufbx" / name, root / "fbx" / name)
    shutil.copytree(MODELS / "usd" / "layered", root / "usd" / "layered")
    copy(MODELS / "usd" / "head_body.usdz", root / "usd" / "head_body.usdz")
    copy(MODELS / "usd" / "head_body.usda", root / "usd" / "head_body.usda")
    shutil.copytree(MODELS / "usd" / "others" / "SubdivisionSurfaces" / "Pyramid", root / "usd" / "pyramid")
    copy(MODELS / "fox" / "Fox.glb", root / "glb" / "Fox.glb")
    copy(MODELS / "NormalTangentTest.glb", root / "glb" / "NormalTangentTest.glb")
    copy(MODELS / "compressed" / "teapot_mo.glb", root / "glb" / "deep" / "teapot_mo.glb")
    (root / "vrm").mkdir()
    (root / "vrm" / "fox.vrm").write_bytes(vrm_of((MODELS / "fox" / "Fox.glb").read_bytes()))
    # Two models of one folder with one stem: the second is named cube-obj.glb.
    copy(MODELS / "ufbx" / "blender_272_cube_7400_binary.fbx", root / "mixed" / "cube.fbx")
    copy(MODELS / "cornell_box" / "cornell_box.obj", root / "mixed" / "cube.obj")
    copy(MODELS / "cornell_box" / "cornell_box.mtl", root / "mixed" / "cornell_box.mtl")
    # Hidden folders are not taken.
    copy(MODELS / "fox" / "Fox.glb", root / ".cache" / "Fox.glb")
    (root / "broken").mkdir()
    (root / "broken" / "corrupt.glb").write_bytes(b"glTF\x02\x00\x00\x00" + os.urandom(200))


def listing(folder: Path):
    return sorted(
        str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file() and "_seamlit" not in p.parts
    )


def assert_same_tree(actual: Path, expected: Path) -> None:
    assert listing(actual) == listing(expected)
    for name in listing(expected):
        assert (actual / name).read_bytes() == (expected / name).read_bytes(), name


def report(path) -> list:
    return pq.read_table(str(path)).to_pylist()


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def s3():
    """moto's S3 server on 127.0.0.1 (a free port), its address in the standard AWS
    variables (the Ray workers started after this inherit them)."""
    port = free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "moto.server", "-H", "127.0.0.1", "-p", str(port)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    env = {
        "AWS_ENDPOINT_URL": f"http://127.0.0.1:{port}",
        "AWS_ACCESS_KEY_ID": "testing",
        "AWS_SECRET_ACCESS_KEY": "testing",
        "AWS_REGION": "us-east-1",
    }
    saved = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    client = boto3.client("s3", endpoint_url=env["AWS_ENDPOINT_URL"])
    for _ in range(100):
        try:
            client.list_buckets()
            break
        except Exception:
            time.sleep(0.1)
    yield client
    server.terminate()
    server.wait(timeout=30)
    for k, v in saved.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v


@pytest.fixture(scope="module")
def cluster(s3):
    """Two nodes of one CPU each (the head and one more)."""
    c = Cluster(initialize_head=True, head_node_args={"num_cpus": 1})
    c.add_node(num_cpus=1)
    c.wait_for_nodes()
    ray.init(address=c.address, log_to_driver=False)
    yield c
    ray.shutdown()
    c.shutdown()


@pytest.fixture(scope="module")
def tree(tmp_path_factory):
    root = tmp_path_factory.mktemp("library")
    make_tree(root / "src")
    expected = root / "expected"
    done = cli("fix", root / "src", "-o", expected)
    # Folder mode refuses the corrupted file and a USD layer without geometry (bad input:
    # exit status 2) and fixes the rest.
    assert done.returncode == 2, done.stderr
    refused = sorted(
        line[len("error: ") :].split(":")[0][len(str(root / "src")) + 1 :]
        for line in done.stderr.splitlines()
        if line.startswith("error: " + str(root / "src"))
    )
    assert refused == ["broken/corrupt.glb", "usd/pyramid/mtl.usda"], done.stderr
    (root / "refused.json").write_text(json.dumps(refused))
    return root


def test_a_folder_is_fixed_byte_for_byte_as_folder_mode_and_every_file_is_reported(cluster, tree, tmp_path):
    out = tmp_path / "out"
    summary = seamlit.ray.fix(str(tree / "src"), str(out), pictures=2, progress=False)
    assert_same_tree(out, tree / "expected")
    assert "mixed/cube-obj.glb" in listing(out) and "vrm/fox.vrm" in listing(out)

    rows = {r["path"]: r for r in report(out / "_seamlit" / "report.parquet")}
    inputs = [
        p
        for p in listing(tree / "src")
        if Path(p).suffix in (".glb", ".gltf", ".obj", ".fbx", ".usda", ".usdz", ".usd", ".vrm") and not p.startswith(".")
    ]
    assert sorted(rows) == sorted(inputs)
    refused = json.loads((tree / "refused.json").read_text())
    assert sorted(p for p, r in rows.items() if r["status"] == "refused") == refused
    error = rows["broken/corrupt.glb"]["error"]
    assert error.startswith("broken/corrupt.glb: ") and "\n" not in error, error
    assert summary.refused == len(refused) and summary.failed == 0 and summary.skipped == 0
    assert summary.fixed + summary.unchanged == len(inputs) - len(refused)
    assert summary.fixed > 0 and summary.unchanged > 0

    for path, row in rows.items():
        if path in refused:
            continue
        assert row["status"] in ("fixed", "unchanged"), row
        written = (out / row["output_path"]).read_bytes()
        import hashlib

        assert row["output_sha256"] == hashlib.sha256(written).hexdigest()
        assert row["input_sha256"] == hashlib.sha256((tree / "src" / path).read_bytes()).hexdigest()
        # The counts are those `seamlit inspect --json` gives for the file.
        measured = cli("inspect", "--json", tree / "src" / path)
        assert measured.returncode == 0, measured.stderr
        truth = json.loads(measured.stdout)
        before = truth["as_loaded"]
        assert (row["objects"], row["triangles"], row["shared_positions"]) == (
            before["objects"],
            before["triangles"],
            before["shared_positions"],
        ), path
        assert row["largest_seam_before_deg"] == pytest.approx(before["cross_object"]["max_normal_angle_deg"]), path
        assert row["largest_seam_after_deg"] == pytest.approx(truth["model"]["cross_object"]["max_normal_angle_deg"]), path
        # What the repair decided, and whether the fix changed anything, as inspect says.
        changes = truth["changes"]["model"]
        shared = changes["shared"]
        assert (row["seams_repaired"], row["kept_hard_edges"], row["kept_custom"]) == (
            shared["repaired"],
            shared["hard_edges"],
            shared["custom"],
        ), path
        changed = any(o["normals_changed"] or o["vertices_split"] for o in changes["objects"])
        assert row["status"] == ("fixed" if changed else "unchanged"), path
    # Ray reserved memory for each task, more for a larger file.
    small = rows["obj/cornell_box/cornell_box.obj"]["memory_bytes"]
    large = rows["glb/NormalTangentTest.glb"]["memory_bytes"]
    assert small and large and large > small
    assert large > 20 * (tree / "src" / "glb" / "NormalTangentTest.glb").stat().st_size
    page = (out / "_seamlit" / "summary.html").read_text()
    assert "<svg" in page and "broken/corrupt.glb" in page
    # The two files that changed most, each pictured before and after by `seamlit render`.
    assert page.count("<section>") == 2 and page.count('<img src="data:image/png;base64,') == 4, page[-3000:]


def test_an_object_store_is_fixed_byte_for_byte_as_folder_mode(cluster, tree, s3, tmp_path):
    s3.create_bucket(Bucket="library")
    src = tree / "src"
    for name in listing(src):
        s3.upload_file(str(src / name), "library", f"models/{name}")
    summary = seamlit.ray.fix("s3://library/models", "s3://library/fixed", pictures=1, progress=False)
    assert summary.refused == 2 and summary.failed == 0
    out = tmp_path / "out"
    for page in s3.get_paginator("list_objects_v2").paginate(Bucket="library", Prefix="fixed/"):
        for item in page.get("Contents", []):
            target = out / item["Key"][len("fixed/") :]
            target.parent.mkdir(parents=True, exist_ok=True)
            s3.download_file("library", item["Key"], str(target))
    assert_same_tree(out, tree / "expected")
    rows = report(out / "_seamlit" / "report.parquet")
    assert {r["status"] for r in rows} <= {"fixed", "unchanged", "refused"}
    assert (out / "_seamlit" / "summary.html").read_text().count('<img src="data:image/png;base64,') == 2
    # Hashed where they were fixed, in memory: the bytes read and the bytes uploaded.
    import hashlib

    for row in rows:
        assert row["input_sha256"] == hashlib.sha256((src / row["path"]).read_bytes()).hexdigest(), row["path"]
        if row["status"] != "refused":
            written = (out / row["output_path"]).read_bytes()
            assert row["output_sha256"] == hashlib.sha256(written).hexdigest(), row["path"]


def grid_obj(path: Path, n: int) -> None:
    """Two n x n grids, side by side as two objects with their own copies of the shared
    edge, on a bumpy surface (so the copies' normals differ per object)."""
    import numpy as np

    lines = []
    for obj, x0 in (("left", -1.0), ("right", 0.0)):
        u, v = np.meshgrid(np.linspace(x0, x0 + 1.0, n), np.linspace(0.0, 1.0, n))
        z = 0.2 * np.sin(3.0 * u) * np.cos(2.0 * v)
        lines.append(f"o {obj}")
        lines += [f"v {a:.6f} {b:.6f} {c:.6f}" for a, b, c in zip(u.ravel(), v.ravel(), z.ravel())]
        base = 1 if obj == "left" else n * n + 1
        i = np.arange(n - 1)
        corner = (i[:, None] * n + i[None, :]).ravel() + base
        lines += [f"f {a} {a + 1} {a + n + 1}\nf {a} {a + n + 1} {a + n}" for a in corner]
    path.write_text("\n".join(lines) + "\n")


def test_an_output_larger_than_one_upload_part_reaches_the_object_store_whole(cluster, s3, tmp_path):
    # Arrow uploads an object of more than one part (10 MiB) in parts; the output of this
    # model is about 15 MB. It must arrive whole, the bytes folder mode writes.
    src = tmp_path / "src"
    src.mkdir()
    grid_obj(src / "grid.obj", 400)
    expected = tmp_path / "expected"
    assert cli("fix", src, "-o", expected).returncode == 0
    size = (expected / "grid.glb").stat().st_size
    assert size > 12 * 2**20, size
    s3.create_bucket(Bucket="large")
    s3.upload_file(str(src / "grid.obj"), "large", "models/grid.obj")
    summary = seamlit.ray.fix("s3://large/models", "s3://large/fixed", pictures=0, progress=False)
    assert (summary.fixed, summary.failed, summary.refused) == (1, 0, 0), summary.rows
    body = s3.get_object(Bucket="large", Key="fixed/grid.glb")["Body"].read()
    assert body == (expected / "grid.glb").read_bytes()
    assert summary.rows[0]["output_sha256"] == seamlit.ray._task.sha256(body)


def test_a_model_of_several_files_in_a_folder_is_fixed_straight_into_a_local_dst(tmp_path, monkeypatch):
    # An OBJ with its MTL, and USD layers, from a local SRC into a GLB in a local DST: fixed by
    # path and saved in place (a temporary name renamed), with no scratch folder or copy.
    from seamlit.ray import _task

    def no_folder(*args, **kwargs):
        raise AssertionError("the task made a scratch folder")

    monkeypatch.setattr(_task.tempfile, "mkdtemp", no_folder)
    src, dst = tmp_path / "src", tmp_path / "dst"
    shutil.copytree(MODELS / "cornell_box", src / "cornell")
    shutil.copytree(MODELS / "usd" / "layered", src / "layered")
    options = {"mode": "model", "tessellation": 16, "skin_seams": "match", "samples": 30}
    for name in ("cornell/cornell_box.obj", "layered/shot.usda"):
        output = str(Path(name).with_suffix(".glb"))
        row = _task.process(_task.Job(relative=name, src=str(src), dst=str(dst), output=output,
                                      options=options, flags=(), options_key=""))
        assert row["status"] in ("fixed", "unchanged"), row
        assert cli("fix", src / name, "-o", tmp_path / "cli.glb").returncode == 0
        assert (dst / output).read_bytes() == (tmp_path / "cli.glb").read_bytes(), name
        assert row["output_sha256"] == _task.sha256((dst / output).read_bytes())
    assert sorted(p.name for p in (dst / "cornell").iterdir()) == ["cornell_box.glb"]


def test_an_output_that_cannot_be_written_is_a_failed_row_naming_it(tmp_path):
    # DST's folder for the output is taken by a file: the row says so on one line, and
    # nothing is left under the output's name.
    from seamlit.ray import _task

    src, dst = tmp_path / "src", tmp_path / "dst"
    (src / "glb").mkdir(parents=True)
    shutil.copy(MODELS / "fox" / "Fox.glb", src / "glb" / "Fox.glb")
    dst.mkdir()
    (dst / "glb").write_text("a file where the output's folder goes")
    options = {"mode": "model", "tessellation": 16, "skin_seams": "match", "samples": 30}
    row = _task.process(_task.Job(relative="glb/Fox.glb", src=str(src), dst=str(dst), output="glb/Fox.glb",
                                  options=options, flags=(), options_key=""))
    assert row["status"] == "failed", row
    assert row["error"].startswith(f"glb/Fox.glb: cannot write glb/Fox.glb to {dst}: "), row["error"]
    assert "\n" not in row["error"] and row["output_sha256"] is None
    assert sorted(p.name for p in dst.iterdir()) == ["glb"]
    # An OBJ saved straight into DST by the library, where a folder has the output's name.
    shutil.copytree(MODELS / "cornell_box", src / "obj")
    (dst / "obj" / "cornell_box.glb").mkdir(parents=True)
    row = _task.process(_task.Job(relative="obj/cornell_box.obj", src=str(src), dst=str(dst),
                                  output="obj/cornell_box.glb", options=options, flags=(), options_key=""))
    assert row["status"] == "failed", row
    assert row["error"] == f"obj/cornell_box.obj: cannot write obj/cornell_box.glb to {dst}: Is a directory (os error 21)"
    assert sorted(p.name for p in (dst / "obj").iterdir()) == ["cornell_box.glb"]


def test_models_of_several_files_from_an_object_store_are_fixed_in_memory(tree, s3, tmp_path, monkeypatch):
    # A .gltf, an OBJ and USD layers from s3:// are read with the files beside them into
    # memory and fixed there (no scratch folder on the worker), into folder mode's bytes.
    from seamlit.ray import _files, _task

    def no_folder(*args, **kwargs):
        raise AssertionError("the task made a scratch folder")

    s3.create_bucket(Bucket="several")
    src = tree / "src"
    for name in listing(src):
        s3.upload_file(str(src / name), "several", f"models/{name}")
    monkeypatch.setattr(_task.tempfile, "mkdtemp", no_folder)
    inputs = [n for n in listing(src) if _files.extension(n) in ("gltf", "obj", "usda") and not n.startswith("broken")]
    names = _files.output_names(sorted(set(_files.model_files(*_files.resolve(str(src)), recurse=True, skip=None))), "glb")
    dst = tmp_path / "dst"
    fixed = 0
    for name in inputs:
        if name not in names:
            continue  # a layer folder mode does not take as a model
        job = _task.Job(relative=name, src="s3://several/models", dst=str(dst), output=names[name],
                        options={"mode": "model", "tessellation": 16, "skin_seams": "match", "samples": 30},
                        flags=(), options_key="")
        row = _task.process(job)
        expected = tree / "expected" / names[name]
        if not expected.exists():
            assert row["status"] == "refused", row  # refused by folder mode too
            continue
        assert row["status"] in ("fixed", "unchanged"), row
        assert (dst / names[name]).read_bytes() == expected.read_bytes(), name
        fixed += 1
    assert fixed >= 5, fixed


def test_a_second_run_skips_what_it_fixed_and_fixes_what_changed(cluster, tree, tmp_path):
    src = tmp_path / "src"
    shutil.copytree(tree / "src", src)
    out = tmp_path / "out"
    first = seamlit.ray.fix(str(src), str(out), pictures=0, progress=False)
    assert first.skipped == 0
    again = seamlit.ray.fix(str(src), str(out), pictures=0, progress=False)
    assert again.skipped == first.files
    assert again.fixed == again.unchanged == again.refused == again.failed == 0
    # The command line, its defaults spelled out, is the same run: it skips everything too,
    # says so in its one line, and exits 0 (this run refused nothing).
    done = subprocess.run(
        [sys.executable, "-m", "seamlit.ray", "fix", str(src), str(out), "--address", cluster.address, "--quiet", "--pictures", "0"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    assert f"0 fixed, 0 unchanged, 0 refused, 0 failed, {first.files} skipped of {first.files} files" in done.stdout
    # One input changed (the teapot replaced by another model), one option changed.
    shutil.copy(MODELS / "lowpoly" / "kenney-platformer-cube.glb", src / "glb" / "deep" / "teapot_mo.glb")
    third = seamlit.ray.fix(str(src), str(out), pictures=0, progress=False)
    assert third.skipped == first.files - 1
    assert (out / "glb" / "deep" / "teapot_mo.glb").read_bytes() != (tree / "expected" / "glb" / "deep" / "teapot_mo.glb").read_bytes()
    other = seamlit.ray.fix(str(src), str(out), pictures=0, progress=False, crease=30)
    assert other.skipped == 0


def test_inspect_writes_the_report_and_no_model(cluster, tree, tmp_path):
    target = tmp_path / "survey" / "report.parquet"
    summary = seamlit.ray.inspect(str(tree / "src"), str(target), progress=False)
    assert listing(tmp_path) == ["survey/report.parquet"]
    rows = {r["path"]: r for r in report(target)}
    assert rows["broken/corrupt.glb"]["status"] == "refused"
    fox = json.loads(cli("inspect", "--json", tree / "src" / "glb" / "Fox.glb").stdout)
    assert rows["glb/Fox.glb"]["triangles"] == fox["as_loaded"]["triangles"]
    assert rows["glb/Fox.glb"]["output_path"] is None
    assert summary.refused == 2


def slow_model(path: Path, n: int = 500) -> None:
    """Two grids of n x n quads that meet along one edge: seconds of work for a fix."""
    import numpy as np

    lines = []
    base = 1
    for part in range(2):
        xs, ys = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
        z = np.sin(xs * 3) * 0.1
        pts = np.stack([xs + part, ys, z], -1).reshape(-1, 3)
        lines.append(f"o part{part}")
        lines.extend("v %.6f %.6f %.6f" % tuple(p) for p in pts)
        i = np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]
        a = (i + base).ravel()
        quads = np.stack([a, a + 1, a + n + 2, a + n + 1], -1)
        lines.extend("f %d %d %d %d" % tuple(q) for q in quads)
        base += len(pts)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n")


def worker_of(task_name: str, timeout: float = 120.0) -> int:
    """The pid of the Ray worker running the task (its process title is ``ray::NAME``)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        for entry in os.listdir("/proc"):
            if not entry.isdigit():
                continue
            try:
                title = Path(f"/proc/{entry}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
            except OSError:
                continue
            if title.startswith(f"ray::{task_name}"):
                return int(entry)
        time.sleep(0.02)
    raise AssertionError(f"no worker ran {task_name!r} within {timeout} s")


def run_in_thread(**kwargs):
    result = {}

    def target():
        try:
            result["summary"] = seamlit.ray.fix(pictures=0, progress=False, **kwargs)
        except BaseException as e:  # reported by the test
            result["error"] = e

    thread = threading.Thread(target=target)
    thread.start()
    return thread, result


def test_a_worker_killed_while_it_fixes_a_file_is_retried_once_then_the_file_is_failed(cluster, tmp_path):
    src = tmp_path / "src"
    slow_model(src / "slow" / "big.obj")
    shutil.copy(MODELS / "fox" / "Fox.glb", src / "Fox.glb")
    # Killed once: retried, and done.
    thread, result = run_in_thread(src=str(src), dst=str(tmp_path / "once"))
    os.kill(worker_of("seamlit fix slow/big.obj"), signal.SIGKILL)
    thread.join(timeout=600)
    rows = {r["path"]: r for r in result["summary"].rows}
    assert rows["slow/big.obj"]["status"] == "fixed", rows["slow/big.obj"]
    expected = tmp_path / "expected"
    assert cli("fix", src, "-o", expected).returncode == 0
    assert_same_tree(tmp_path / "once", expected)

    # Killed on both tries: a failed row with the reason; the other file is done.
    thread, result = run_in_thread(src=str(src), dst=str(tmp_path / "twice"))
    first = worker_of("seamlit fix slow/big.obj")
    os.kill(first, signal.SIGKILL)
    deadline = time.monotonic() + 120
    while True:
        second = worker_of("seamlit fix slow/big.obj")
        if second != first:
            break
        assert time.monotonic() < deadline
        time.sleep(0.05)
    os.kill(second, signal.SIGKILL)
    thread.join(timeout=600)
    summary = result["summary"]
    rows = {r["path"]: r for r in summary.rows}
    assert rows["slow/big.obj"]["status"] == "failed"
    assert "slow/big.obj" in rows["slow/big.obj"]["error"] and "died" in rows["slow/big.obj"]["error"]
    assert rows["Fox.glb"]["status"] == "fixed"
    assert not (tmp_path / "twice" / "slow" / "big.glb").exists()
    assert summary.failed == 1


def test_small_files_go_several_to_a_task_and_large_ones_alone():
    sizes = {f"s{i}": 1000 for i in range(10)}
    sizes["big"] = seamlit.ray._ALONE_BYTES
    inputs = ["s0", "s1", "big", *[f"s{i}" for i in range(2, 10)]]
    # Ten small files on 1 CPU: at least 4 tasks of them, so 3 files a task; the large one alone.
    assert seamlit.ray._batches(inputs, sizes, cpus=1) == [
        ["big"],
        ["s0", "s1", "s2"],
        ["s3", "s4", "s5"],
        ["s6", "s7", "s8"],
        ["s9"],
    ]
    # Many on 1 CPU: tasks of one size, none made smaller toward the end (nothing to balance).
    library = {f"s{i}": 1000 for i in range(1008)}
    counts = [len(b) for b in seamlit.ray._batches(list(library), library, cpus=1)]
    assert counts == [1008 // seamlit.ray._TASKS_PER_CPU] * seamlit.ray._TASKS_PER_CPU
    # Many CPUs: one file a task.
    assert seamlit.ray._batches(inputs, sizes, cpus=8) == [["s0"], ["big"], *[[f"s{i}"] for i in range(1, 10)]]
    # A task holds at most _BATCH_BYTES of small files, and at most _BATCH_FILES of them.
    near = seamlit.ray._ALONE_BYTES - 1
    count = seamlit.ray._BATCH_BYTES // near * 10
    many = {f"s{i}": near for i in range(count)}
    batches = seamlit.ray._batches(list(many), many, cpus=1)
    assert max(map(len, batches)) == seamlit.ray._BATCH_BYTES // near
    assert max(sum(many[r] for r in b) for b in batches) <= seamlit.ray._BATCH_BYTES
    tiny = {f"s{i}": 1 for i in range(seamlit.ray._BATCH_FILES * 10)}
    assert max(map(len, seamlit.ray._batches(list(tiny), tiny, cpus=1))) == seamlit.ray._BATCH_FILES
    # Many small files on 2 CPUs: tasks get smaller toward the end, down to a few files each.
    library = {f"s{i}": 1000 for i in range(1008)}
    counts = [len(b) for b in seamlit.ray._batches(list(library), library, cpus=2)]
    assert sum(counts) == 1008 and counts == sorted(counts, reverse=True)
    assert counts[0] == 1008 // (2 * seamlit.ray._TASKS_PER_CPU)
    assert min(counts[:-1]) == seamlit.ray._LAST_BATCH_FILES


def test_asset_paths_are_found_as_the_pattern_finds_them():
    from seamlit.ray import _files

    pattern = rb"[A-Za-z0-9_./\\:-]+\.(?:usda|usdc|usdz|usd|png|jpg|jpeg|exr|tif|tiff|hdr|tga|bmp|ktx2)\b"
    rng = random.Random(7)
    pieces = [b".", b"usda", b"usd", b"png", b"x", b"9", b"-", b"/", b"\\", b" ", b"@", b"\n", b"a.usdc", b"z"]
    for _ in range(20000):
        data = b"".join(rng.choice(pieces) for _ in range(rng.randrange(1, 24)))
        assert _files._asset_paths(data) == re.findall(pattern, data), data
    for layer in sorted(MODELS.rglob("*.usd[ac]")):
        data = layer.read_bytes()
        assert _files._asset_paths(data) == re.findall(pattern, data), layer


def test_a_worker_killed_in_a_task_of_several_files_loses_none_of_them(cluster, tmp_path, monkeypatch):
    src = tmp_path / "src"
    slow_model(src / "slow" / "big.obj")
    for i in range(5):
        shutil.copy(MODELS / "fox" / "Fox.glb", src / f"fox{i}.glb")
    # All six files in one task (the slow model is large: it would run alone).
    monkeypatch.setattr(seamlit.ray, "_ALONE_BYTES", 1 << 30)
    monkeypatch.setattr(seamlit.ray, "_BATCH_BYTES", 1 << 30)
    monkeypatch.setattr(seamlit.ray, "_TASKS_PER_CPU", 0.01)
    monkeypatch.setattr(seamlit.ray, "_SHARES_PER_CPU", 0.01)
    expected = tmp_path / "expected"
    assert cli("fix", src, "-o", expected).returncode == 0

    # The task's worker killed once: each of its files run again alone, and done.
    thread, result = run_in_thread(src=str(src), dst=str(tmp_path / "once"))
    batch = worker_of("seamlit fix fox0.glb (+5 files)")
    time.sleep(1.0)  # into the slow model, the five foxes done and lost with the worker
    os.kill(batch, signal.SIGKILL)
    thread.join(timeout=600)
    assert "error" not in result, result.get("error")
    assert result["summary"].fixed == 6, [r for r in result["summary"].rows if r["status"] != "fixed"]
    assert_same_tree(tmp_path / "once", expected)

    # Killed in the task and again alone: that file failed, the rest done.
    thread, result = run_in_thread(src=str(src), dst=str(tmp_path / "twice"))
    os.kill(worker_of("seamlit fix fox0.glb (+5 files)"), signal.SIGKILL)
    os.kill(worker_of("seamlit fix slow/big.obj"), signal.SIGKILL)
    thread.join(timeout=600)
    rows = {r["path"]: r for r in result["summary"].rows}
    assert rows["slow/big.obj"]["status"] == "failed" and "died" in rows["slow/big.obj"]["error"], rows["slow/big.obj"]
    assert all(rows[f"fox{i}.glb"]["status"] == "fixed" for i in range(5)), rows
    assert not (tmp_path / "twice" / "slow" / "big.glb").exists()


def test_a_node_lost_mid_run_loses_no_file(cluster, tmp_path):
    src = tmp_path / "src"
    for i in range(3):
        slow_model(src / f"part{i}" / "big.obj", n=300)
    for i in range(6):
        shutil.copy(MODELS / "fox" / "Fox.glb", src / f"fox{i}.glb")
    doomed = cluster.add_node(num_cpus=1)
    cluster.wait_for_nodes()
    thread, result = run_in_thread(src=str(src), dst=str(tmp_path / "out"))
    # Wait until the doomed node's worker runs a file, then kill the node (its raylet and
    # workers, no graceful shutdown).
    deadline = time.monotonic() + 120
    raylet = doomed.all_processes["raylet"][0].process.pid
    while not any(_parent(pid) == raylet for pid in _seamlit_workers()):
        assert time.monotonic() < deadline, "no task reached the added node"
        time.sleep(0.05)
    cluster.remove_node(doomed, allow_graceful=False)
    thread.join(timeout=600)
    assert "error" not in result, result.get("error")
    summary = result["summary"]
    assert summary.fixed == 9 and summary.failed == 0, [r for r in summary.rows if r["status"] != "fixed"]
    expected = tmp_path / "expected"
    assert cli("fix", src, "-o", expected).returncode == 0
    assert_same_tree(tmp_path / "out", expected)


def _seamlit_workers():
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                title = Path(f"/proc/{entry}/cmdline").read_bytes()
            except OSError:
                continue
            if title.startswith(b"ray::seamlit fix"):
                yield int(entry)


def _parent(pid: int) -> int:
    """The parent process of ``pid`` (a Ray worker's is its node's raylet), 0 if gone."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return 0
    return int(stat.rsplit(")", 1)[1].split()[1])


def test_fix_bytes_gives_the_bytes_the_command_line_writes(tmp_path):
    for name in ("NormalTangentTest.glb", "fox/Fox.glb", "usd/head_body.usdz"):
        data = (MODELS / name).read_bytes()
        out, result = seamlit.fix_bytes(data, Path(name).name)
        assert cli("fix", MODELS / name, "-o", tmp_path / "x.glb").returncode == 0
        assert out == (tmp_path / "x.glb").read_bytes(), name
        assert result["output"] == Path(name).stem + ".glb"
    # The report as loaded and after: head_body's 22.5-degree seam is closed.
    assert result["as_loaded"]["cross_object"]["max_normal_angle_deg"] > 20
    assert result["fixed"]["cross_object"]["max_normal_angle_deg"] < 0.01
    with pytest.raises(seamlit.SeamlitError, match="scene.gltf"):
        seamlit.fix_bytes(b"{}", "scene.gltf")
    with pytest.raises(seamlit.SeamlitError, match="bad.glb"):
        seamlit.fix_bytes(b"glTF\x02\x00\x00\x00garbage", "bad.glb")


def test_a_model_in_one_file_is_fixed_in_memory_on_the_worker(tmp_path, monkeypatch):
    # A worker's task for a GLB, USDZ or FBX neither stages the model nor its output on disk:
    # one library call reads it, fixes it and writes the output to DST once, complete.
    from seamlit.ray import _task

    def no_folder(*args, **kwargs):
        raise AssertionError("the task made a scratch folder")

    monkeypatch.setattr(_task.tempfile, "mkdtemp", no_folder)
    src, dst = tmp_path / "src", tmp_path / "dst"
    for name in ("fox/Fox.glb", "usd/head_body.usdz", "ufbx/blender_293_half_skinned_7400_binary.fbx"):
        source = MODELS / name
        (src / Path(name).parent).mkdir(parents=True, exist_ok=True)
        shutil.copy(source, src / name)
        output = str(Path(name).with_suffix(".glb"))
        job = _task.Job(relative=name, src=str(src), dst=str(dst), output=output,
                        options={"mode": "model", "tessellation": 16, "skin_seams": "match", "samples": 30},
                        flags=(), options_key="")
        row = _task.process(job)
        assert row["status"] in ("fixed", "unchanged"), row
        assert cli("fix", source, "-o", tmp_path / "cli.glb").returncode == 0
        assert (dst / output).read_bytes() == (tmp_path / "cli.glb").read_bytes(), name
        assert row["output_sha256"] == _task.sha256((dst / output).read_bytes())
    broken = src / "broken.usdz"
    broken.write_bytes(b"PK\x03\x04 not a package")
    row = _task.process(_task.Job(relative="broken.usdz", src=str(src), dst=str(dst), output="broken.glb",
                                  options={"mode": "model"}, flags=(), options_key=""))
    assert row["status"] == "refused" and row["error"].startswith("broken.usdz"), row
    assert not (dst / "broken.glb").exists()


def test_digests_made_together_are_hashlib_s(tmp_path):
    # A task hashes its files together (seamlit._seamlit.Digests): messages of about one
    # length side by side, the rest alone. Every length around SHA-256's block and padding
    # boundaries, lengths that group and lengths that do not, files and bytes; a file that
    # cannot be read has no digest, and the others are not disturbed by it.
    from seamlit import _seamlit

    rng = random.Random(44)
    lengths = [0, 1, 55, 56, 57, 63, 64, 65, 119, 120, 121, 127, 128, 129, 4095, 4096, 4097, 1 << 20]
    lengths += [50_000] * 33 + [rng.randrange(0, 300_000) for _ in range(60)]
    digests, expected = _seamlit.Digests(), {}
    for key, n in enumerate(lengths):
        data = rng.randbytes(n)
        if key % 3 == 0:
            path = tmp_path / f"m{key}"
            path.write_bytes(data)
            digests.add_file(key, str(path))
        else:
            digests.add_bytes(key, data)
        expected[key] = hashlib.sha256(data).hexdigest()
    digests.add_file(len(lengths), str(tmp_path / "gone"))
    expected[len(lengths)] = None
    assert len(digests) == len(lengths) + 1
    assert digests.held() == sum(n for k, n in enumerate(lengths) if k % 3)
    assert dict(digests.take()) == expected
    assert len(digests) == 0 and digests.held() == 0 and digests.take() == []


def copied_jobs(names, copies, src, dst_of):
    """A task's jobs: `copies` copies of the models `names` under SRC (`c0/`, `c1/`, ...),
    each fixed into the DST `dst_of(copy)` under its own name."""
    from seamlit.ray import _task

    jobs = []
    for k in range(copies):
        for name in names:
            relative = f"c{k}/{Path(name).name}"
            (src / relative).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(MODELS / name, src / relative)
            jobs.append(_task.Job(relative=relative, src=str(src), dst=dst_of(k), output=relative,
                                  options={"mode": "model"}, flags=(), options_key=""))
    return jobs


def test_a_task_s_rows_carry_the_hashes_of_its_files_whenever_they_are_made(tmp_path, monkeypatch):
    # GLBs fixed by path into a local DST leave their hashes to the end of the task (or to
    # whenever the outputs held pass Hashes.HELD): the rows are the same either way, and
    # the same as hashing each file on its own.
    from seamlit.ray import _task

    src, dst = tmp_path / "src", tmp_path / "dst"
    names = ["fox/Fox.glb", "NormalTangentTest.glb", "emissive_strength_test/EmissiveStrengthTest.glb"]
    jobs = copied_jobs(names, 4, src, lambda k: str(dst))
    batched = _task.process_batch(jobs)
    monkeypatch.setattr(_task.Hashes, "HELD", 1)
    flushed_each_time = _task.process_batch(jobs)
    monkeypatch.setattr(_task.Hashes, "of_package", classmethod(lambda cls: None))
    one_by_one = _task.process_batch(jobs)
    for job, *rows in zip(jobs, batched, flushed_each_time, one_by_one):
        assert rows[0]["status"] in ("fixed", "unchanged"), rows[0]
        expected = (
            hashlib.sha256((src / job.relative).read_bytes()).hexdigest(),
            hashlib.sha256((dst / job.output).read_bytes()).hexdigest(),
        )
        for row in rows:
            assert (row["input_sha256"], row["output_sha256"]) == expected, job.relative


def test_an_input_written_before_its_hash_is_made_has_none_and_is_fixed_again(tmp_path):
    # A task hashes its inputs at its end, after fixing them: an input written since (or
    # replaced by another file, even one of the same bytes) has no input hash and says why,
    # never the hash of bytes that were not the ones fixed, so that the next run fixes it
    # again instead of skipping it as done. The rows beside it keep their hashes.
    import dataclasses

    from seamlit.ray import _task

    src, dst = tmp_path / "src", tmp_path / "dst"
    jobs = copied_jobs(["fox/Fox.glb", "NormalTangentTest.glb"], 2, src, lambda k: str(dst))
    hashes = _task.Hashes.of_package()
    rows = [_task.process(job, None, hashes) for job in jobs]
    written, replaced = src / jobs[0].relative, src / jobs[1].relative
    with open(written, "ab") as f:
        f.write(b"\0\0\0\0")
    copy = replaced.with_name("copy.glb")
    shutil.copy(replaced, copy)
    os.replace(copy, replaced)
    hashes.flush()
    for row in rows[:2]:
        assert row["status"] in ("fixed", "unchanged") and row["input_sha256"] is None, row
        assert any(w.startswith(row["path"]) and "changed or went away" in w for w in row["warnings"]), row
    for job, row in zip(jobs[2:], rows[2:]):
        assert row["input_sha256"] == hashlib.sha256((src / job.relative).read_bytes()).hexdigest(), row
        assert not any("changed" in w for w in row["warnings"]), row
    # The next run compares each input with the hash its row holds.
    again = [
        dataclasses.replace(job, previous=(row["input_sha256"], row["companions_sha256"]), previous_output=job.output)
        for job, row in zip(jobs, rows)
    ]
    assert [_task.process(job)["skipped"] for job in again] == [False, False, True, True]


def test_a_task_s_rows_fixed_in_memory_carry_their_hashes_and_an_unwritten_one_none(s3, tmp_path):
    # GLBs fixed in memory (for an object-store DST) leave their hashes to the end of the
    # task too; an output whose upload fails is a failed row without an output hash, and the
    # rows beside it are not disturbed.
    from seamlit.ray import _task

    s3.create_bucket(Bucket="hashes")
    src = tmp_path / "src"
    # The middle copy's bucket does not exist: its uploads fail.
    dst_of = lambda k: "s3://no-such-bucket/out" if k == 1 else "s3://hashes/out"
    jobs = copied_jobs(["fox/Fox.glb", "NormalTangentTest.glb"], 3, src, dst_of)
    rows = _task.process_batch(jobs)
    for job, row in zip(jobs, rows):
        assert row["input_sha256"] == hashlib.sha256((src / job.relative).read_bytes()).hexdigest(), job.relative
        if "no-such-bucket" in job.dst:
            assert row["status"] == "failed" and row["output_sha256"] is None, row
            continue
        assert row["status"] in ("fixed", "unchanged"), row
        written = s3.get_object(Bucket="hashes", Key=f"out/{job.output}")["Body"].read()
        assert row["output_sha256"] == hashlib.sha256(written).hexdigest(), job.relative
