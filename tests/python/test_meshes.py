"""Device.build from arrays and files: the same .mvx bytes as the CLI, save / open, info, colours."""
import pathlib

import numpy as np
import pytest

import megavox

import helpers_geometry

RESOLUTION = 128


def read(path):
    with open(path, "rb") as f:
        return f.read()


@pytest.mark.parametrize("fmt", ["svdag", "ssvdag"])
@pytest.mark.parametrize("mesh", ["cube", "sphere", "big_sphere"])
def test_build_from_arrays_equals_cli(selector, device, cli, write_mesh, tmp_path, request, mesh, fmt):
    v, t = request.getfixturevalue(mesh)
    ply = write_mesh(v, t)
    ours, theirs = tmp_path / "py.mvx", tmp_path / "cli.mvx"
    scene = device.build((v, t), resolution=RESOLUTION, format=fmt, output=str(ours))
    cli("build", ply, "--resolution", RESOLUTION, "--format", fmt, "-o", theirs, "-q", device=selector)
    assert read(ours) == read(theirs)
    assert scene.info["encoding"] == fmt
    assert scene.info["resolution"] == RESOLUTION


def test_build_from_path_equals_arrays(device, sphere, write_mesh, tmp_path):
    v, t = sphere
    ply = write_mesh(v, t)
    device.build((v, t), resolution=RESOLUTION, output=str(tmp_path / "arrays.mvx"))
    device.build(str(ply), resolution=RESOLUTION, output=str(tmp_path / "str.mvx"))
    device.build(pathlib.Path(ply), resolution=RESOLUTION, output=tmp_path / "pathlike.mvx")
    arrays = read(tmp_path / "arrays.mvx")
    assert read(tmp_path / "str.mvx") == arrays
    assert read(tmp_path / "pathlike.mvx") == arrays


def test_index_types_give_the_same_bytes(device, sphere, tmp_path):
    v, t = sphere
    device.build((v, t.astype(np.uint32)), resolution=64, output=str(tmp_path / "u32.mvx"))
    device.build((v, t.astype(np.int32)), resolution=64, output=str(tmp_path / "i32.mvx"))
    device.build((v, t.astype(np.int64)), resolution=64, output=str(tmp_path / "i64.mvx"))
    want = read(tmp_path / "u32.mvx")
    assert read(tmp_path / "i32.mvx") == want
    assert read(tmp_path / "i64.mvx") == want


def test_in_core_cube_gives_the_same_bytes(device, sphere, tmp_path):
    v, t = sphere
    device.build((v, t), resolution=RESOLUTION, output=str(tmp_path / "default.mvx"))
    device.build((v, t), resolution=RESOLUTION, cube=megavox.IN_CORE, output=str(tmp_path / "in_core.mvx"))
    assert read(tmp_path / "in_core.mvx") == read(tmp_path / "default.mvx")


@pytest.mark.parametrize("shape", ["gpu", "cpu"])
def test_kernel_shapes_give_the_same_bytes(selector, device, sphere, tmp_path, shape):
    v, t = sphere
    device.build((v, t), resolution=64, format="ssvdag", output=str(tmp_path / "default.mvx"))
    shaped = megavox.Device(selector, kernel_shape=shape)
    shaped.build((v, t), resolution=64, format="ssvdag", output=str(tmp_path / "shaped.mvx"))
    assert read(tmp_path / "shaped.mvx") == read(tmp_path / "default.mvx")


def test_build_options_match_cli(selector, device, cli, sphere, write_mesh, tmp_path):
    v, t = sphere
    ply = write_mesh(v, t)
    device.build((v, t), resolution=64, format="svo", voxelize="thin", grid_origin="min",
                 output=str(tmp_path / "py.mvx"))
    cli("build", ply, "--resolution", 64, "--format", "svo", "--voxelize", "thin", "--grid-origin", "min",
        "-o", tmp_path / "cli.mvx", "-q", device=selector)
    assert read(tmp_path / "py.mvx") == read(tmp_path / "cli.mvx")


def test_save_and_open_round_trip(device, cli, sphere, tmp_path):
    v, t = sphere
    scene = device.build((v, t), resolution=RESOLUTION)  # a scratch file of its own
    saved = tmp_path / "saved.mvx"
    scene.save(str(saved))
    assert saved.is_file()
    cli("info", saved)  # the CLI validates every checksum, page and structure
    opened = device.open(str(saved))
    for key in ("encoding", "resolution", "levels", "voxels", "origin", "voxel_size", "lower", "upper"):
        assert opened.info[key] == scene.info[key], key
    origins, directions = helpers_geometry.rays_at((0.3, -0.2, 0.1), 3.0, 256)
    assert opened.trace(origins, directions).tobytes() == scene.trace(origins, directions).tobytes()
    again = device.open(saved)  # os.PathLike too
    assert again.info["voxels"] == scene.info["voxels"]


def test_info_fields(selector, device, capi, sphere, tmp_path):
    v, t = sphere
    path = tmp_path / "s.mvx"
    scene = device.build((v, t), resolution=RESOLUTION, format="ssvdag", output=str(path))
    info = scene.info
    assert set(info) >= {"encoding", "resolution", "levels", "voxels", "bytes", "origin", "voxel_size", "lower",
                         "upper"}
    assert info["encoding"] == "ssvdag"
    assert info["resolution"] == RESOLUTION
    assert isinstance(info["voxels"], int) and info["voxels"] > 0
    assert isinstance(info["bytes"], int) and info["bytes"] > 0
    assert len(info["origin"]) == 3 and len(info["lower"]) == 3 and len(info["upper"]) == 3
    np.testing.assert_allclose(info["lower"], v.min(axis=0), atol=1e-6)
    np.testing.assert_allclose(info["upper"], v.max(axis=0), atol=1e-6)
    extent = float((v.max(axis=0) - v.min(axis=0)).max())
    assert info["voxel_size"] * RESOLUTION == pytest.approx(extent, rel=1e-6)
    # The C API's record of the same file.
    scene_c = capi.open(path)
    try:
        want = capi.scene_info(scene_c)
    finally:
        capi.release_scene(scene_c)
    for key, value in want.items():
        got = info[key]
        assert (tuple(got) if isinstance(value, tuple) else got) == value, key
    assert scene.colour_entries == 0
    assert scene.device.info["selector"] == selector
    stats = scene.stats
    assert set(stats) >= {"paged", "cache_bytes", "passes", "pages_streamed", "peak_device_bytes"}


def test_device_info(selector, device):
    info = device.info
    assert set(info) >= {"name", "backend", "selector", "memory_budget", "memory_used", "host_memory_budget"}
    assert info["selector"] == selector
    assert info["backend"] in ("opencl", "vulkan")
    assert info["memory_budget"] > 0 and info["host_memory_budget"] > 0


@pytest.mark.parametrize("channels", [3, 4])
def test_coloured_build(selector, device, capi, cli, sphere, write_mesh, tmp_path, channels):
    v, t = sphere
    rgb = helpers_geometry.vertex_colours(v)
    colours = rgb if channels == 3 else np.concatenate([rgb, np.full((len(v), 1), 7, np.uint8)], axis=1)
    path = tmp_path / "coloured.mvx"
    scene = device.build((v, t, colours), resolution=64, output=str(path))
    assert scene.colour_entries > 0
    # The same bytes as the CLI's build of the coloured PLY (alpha dropped).
    cli("build", write_mesh(v, t, rgb), "--resolution", 64, "-o", tmp_path / "cli.mvx", "-q", device=selector)
    assert read(path) == read(tmp_path / "cli.mvx")
    scene_c = capi.open(path)
    try:
        assert scene.colour_entries == capi.colour_entries(scene_c)
    finally:
        capi.release_scene(scene_c)
    origins, directions = helpers_geometry.rays_at((0.3, -0.2, 0.1), 3.0, 400)
    hits, rgba = scene.trace(origins, directions, colours=True)
    assert hits.dtype == megavox.HIT_DTYPE and hits.shape == (400,)
    assert rgba.dtype == np.uint8 and rgba.shape == (400, 4)
    hit = np.isfinite(hits["t"])
    assert hit.sum() > 50 and (~hit).sum() > 0
    assert (rgba[hit, 3] == 255).all()
    assert (rgba[hit, :3].astype(int).sum(axis=1) > 0).all()
    assert (rgba[~hit] == 0).all()
    # Colours do not change the hits.
    assert scene.trace(origins, directions).tobytes() == hits.tobytes()
