import os
from typing import Callable, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import Device

Image = npt.NDArray[Union[np.uint8, np.uint16]]

def apply(image: Image, *, rect: Optional[Tuple[int, int, int, int]] = None,
          seeds: Optional[npt.NDArray[np.uint8]] = None, model: Union[None, str, bytes, os.PathLike] = None,
          iterations: int = 5, erode: int = 2, device: Optional[Device] = None,
          progress: Optional[Callable[[str, float], Optional[bool]]] = None) -> npt.NDArray[np.uint8]: ...
def train(images: Sequence[Image], masks: Sequence[npt.NDArray[np.uint8]], out: Union[str, bytes, os.PathLike], *,
          device: Optional[Device] = None) -> None: ...
