"""Checks the Python module on a scan: builds it from numpy arrays, traces rays, and compares with the C API and
the CLI on the same file. Prints one JSON object.

    PYTHONPATH=build/python python3 python/examples/scan_check.py MESH.ply --cli build/megavox \
        --library build/libmegavox.so [--resolution 2048] [--rays 100000] [--repeats 3] [--device ocl:0]

- bytes: the .mvx built from the arrays equals the CLI's build of the file (same options);
- hits: 100,000 rays traced through the module equal the C API's (ctypes on libmegavox.so), byte for byte;
- seconds: the module's build stages (from the call to the start of the "write" stage, its "read" stage
  excluded) against the CLI's `--json` seconds without "read" and "write"; best of --repeats each.
"""
import argparse
import ctypes
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import megavox
from ply_arrays import read_ply


class TraceRay(ctypes.Structure):
    _fields_ = [("org", ctypes.c_float * 3), ("dir", ctypes.c_float * 3), ("tmax", ctypes.c_float)]


def capi_hits(library, selector, path, origins, directions):
    """The C API's hits of the rays, as bytes (32 per ray)."""
    lib = ctypes.CDLL(library)
    lib.mvNewDevice.restype = ctypes.c_void_p
    lib.mvOpenScene.restype = ctypes.c_void_p
    lib.mvOpenScene.argtypes = [ctypes.c_void_p, ctypes.c_char_p]
    lib.mvTraceRays.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t, ctypes.c_void_p]
    lib.mvReleaseScene.argtypes = [ctypes.c_void_p]
    lib.mvReleaseDevice.argtypes = [ctypes.c_void_p]
    dev = lib.mvNewDevice(f"device={selector}".encode())
    scene = lib.mvOpenScene(dev, path.encode())
    n = len(origins)
    rays = (TraceRay * n)()
    for i in range(n):
        rays[i].org[:] = origins[i].tolist()
        rays[i].dir[:] = directions[i].tolist()
        rays[i].tmax = float("inf")
    hits = ctypes.create_string_buffer(32 * n)
    code = lib.mvTraceRays(scene, rays, hits, n, None)
    lib.mvReleaseScene(scene)
    lib.mvReleaseDevice(dev)
    if code != 0:
        raise RuntimeError(f"mvTraceRays failed with code {code}")
    return hits.raw


def module_build_seconds(device, arrays, resolution, output):
    """The build's stages from the call to the start of writing, its "read" stage (checking the arrays) excluded."""
    marks = {}
    start = time.perf_counter()

    def progress(stage, fraction):
        marks.setdefault(stage, time.perf_counter() - start)
        if stage != "read":
            marks.setdefault("after read", time.perf_counter() - start)

    device.build(arrays, resolution=resolution, output=output, progress=progress)
    return marks["write"] - marks.get("after read", 0.0)


def cli_build_seconds(cli, selector, mesh, resolution, output):
    out = subprocess.run([cli, "--device", selector, "build", mesh, "--resolution", str(resolution), "-o", output,
                          "--json"], check=True, capture_output=True, text=True).stdout
    seconds = json.loads(out)["seconds"]
    return sum(v for k, v in seconds.items() if k not in ("read", "write"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mesh")
    ap.add_argument("--cli", required=True)
    ap.add_argument("--library", required=True)
    ap.add_argument("--resolution", type=int, default=2048)
    ap.add_argument("--rays", type=int, default=100000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--device", default=None)
    a = ap.parse_args()

    device = megavox.Device(a.device)
    selector = device.info["selector"]
    vertices, triangles = read_ply(a.mesh)
    with tempfile.TemporaryDirectory() as tmp:
        mine, theirs = os.path.join(tmp, "arrays.mvx"), os.path.join(tmp, "cli.mvx")
        module_best = min(module_build_seconds(device, (vertices, triangles), a.resolution, mine)
                          for _ in range(a.repeats))
        cli_best = min(cli_build_seconds(a.cli, selector, a.mesh, a.resolution, theirs) for _ in range(a.repeats))
        same_bytes = open(mine, "rb").read() == open(theirs, "rb").read()

        scene = device.open(mine)
        info = scene.info
        rng = np.random.default_rng(7)
        lo, hi = np.array(info["lower"]), np.array(info["upper"])
        centre, radius = (lo + hi) / 2, np.linalg.norm(hi - lo)
        d = rng.normal(size=(a.rays, 3))
        origins = (centre + radius * d / np.linalg.norm(d, axis=1, keepdims=True)).astype(np.float32)
        targets = lo + (hi - lo) * rng.random((a.rays, 3))
        directions = (targets - origins).astype(np.float32)
        t0 = time.perf_counter()
        hits = scene.trace(origins, directions)
        trace_seconds = time.perf_counter() - t0
        same_hits = hits.tobytes() == capi_hits(a.library, selector, mine, origins, directions)

    report = {"mesh": a.mesh, "device": selector, "vertices": len(vertices), "triangles": len(triangles),
              "resolution": a.resolution, "voxels": info["voxels"], "same_mvx_bytes_as_cli": same_bytes,
              "rays": a.rays, "hits": int(np.isfinite(hits["t"]).sum()), "same_hits_as_c_api": same_hits,
              "trace_seconds": trace_seconds, "module_build_stage_seconds": module_best,
              "cli_build_stage_seconds": cli_best, "ratio_to_cli": module_best / cli_best}
    print(json.dumps(report, indent=2))
    return 0 if same_bytes and same_hits else 1


if __name__ == "__main__":
    sys.exit(main())
