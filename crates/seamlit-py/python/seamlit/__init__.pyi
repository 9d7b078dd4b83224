import os
from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str

PathLike = Union[str, os.PathLike[str]]
Mode = Literal["flat", "object", "model"]
Weighting = Literal["angle", "area", "angle-area", "uniform"]
Tangents = Literal["seamlit", "mikktspace", "none"]
Normals = Literal["auto", "smooth-shared", "keep", "recompute"]

class SeamlitError(ValueError): ...

class Fixed(TypedDict):
    normals: npt.NDArray[np.float32]
    tangents: Optional[npt.NDArray[np.float32]]
    remap: npt.NDArray[np.uint32]
    triangles: npt.NDArray[np.uint32]

def fix_file(
    input: PathLike,
    output: PathLike,
    *,
    mode: Mode = "model",
    crease: Optional[float] = None,
    weld_tolerance: Union[str, float, None] = None,
    weighting: Optional[Weighting] = None,
    tangents: Optional[Tangents] = None,
    normals: Optional[Normals] = None,
    tessellation: int = 16,
    overwrite_input: bool = False,
    keep_compression: bool = False,
    asset_roots: Sequence[PathLike] = (),
    skin_seams: Literal["match", "keep"] = "match",
    samples: int = 30,
) -> Dict[str, Any]: ...
SELF_CONTAINED: Tuple[str, ...]

def fix_bytes(
    data: bytes,
    name: str,
    *,
    mode: Mode = "model",
    crease: Optional[float] = None,
    weld_tolerance: Union[str, float, None] = None,
    weighting: Optional[Weighting] = None,
    tangents: Optional[Tangents] = None,
    normals: Optional[Normals] = None,
    keep_compression: bool = False,
    skin_seams: Literal["match", "keep"] = "match",
) -> Tuple[bytes, Dict[str, Any]]: ...
def inspect(
    path: PathLike,
    *,
    mode: Mode = "model",
    crease: Optional[float] = None,
    weld_tolerance: Union[str, float, None] = None,
    weighting: Optional[Weighting] = None,
    tangents: Optional[Tangents] = None,
    normals: Optional[Normals] = None,
    tessellation: int = 16,
    asset_roots: Sequence[PathLike] = (),
) -> Dict[str, Any]: ...
def fix(
    objects: Sequence[Mapping[str, Any]],
    *,
    mode: Mode = "model",
    crease: Optional[float] = None,
    weld_tolerance: Union[str, float, None] = None,
    weighting: Optional[Weighting] = None,
    tangents: Optional[Tangents] = None,
    normals: Optional[Normals] = None,
) -> List[Fixed]: ...
