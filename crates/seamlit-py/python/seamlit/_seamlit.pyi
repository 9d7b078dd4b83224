"""Type stubs for the native module (crates/seamlit-py/src/lib.rs). Call the functions of
the ``seamlit`` package instead: they check and convert their arguments."""

from typing import List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

class SeamlitError(ValueError):
    """A model seamlit cannot read or fix, or options it does not accept."""

def fix_file(input: str, output: str, settings: str) -> str: ...
def fix_model_bytes(
    data: bytes,
    name: str,
    output: str,
    settings: str,
    companions: Sequence[Tuple[str, bytes]] = ...,
    row: bool = ...,
    digests: Optional["Digests"] = None,
    keys: Tuple[int, int] = ...,
) -> Tuple[bytes, str]: ...
def fix_file_row(
    input: str,
    output: str,
    settings: str,
    digests: Optional["Digests"] = None,
    keys: Tuple[int, int] = ...,
) -> str: ...

class Digests:
    """Files and bytes to SHA-256 together (``seamlit.ray``'s task): each under a key."""

    def __init__(self) -> None: ...
    def add_file(self, key: int, path: str) -> None: ...
    def add_bytes(self, key: int, data: bytes) -> None: ...
    def held(self) -> int: ...
    def __len__(self) -> int: ...
    def take(self) -> List[Tuple[int, Optional[str]]]: ...

def inspect(path: str, settings: str) -> str: ...
def fix(
    objects: Sequence[
        Tuple[
            str,
            npt.NDArray[np.float32],
            npt.NDArray[np.uint32],
            Optional[npt.NDArray[np.float32]],
            Optional[npt.NDArray[np.float32]],
            Optional[npt.NDArray[np.float32]],
            Optional[npt.NDArray[np.float32]],
        ]
    ],
    settings: str,
) -> List[
    Tuple[
        npt.NDArray[np.float32],
        Optional[npt.NDArray[np.float32]],
        npt.NDArray[np.uint32],
        npt.NDArray[np.uint32],
    ]
]: ...
