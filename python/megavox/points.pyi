import os
from typing import Any, Callable, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import Device

def build(source: Union[str, bytes, os.PathLike, npt.NDArray[np.floating]], out: Union[str, bytes, os.PathLike], *,
          format: str = "mvx", depth: int = 0, max_node_points: int = 16384,
          rgb: Optional[npt.NDArray[Union[np.uint8, np.uint16]]] = None,
          intensity: Optional[npt.NDArray[np.uint16]] = None, classification: Optional[npt.NDArray[np.uint8]] = None,
          tiles_version: str = "1.1", crs: Optional[str] = None,
          bounds: Optional[Tuple[float, float, float, float, float, float]] = None, device: Optional[Device] = None, progress: Optional[Callable[[str, float], Optional[bool]]] = None) -> None: ...

class PointHierarchy:
    info: dict[str, Any]
    nodes: np.ndarray
    xyz: npt.NDArray[np.float64]
    rgb: Optional[npt.NDArray[np.uint16]]
    intensity: Optional[npt.NDArray[np.uint16]]
    extra: Optional[npt.NDArray[np.uint8]]
    normal: Optional[npt.NDArray[np.float32]]
    def __len__(self) -> int: ...
    def node_points(self, i: int) -> slice: ...
    def field(self, name: str) -> np.ndarray: ...
    def leaves(self) -> npt.NDArray[np.intp]: ...

def open(path: Union[str, bytes, os.PathLike], device: Optional[Device] = None) -> PointHierarchy: ...
