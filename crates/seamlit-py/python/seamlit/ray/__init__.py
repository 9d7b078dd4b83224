"""seamlit on Ray: fix or survey a library of models, in a folder or an object store, on a
Ray cluster, with a report of every file.

Two calls, and the command line ``python -m seamlit.ray fix|inspect`` over them:

- :func:`fix` -- ``seamlit fix SRC -o DST`` for a cluster: the same files are taken, the
  same outputs written under the same names (byte for byte the folder mode's), plus
  ``DST/_seamlit/report.parquet`` (one row per input) and ``DST/_seamlit/summary.html``;
- :func:`inspect` -- the same report without fixing anything.

SRC and DST are local or shared folders, or URIs ``pyarrow.fs`` resolves
(``s3://bucket/prefix``; endpoint and credentials from ``AWS_ENDPOINT_URL``,
``AWS_ACCESS_KEY_ID``, ``AWS_SECRET_ACCESS_KEY``). A file seamlit refuses is a ``refused``
row; a file whose worker dies (a native crash, out of memory, a lost node) is tried once
more, then a ``failed`` row. A second run over the same SRC, DST and options skips the
inputs whose bytes the last report already holds. See docs/fleet.md.

Needs Ray (``pip install 'seamlit[ray]'``).
"""

from __future__ import annotations

import json
import math
import sys
import time
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Tuple

# Not _report (Parquet): the workers import this package for its tasks and need none of it.
from . import _files
from ._task import Crashed, Job, Row, empty_row, process, process_batch

__all__ = ["Summary", "fix", "inspect"]


@dataclass(frozen=True)
class Summary:
    """What a run did: counts by status, files skipped as unchanged since the last run, and
    where the report is."""

    fixed: int
    unchanged: int
    refused: int
    failed: int
    skipped: int
    seconds: float
    report: str
    rows: Tuple[Row, ...]

    @property
    def files(self) -> int:
        return len(self.rows)

    def line(self) -> str:
        """The one line a run ends with."""
        done = self.files - self.skipped
        rate = done / self.seconds if self.seconds > 0 else 0.0
        return (
            f"seamlit.ray: {self.fixed} fixed, {self.unchanged} unchanged, {self.refused} refused, "
            f"{self.failed} failed, {self.skipped} skipped of {self.files} files "
            f"in {self.seconds:.1f} s ({rate:.2f} files/s); report {self.report}"
        )


#: Options of ``seamlit fix`` and their command-line flags (``None``: a switch).
_FLAGS: Dict[str, Optional[str]] = {
    "mode": "--mode",
    "crease": "--crease",
    "weld_tolerance": "--weld-tolerance",
    "weighting": "--weighting",
    "tangents": "--tangents",
    "normals": "--normals",
    "tessellation": "--tessellation",
    "skin_seams": "--skin-seams",
    "samples": "--samples",
    "keep_compression": None,
    "overwrite_input": None,
}


def _flags(options: Dict[str, Any]) -> Tuple[str, ...]:
    flags: List[str] = []
    for name, value in sorted(options.items()):
        if name == "asset_roots":
            for root in value:
                flags += ["--asset-root", str(root)]
            continue
        flag = _FLAGS.get(name)
        if name not in _FLAGS:
            raise ValueError(f"{name}: not an option of seamlit fix")
        if flag is None:
            if value:
                flags.append("--" + name.replace("_", "-"))
        elif value is not None:
            flags += [flag, str(value)]
    return tuple(flags)


#: Tasks ask for memory in multiples of this: tasks of one shape share Ray's leased workers
#: (a scheduling class each), so a task of small files asks what any other does.
_MEMORY_STEP = 64 * 2**20


def _memory(size: int) -> int:
    """Bytes of memory a task asks Ray for: a base for the process and the fix's working
    set, which grows with the model (measured: about 40 bytes per byte of a GLB), rounded up
    to a multiple of ``_MEMORY_STEP``."""
    needed = 256 * 2**20 + 48 * size
    return -(-needed // _MEMORY_STEP) * _MEMORY_STEP


def _largest_node_memory() -> Optional[float]:
    import ray

    sizes = [n["Resources"].get("memory", 0.0) for n in ray.nodes() if n.get("Alive")]
    return max(sizes) if sizes else None


def _run(
    kind: str,
    src: str,
    dst: Optional[str],
    report_uri: str,
    *,
    address: Optional[str],
    output_format: str,
    recurse: bool,
    pictures: int,
    engine: str,
    progress: bool,
    options: Dict[str, Any],
) -> Summary:
    import ray

    from . import _report

    if output_format not in _files.OUTPUT_FORMATS:
        raise ValueError(f"format={output_format!r}: expected one of {', '.join(_files.OUTPUT_FORMATS)}")
    if options.get("keep_compression") and output_format == "obj":
        raise ValueError(
            f"{dst}: --keep-compression needs glTF or GLB output (an OBJ file holds no compressed geometry)"
        )
    flags = _flags(options)
    options_key = _options_key(kind, output_format, options)

    src_fs, src_root = _files.resolve(src)
    skip = None
    if dst is not None:
        dst_fs, dst_root = _files.resolve(dst)
        if type(dst_fs) is type(src_fs):
            skip = dst_root
    inputs = _files.model_files(src_fs, src_root, recurse=recurse, skip=skip)
    if not inputs:
        where = "in this folder or its subfolders" if recurse else "in this folder"
        raise ValueError(
            f"{src}: no model files (.obj, .gltf, .glb, .vrm, .fbx, .usda, .usdc, .usdz, Newell patches) {where}"
        )
    names = _files.output_names(inputs, output_format) if dst is not None else {}
    sizes = {
        info.path[len(src_root) + 1 :]: info.size
        for info in src_fs.get_file_info([src_root + "/" + r for r in inputs])
    }
    previous = _report.read_previous(report_uri)

    if not ray.is_initialized():
        ray.init(address=address, log_to_driver=False, logging_level="WARNING")
    largest = _largest_node_memory()
    cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
    started = time.perf_counter()
    jobs = _jobs(inputs, previous, src, dst, names, options, flags, options_key, engine)
    tasks = _Tasks(kind, sizes, largest)
    for batch in _batches(inputs, sizes, cpus):
        tasks.submit([jobs[r] for r in batch], again=False)
    rows: Dict[str, Row] = {}
    bar = _Progress(len(inputs), kind, progress)
    for job, row in tasks.rows():
        if row.get("skipped"):
            kept = dict(previous[job.relative])
            kept["skipped"] = True
            row = kept
        rows[job.relative] = row
        bar.advance(row)
    bar.close()
    seconds = time.perf_counter() - started
    ordered = [rows[r] for r in inputs]
    _report.write(report_uri, ordered)
    if dst is not None and kind == "fix":
        _report.summary_html(src, dst, ordered, pictures=pictures, seconds=seconds)
    return _summary(ordered, seconds, report_uri)


def _options_key(kind: str, output_format: str, options: Dict[str, Any]) -> str:
    """The options as the key of a run, defaults filled in (the command line passes them, the
    Python call may not: both are one run for the skip)."""
    defaults: Dict[str, Any] = {"mode": "model", "tessellation": 16}
    if kind == "fix":
        defaults.update(skin_seams="match", samples=30, keep_compression=False, overwrite_input=False)
    keyed = {**defaults, **{k: v for k, v in options.items() if v is not None}}
    return json.dumps({"kind": kind, "format": output_format, **keyed}, sort_keys=True, default=str)


def _summary(ordered: List[Row], seconds: float, report_uri: str) -> Summary:
    """The run's counts by status (skipped rows apart) over its rows in input order."""
    count = lambda status: sum(1 for r in ordered if r["status"] == status and not r.get("skipped"))
    return Summary(
        fixed=count("fixed"),
        unchanged=count("unchanged"),
        refused=count("refused"),
        failed=count("failed"),
        skipped=sum(1 for r in ordered if r.get("skipped")),
        seconds=seconds,
        report=report_uri,
        rows=tuple(ordered),
    )


def _jobs(
    inputs: List[str],
    previous: Dict[str, Row],
    src: str,
    dst: Optional[str],
    names: Dict[str, str],
    options: Dict[str, Any],
    flags: Tuple[str, ...],
    options_key: str,
    engine: str,
) -> Dict[str, Job]:
    """Each input's job; with the previous run's hashes where its row may be carried over
    (the same options, and a status that is the file's own: not ``failed``)."""
    jobs: Dict[str, Job] = {}
    for relative in inputs:
        earlier = previous.get(relative)
        key, earlier_output = None, None
        if earlier is not None and earlier.get("options") == options_key and earlier["status"] in (
            "fixed",
            "unchanged",
            "refused",
        ):
            key = (earlier.get("input_sha256"), earlier.get("companions_sha256"))
            earlier_output = earlier.get("output_path") if earlier["status"] != "refused" else None
        jobs[relative] = Job(
            relative=relative,
            src=src,
            dst=dst,
            output=names.get(relative),
            options=options,
            flags=flags,
            options_key=options_key,
            previous=key,
            previous_output=earlier_output,
            engine=engine,
        )

    return jobs


#: Files of this size or more go alone to a task (each asks Ray for its own memory).
_ALONE_BYTES = 4 * 2**20
#: The smaller ones go together, at most this many bytes of them a task...
_BATCH_BYTES = 64 * 2**20
#: ...and at most this many files (a task's files are retried one by one when its worker
#: dies, and the progress moves a task at a time).
_BATCH_FILES = 256
#: A task takes the small files not yet in one over this many per CPU: tasks get smaller
#: toward the end of the run, so that the CPUs finish together.
_SHARES_PER_CPU = 2
#: Batches are made small enough for at least this many tasks per CPU of the cluster.
_TASKS_PER_CPU = 4
#: Toward the end, tasks of no fewer files than this (unless there are few): Ray's cost per
#: task is more than fixing a small model takes.
_LAST_BATCH_FILES = 4


def _batches(inputs: List[str], sizes: Dict[str, int], cpus: int) -> List[List[str]]:
    """The files of each task, in the order of ``inputs``: a file of ``_ALONE_BYTES`` or
    more alone, the smaller ones together, each task taking a share of those left (guided
    self-scheduling; on one CPU, ``_TASKS_PER_CPU`` tasks of one size). Ray's cost per task,
    about 3 ms between one task's end and the next one's start on a worker, is more than
    fixing a small model takes (49 tasks of 1,008 small files on one CPU spent 0.16 s of 2.9 s
    so), and a run's last tasks, if large, leave CPUs idle (BENCHMARKS.md, seamlit.ray)."""
    left = sum(1 for r in inputs if (sizes.get(r) or 0) < _ALONE_BYTES)
    most = max(1, min(_BATCH_FILES, math.ceil(left / (_TASKS_PER_CPU * cpus))))
    least = min(_LAST_BATCH_FILES, most)
    batches: List[List[str]] = []
    current: List[str] = []
    current_bytes = 0
    per_task = 0
    for relative in inputs:
        size = sizes.get(relative) or 0
        if size >= _ALONE_BYTES:
            batches.append([relative])
            continue
        if current and (len(current) >= per_task or current_bytes + size > _BATCH_BYTES):
            batches.append(current)
            current, current_bytes = [], 0
        if not current:
            # One CPU has no end to balance: its tasks stay the first one's size.
            share = most if cpus == 1 else math.ceil(left / (_SHARES_PER_CPU * cpus))
            per_task = max(least, min(most, share))
        current.append(relative)
        current_bytes += size
        left -= 1
    if current:
        batches.append(current)
    return batches


class _Tasks:
    """The Ray tasks of a run and what comes back from them, file by file.

    A task of one file is retried once by Ray when its worker dies. A task of several files
    is not: when its worker dies, each of its files is run again alone, once, and so is a
    file whose ``seamlit`` process died inside it (its row's ``_crashed``). Either way a file
    is tried twice, then reported ``failed``."""

    def __init__(self, kind: str, sizes: Dict[str, int], largest: Optional[float]) -> None:
        import ray

        self.kind, self.sizes, self.largest = kind, sizes, largest
        self.one, self.many = ray.remote(process), ray.remote(process_batch)
        self.pending: Dict[Any, Tuple[List[Job], bool]] = {}

    def submit(self, jobs: List[Job], again: bool) -> None:
        """Starts a task for ``jobs``; ``again``: a second try, not retried."""
        # One file after another in the task: the largest one's memory.
        memory = max(_memory(self.sizes.get(j.relative) or 0) for j in jobs)
        if self.largest:
            memory = min(memory, int(self.largest))
        first = jobs[0].relative
        name = f"seamlit {self.kind} {first}" + (f" (+{len(jobs) - 1} files)" if len(jobs) > 1 else "")
        # Spread over the nodes: with the default (the driver's node first) the tasks of a
        # run went to one node while the other's CPU sat idle (BENCHMARKS.md, seamlit.ray).
        settings: Dict[str, Any] = dict(name=name, memory=memory, num_cpus=1, scheduling_strategy="SPREAD")
        if len(jobs) == 1:
            retries = 0 if again else 1
            ref = self.one.options(**settings, max_retries=retries, retry_exceptions=[Crashed]).remote(jobs[0])
        else:
            ref = self.many.options(**settings, max_retries=0).remote(jobs)
        self.pending[ref] = (jobs, again)

    def rows(self):
        """Yields (job, row) for every file as its task ends, running again what needs it."""
        import ray

        while self.pending:
            done, _ = ray.wait(list(self.pending), num_returns=1, timeout=1.0)
            for ref in done:
                jobs, again = self.pending.pop(ref)
                try:
                    result = ray.get(ref)
                except Exception as e:  # the worker died (twice for a single), or the task broke
                    if len(jobs) > 1:
                        for job in jobs:
                            self.submit([job], again=True)
                        continue
                    row = empty_row(jobs[0])
                    row.update(status="failed", error=f"{jobs[0].relative}: {_death(e)}")
                    yield jobs[0], row
                    continue
                for job, row in zip(jobs, result if len(jobs) > 1 else [result]):
                    if "_crashed" in row:
                        self.submit([job], again=True)
                    else:
                        yield job, row


def _death(error: BaseException) -> str:
    """The reason a task gave no row, on one line."""
    import ray.exceptions as rex

    if isinstance(error, rex.OutOfMemoryError):
        what = "its worker ran out of memory (killed by Ray's memory monitor), twice"
    elif isinstance(error, (rex.WorkerCrashedError, rex.NodeDiedError, rex.LocalRayletDiedError)):
        what = "its worker process died while fixing it (a native crash, the OOM killer or a lost node), twice"
    elif isinstance(error, rex.RayTaskError) and isinstance(error.cause, Crashed):
        return f"{error.cause} (tried twice)".split(": ", 1)[-1]
    elif isinstance(error, rex.RayTaskError):
        what = f"internal error in seamlit.ray: {error.cause!r}"
    else:
        what = f"{type(error).__name__}"
    first = str(error).strip().splitlines()
    detail = first[0] if first else ""
    return f"{what} ({detail})" if detail and detail not in what else what


class _Progress:
    """Ray-style progress on stderr: a tqdm bar on a terminal, a line every few seconds
    otherwise."""

    def __init__(self, total: int, kind: str, enabled: bool) -> None:
        self.total, self.done, self.enabled = total, 0, enabled
        self.counts: Dict[str, int] = {}
        self.last = time.monotonic()
        self.bar = None
        if enabled and sys.stderr.isatty():
            try:
                from tqdm import tqdm

                self.bar = tqdm(total=total, desc=f"seamlit {kind}", unit="file", file=sys.stderr)
            except ImportError:
                self.bar = None

    def advance(self, row: Row) -> None:
        self.done += 1
        status = "skipped" if row.get("skipped") else row["status"]
        self.counts[status] = self.counts.get(status, 0) + 1
        if not self.enabled:
            return
        if self.bar is not None:
            self.bar.update(1)
            self.bar.set_postfix(self.counts, refresh=False)
        elif time.monotonic() - self.last > 5 or self.done == self.total:
            self.last = time.monotonic()
            counts = ", ".join(f"{n} {s}" for s, n in sorted(self.counts.items()))
            print(f"seamlit.ray: {self.done}/{self.total} files ({counts})", file=sys.stderr, flush=True)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def fix(
    src: str,
    dst: str,
    *,
    address: Optional[str] = None,
    output_format: str = "glb",
    recurse: bool = True,
    pictures: int = 24,
    engine: str = "auto",
    progress: bool = True,
    **options: Any,
) -> Summary:
    """Fixes every model under ``src`` into ``dst`` on a Ray cluster, as ``seamlit fix SRC
    -o DST`` does on one machine, and writes ``dst/_seamlit/report.parquet`` and
    ``dst/_seamlit/summary.html``.

    ``address``: the cluster (as ``ray.init`` takes it; ``None``: ``RAY_ADDRESS`` or a
    local one). ``output_format`` (``--format``): ``glb``, ``gltf`` or ``obj``;
    ``recurse=False`` is ``--no-recurse``. ``options``: those of ``seamlit fix``
    (``mode``, ``crease``, ``weld_tolerance``, ``weighting``, ``tangents``, ``normals``,
    ``tessellation``, ``asset_roots``, ``keep_compression``, ``skin_seams``, ``samples``).
    ``pictures``: how many of the files that changed most get before/after pictures in the
    summary. ``engine``: ``auto`` (the ``seamlit`` command line when the workers have it,
    ``SEAMLIT_BIN`` or on ``PATH``, else the package's own fix), ``cli`` or ``package``.

    Raises ``ValueError`` (one line) when there is nothing to do: no model files, options
    ``seamlit fix`` refuses.
    """
    report = _files.Place(dst).uri.rstrip("/") + f"/{_files.AUDIT_FOLDER}/report.parquet"
    return _run(
        "fix",
        src,
        dst,
        report,
        address=address,
        output_format=output_format,
        recurse=recurse,
        pictures=pictures,
        engine=engine,
        progress=progress,
        options=options,
    )


def inspect(
    src: str,
    report: str,
    *,
    address: Optional[str] = None,
    recurse: bool = True,
    progress: bool = True,
    **options: Any,
) -> Summary:
    """Measures every model under ``src`` (the seams as loaded and after a fix) without
    writing any model, into the parquet file ``report`` (same columns as :func:`fix`'s;
    ``status`` says what a fix would do, the output columns are empty)."""
    return _run(
        "inspect",
        src,
        None,
        report,
        address=address,
        output_format="glb",
        recurse=recurse,
        pictures=0,
        engine="package",
        progress=progress,
        options=options,
    )
