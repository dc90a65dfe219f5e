"""megavox's exceptions: one class per C API error code (MvError), under megavox.Error."""


class Error(Exception):
    """A megavox call failed. ``code`` is the C API's name of the failure (``"MV_ERROR_INPUT"``, ...)."""

    code = "MV_ERROR_UNKNOWN"

    def __init__(self, message="", code=None):
        super().__init__(message)
        if code is not None:
            self.code = code


class UnknownError(Error):
    """A fault inside megavox, not the caller's."""
    code = "MV_ERROR_UNKNOWN"


class InvalidArgumentError(Error, ValueError):
    """A bad argument: a wrong array shape, dtype or layout, an unknown option or name."""
    code = "MV_ERROR_INVALID_ARGUMENT"


class InvalidOperationError(Error):
    """The call does not apply to this object now."""
    code = "MV_ERROR_INVALID_OPERATION"


class OutOfMemoryError(Error, MemoryError):
    """The device or host memory budget cannot hold the work."""
    code = "MV_ERROR_OUT_OF_MEMORY"


class UnsupportedDeviceError(Error):
    """No device matches the selector."""
    code = "MV_ERROR_UNSUPPORTED_DEVICE"


class CancelledError(Error):
    """A progress callback returned False."""
    code = "MV_ERROR_CANCELLED"


class InputError(Error):
    """The input file or arrays are malformed, or not what the call takes."""
    code = "MV_ERROR_INPUT"


class IoError(Error, OSError):
    """A file or folder cannot be opened, read, written or renamed."""
    code = "MV_ERROR_IO"


class DeviceError(Error):
    """The device or its driver failed."""
    code = "MV_ERROR_DEVICE"


_BY_CODE = {cls.code: cls for cls in (UnknownError, InvalidArgumentError, InvalidOperationError, OutOfMemoryError,
                                      UnsupportedDeviceError, CancelledError, InputError, IoError, DeviceError)}


def error_class(code):
    """The exception class of a C API error name (the compiled core raises through it)."""
    return _BY_CODE.get(code, UnknownError)
