# Typed stubs of megavox (the compiled core megavox._megavox and the pure-Python parts), for editors and type checkers.
import os
from typing import Any, Callable, Optional, Sequence, Tuple, Union, overload, Literal

import numpy as np
import numpy.typing as npt

from . import mask as mask
from . import points as points
from ._errors import (CancelledError as CancelledError, DeviceError as DeviceError, Error as Error,
                      InputError as InputError, InvalidArgumentError as InvalidArgumentError,
                      InvalidOperationError as InvalidOperationError, IoError as IoError,
                      OutOfMemoryError as OutOfMemoryError, UnknownError as UnknownError,
                      UnsupportedDeviceError as UnsupportedDeviceError)

__version__: str
IN_CORE: int
HIT_DTYPE: np.dtype
NODE_DTYPE: np.dtype

PathLike = Union[str, bytes, os.PathLike]
Size = Union[int, str]
Progress = Callable[[str, float], Optional[bool]]
Camera = dict  # {"eye": (x, y, z), "target": (x, y, z), "up": (x, y, z), "fov": degrees}

def devices() -> list[dict[str, Any]]: ...
def write_image(path: PathLike, rgba: npt.NDArray[np.uint8]) -> None: ...

class Scene:
    @property
    def device(self) -> Device: ...
    @property
    def info(self) -> dict[str, Any]: ...
    @property
    def stats(self) -> dict[str, Any]: ...
    @property
    def colour_entries(self) -> int: ...
    def save(self, path: PathLike) -> None: ...
    @overload
    def trace(self, origins: npt.NDArray[np.float32], directions: npt.NDArray[np.float32],
              tmax: Union[None, float, npt.NDArray[np.float32]] = ..., *, max_steps: Optional[int] = ...,
              colours: Literal[False] = ...) -> np.ndarray: ...
    @overload
    def trace(self, origins: npt.NDArray[np.float32], directions: npt.NDArray[np.float32],
              tmax: Union[None, float, npt.NDArray[np.float32]] = ..., *, max_steps: Optional[int] = ...,
              colours: Literal[True]) -> Tuple[np.ndarray, npt.NDArray[np.uint8]]: ...
    def view_camera(self, view: str = "iso", fov: Optional[float] = None) -> Camera: ...
    def render(self, width: int, height: int, *, camera: Optional[Camera] = None, view: str = "iso",
               shading: str = "shaded", lod_pixels: float = 1.0, ao_samples: int = 8) -> npt.NDArray[np.uint8]: ...

MeshArrays = Union[Tuple[npt.NDArray[np.float32], npt.NDArray[Any]],
                   Tuple[npt.NDArray[np.float32], npt.NDArray[Any], Optional[npt.NDArray[np.uint8]]]]

class Device:
    def __init__(self, selector: Optional[str] = None, *, memory: Optional[Size] = None,
                 host_memory: Optional[Size] = None, cache_memory: Optional[Size] = None,
                 kernel_shape: Optional[str] = None) -> None: ...
    @property
    def info(self) -> dict[str, Any]: ...
    def build(self, source: Union[PathLike, MeshArrays], *, resolution: int = 0, format: str = "svdag",
              cube: int = 0, voxelize: str = "conservative", grid_origin: str = "center", grid: Optional[str] = None,
              output: Optional[PathLike] = None, progress: Optional[Progress] = None) -> Scene: ...
    def open(self, path: PathLike) -> Scene: ...
