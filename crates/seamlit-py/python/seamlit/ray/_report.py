"""The run's audit: ``report.parquet`` (one row per input file) and ``summary.html`` (the
counts, a histogram of the largest seam before and after, and pictures of the files that
changed most), both written under their names only when complete."""

from __future__ import annotations

import base64
import html
import os
import shutil
import subprocess
import tempfile
import uuid
from typing import Dict, List, Optional, Sequence

import pyarrow as pa
import pyarrow.parquet as pq
from pyarrow import fs as pafs

from . import _files
from ._task import Row, seamlit_binary

#: The report's columns, in order (docs/fleet.md describes each).
SCHEMA = pa.schema(
    [
        ("path", pa.string()),
        ("status", pa.string()),
        ("error", pa.string()),
        ("objects", pa.int64()),
        ("triangles", pa.int64()),
        ("shared_positions", pa.int64()),
        ("seams_repaired", pa.int64()),
        ("kept_hard_edges", pa.int64()),
        ("kept_custom", pa.int64()),
        ("largest_seam_before_deg", pa.float64()),
        ("largest_seam_after_deg", pa.float64()),
        ("warnings", pa.list_(pa.string())),
        ("seconds", pa.float64()),
        ("output_path", pa.string()),
        ("output_sha256", pa.string()),
        ("input_sha256", pa.string()),
        ("companions_sha256", pa.string()),
        ("options", pa.string()),
        ("skipped", pa.bool_()),
        ("memory_bytes", pa.int64()),
    ]
)


def _put(uri: str, data: bytes) -> None:
    """Writes ``data`` to ``uri`` so that the name holds either the old or the new whole
    file: a temporary name then a rename locally, one upload on an object store."""
    filesystem, path = _files.resolve(uri)
    if isinstance(filesystem, pafs.LocalFileSystem):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        partial = f"{path}.{uuid.uuid4().hex[:8]}.partial"
        with open(partial, "wb") as f:
            f.write(data)
        os.replace(partial, path)
    else:
        with filesystem.open_output_stream(path) as out:
            out.write(data)


def write(uri: str, rows: Sequence[Row]) -> None:
    """Writes the report (parquet) to ``uri``."""
    columns = {name: [row.get(name) for row in rows] for name in SCHEMA.names}
    table = pa.table(columns, schema=SCHEMA)
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink)
    _put(uri, sink.getvalue().to_pybytes())


def read_previous(uri: str) -> Dict[str, Row]:
    """The rows of an earlier run's report at ``uri`` by path; empty when there is none."""
    filesystem, path = _files.resolve(uri)
    try:
        with filesystem.open_input_file(path) as f:
            table = pq.read_table(f)
    except (FileNotFoundError, OSError, pa.ArrowInvalid):
        return {}
    return {row["path"]: row for row in table.to_pylist()}


def _histogram(rows: Sequence[Row]) -> str:
    """An SVG histogram of the largest seam (degrees) before and after, 5-degree bins."""
    bins = 18
    before = [0] * bins
    after = [0] * bins
    for row in rows:
        for value, counts in ((row.get("largest_seam_before_deg"), before), (row.get("largest_seam_after_deg"), after)):
            if value is not None:
                counts[min(int(value // 5), bins - 1)] += 1
    top = max(before + after + [1])
    width, height, bar = 720, 220, 720 / bins
    parts = [f'<svg width="{width}" height="{height + 40}" role="img" aria-label="histogram">']
    for i in range(bins):
        for j, (counts, colour) in enumerate(((before, "#d9534f"), (after, "#2a7ab0"))):
            h = counts[i] / top * height
            x = i * bar + j * bar / 2 + 2
            parts.append(
                f'<rect x="{x:.1f}" y="{height - h:.1f}" width="{bar / 2 - 3:.1f}" height="{h:.1f}" '
                f'fill="{colour}"><title>{i * 5}-{i * 5 + 5}°: {counts[i]}</title></rect>'
            )
        parts.append(f'<text x="{i * bar + 2:.1f}" y="{height + 15}" font-size="10">{i * 5}°</text>')
    parts.append(
        f'<text x="0" y="{height + 35}" font-size="12"><tspan fill="#d9534f">■ before</tspan> '
        f'<tspan fill="#2a7ab0">■ after</tspan> (files per 5° of largest normal angle across a seam; last bin: 85° and more)</text>'
    )
    parts.append("</svg>")
    return "".join(parts)


def _render(binary: str, model: str, png: str, keep: bool, mode: Optional[str]) -> Optional[str]:
    """Renders ``model`` with ``seamlit render``; the error line when it cannot."""
    command = [binary, "render", model, "-o", png, "--size", "320x240"]
    if keep:
        command += ["--normals", "keep"]
    if mode:
        command += ["--mode", mode]
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=120)
    except subprocess.TimeoutExpired:
        return "rendering took over 2 minutes"
    if done.returncode != 0 or not os.path.isfile(png):
        lines = [l for l in done.stderr.splitlines() if l.strip()]
        return lines[-1] if lines else f"seamlit render exited with {done.returncode}"
    return None


def _stage(uri_root: str, relative: str, into: str, follow: bool) -> str:
    """A local copy of ``relative`` under ``uri_root`` (with what travels with it), or the
    file itself when the root is a local folder."""
    from ._task import _gather, _read

    filesystem, root = _files.resolve(uri_root)
    if isinstance(filesystem, pafs.LocalFileSystem):
        return root + "/" + relative
    data = _read(filesystem, root + "/" + relative)
    files = {relative: data}
    if follow:
        files.update(_gather(filesystem, root, relative, data))
    for name, body in files.items():
        path = os.path.join(into, *name.split("/"))
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(body)
    return os.path.join(into, *relative.split("/"))


def _picture(path: str) -> str:
    with open(path, "rb") as f:
        return "data:image/png;base64," + base64.b64encode(f.read()).decode()


def summary_html(src: str, dst: str, rows: Sequence[Row], *, pictures: int, seconds: float) -> None:
    """Writes ``dst/_seamlit/summary.html``."""
    counts: Dict[str, int] = {}
    for row in rows:
        key = "skipped" if row.get("skipped") else row["status"]
        counts[key] = counts.get(key, 0) + 1
    changed = [
        r
        for r in rows
        if r["status"] == "fixed" and r.get("largest_seam_before_deg") is not None
    ]
    changed.sort(key=lambda r: -((r["largest_seam_before_deg"] or 0) - (r["largest_seam_after_deg"] or 0)))
    shown = changed[: max(pictures, 0)]
    binary = seamlit_binary()
    cards: List[str] = []
    scratch = tempfile.mkdtemp(prefix="seamlit-summary-")
    try:
        for i, row in enumerate(shown):
            images = []
            for side, (root, relative, keep, mode) in (
                ("before", (src, row["path"], True, "object")),
                ("after", (dst, row["output_path"], True, None)),
            ):
                if binary is None:
                    images.append("<p>no picture: the seamlit command line is not installed here</p>")
                    continue
                try:
                    local = _stage(root, relative, os.path.join(scratch, f"{i}-{side}"), True)
                except OSError as e:
                    images.append(f"<p>no picture: {html.escape(str(e))}</p>")
                    continue
                png = os.path.join(scratch, f"{i}-{side}.png")
                problem = _render(binary, local, png, keep, mode)
                if problem:
                    images.append(f"<p>no picture: {html.escape(problem)}</p>")
                else:
                    images.append(f'<figure><img src="{_picture(png)}" alt="{side}"><figcaption>{side}</figcaption></figure>')
            before = row["largest_seam_before_deg"]
            after = row["largest_seam_after_deg"]
            cards.append(
                f"<section><h3>{html.escape(row['path'])}</h3><p>largest seam {before:.2f}° → "
                f"{(after or 0):.2f}°; {row['seams_repaired']} seams repaired, {row['objects']} objects, "
                f"{row['triangles']} triangles</p><div class=pair>{''.join(images)}</div></section>"
            )
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    problems = [r for r in rows if r["status"] in ("refused", "failed")]
    listing = "".join(
        f"<li><b>{html.escape(r['status'])}</b> {html.escape(r['error'] or '')}</li>" for r in problems
    )
    order = ("fixed", "unchanged", "refused", "failed", "skipped")
    table = "".join(f"<tr><th>{s}</th><td>{counts.get(s, 0)}</td></tr>" for s in order)
    page = f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>seamlit run: {html.escape(src)}</title>
<style>body{{font-family:sans-serif;max-width:1100px;margin:2em auto}} .pair{{display:flex;gap:1em}}
figure{{margin:0}} table{{border-collapse:collapse}} th,td{{padding:2px 12px;text-align:left}}</style></head>
<body><h1>seamlit fix</h1>
<p>{html.escape(src)} → {html.escape(dst)}: {len(rows)} files in {seconds:.1f} s. Every file's row is in
<code>report.parquet</code> beside this page.</p>
<table>{table}</table>
<h2>Largest seam per file, before and after</h2>{_histogram([r for r in rows if r['status'] in ('fixed', 'unchanged')])}
<h2>Refused and failed</h2><ul>{listing or '<li>none</li>'}</ul>
<h2>The {len(shown)} files that changed most</h2>
<p>Before: the input as loaded (authored normals, objects smoothed one by one where they have none); after: the output.</p>
{''.join(cards)}
</body></html>
"""
    _put(dst.rstrip("/") + f"/{_files.AUDIT_FOLDER}/summary.html", page.encode())
