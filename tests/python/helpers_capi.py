"""The C API through ctypes (libmegavox.so at $MEGAVOX_LIBRARY): the oracle the Python module is checked against."""
import ctypes
import os

import numpy as np

RAY_DTYPE = np.dtype([("org", "<f4", (3,)), ("dir", "<f4", (3,)), ("tmax", "<f4")])  # MvTraceRay, 28 bytes
HIT_BYTES = 32  # MvTraceHit


class MvTraceArguments(ctypes.Structure):
    _fields_ = [("byteSize", ctypes.c_size_t), ("maxSteps", ctypes.c_uint32)]


class MvSceneInfo(ctypes.Structure):
    _fields_ = [
        ("encoding", ctypes.c_char * 16),
        ("resolution", ctypes.c_uint32),
        ("levels", ctypes.c_uint32),
        ("voxels", ctypes.c_uint64),
        ("bytes", ctypes.c_uint64),
        ("origin", ctypes.c_double * 3),
        ("voxelSize", ctypes.c_double),
        ("lower", ctypes.c_double * 3),
        ("upper", ctypes.c_double * 3),
    ]


def library_path():
    return os.environ.get("MEGAVOX_LIBRARY", "")


class CApi:
    """One device of the C API (config "device=SEL"); scenes opened from .mvx files."""

    def __init__(self, path, selector):
        lib = ctypes.CDLL(path)
        lib.mvNewDevice.restype = ctypes.c_void_p
        lib.mvNewDevice.argtypes = [ctypes.c_char_p]
        lib.mvReleaseDevice.argtypes = [ctypes.c_void_p]
        lib.mvGetDeviceError.restype = ctypes.c_int
        lib.mvGetDeviceError.argtypes = [ctypes.c_void_p]
        lib.mvGetDeviceLastErrorMessage.restype = ctypes.c_char_p
        lib.mvGetDeviceLastErrorMessage.argtypes = [ctypes.c_void_p]
        lib.mvOpenScene.restype = ctypes.c_void_p
        lib.mvOpenScene.argtypes = [ctypes.c_void_p, ctypes.c_char_p]
        lib.mvReleaseScene.argtypes = [ctypes.c_void_p]
        lib.mvTraceRays.restype = ctypes.c_int
        lib.mvTraceRays.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t, ctypes.c_void_p]
        lib.mvTraceRaysRgba.restype = ctypes.c_int
        lib.mvTraceRaysRgba.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p,
                                        ctypes.c_size_t, ctypes.c_void_p]
        lib.mvGetSceneInfo.restype = ctypes.c_int
        lib.mvGetSceneInfo.argtypes = [ctypes.c_void_p, ctypes.POINTER(MvSceneInfo)]
        lib.mvGetSceneColourEntries.restype = ctypes.c_int
        lib.mvGetSceneColourEntries.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_uint64)]
        lib.mvGetVersionString.restype = ctypes.c_char_p
        lib.mvInitTraceArguments.argtypes = [ctypes.POINTER(MvTraceArguments)]
        self.lib = lib
        self.device = lib.mvNewDevice(("device=" + selector).encode())
        if not self.device:
            raise RuntimeError("mvNewDevice(device=%s) failed: %s"
                               % (selector, lib.mvGetDeviceLastErrorMessage(None).decode()))

    def _fail(self, what):
        raise RuntimeError("%s failed: %s" % (what, self.lib.mvGetDeviceLastErrorMessage(self.device).decode()))

    def open(self, path):
        scene = self.lib.mvOpenScene(self.device, os.fsencode(path))
        if not scene:
            self._fail("mvOpenScene(%s)" % path)
        return scene

    def release_scene(self, scene):
        self.lib.mvReleaseScene(scene)

    def close(self):
        if self.device:
            self.lib.mvReleaseDevice(self.device)
            self.device = None

    def trace(self, scene, origins, directions, tmax=None, rgba=False, max_steps=None):
        """Raw hit bytes (N * 32), and the rgba bytes (N * 4) when rgba."""
        n = len(origins)
        rays = np.zeros(n, RAY_DTYPE)
        rays["org"] = origins
        rays["dir"] = directions
        rays["tmax"] = np.inf if tmax is None else tmax
        hits = ctypes.create_string_buffer(HIT_BYTES * n)
        args = None
        if max_steps is not None:
            args = MvTraceArguments()
            self.lib.mvInitTraceArguments(ctypes.byref(args))
            args.maxSteps = max_steps
            args = ctypes.byref(args)
        if rgba:
            colours = ctypes.create_string_buffer(4 * n)
            rc = self.lib.mvTraceRaysRgba(scene, rays.ctypes.data, hits, colours, n, args)
        else:
            rc = self.lib.mvTraceRays(scene, rays.ctypes.data, hits, n, args)
        if rc != 0:
            self._fail("mvTraceRays")
        return (hits.raw, colours.raw) if rgba else hits.raw

    def scene_info(self, scene):
        info = MvSceneInfo()
        if self.lib.mvGetSceneInfo(scene, ctypes.byref(info)) != 0:
            self._fail("mvGetSceneInfo")
        return {
            "encoding": info.encoding.decode(),
            "resolution": info.resolution,
            "levels": info.levels,
            "voxels": info.voxels,
            "bytes": info.bytes,
            "origin": tuple(info.origin),
            "voxel_size": info.voxelSize,
            "lower": tuple(info.lower),
            "upper": tuple(info.upper),
        }

    def colour_entries(self, scene):
        n = ctypes.c_uint64()
        if self.lib.mvGetSceneColourEntries(scene, ctypes.byref(n)) != 0:
            self._fail("mvGetSceneColourEntries")
        return n.value

    def version(self):
        return self.lib.mvGetVersionString().decode()
