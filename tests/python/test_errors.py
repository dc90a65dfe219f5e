"""Refused arguments (ValueError naming the argument), lossless conversions accepted, bad files, error classes."""
import numpy as np
import pytest

import megavox
from megavox import mask, points

import helpers_geometry

ERROR_CODES = {
    "UnknownError": "MV_ERROR_UNKNOWN",
    "InvalidArgumentError": "MV_ERROR_INVALID_ARGUMENT",
    "InvalidOperationError": "MV_ERROR_INVALID_OPERATION",
    "OutOfMemoryError": "MV_ERROR_OUT_OF_MEMORY",
    "UnsupportedDeviceError": "MV_ERROR_UNSUPPORTED_DEVICE",
    "CancelledError": "MV_ERROR_CANCELLED",
    "InputError": "MV_ERROR_INPUT",
    "IoError": "MV_ERROR_IO",
    "DeviceError": "MV_ERROR_DEVICE",
}


def read(path):
    with open(path, "rb") as f:
        return f.read()


# ---- the classes ----

def test_exception_hierarchy():
    assert issubclass(megavox.Error, Exception)
    for name in ERROR_CODES:
        cls = getattr(megavox, name)
        assert issubclass(cls, megavox.Error), name
    assert issubclass(megavox.InvalidArgumentError, ValueError)
    assert issubclass(megavox.OutOfMemoryError, MemoryError)
    assert issubclass(megavox.IoError, OSError)
    assert not issubclass(megavox.InputError, megavox.IoError)
    assert not issubclass(megavox.CancelledError, megavox.InvalidArgumentError)


def check_code(error, cls_name):
    assert isinstance(error, getattr(megavox, cls_name))
    assert isinstance(error.code, str)
    assert error.code == ERROR_CODES[cls_name]


# ---- meshes ----

@pytest.fixture
def mesh(sphere):
    return sphere


def test_float64_vertices_refused(device, mesh):
    v, t = mesh
    with pytest.raises(ValueError, match="vertices") as e:
        device.build((v.astype(np.float64), t), resolution=64)
    check_code(e.value, "InvalidArgumentError")


@pytest.mark.parametrize("shape", ["n2", "n4", "flat", "n31"])
def test_vertex_shapes_refused(device, mesh, shape):
    v, t = mesh
    bad = {"n2": v[:, :2], "n4": np.concatenate([v, v[:, :1]], axis=1), "flat": v.reshape(-1),
           "n31": v[:, :, None]}[shape]
    with pytest.raises(ValueError, match="vertices"):
        device.build((np.ascontiguousarray(bad), t), resolution=64)


@pytest.mark.parametrize("kind", ["m2", "flat", "float32", "int64_too_big", "uint64_too_big"])
def test_triangle_arrays_refused(device, mesh, kind):
    v, t = mesh
    if kind == "m2":
        bad = np.ascontiguousarray(t[:, :2])
    elif kind == "flat":
        bad = t.reshape(-1)
    elif kind == "float32":
        bad = t.astype(np.float32)
    else:
        bad = t.astype(np.int64 if kind == "int64_too_big" else np.uint64)
        bad[0, 0] = 2 ** 33
    with pytest.raises(ValueError, match="triangles") as e:
        device.build((v, bad), resolution=64)
    check_code(e.value, "InvalidArgumentError")


def test_out_of_range_index_refused(device, mesh):
    v, t = mesh
    bad = t.copy()
    bad[3, 1] = len(v)
    with pytest.raises(megavox.Error) as e:
        device.build((v, bad), resolution=64)
    assert e.value.code in ("MV_ERROR_INVALID_ARGUMENT", "MV_ERROR_INPUT")


@pytest.mark.parametrize("kind", ["n2", "short", "float", "flat"])
def test_colour_arrays_refused(device, mesh, kind):
    v, t = mesh
    c = helpers_geometry.vertex_colours(v)
    bad = {"n2": np.ascontiguousarray(c[:, :2]), "short": c[:-1], "float": c.astype(np.float32),
           "flat": c.reshape(-1)}[kind]
    with pytest.raises(ValueError, match="colours"):
        device.build((v, t, bad), resolution=64)


def test_non_contiguous_vertices_accepted(device, mesh, tmp_path):
    v, t = mesh
    device.build((v, t), resolution=64, output=str(tmp_path / "plain.mvx"))
    wide = np.zeros((len(v), 5), np.float32)
    wide[:, 1:4] = v
    strided = wide[:, 1:4]
    assert not strided.flags.c_contiguous
    device.build((strided, t), resolution=64, output=str(tmp_path / "strided.mvx"))
    device.build((np.asfortranarray(v), np.asfortranarray(t)), resolution=64, output=str(tmp_path / "fortran.mvx"))
    plain = read(tmp_path / "plain.mvx")
    assert read(tmp_path / "strided.mvx") == plain
    assert read(tmp_path / "fortran.mvx") == plain


@pytest.mark.parametrize("kwargs", [{"format": "bogus"}, {"resolution": 100}, {"voxelize": "thick"},
                                    {"grid_origin": "corner"}])
def test_bad_build_options_refused(device, mesh, kwargs):
    v, t = mesh
    options = dict(resolution=64)
    options.update(kwargs)
    with pytest.raises(megavox.InvalidArgumentError):
        device.build((v, t), **options)


# ---- rays ----

@pytest.fixture
def scene(device, mesh):
    v, t = mesh
    return device.build((v, t), resolution=64)


@pytest.fixture
def rays():
    return helpers_geometry.rays_at((0.3, -0.2, 0.1), 3.0, 100)


def test_float64_origins_refused(scene, rays):
    o, d = rays
    with pytest.raises(ValueError, match="origins") as e:
        scene.trace(o.astype(np.float64), d)
    check_code(e.value, "InvalidArgumentError")
    with pytest.raises(ValueError, match="directions"):
        scene.trace(o, d.astype(np.float64))


def test_ray_shapes_refused(scene, rays):
    o, d = rays
    with pytest.raises(ValueError, match="origins"):
        scene.trace(np.ascontiguousarray(o[:, :2]), d)
    with pytest.raises(ValueError, match="origins"):
        scene.trace(o.reshape(-1), d)
    with pytest.raises(ValueError, match="directions"):
        scene.trace(o, np.ascontiguousarray(d[:, :2]))
    with pytest.raises(ValueError, match="directions"):
        scene.trace(o, d[:-1])
    with pytest.raises(ValueError, match="tmax"):
        scene.trace(o, d, np.ones(len(o) - 1, np.float32))
    with pytest.raises(ValueError, match="tmax"):
        scene.trace(o, d, np.ones((len(o), 1), np.float32))


def test_non_contiguous_rays_accepted(scene, rays):
    o, d = rays
    want = scene.trace(o, d).tobytes()
    packed = np.concatenate([o, d], axis=1)  # (N, 6): two strided views
    assert not packed[:, :3].flags.c_contiguous
    assert scene.trace(packed[:, :3], packed[:, 3:]).tobytes() == want
    assert scene.trace(np.asfortranarray(o), np.asfortranarray(d)).tobytes() == want
    doubled = np.repeat(o, 2, axis=0)[::2]
    assert scene.trace(doubled, d).tobytes() == want
    tmax = np.repeat(np.full(len(o), 2.0, np.float32), 2)[::2]
    assert scene.trace(o, d, tmax).tobytes() == scene.trace(o, d, 2.0).tobytes()


def test_bad_render_options_refused(scene):
    with pytest.raises(megavox.InvalidArgumentError):
        scene.render(32, 32, shading="bogus")
    with pytest.raises(megavox.InvalidArgumentError):
        scene.render(32, 32, view="sideways")


def test_write_image_refuses_wrong_arrays(tmp_path):
    with pytest.raises(ValueError, match="rgba"):
        megavox.write_image(str(tmp_path / "a.png"), np.zeros((8, 8, 2), np.uint8))
    with pytest.raises(ValueError, match="rgba"):
        megavox.write_image(str(tmp_path / "a.png"), np.zeros((8, 8, 4), np.float32))
    with pytest.raises(ValueError, match="rgba"):
        megavox.write_image(str(tmp_path / "a.png"), np.zeros((8, 32), np.uint8))
    assert not (tmp_path / "a.png").exists()


# ---- points ----

def test_point_arrays_refused(device, tmp_path):
    xyz, rgb = helpers_geometry.cloud(100)
    out = str(tmp_path / "p.mvx")
    with pytest.raises(ValueError, match="xyz|source"):
        points.build(np.ascontiguousarray(xyz[:, :2]), out, device=device)
    with pytest.raises(ValueError, match="rgb"):
        points.build(xyz, out, rgb=rgb[:-1], device=device)
    with pytest.raises(ValueError, match="rgb"):
        points.build(xyz, out, rgb=rgb.astype(np.float32), device=device)
    with pytest.raises(ValueError, match="intensity"):
        points.build(xyz, out, intensity=np.zeros(99, np.uint16), device=device)
    with pytest.raises(ValueError, match="classification"):
        points.build(xyz, out, classification=np.zeros((100, 2), np.uint8), device=device)
    with pytest.raises(megavox.InvalidArgumentError):
        points.build(xyz, out, format="las", device=device)
    assert not (tmp_path / "p.mvx").exists()


# ---- files ----

def assert_names(error, path):
    assert str(path) in str(error), "the message %r does not name %s" % (str(error), path)


def test_missing_mesh_file(device, tmp_path):
    path = tmp_path / "missing.ply"
    with pytest.raises((megavox.InputError, megavox.IoError)) as e:
        device.build(str(path), resolution=64)
    assert_names(e.value, path)


def test_damaged_mesh_file(device, tmp_path):
    path = tmp_path / "damaged.ply"
    path.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 99\nproperty float x\nend_header\n\x00")
    with pytest.raises((megavox.InputError, megavox.IoError)) as e:
        device.build(str(path), resolution=64)
    assert_names(e.value, path)


def test_missing_and_damaged_mvx(device, tmp_path):
    missing = tmp_path / "missing.mvx"
    with pytest.raises((megavox.InputError, megavox.IoError)) as e:
        device.open(str(missing))
    assert_names(e.value, missing)
    damaged = tmp_path / "damaged.mvx"
    damaged.write_bytes(b"MVX\x00" + bytes(200))
    with pytest.raises((megavox.InputError, megavox.IoError)) as e:
        device.open(str(damaged))
    assert_names(e.value, damaged)


def test_output_in_a_missing_folder(device, mesh, tmp_path):
    v, t = mesh
    out = tmp_path / "no" / "such" / "folder" / "x.mvx"
    with pytest.raises((megavox.IoError, megavox.InputError)) as e:
        device.build((v, t), resolution=64, output=str(out))
    assert_names(e.value, out.parent)


def test_point_files(device, tmp_path):
    missing = tmp_path / "missing.ply"
    with pytest.raises((megavox.InputError, megavox.IoError)) as e:
        points.build(str(missing), str(tmp_path / "out.mvx"), device=device)
    assert_names(e.value, missing)
    damaged = tmp_path / "damaged.mvx"
    damaged.write_bytes(bytes(100))
    with pytest.raises((megavox.InputError, megavox.IoError)) as e:
        points.open(str(damaged), device=device)
    assert_names(e.value, damaged)


def test_missing_mask_model(device, tmp_path):
    image, _ = helpers_geometry.disc_image()
    model = tmp_path / "missing.mvm"
    with pytest.raises((megavox.InputError, megavox.IoError)) as e:
        mask.apply(image, model=str(model), device=device)
    assert_names(e.value, model)


# ---- devices ----

def test_unknown_device():
    with pytest.raises(megavox.UnsupportedDeviceError) as e:
        megavox.Device("no-such-device-xyzzy")
    check_code(e.value, "UnsupportedDeviceError")
    with pytest.raises(megavox.UnsupportedDeviceError):
        megavox.Device("ocl:99")


def test_device_memory(selector):
    d = megavox.Device(selector, memory="256M")
    assert d.info["memory_budget"] == 256 << 20
    d = megavox.Device(selector, memory=300 << 20, host_memory="1G")
    assert d.info["memory_budget"] == 300 << 20
    assert d.info["host_memory_budget"] == 1 << 30
    with pytest.raises(megavox.InvalidArgumentError):
        megavox.Device(selector, memory="lots")
