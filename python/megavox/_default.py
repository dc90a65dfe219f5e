"""The device the module-level functions use when given none: one Device(), opened on first use."""
import threading

_lock = threading.Lock()
_device = None


def device(given=None):
    """`given` when it is a Device, else the shared default one."""
    global _device
    if given is not None:
        return given
    with _lock:
        if _device is None:
            from ._megavox import Device
            _device = Device()
        return _device
