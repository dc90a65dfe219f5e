"""Fixtures of the megavox Python tests: every device found, small meshes, the CLI and the C API.

Run as: PYTHONPATH=<build>/python MEGAVOX_CLI=<build>/megavox MEGAVOX_LIBRARY=<build>/libmegavox.so \
        python3 -m pytest tests/python -q
"""
import os
import subprocess
import sys

import numpy as np
import pytest

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import megavox  # noqa: E402  (the module under test: its absence is a failure, not a skip)

import helpers_capi  # noqa: E402
import helpers_files  # noqa: E402
import helpers_geometry  # noqa: E402

RESOLUTION = 128

_SELECTORS = None


def device_selectors():
    """The selector of every device megavox.devices() finds ("ocl:0", "vk:0", ...), asked once."""
    global _SELECTORS
    if _SELECTORS is None:
        _SELECTORS = [d["selector"] for d in megavox.devices()]
    return _SELECTORS


def pytest_generate_tests(metafunc):
    # "selector": the test runs on every device found.
    if "selector" in metafunc.fixturenames:
        metafunc.parametrize("selector", device_selectors())


@pytest.fixture(scope="session")
def selectors():
    """Every device selector megavox.devices() lists."""
    return list(device_selectors())


_DEVICES = {}


@pytest.fixture
def device(selector):
    """A megavox.Device on the selector, shared by the session's tests (a test that releases devices makes its own)."""
    if selector not in _DEVICES:
        _DEVICES[selector] = megavox.Device(selector)
    return _DEVICES[selector]


@pytest.fixture(scope="session")
def cli_path():
    path = os.environ.get("MEGAVOX_CLI")
    if not path or not os.path.isfile(path):
        pytest.skip("MEGAVOX_CLI does not name the megavox CLI binary")
    return path


@pytest.fixture
def cli(cli_path):
    """cli(*args, device=SEL): runs `megavox [--device SEL] args...`, failing the test on a non-zero exit."""

    def run(*args, device=None, check=True):
        cmd = [cli_path] + (["--device", device] if device else []) + [str(a) for a in args]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
        if check and proc.returncode != 0:
            pytest.fail("%s exited %d:\n%s%s" % (" ".join(cmd), proc.returncode, proc.stdout, proc.stderr))
        return proc

    return run


@pytest.fixture
def capi(selector):
    """The C API (libmegavox.so at $MEGAVOX_LIBRARY through ctypes) on the same device."""
    path = helpers_capi.library_path()
    if not path or not os.path.isfile(path):
        pytest.skip("MEGAVOX_LIBRARY does not name libmegavox.so")
    api = helpers_capi.CApi(path, selector)
    yield api
    api.close()


@pytest.fixture(scope="session")
def cube():
    """The cube [-1, 1]^3: 8 vertices, 12 triangles."""
    return helpers_geometry.cube_mesh()


@pytest.fixture(scope="session")
def sphere():
    """An ellipsoid off the origin: an icosphere of 1280 triangles scaled (1, 0.8, 0.6) and moved."""
    v, t = helpers_geometry.icosphere(3)
    v = (v * np.array([1.0, 0.8, 0.6], np.float32) + np.array([0.3, -0.2, 0.1], np.float32)).astype(np.float32)
    return v, t


@pytest.fixture(scope="session")
def big_sphere():
    """A unit icosphere of 5120 triangles (2562 vertices)."""
    return helpers_geometry.icosphere(4)


@pytest.fixture
def write_mesh(tmp_path):
    """write_mesh(vertices, triangles, colours=None, name="mesh.ply") -> the path of a binary PLY."""

    def write(vertices, triangles, colours=None, name="mesh.ply"):
        path = tmp_path / name
        helpers_files.write_ply_mesh(path, vertices, triangles, colours)
        return path

    return write
