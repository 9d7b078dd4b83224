"""seamlit: normals and tangents that agree across the objects of a model.

Artists deliver one surface as several objects (a head and a body, the 32 patches of a
teapot). Each object carries its own copy of the vertices along the shared boundary, so
normals computed object by object show a line where the objects meet under per-pixel
lighting. seamlit smooths across all objects of the model, re-orthogonalises the tangent
frame and keeps its handedness, so the seam is gone.

Three calls, the same steps as the ``seamlit`` command line:

- :func:`fix_file` -- ``seamlit fix INPUT -o OUTPUT``: a model file in, a fixed file out
  (glTF and GLB keep everything seamlit does not own);
- :func:`inspect` -- ``seamlit inspect``: the seam report, as loaded and after a fix;
- :func:`fix` -- the fix on NumPy arrays, for meshes you hold in memory;
- :func:`fix_bytes` -- :func:`fix_file` for a self-contained model file held in memory (GLB,
  VRM, USDZ, FBX), as ``seamlit fix DIR -o DIR`` writes it (GLB; a VRM stays a VRM).

On a Ray cluster, over folders or object stores: :mod:`seamlit.ray` (``pip install
'seamlit[ray]'``).

Options mirror the command line's flags (``--mode``, ``--crease``, ``--weld-tolerance``,
``--weighting``, ``--tangents``, ``--normals``); see ``seamlit fix --help``. Errors are
:class:`SeamlitError` (a ``ValueError``) with the command line's one-line message, naming
the file and the place, or ``FileNotFoundError`` for a missing file.

For trimesh users, :func:`seamlit.trimesh.fix_scene` fixes a ``trimesh.Scene`` in place.
"""

from __future__ import annotations

import json
import os
from inspect import signature as _signature
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _seamlit
from ._seamlit import SeamlitError, __version__

__all__ = ["SeamlitError", "__version__", "fix", "fix_bytes", "fix_file", "inspect"]

PathLike = Union[str, "os.PathLike[str]"]

_MODES = ("flat", "object", "model")
_WEIGHTINGS = ("angle", "area", "angle-area", "uniform")
_TANGENTS = ("seamlit", "mikktspace", "none")
_NORMALS = ("auto", "smooth-shared", "keep", "recompute")


def _choice(name: str, value: Optional[str], allowed: Sequence[str]) -> Optional[str]:
    if value is None:
        return None
    if value not in allowed:
        raise SeamlitError(f"{name}={value!r}: expected one of {', '.join(allowed)}")
    return value


def _settings(
    mode: str,
    crease: Optional[float],
    weld_tolerance: Union[str, float, None],
    weighting: Optional[str],
    tangents: Optional[str],
    normals: Optional[str],
    **more: Any,
) -> str:
    """What the native module takes (JSON): the fix options by their Rust names, the
    tolerance in the command line's spelling, and the other flags."""
    options: Dict[str, Any] = {"mode": _choice("mode", mode, _MODES)}
    if crease is not None:
        crease = float(crease)
        if not 0.0 <= crease <= 180.0:
            raise SeamlitError(f"crease={crease}: expected an angle between 0 and 180 degrees")
        options["crease_angle_deg"] = crease
    if weighting is not None:
        options["weighting"] = _choice("weighting", weighting, _WEIGHTINGS)
    if tangents is not None:
        options["tangents"] = _choice("tangents", tangents, _TANGENTS)
    if normals is not None:
        options["normals"] = _choice("normals", normals, _NORMALS)
    settings: Dict[str, Any] = {"fix": options, "tangents_asked": tangents is not None}
    if weld_tolerance is not None:
        settings["weld_tolerance"] = str(weld_tolerance)
    settings.update(more)
    return json.dumps(settings)


def fix_file(
    input: PathLike,
    output: PathLike,
    *,
    mode: str = "model",
    crease: Optional[float] = None,
    weld_tolerance: Union[str, float, None] = None,
    weighting: Optional[str] = None,
    tangents: Optional[str] = None,
    normals: Optional[str] = None,
    tessellation: int = 16,
    overwrite_input: bool = False,
    keep_compression: bool = False,
    asset_roots: Sequence[PathLike] = (),
    skin_seams: str = "match",
    samples: int = 30,
) -> Dict[str, Any]:
    """Fix a model file and write the result, as ``seamlit fix INPUT -o OUTPUT`` does: the
    same steps in the same library call, so the same bytes for the same options.

    The output format follows ``output``'s extension (``.glb``, ``.gltf``, ``.obj``, ``.vrm``,
    ``.usda``, ``.usdz``). A glTF or GLB input written as glTF or GLB is the input document
    with only normals, tangents, split vertices, indices (and matched skin weights) changed.
    Meshopt-compressed geometry is written uncompressed unless ``keep_compression`` is set
    (``--keep-compression``); a Draco input or an OBJ output with ``keep_compression`` raises
    ``SeamlitError``. ``asset_roots`` (``--asset-root``): confines a USD stage's layers and
    textures to the input's folder and these (the strict mode; by default they are read
    wherever USD resolves them). ``skin_seams`` (``--skin-seams``):
    ``"match"`` gives the copies of a shared position one set of skin weights, so the seam
    stays closed when posed; ``"keep"`` leaves the weights as authored. ``samples``
    (``--samples``): times of each animation the seams in motion are measured at.

    Returns a dict: ``input``, ``output``, ``options`` (as used), ``as_loaded`` and ``fixed``
    (the seam reports before and after; ``report`` is ``fixed`` under its earlier name),
    ``changes`` (per object: normals kept or computed, vertices changed and split),
    ``skin_seams_matched``, ``motion`` (per animation, before and after), ``morph_seams``,
    ``summary`` (the lines ``seamlit fix`` prints) and ``warnings``.
    """
    return _fix_measured(
        input,
        output,
        mode=mode,
        crease=crease,
        weld_tolerance=weld_tolerance,
        weighting=weighting,
        tangents=tangents,
        normals=normals,
        tessellation=tessellation,
        overwrite_input=overwrite_input,
        keep_compression=keep_compression,
        asset_roots=asset_roots,
        skin_seams=skin_seams,
        samples=samples,
    )


#: :func:`fix_file`'s parameters, read once (the fleet checks every file's options with them).
_FIX_FILE = _signature(fix_file)


def _file_settings(**options: Any) -> str:
    """The settings of :func:`fix_file`'s options (its defaults for those not given), checked;
    an option it does not know raises ``SeamlitError``. Kept per set of options: a fleet's
    task asks for the same ones for every file."""
    key = repr(sorted(options.items()))
    settings = _SETTINGS.get(key)
    if settings is None:
        settings = _file_settings_checked(options)
        if len(_SETTINGS) < 64:
            _SETTINGS[key] = settings
    return settings


_SETTINGS: Dict[str, str] = {}


def _file_settings_checked(options: Dict[str, Any]) -> str:
    try:
        bound = _FIX_FILE.bind("", "", **options)
    except TypeError:
        known = set(_FIX_FILE.parameters) - {"input", "output"}
        unknown = sorted(set(options) - known)
        raise SeamlitError(f"{', '.join(unknown)}: not an option of seamlit fix") from None
    bound.apply_defaults()
    o = bound.arguments
    if o["skin_seams"] not in ("match", "keep"):
        raise SeamlitError(f"skin_seams={o['skin_seams']!r}: expected match or keep")
    if not 2 <= int(o["samples"]) <= 100_000:
        raise SeamlitError(f"samples={o['samples']!r}: expected 2 to 100000")
    return _settings(
        o["mode"],
        o["crease"],
        o["weld_tolerance"],
        o["weighting"],
        o["tangents"],
        o["normals"],
        tessellation=int(o["tessellation"]),
        overwrite_input=bool(o["overwrite_input"]),
        keep_compression=bool(o["keep_compression"]),
        asset_roots=[os.fspath(r) for r in o["asset_roots"]],
        match_skin_seams=o["skin_seams"] == "match",
        samples=int(o["samples"]),
    )


def _fix_bytes_measured(
    data: bytes, name: str, out_name: str, companions: Optional[Dict[str, bytes]] = None, **options: Any
) -> Tuple[bytes, Dict[str, Any]]:
    """:func:`fix_bytes` with the options as :mod:`seamlit.ray` holds them (any of
    :func:`fix_file`'s), written as ``out_name`` (``.glb`` or ``.vrm``); ``companions``: the
    files of a model of several (path beside ``name``'s -> bytes), read from memory too."""
    files = list((companions or {}).items())
    output, text = _seamlit.fix_model_bytes(bytes(data), name, out_name, _file_settings(**options), files)
    result = json.loads(text)
    result["report"] = result["fixed"]
    return output, result


def _fix_measured(input: PathLike, output: PathLike, **options: Any) -> Dict[str, Any]:
    """:func:`fix_file` with the options as :mod:`seamlit.ray` holds them (a dict of
    ``seamlit fix``'s options); an option it does not know raises ``SeamlitError``."""
    settings = _file_settings(**options)
    result = json.loads(_seamlit.fix_file(os.fspath(input), os.fspath(output), settings))
    result["report"] = result["fixed"]
    return result


def _fix_file_row(
    input: PathLike, output: PathLike, digests: Any = None, keys: Tuple[int, int] = (0, 0), **options: Any
) -> Dict[str, Any]:
    """:mod:`seamlit.ray`'s fix of a local file into a local ``.glb`` or ``.vrm`` (the bytes
    :func:`fix_file` writes) in one native call: the report row's columns (``input_sha256``,
    ``output_sha256``, the seam counts and angles, ``warnings``) and ``changed``. With
    ``digests`` (a ``_seamlit.Digests``), the two hashes are ``None`` and the files go to it
    under ``keys`` (input, output), to be hashed with others."""
    settings = _file_settings(**options)
    return json.loads(_seamlit.fix_file_row(os.fspath(input), os.fspath(output), settings, digests, keys))


def _fix_bytes_row(
    data: bytes,
    name: str,
    out_name: str,
    companions: Optional[Dict[str, bytes]] = None,
    digests: Any = None,
    keys: Tuple[int, int] = (0, 0),
    **options: Any,
) -> Tuple[bytes, Dict[str, Any]]:
    """:func:`_fix_bytes_measured` with :func:`_fix_file_row`'s row in place of the report
    (and, as there, its two hashes left to ``digests`` where given)."""
    files = list((companions or {}).items())
    settings = _file_settings(**options)
    output, text = _seamlit.fix_model_bytes(bytes(data), name, out_name, settings, files, True, digests, keys)
    return output, json.loads(text)


#: Extensions of the models :func:`fix_bytes` takes: one file each, nothing beside it.
SELF_CONTAINED = ("glb", "vrm", "usdz", "fbx")


def fix_bytes(
    data: bytes,
    name: str,
    *,
    mode: str = "model",
    crease: Optional[float] = None,
    weld_tolerance: Union[str, float, None] = None,
    weighting: Optional[str] = None,
    tangents: Optional[str] = None,
    normals: Optional[str] = None,
    keep_compression: bool = False,
    skin_seams: str = "match",
) -> Tuple[bytes, Dict[str, Any]]:
    """Fix a self-contained model file held in memory: ``data`` is the file, ``name`` its
    name (the extension says the format: ``.glb``, ``.vrm``, ``.usdz`` or ``.fbx``).

    Returns the output file's bytes, the bytes ``seamlit fix DIR -o DIR`` writes for it with
    the same options (GLB; a VRM avatar stays a VRM; skin weights matched at seams unless
    ``skin_seams="keep"``), and a dict: ``input``, ``output`` (the output's name),
    ``options``, ``as_loaded`` and ``fixed`` (the seam reports before and after),
    ``changes`` and ``warnings``. Raises ``SeamlitError`` naming ``name`` for a model seamlit
    refuses, or for a format that needs files beside it (glTF, OBJ, USD layers: use
    :func:`fix_file` on a folder).

    The file is read, fixed and written in memory, as the one file of a set in memory (the
    readers look for anything it names there: a USDZ's layers and textures are inside it; an
    FBX's external textures are not, and are warned of as missing).
    """
    ext = name.rsplit(".", 1)[-1].lower() if "." in name else ""
    if ext not in SELF_CONTAINED:
        raise SeamlitError(
            f"{name}: fix_bytes takes a model in one file (.glb, .vrm, .usdz, .fbx); "
            "a .gltf, .obj or USD layer needs the files beside it: use fix_file"
        )
    base = os.path.basename(name.replace("\\", "/")) or f"model.{ext}"
    stem = base.rsplit(".", 1)[0] or "model"
    out_name = f"{stem}.{'vrm' if ext == 'vrm' else 'glb'}"
    return _fix_bytes_measured(
        data,
        name,
        out_name,
        mode=mode,
        crease=crease,
        weld_tolerance=weld_tolerance,
        weighting=weighting,
        tangents=tangents,
        normals=normals,
        keep_compression=keep_compression,
        skin_seams=skin_seams,
    )


def inspect(
    path: PathLike,
    *,
    mode: str = "model",
    crease: Optional[float] = None,
    weld_tolerance: Union[str, float, None] = None,
    weighting: Optional[str] = None,
    tangents: Optional[str] = None,
    normals: Optional[str] = None,
    tessellation: int = 16,
    asset_roots: Sequence[PathLike] = (),
) -> Dict[str, Any]:
    """The seam report of a model file, as loaded and after a fix; nothing is written.
    ``asset_roots`` as for :func:`fix_file`.

    Returns a dict: ``file``, ``options``, ``as_loaded`` and ``fixed`` (seam reports: shared
    positions, the largest normal and tangent angles across object boundaries in
    ``cross_object``...), ``changes`` and ``warnings``.
    """
    settings = _settings(
        mode,
        crease,
        weld_tolerance,
        weighting,
        tangents,
        normals,
        tessellation=int(tessellation),
        asset_roots=[os.fspath(r) for r in asset_roots],
    )
    text = _seamlit.inspect(os.fspath(path), settings)
    return json.loads(text)


def _array(value: Any, dtype: type, name: str, index: int) -> Optional[np.ndarray]:
    if value is None:
        return None
    array = np.ascontiguousarray(value, dtype=dtype)
    if array.ndim != 2:
        raise SeamlitError(f"object {index}: {name} must be a 2-D array, not {array.ndim}-D")
    return array


def fix(
    objects: Sequence[Mapping[str, Any]],
    *,
    mode: str = "model",
    crease: Optional[float] = None,
    weld_tolerance: Union[str, float, None] = None,
    weighting: Optional[str] = None,
    tangents: Optional[str] = None,
    normals: Optional[str] = None,
) -> List[Dict[str, Any]]:
    """Fix normals and tangents across several objects held as NumPy arrays.

    Each object is a mapping with ``positions`` (n x 3 float32), ``triangles`` (m x 3
    uint32) and optionally ``uvs`` (n x 2), ``normals`` (n x 3), ``tangents`` (n x 4, w the
    handedness), ``transform`` (4 x 4, row-major, translation in the last column: the
    object's placement in the model) and ``name``. Arrays of other dtypes are converted;
    contiguous arrays of the right dtype are read without a copy.

    The objects are fixed together, so the normals agree where they meet. Returns, per
    object, a dict: ``normals`` (n' x 3), ``tangents`` (n' x 4, or ``None`` without UVs),
    ``remap`` (n': the input vertex each output vertex copies; ``n' > n`` where a vertex
    needed two frames and was split) and ``triangles`` (m x 3, indexing the output
    vertices). The GIL is released while the fix runs.

    Without ``normals``, an object's normals are computed; with them, ``normals="auto"``
    (the default) keeps them and repairs only the seams that smoothing each object alone
    made: where objects meet, copies that carry their own face's normal (authored hard
    edges) or custom normals stay as they are. ``normals="smooth-shared"`` averages every
    shared position within the crease instead.
    """
    settings = _settings(mode, crease, weld_tolerance, weighting, tangents, normals)
    arrays = []
    for i, o in enumerate(objects):
        if "positions" not in o or "triangles" not in o:
            raise SeamlitError(f"object {i}: needs 'positions' and 'triangles'")
        arrays.append(
            (
                str(o.get("name", f"object{i}")),
                _array(o["positions"], np.float32, "positions", i),
                _array(o["triangles"], np.uint32, "triangles", i),
                _array(o.get("uvs"), np.float32, "uvs", i),
                _array(o.get("normals"), np.float32, "normals", i),
                _array(o.get("tangents"), np.float32, "tangents", i),
                _array(o.get("transform"), np.float32, "transform", i),
            )
        )
    fixed = _seamlit.fix(arrays, settings)
    return [
        {"normals": n, "tangents": t, "remap": r, "triangles": tri} for (n, t, r, tri) in fixed
    ]
