"""Scene.trace: the same hit bytes as the C API's mvTraceRays, tmax forms, HIT_DTYPE, misses."""
import numpy as np
import pytest

import megavox

import helpers_geometry

CENTRE = (0.3, -0.2, 0.1)


@pytest.fixture
def built(device, sphere, tmp_path):
    """(scene, path): the ellipsoid at 128^3, written to path."""
    v, t = sphere
    path = tmp_path / "sphere.mvx"
    return device.build((v, t), resolution=128, output=str(path)), path


@pytest.fixture
def scene_c(capi, built):
    """The same file opened through the C API."""
    scene = capi.open(built[1])
    yield scene
    capi.release_scene(scene)


def test_hit_dtype():
    dt = megavox.HIT_DTYPE
    assert isinstance(dt, np.dtype)
    assert dt.itemsize == 32
    assert dt == np.dtype([("t", "<f4"), ("level", "<u4"), ("cell", "<u4", (3,)), ("normal", "<i4", (3,))])


def test_hits_equal_c_api(built, capi, scene_c):
    scene, _ = built
    origins, directions = helpers_geometry.rays_at(CENTRE, 3.0, 1000)
    hits = scene.trace(origins, directions)
    assert hits.dtype == megavox.HIT_DTYPE
    assert hits.shape == (1000,)
    want = capi.trace(scene_c, origins, directions)
    assert hits.tobytes() == want
    assert np.isfinite(hits["t"]).sum() > 100


def test_hits_of_an_opened_file_equal_c_api(device, built, capi, scene_c):
    _, path = built
    opened = device.open(str(path))
    origins, directions = helpers_geometry.rays_at(CENTRE, 2.5, 300, seed=11)
    assert opened.trace(origins, directions).tobytes() == capi.trace(scene_c, origins, directions)


def test_tmax_none_scalar_and_array(built, capi, scene_c):
    scene, _ = built
    n = 500
    origins, directions = helpers_geometry.rays_at(CENTRE, 3.0, n, seed=5)
    unbounded = scene.trace(origins, directions, None)
    assert unbounded.tobytes() == scene.trace(origins, directions).tobytes()
    assert unbounded.tobytes() == capi.trace(scene_c, origins, directions, np.full(n, np.inf, np.float32))
    t = unbounded["t"]
    cut = float(np.median(t[np.isfinite(t)]))
    scalar = scene.trace(origins, directions, cut)
    assert scalar.tobytes() == capi.trace(scene_c, origins, directions, np.full(n, cut, np.float32))
    assert np.isinf(scalar["t"][np.isfinite(t) & (t > cut * 1.001)]).all()
    rng = np.random.default_rng(2)
    per_ray = rng.uniform(0.2, 1.0, n).astype(np.float32)
    array = scene.trace(origins, directions, per_ray)
    assert array.tobytes() == capi.trace(scene_c, origins, directions, per_ray)
    hit = np.isfinite(array["t"])
    assert (array["t"][hit] <= per_ray[hit]).all()
    # An integer scalar is a bound too.
    assert scene.trace(origins, directions, 1).tobytes() == scene.trace(origins, directions, 1.0).tobytes()


def test_max_steps_equal_c_api(built, capi, scene_c):
    scene, _ = built
    origins, directions = helpers_geometry.rays_at(CENTRE, 3.0, 400, seed=9)
    for steps in (2, 30):
        hits = scene.trace(origins, directions, max_steps=steps)
        assert hits.tobytes() == capi.trace(scene_c, origins, directions, max_steps=steps)
    assert np.isnan(scene.trace(origins, directions, max_steps=2)["t"]).any()  # gave up: NaN


def test_misses_are_infinite(built):
    scene, _ = built
    origins, directions = helpers_geometry.rays_at(CENTRE, 3.0, 64, seed=4)
    away = origins - np.asarray(CENTRE, np.float32)  # pointing away from the model
    hits = scene.trace(origins, away.astype(np.float32))
    assert np.isposinf(hits["t"]).all()
    # Rays that would hit, cut short by tmax.
    towards = -away.astype(np.float32)
    assert np.isfinite(scene.trace(origins, towards)["t"]).all()
    assert np.isposinf(scene.trace(origins, towards, 0.1)["t"]).all()


def test_empty_batch(built):
    scene, _ = built
    hits = scene.trace(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.float32))
    assert hits.dtype == megavox.HIT_DTYPE and hits.shape == (0,)


def test_colours_equal_c_api(device, capi, sphere, tmp_path):
    v, t = sphere
    path = tmp_path / "coloured.mvx"
    scene = device.build((v, t, helpers_geometry.vertex_colours(v)), resolution=64, output=str(path))
    origins, directions = helpers_geometry.rays_at(CENTRE, 3.0, 300, seed=8)
    hits, rgba = scene.trace(origins, directions, colours=True)
    c = capi.open(path)
    try:
        want_hits, want_rgba = capi.trace(c, origins, directions, rgba=True)
    finally:
        capi.release_scene(c)
    assert hits.tobytes() == want_hits
    assert rgba.tobytes() == want_rgba


def test_colour_of_a_ray_cut_by_tmax_is_zero(device, sphere):
    """megavox.h: rgba is 0 for a miss; a ray whose hit lies past its tmax is a miss (t = +inf)."""
    v, t = sphere
    scene = device.build((v, t, helpers_geometry.vertex_colours(v)), resolution=64)
    origins, directions = helpers_geometry.rays_at(CENTRE, 3.0, 64, seed=4)
    towards = (np.asarray(CENTRE, np.float32) - origins).astype(np.float32)
    hits, rgba = scene.trace(origins, towards, 0.1, colours=True)
    assert np.isposinf(hits["t"]).all()
    assert (rgba == 0).all()


def test_paged_scene_traces_the_same(selector, device, cli, sphere, write_mesh, tmp_path):
    """A device with cache_memory= streams a paged .mvx through a page cache smaller than the file: the same hits
    and pictures as resident. (Small pages from the CLI's --page-words, so a small cache holds 64 of them.)"""
    v, t = sphere
    path = tmp_path / "small_pages.mvx"
    cli("build", write_mesh(v, t), "--resolution", 128, "--page-words", 64, "-o", path, "-q", device=selector)
    resident = device.open(str(path))
    streaming = megavox.Device(selector, cache_memory=64 * 256 * 2)
    paged = streaming.open(str(path))
    origins, directions = helpers_geometry.rays_at(CENTRE, 3.0, 500, seed=12)
    assert paged.trace(origins, directions).tobytes() == resident.trace(origins, directions).tobytes()
    stats = paged.stats
    assert stats["paged"]
    assert stats["passes"] >= 1 and stats["pages_streamed"] >= 1 and stats["cache_bytes"] > 0
    assert paged.render(48, 32).tobytes() == resident.render(48, 32).tobytes()
    assert not resident.stats["paged"] and resident.stats["cache_bytes"] == 0
