"""megavox from Python: voxel DAGs, ray queries, pictures, point hierarchies and masks, numpy in and out.

    import megavox
    dev = megavox.Device()                      # the CLI's default device; megavox.devices() lists them
    scene = dev.build((vertices, triangles), resolution=1024, format="ssvdag")
    hits = scene.trace(origins, directions)     # a structured array of megavox.HIT_DTYPE
    picture = scene.render(640, 480)            # (480, 640, 4) uint8

Every call runs on a device with the GIL released. Errors are megavox.Error subclasses, one per C API code.
See docs/python.md.
"""
from ._errors import (CancelledError, DeviceError, Error, InputError, InvalidArgumentError, InvalidOperationError,
                      IoError, OutOfMemoryError, UnknownError, UnsupportedDeviceError)
from ._megavox import IN_CORE, Device, Scene, __version__, devices, write_image
from ._types import HIT_DTYPE, NODE_DTYPE
from . import mask, points

__all__ = ["Device", "Scene", "devices", "write_image", "IN_CORE", "HIT_DTYPE", "NODE_DTYPE", "points", "mask",
           "Error", "UnknownError", "InvalidArgumentError", "InvalidOperationError", "OutOfMemoryError",
           "UnsupportedDeviceError", "CancelledError", "InputError", "IoError", "DeviceError", "__version__"]
