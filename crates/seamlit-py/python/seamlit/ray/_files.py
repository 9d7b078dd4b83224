"""Which files a run takes and what it names their outputs: the rules of ``seamlit fix DIR
-o DIR`` (crates/seamlit/src/cmd/fix.rs: ``model_files``, ``folder_extension``,
``output_name``), on any filesystem ``pyarrow.fs`` resolves.

Paths here are relative to the run's SRC and DST and use ``/`` whatever the filesystem.
"""

from __future__ import annotations

import os
import posixpath
import re
from dataclasses import dataclass
from typing import Dict, Iterable, List, Optional, Sequence, Set, Tuple

from pyarrow import fs as pafs

#: Extensions seamlit reads (``seamlit_io::Format::of``), lower case.
MODEL_EXTENSIONS = frozenset(
    {"obj", "gltf", "glb", "vrm", "fbx", "usda", "usdc", "usdz", "usd", "bpt", "patch", "patches", "newell"}
)
#: Models that are one file: fixed from memory, nothing travels with them.
SELF_CONTAINED = frozenset({"glb", "vrm", "fbx", "usdz", "bpt", "patch", "patches", "newell", ""})
#: The folder mode's output formats (``--format``).
OUTPUT_FORMATS = ("glb", "gltf", "obj")
#: Where a run keeps its report, under DST; never taken as input.
AUDIT_FOLDER = "_seamlit"


def extension(path: str) -> Optional[str]:
    """The extension as ``Path::extension`` gives it (lower case), or ``None``."""
    name = posixpath.basename(path)
    stem, dot, ext = name.rpartition(".")
    if not dot or not stem:
        return None
    return ext.lower()


def stem(path: str) -> str:
    """``Path::file_stem``: the name without its last extension (a leading dot kept)."""
    name = posixpath.basename(path)
    base, dot, _ = name.rpartition(".")
    return base if dot and base else name


def _newell_head(head: bytes) -> bool:
    """A file without an extension is a Newell patch file when its first token is a count."""
    text = head[:64].decode("utf-8", "replace")
    for token in text.replace(",", " ").split():
        return token.isdigit() and token.isascii()
    return False


#: The AWS variables a filesystem is made from: part of the key of :func:`resolve`'s cache.
_AWS_VARIABLES = (
    "AWS_ENDPOINT_URL_S3",
    "AWS_ENDPOINT_URL",
    "AWS_REGION",
    "AWS_DEFAULT_REGION",
    "AWS_ACCESS_KEY_ID",
    "AWS_SECRET_ACCESS_KEY",
    "AWS_SESSION_TOKEN",
)


def resolve(uri: str) -> Tuple[pafs.FileSystem, str]:
    """The filesystem and path of a folder or object-store URI (``s3://bucket/prefix``, a
    local path...). S3's endpoint and credentials come from the standard AWS environment
    variables (``AWS_ENDPOINT_URL``, ``AWS_ACCESS_KEY_ID``, ``AWS_SECRET_ACCESS_KEY``,
    ``AWS_REGION``). Made once per URI, working folder and those variables in a process (a
    task resolves SRC and DST for every file)."""
    if "://" not in uri:  # a local path: relative to the working folder, no credentials
        key: Tuple[str, str, Tuple[Optional[str], ...]] = (uri, os.getcwd(), ())
    else:
        key = (uri, "", tuple(os.environ.get(v) for v in _AWS_VARIABLES))
    found = _RESOLVED.get(key)
    if found is None:
        found = _RESOLVED[key] = _resolve(uri)
    return found


_RESOLVED: Dict[Tuple[str, str, Tuple[Optional[str], ...]], Tuple[pafs.FileSystem, str]] = {}


def _resolve(uri: str) -> Tuple[pafs.FileSystem, str]:
    if "://" not in uri:
        return pafs.LocalFileSystem(), os.path.abspath(uri)
    if uri.startswith("s3://"):
        endpoint = os.environ.get("AWS_ENDPOINT_URL_S3") or os.environ.get("AWS_ENDPOINT_URL")
        region = os.environ.get("AWS_REGION") or os.environ.get("AWS_DEFAULT_REGION")
        # Delayed open: an object smaller than one part is one PutObject, not a multipart
        # upload (fewer requests; and moto's server answers Arrow 26's
        # CompleteMultipartUpload with a reply Arrow reads as an error).
        kwargs: dict = {"allow_delayed_open": True}
        if endpoint:
            scheme, sep, rest = endpoint.partition("://")
            kwargs["endpoint_override"] = rest.rstrip("/") if sep else endpoint
            kwargs["scheme"] = scheme if sep else "https"
        if region:
            kwargs["region"] = region
        return pafs.S3FileSystem(**kwargs), uri[len("s3://") :].rstrip("/")
    filesystem, path = pafs.FileSystem.from_uri(uri)
    return filesystem, path.rstrip("/")


def _sort_key(relative: str) -> Tuple[str, ...]:
    # Rust sorts paths component by component (`a/b` before `a-b`).
    return tuple(relative.split("/"))


def model_files(
    filesystem: pafs.FileSystem,
    root: str,
    *,
    recurse: bool = True,
    skip: Optional[str] = None,
) -> List[str]:
    """The model files under ``root`` (relative paths, sorted as the command line sorts
    them). Hidden entries are skipped, and so is ``skip`` (the output folder, when it lies
    inside the input) and the run's own ``_seamlit`` folder.

    Raises ``FileNotFoundError`` for a missing ``root``; an empty result is the caller's to
    report.
    """
    info = filesystem.get_file_info(root)
    if info.type == pafs.FileType.NotFound and not isinstance(filesystem, pafs.S3FileSystem):
        raise FileNotFoundError(f"{root}: no such folder")
    selector = pafs.FileSelector(root, recursive=recurse, allow_not_found=True)
    skip_norm = skip.rstrip("/") + "/" if skip else None
    files: List[str] = []
    prefix = root.rstrip("/") + "/"
    for entry in filesystem.get_file_info(selector):
        if entry.type != pafs.FileType.File or not entry.path.startswith(prefix):
            continue
        relative = entry.path[len(prefix) :]
        parts = relative.split("/")
        if any(p.startswith(".") for p in parts):
            continue
        if skip_norm and (entry.path + "/").startswith(skip_norm):
            continue
        if parts[0] == AUDIT_FOLDER:
            continue
        ext = extension(relative)
        if ext is None:
            with filesystem.open_input_stream(entry.path) as stream:
                if not _newell_head(stream.read(64)):
                    continue
        elif ext not in MODEL_EXTENSIONS:
            continue
        files.append(relative)
    files.sort(key=_sort_key)
    return files


def folder_extension(relative: str, output_format: str) -> str:
    """The output's extension: ``output_format``'s, but a VRM avatar written as GLB stays
    ``.vrm``."""
    if extension(relative) == "vrm" and output_format == "glb":
        return "vrm"
    return output_format


def output_names(inputs: Sequence[str], output_format: str) -> Dict[str, str]:
    """Every input's output (relative to DST): ``sub/stem.ext``, or ``sub/stem-srcext.ext``
    when an earlier input of the folder already took that name. ``inputs`` in the order
    :func:`model_files` gives them."""
    used: Set[str] = set()
    names: Dict[str, str] = {}
    for relative in inputs:
        folder = posixpath.dirname(relative)
        ext = folder_extension(relative, output_format)
        path = posixpath.join(folder, f"{stem(relative)}.{ext}")
        if path in used:
            src = extension(relative)
            path = posixpath.join(folder, f"{stem(relative)}{'-' + src if src is not None else ''}.{ext}")
        used.add(path)
        names[relative] = path
    return names


@dataclass(frozen=True)
class Place:
    """A folder on a filesystem: SRC or DST of a run (picklable, sent to the workers)."""

    uri: str

    def open(self) -> Tuple[pafs.FileSystem, str]:
        return resolve(self.uri)

    def join(self, relative: str) -> str:
        return self.open()[1] + "/" + relative


def companions_of(name: str, data: bytes) -> Iterable[str]:
    """Files a multi-file model names (relative to its folder): a glTF's buffers and
    images, an OBJ's MTL libraries, an MTL's textures, a USD layer's layers and textures
    (asset paths, found in text or binary layers by their extensions)."""
    ext = extension(name)
    if ext == "gltf":
        import json

        try:
            document = json.loads(data)
        except ValueError:
            return []
        uris = [b.get("uri") for b in document.get("buffers", []) + document.get("images", [])]
        from urllib.parse import unquote

        return [unquote(u) for u in uris if isinstance(u, str) and not u.startswith("data:")]
    if ext in ("obj", "mtl"):
        found = []
        for line in data.decode("utf-8", "replace").splitlines():
            words = line.strip().split()
            if not words:
                continue
            key = words[0].lower()
            if key == "mtllib" or key.startswith("map_") or key in ("bump", "disp", "decal", "refl", "norm"):
                # mtllib may list several names; a map's name is its last word (options
                # such as -bm 1 come first), or the whole rest of the line when the name
                # has spaces: both are tried, a name that is not there is left out.
                found.extend(words[1:] if key == "mtllib" else words[-1:])
                found.append(line.strip()[len(words[0]) :].strip())
        return found
    if ext in ("usda", "usdc", "usd"):
        names = set()
        for match in _asset_paths(data):
            text = match.decode("utf-8", "replace").replace("\\", "/")
            if "://" in text or text.startswith("/"):
                continue
            names.add(text)
        return sorted(names)
    return []


#: An asset path's extension in a USD layer (its dot, the name, a word boundary).
_ASSET_EXTENSION = re.compile(rb"\.(?:usda|usdc|usdz|usd|png|jpg|jpeg|exr|tif|tiff|hdr|tga|bmp|ktx2)\b")
#: The bytes an asset path is made of.
_PATH_BYTES = frozenset(b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_./\\:-")


def _asset_paths(data: bytes) -> List[bytes]:
    r"""What ``re.findall(rb"[A-Za-z0-9_./\\:-]+\.(?:usda|...|ktx2)\b", data)`` finds: each
    run of path bytes up to its last known extension, with at least one byte before that
    extension's dot. Found from the extensions backwards: the pattern itself backtracks at
    every byte of every number in a text layer (0.95 ms for an 18 KB layer, 0.08 ms so)."""
    found: List[Tuple[int, int]] = []
    for match in _ASSET_EXTENSION.finditer(data):
        dot = start = match.start()
        while start > 0 and data[start - 1] in _PATH_BYTES:
            start -= 1
        if start == dot:
            continue
        if found and found[-1][0] == start:  # a later extension in the same run: the match ends there
            found[-1] = (start, match.end())
        else:
            found.append((start, match.end()))
    return [data[a:b] for a, b in found]
