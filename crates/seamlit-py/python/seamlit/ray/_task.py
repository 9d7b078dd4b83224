"""One file's work, run in a Ray worker: read the model (and the files that travel with it)
from SRC, fix or inspect it, write the output to DST under its final name only when it is
complete, and return the file's row of the report.

Every failure that is the file's (a model seamlit refuses, a file missing beside it) is a
``refused`` row; only a dead worker process (a native crash, the out-of-memory killer, a lost
node) escapes from here, and the driver retries that once (Ray's ``max_retries``).

Small files go several to a task (:func:`process_batch`): Ray's cost per task, several
milliseconds, is more than fixing a small model takes. A batch is not retried as a whole:
when its worker dies, the driver runs each of its files again alone, once.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import posixpath
import shutil
import subprocess
import tempfile
import time
import uuid
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Sequence, Tuple

from pyarrow import fs as pafs

from . import _files

#: The report's row for one input file (see docs/fleet.md for the columns).
Row = Dict[str, Any]


@dataclass(frozen=True)
class Job:
    """What a worker needs to process one file (sent to it pickled)."""

    relative: str
    src: str
    dst: Optional[str]
    output: Optional[str]
    options: Dict[str, Any]
    flags: Tuple[str, ...]
    options_key: str
    #: The previous run's input and companion hashes, when its row may be carried over.
    previous: Optional[Tuple[str, str]] = None
    #: The previous run's output (relative to DST) that must still be there to skip.
    previous_output: Optional[str] = None
    engine: str = "auto"


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def empty_row(job: Job) -> Row:
    """A row with every column, nothing measured yet."""
    return {
        "path": job.relative,
        "status": None,
        "error": None,
        "objects": None,
        "triangles": None,
        "shared_positions": None,
        "seams_repaired": None,
        "kept_hard_edges": None,
        "kept_custom": None,
        "largest_seam_before_deg": None,
        "largest_seam_after_deg": None,
        "warnings": [],
        "seconds": 0.0,
        "output_path": job.output,
        "output_sha256": None,
        "input_sha256": None,
        "companions_sha256": None,
        "options": job.options_key,
        "skipped": False,
        "memory_bytes": None,
    }


def seamlit_binary() -> Optional[str]:
    """The ``seamlit`` command line the worker can run: ``SEAMLIT_BIN`` or the one on
    ``PATH``; ``None`` when there is none."""
    path = os.environ.get("SEAMLIT_BIN") or shutil.which("seamlit")
    return path if path and os.path.isfile(path) else None


def _read(filesystem: pafs.FileSystem, path: str) -> bytes:
    if isinstance(filesystem, pafs.LocalFileSystem):
        # A file of known size, read in one call (a stream reads it in chunks: 20 times
        # slower for a 2 MB model).
        with filesystem.open_input_file(path) as file:
            return file.read()
    with filesystem.open_input_stream(path) as stream:
        return stream.read()


def _gather(
    filesystem: pafs.FileSystem, root: str, relative: str, data: bytes
) -> Dict[str, bytes]:
    """The model's companions (relative to SRC -> bytes), followed from file to file (an OBJ
    names its MTL, the MTL its textures; a USD layer its layers). Names that leave SRC or do
    not exist are left out: the loader then names what is missing."""
    found: Dict[str, bytes] = {}
    pending = [(relative, data)]
    seen = {relative}
    while pending:
        name, content = pending.pop()
        folder = posixpath.dirname(name)
        for companion in _files.companions_of(name, content):
            path = posixpath.normpath(posixpath.join(folder, companion))
            if path.startswith("../") or path == ".." or path in seen:
                continue
            seen.add(path)
            try:
                body = _read(filesystem, root + "/" + path)
            except (FileNotFoundError, OSError):
                continue
            found[path] = body
            if _files.extension(path) in ("mtl", "usda", "usdc", "usd", "gltf"):
                pending.append((path, body))
    return found


def _companions_digest(files: Dict[str, bytes]) -> str:
    digest = hashlib.sha256()
    for name in sorted(files):
        digest.update(name.encode() + b"\0" + sha256(files[name]).encode() + b"\n")
    return digest.hexdigest()


#: The companions' digest of a model in one file.
_NO_COMPANIONS = _companions_digest({})


def _first_line(text: str) -> str:
    for line in text.splitlines():
        line = line.strip()
        if line.startswith("error: "):
            return line[len("error: ") :]
    lines = [l.strip() for l in text.splitlines() if l.strip()]
    return lines[-1] if lines else "failed without a message"


def _measure(row: Row, report: Dict[str, Any]) -> None:
    """Fills the row's seam columns from a ``seamlit.inspect`` result."""
    before = report["as_loaded"]
    after = report["fixed"]
    shared = report["changes"].get("shared", {})
    row["objects"] = before["objects"]
    row["triangles"] = before["triangles"]
    row["shared_positions"] = before["shared_positions"]
    row["seams_repaired"] = shared.get("repaired", 0)
    row["kept_hard_edges"] = shared.get("hard_edges", 0)
    row["kept_custom"] = shared.get("custom", 0)
    row["largest_seam_before_deg"] = before["cross_object"].get("max_normal_angle_deg")
    row["largest_seam_after_deg"] = after["cross_object"].get("max_normal_angle_deg")
    row["warnings"] = [str(w) for w in report.get("warnings", [])]
    objects = report["changes"].get("objects", [])
    row["_changed"] = any(o.get("normals_changed") or o.get("vertices_split") for o in objects)


def _measure_row(row: Row, result: Dict[str, Any]) -> bool:
    """Fills the row's columns from a native fix's row (``seamlit._fix_file_row``); returns
    whether the fix changed the model."""
    changed = bool(result.pop("changed"))
    row.update(result)
    return changed


def _inspect_options(options: Dict[str, Any]) -> Dict[str, Any]:
    keep = ("mode", "crease", "weld_tolerance", "weighting", "tangents", "normals", "tessellation", "asset_roots")
    return {k: v for k, v in options.items() if k in keep}


class Unwritten(OSError):
    """An output that could not be written to DST (a full disk, a refused upload): the
    file's row is ``failed`` with this one line, never the run's end."""


def _unwritten(output: str, dst: str, reason: object) -> Unwritten:
    """``reason`` (an exception or its message) on one line, with the output and DST."""
    lines = str(reason).strip().splitlines()
    return Unwritten(f"cannot write {output} to {dst}: {lines[0] if lines else type(reason).__name__}")


class Crashed(RuntimeError):
    """The ``seamlit`` process fixing a file died from a signal (a native crash, the
    out-of-memory killer): Ray retries the task as it does for a dead worker."""


def _run_cli(binary: str, local_input: str, local_output: str, flags: Sequence[str], relative: str) -> Tuple[int, str]:
    # One thread per task: Ray gave the task one CPU.
    env = dict(os.environ)
    env.setdefault("RAYON_NUM_THREADS", "1")
    done = subprocess.run(
        [binary, "fix", local_input, "-o", local_output, *flags],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    if done.returncode < 0:
        raise Crashed(f"{relative}: the seamlit process fixing it died from signal {-done.returncode}")
    return done.returncode, done.stderr + done.stdout


def _publish(filesystem: pafs.FileSystem, root: str, staged: str, output_relative: str, dst: str) -> None:
    """Moves every file the fix wrote (the output, and a .gltf's or .obj's files beside it)
    from the staging folder to DST. A file appears under its name only complete: a rename
    on a local filesystem, one upload (one object) on an object store."""
    folder = posixpath.dirname(output_relative)
    local = isinstance(filesystem, pafs.LocalFileSystem)
    try:
        _publish_files(filesystem, root, staged, folder, local)
    except OSError as e:
        raise _unwritten(output_relative, dst, e) from e


def _publish_files(filesystem: pafs.FileSystem, root: str, staged: str, folder: str, local: bool) -> None:
    for dirpath, _, names in os.walk(staged):
        for name in sorted(names):
            source = os.path.join(dirpath, name)
            inner = os.path.relpath(source, staged).replace(os.sep, "/")
            target = root + "/" + posixpath.join(folder, inner)
            if local:
                os.makedirs(os.path.dirname(target), exist_ok=True)
                partial = f"{target}.{uuid.uuid4().hex[:8]}.partial"
                with open(source, "rb") as f, open(partial, "wb") as out:
                    shutil.copyfileobj(f, out, 1 << 20)
                    # On disk before it has its name, as the command line writes.
                    out.flush()
                    os.fsync(out.fileno())
                os.replace(partial, target)
            else:
                with open(source, "rb") as f, filesystem.open_output_stream(target) as out:
                    shutil.copyfileobj(f, out, 1 << 20)


#: glibc's ``mallopt`` parameters (malloc.h).
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
_allocator_tuned = False


def _tune_allocator() -> None:
    """Keeps the worker's freed memory for its next file instead of handing it back to the
    system at once (glibc's malloc, where it is the allocator): blocks up to 32 MiB come from
    the heap, not fresh mappings, and up to 128 MiB of free heap stay with the process.
    Fixing a file one after another, a 2 MB model's buffers were otherwise mapped, faulted
    in page by page and unmapped again for every file (its fix 7.9 ms instead of 4.0)."""
    global _allocator_tuned
    if _allocator_tuned:
        return
    _allocator_tuned = True
    try:
        libc = ctypes.CDLL("libc.so.6")
        libc.mallopt(_M_MMAP_THRESHOLD, 32 * 2**20)
        libc.mallopt(_M_TRIM_THRESHOLD, 128 * 2**20)
    except (OSError, AttributeError):  # not glibc: its own allocator's defaults
        pass


def process(job: Job, memory: Optional[int] = None, hashes: Optional["Hashes"] = None) -> Row:
    """Fixes (``job.dst`` set) or inspects one file and returns its row; the row of a file
    whose input and options are those of the previous run is marked ``skipped``.
    ``memory``: what Ray reserved for the task, when the caller knows it (else asked).
    ``hashes``: where a file fixed by path into a local DST leaves its input and output to be
    hashed with the task's others (the row's two hashes are filled when it is flushed)."""
    # One thread per task (Ray gave it one CPU), set before the native module starts its pool.
    os.environ.setdefault("RAYON_NUM_THREADS", "1")
    _tune_allocator()
    import seamlit

    started = time.perf_counter()
    row = empty_row(job)
    row["memory_bytes"] = memory if memory is not None else _reserved_memory()
    src_fs, src_root = _files.resolve(job.src)
    local_src = isinstance(src_fs, pafs.LocalFileSystem)
    # Made where a model is staged or an output written on the worker (not for a model fixed
    # in memory: one in one file, or one from an object store with its files, into a GLB).
    scratch: Optional[str] = None
    try:
        ext = _files.extension(job.relative) or ""
        if job.previous is None and ext in _files.SELF_CONTAINED and local_src and _into_local_file(job):
            # Nothing to compare with: read, hashed, fixed and written in one native call.
            row["companions_sha256"] = _NO_COMPANIONS
            return _fix_native(job, row, src_root + "/" + job.relative, job.options, None, hashes)
        try:
            data = _read(src_fs, src_root + "/" + job.relative)
        except (FileNotFoundError, OSError) as e:
            row.update(status="refused", error=f"{job.relative}: cannot read it: {e}")
            return row
        companions = {} if ext in _files.SELF_CONTAINED else _gather(src_fs, src_root, job.relative, data)
        row["companions_sha256"] = _companions_digest(companions)
        if job.previous is not None:
            row["input_sha256"] = sha256(data)
            if job.previous == (row["input_sha256"], row["companions_sha256"]) and _still_there(job):
                row["skipped"] = True
                return row

        if _in_memory(job, ext, local_src):
            return _fix_in_memory(job, row, data, companions, hashes)
        if local_src and _into_local_file(job):
            return _fix_native(job, row, src_root + "/" + job.relative, job.options, None, hashes)
        row["input_sha256"] = row["input_sha256"] or sha256(data)

        scratch = tempfile.mkdtemp(prefix="seamlit-ray-", dir=_scratch_root())
        # The model as a local file: SRC's own when SRC is local, else a staged copy.
        local_input = src_root + "/" + job.relative if local_src else _stage(scratch, job.relative, data, companions)
        options = dict(job.options)
        if not local_src and options.get("asset_roots"):  # SRC-relative: their staged copies
            options["asset_roots"] = [os.path.join(scratch, "in", r) for r in options["asset_roots"]]

        if job.dst is not None and job.output is not None and _native(job.engine):
            return _fix_native(job, row, local_input, options, scratch)

        try:
            report = seamlit.inspect(local_input, **_inspect_options(options))
        except (seamlit.SeamlitError, FileNotFoundError) as e:
            row.update(status="refused", error=_relative_message(str(e), local_input, job.relative))
            return row
        _measure(row, report)
        changed = row.pop("_changed")

        if job.dst is not None and job.output is not None:
            staged = os.path.join(scratch, "out")
            os.makedirs(staged)
            local_output = os.path.join(staged, posixpath.basename(job.output))
            binary = seamlit_binary() if job.engine in ("auto", "cli") else None
            if binary is not None:
                code, text = _run_cli(binary, local_input, local_output, job.flags, job.relative)
                if code != 0:
                    status = "refused" if code == 2 else "failed"
                    row.update(status=status, error=_relative_message(_first_line(text), local_input, job.relative))
                    return row
            else:
                try:
                    seamlit.fix_file(local_input, local_output, **options)
                except (seamlit.SeamlitError, FileNotFoundError) as e:
                    row.update(status="refused", error=_relative_message(str(e), local_input, job.relative))
                    return row
            with open(local_output, "rb") as f:
                row["output_sha256"] = sha256(f.read())
            dst_fs, dst_root = _files.resolve(job.dst)
            _publish(dst_fs, dst_root, staged, job.output, job.dst)
            row["status"] = "fixed" if changed else "unchanged"
        else:
            row["output_path"] = None
            row["status"] = "fixed" if changed else "unchanged"
        return row
    except Unwritten as e:
        row.update(status="failed", error=f"{job.relative}: {e}", output_sha256=None)
        return row
    finally:
        row["seconds"] = time.perf_counter() - started
        if scratch is not None:
            shutil.rmtree(scratch, ignore_errors=True)


def process_batch(jobs: Sequence[Job]) -> List[Row]:
    """Processes several files one after another in one task and returns their rows in the
    same order. A file whose ``seamlit`` process dies (:class:`Crashed`) is not retried
    here: its row carries ``_crashed`` (the reason) and the driver runs it again alone; the
    files after it are still done. A crash of the worker itself ends the whole task, and the
    driver runs each of its files again alone."""
    rows: List[Row] = []
    memory = _reserved_memory()  # the task's, the same for each of its files
    hashes = Hashes.of_package()
    for job in jobs:
        try:
            rows.append(process(job, memory, hashes))
        except Crashed as e:
            row = empty_row(job)
            row["_crashed"] = str(e)
            rows.append(row)
        if hashes is not None and hashes.full():
            hashes.flush()
    if hashes is not None:
        hashes.flush()
    return rows


class Hashes:
    """The report's SHA-256 of a task's files, made together (``seamlit._seamlit.Digests``:
    messages of about one size hashed side by side, 2.6 times faster on this project's
    benchmark library than one after another). A file's input and output are added when it
    is fixed (by path into a local DST, or in memory), under keys that name its row and
    column; :meth:`flush` hashes them and fills the rows in. The bytes wait in memory:
    flushed when they pass :attr:`HELD`."""

    #: Bytes held (outputs, and inputs fixed in memory) before what waits is hashed.
    HELD = 64 * 2**20

    def __init__(self, native: Any) -> None:
        self.native = native
        self.slots: Dict[int, Tuple[Row, str]] = {}
        self.next_key = 0

    @classmethod
    def of_package(cls) -> "Hashes":
        """A set backed by the extension module's ``Digests`` (the tests replace this to hash
        one file after another, as ``process`` alone does)."""
        import seamlit

        return cls(seamlit._seamlit.Digests())

    def keys(self, row: Row) -> Tuple[int, int]:
        """The keys of ``row``'s input and output hashes."""
        keys = (self.next_key, self.next_key + 1)
        self.slots[keys[0]] = (row, "input_sha256")
        self.slots[keys[1]] = (row, "output_sha256")
        self.next_key += 2
        return keys

    def forget(self, keys: Sequence[int]) -> None:
        """Drops keys whose digests the row no longer wants (its files were not added, or
        its output was not written)."""
        for key in keys:
            self.slots.pop(key, None)

    def full(self) -> bool:
        return self.native.held() >= self.HELD

    def flush(self) -> None:
        """Hashes what was added and fills each row's column in: ``None``, with a warning,
        for an input that can no longer be read or is no longer the file that was fixed
        (the next run fixes it again rather than skip it as done)."""
        for key, digest in self.native.take():
            slot = self.slots.pop(key, None)
            if slot is not None:
                row, column = slot
                row[column] = digest
                if digest is None and column == "input_sha256":
                    row["warnings"] = [*row["warnings"], f"{row['path']}: {_CHANGED}"]


#: Why a row has no input hash (its file changed, or went, while its task ran).
_CHANGED = "changed or went away while it was fixed: no input hash; the next run fixes it again"


def _reserved_memory() -> Optional[int]:
    """The memory Ray reserved for this task (asked from the file's size), when in Ray."""
    try:
        import ray

        memory = ray.get_runtime_context().get_assigned_resources().get("memory")
    except Exception:  # not in a Ray worker
        return None
    return int(memory) if memory else None


def _native(engine: str) -> bool:
    """Whether the task fixes in its own process with the extension module's ``fix_file``
    (the command line's steps in the same library call, one load): ``auto`` and
    ``package``."""
    return engine in ("auto", "package")


def _fix_native(
    job: Job,
    row: Row,
    local_input: str,
    options: Dict[str, Any],
    scratch: Optional[str],
    hashes: Optional[Hashes] = None,
) -> Row:
    """Fixes the model at ``local_input`` by path: into ``scratch`` and from there to DST
    (:func:`_publish`), or, without ``scratch``, straight into its place in a local DST (the
    library's save writes it under a temporary name and renames it, as the command line).
    There, a GLB's or VRM's input and output go to ``hashes``, where given."""
    import seamlit

    assert job.dst is not None and job.output is not None
    dst_fs, dst_root = _files.resolve(job.dst)
    if scratch is None:
        staged = None
        local_output = dst_root + "/" + job.output
        try:
            os.makedirs(os.path.dirname(local_output), exist_ok=True)
        except OSError as e:
            raise _unwritten(job.output, job.dst, e) from e
    else:
        staged = os.path.join(scratch, "out")
        os.makedirs(staged)
        local_output = os.path.join(staged, posixpath.basename(job.output))
    # A GLB or VRM: written and hashed by the native call; other outputs (several files)
    # are hashed from the file written.
    one_file = job.output.lower().endswith((".glb", ".vrm"))
    try:
        if one_file and staged is None and hashes is not None:
            # Written in place: nothing after this can fail the row, so its hashes can wait.
            keys = hashes.keys(row)
            try:
                result = seamlit._fix_file_row(local_input, local_output, hashes.native, keys, **options)
            except BaseException:
                hashes.forget(keys)  # added by the native call only where it succeeded
                raise
            changed = _measure_row(row, result)
        elif one_file:
            changed = _measure_row(row, seamlit._fix_file_row(local_input, local_output, **options))
        else:
            _measure(row, seamlit._fix_measured(local_input, local_output, **options))
            changed = row.pop("_changed")
    except (seamlit.SeamlitError, FileNotFoundError) as e:
        message = str(e)
        # The save's error names the output (the model's name the input): not the file's fault.
        if staged is None and message.startswith(local_output):
            raise _unwritten(job.output, job.dst, message[len(local_output) :].lstrip(": ")) from e
        row.update(status="refused", error=_relative_message(message, local_input, job.relative))
        _hash_input(row, local_input)
        return row
    if not one_file:
        _hash_input(row, local_input)
        with open(local_output, "rb") as f:
            row["output_sha256"] = sha256(f.read())
    if staged is not None:
        _publish(dst_fs, dst_root, staged, job.output, job.dst)
    row["status"] = "fixed" if changed else "unchanged"
    return row


def _into_local_file(job: Job) -> bool:
    """Whether the job's output is one file (a GLB; a VRM's VRM) in a local DST, written
    there by the native fix itself."""
    if job.dst is None or job.output is None or not _native(job.engine):
        return False
    if not job.output.lower().endswith((".glb", ".vrm")):
        return False
    return isinstance(_files.resolve(job.dst)[0], pafs.LocalFileSystem)


def _in_memory(job: Job, ext: str, local_src: bool) -> bool:
    """Whether the job is fixed in memory by the extension module (:func:`seamlit.fix_bytes`'s
    library call), into the one file it writes (a GLB; a VRM's VRM), with no file read or
    written on the worker: a model in one file (GLB, VRM, USDZ, FBX), and one of several
    from an object store with the files gathered beside it (the set staging would write),
    unless asset roots map SRC's folders to staged ones. A model of several from a folder is
    read by path (the loader finds what the gathering may miss)."""
    import seamlit

    if job.dst is None or job.output is None or not _native(job.engine):
        return False
    if ext in seamlit.SELF_CONTAINED:
        return job.output.lower().endswith(".vrm" if ext == "vrm" else ".glb")
    several = ext in ("gltf", "obj", "usda", "usdc", "usd") and not job.options.get("asset_roots")
    return several and not local_src and job.output.lower().endswith(".glb")


def _stage(scratch: str, relative: str, data: bytes, companions: Dict[str, bytes]) -> str:
    """Writes the model and its companions at their relative places under ``scratch/in`` (a
    memory-backed folder where there is one) and returns the model's path there."""
    stage = os.path.join(scratch, "in")
    for name, body in [(relative, data), *companions.items()]:
        path = os.path.join(stage, *name.split("/"))
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(body)
    return os.path.join(stage, *relative.split("/"))


def _fix_in_memory(
    job: Job, row: Row, data: bytes, companions: Dict[str, bytes], hashes: Optional[Hashes] = None
) -> Row:
    """Fixes a model in memory (with ``companions``, SRC-relative paths -> bytes, for one of
    several files) and writes its output to DST (complete or not at all: a rename on a local
    filesystem, one upload on an object store). The input and output go to ``hashes``, where
    given (a row whose input was hashed to compare with the previous run keeps that hash)."""
    import seamlit

    assert job.dst is not None and job.output is not None
    deferred = hashes is not None and row["input_sha256"] is None
    keys = hashes.keys(row) if deferred else (0, 0)
    try:
        # Named by its path in SRC: errors and warnings name it so.
        output, result = seamlit._fix_bytes_row(
            data,
            job.relative,
            posixpath.basename(job.output),
            companions,
            hashes.native if deferred else None,
            keys,
            **job.options,
        )
    except BaseException as e:
        if deferred:
            hashes.forget(keys)  # added by the native call only where it succeeded
        if not isinstance(e, seamlit.SeamlitError):
            raise
        row.update(status="refused", error=_relative_message(str(e), job.relative, job.relative))
        row["input_sha256"] = row["input_sha256"] or sha256(data)
        return row
    changed = _measure_row(row, result)
    dst_fs, dst_root = _files.resolve(job.dst)
    try:
        _write(dst_fs, dst_root, job.output, output, job.dst)
    except Unwritten:
        if deferred:
            hashes.forget(keys[1:])  # no output: the row's output hash stays empty
        raise
    row["status"] = "fixed" if changed else "unchanged"
    return row


def _write(filesystem: pafs.FileSystem, root: str, output: str, data: bytes, dst: str) -> None:
    """Writes ``data`` to ``output`` under ``root`` (DST's place on ``filesystem``) so that
    it appears under its name only complete; raises :class:`Unwritten` naming ``dst``."""
    try:
        _write_file(filesystem, root + "/" + output, data)
    except OSError as e:
        raise _unwritten(output, dst, e) from e


def _write_file(filesystem: pafs.FileSystem, target: str, data: bytes) -> None:
    if isinstance(filesystem, pafs.LocalFileSystem):
        os.makedirs(os.path.dirname(target), exist_ok=True)
        partial = f"{target}.{uuid.uuid4().hex[:8]}.partial"
        with open(partial, "wb") as out:
            out.write(data)
            out.flush()
            os.fsync(out.fileno())
        os.replace(partial, target)
    else:
        with filesystem.open_output_stream(target) as out:
            out.write(data)


def _hash_input(row: Row, path: str) -> None:
    """The input's SHA-256 where the native call did not give it (it refused the file)."""
    if row["input_sha256"] is None:
        try:
            with open(path, "rb") as f:
                row["input_sha256"] = sha256(f.read())
        except OSError:  # gone since: the row says why it was refused
            pass


def _still_there(job: Job) -> bool:
    """Whether the previous run's output of the job is still in DST (a file whose output was
    removed is fixed again)."""
    if job.dst is None or job.previous_output is None:
        return True
    filesystem, root = _files.resolve(job.dst)
    return filesystem.get_file_info(root + "/" + job.previous_output).type == pafs.FileType.File


def _relative_message(message: str, local: str, relative: str) -> str:
    """The error's one line, naming the file by its path in SRC instead of the worker's
    local copy."""
    line = message.strip().splitlines()[0] if message.strip() else "failed without a message"
    return line.replace(local, relative)


def _scratch_root() -> Optional[str]:
    """A memory-backed folder for staged copies where the machine has one."""
    return "/dev/shm" if os.path.isdir("/dev/shm") and os.access("/dev/shm", os.W_OK) else None
