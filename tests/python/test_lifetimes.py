"""Progress callbacks (cancel, exceptions), objects released in any order, traces from several threads."""
import gc
import os
import threading
import time

import numpy as np
import pytest

import megavox
from megavox import mask, points

import helpers_geometry

CENTRE = (0.3, -0.2, 0.1)


class Stop(Exception):
    pass


def test_progress_called_with_stage_and_fraction(device, sphere, tmp_path):
    v, t = sphere
    calls = []

    def progress(stage, fraction):
        calls.append((stage, fraction))
        return True

    device.build((v, t), resolution=128, output=str(tmp_path / "s.mvx"), progress=progress)
    assert calls
    for stage, fraction in calls:
        assert isinstance(stage, str) and stage
        assert isinstance(fraction, float)
        assert 0.0 <= fraction <= 1.0
    assert (tmp_path / "s.mvx").is_file()


def test_progress_of_a_file_build(device, sphere, write_mesh, tmp_path):
    v, t = sphere
    calls = []
    device.build(str(write_mesh(v, t)), resolution=64, progress=lambda stage, fraction: calls.append(stage))
    assert calls  # a callback returning None goes on


def test_returning_false_cancels(device, sphere, tmp_path):
    v, t = sphere
    out = tmp_path / "out"
    out.mkdir()
    calls = []

    def progress(stage, fraction):
        calls.append(stage)
        return False

    with pytest.raises(megavox.CancelledError) as e:
        device.build((v, t), resolution=128, output=str(out / "s.mvx"), progress=progress)
    assert e.value.code == "MV_ERROR_CANCELLED"
    assert calls
    assert os.listdir(out) == []  # nothing of the output, not even a temporary
    # The device works on after a cancelled build.
    assert device.build((v, t), resolution=64).info["voxels"] > 0


def test_exception_in_callback_is_reraised_as_is(device, sphere, tmp_path):
    v, t = sphere
    out = tmp_path / "out"
    out.mkdir()
    raised = Stop("from the callback")

    def progress(stage, fraction):
        raise raised

    with pytest.raises(Stop) as e:
        device.build((v, t), resolution=128, output=str(out / "s.mvx"), progress=progress)
    assert e.value is raised
    assert os.listdir(out) == []
    assert device.build((v, t), resolution=64).info["voxels"] > 0


def test_points_progress_and_cancel(device, tmp_path):
    xyz, rgb = helpers_geometry.cloud(2000)
    calls = []
    points.build(xyz, str(tmp_path / "p.mvx"), rgb=rgb, device=device,
                 progress=lambda stage, fraction: calls.append((stage, fraction)) or True)
    assert calls and all(isinstance(s, str) and 0.0 <= f <= 1.0 for s, f in calls)
    out = tmp_path / "out"
    out.mkdir()
    with pytest.raises(megavox.CancelledError):
        points.build(xyz, str(out / "p.mvx"), device=device, progress=lambda stage, fraction: False)
    raised = Stop()

    def fail(stage, fraction):
        raise raised

    with pytest.raises(Stop) as e:
        points.build(xyz, str(out / "tiles"), format="3dtiles", device=device, progress=fail)
    assert e.value is raised
    assert os.listdir(out) == []


def test_mask_progress_and_cancel(device):
    image, _ = helpers_geometry.disc_image()
    rect = (20, 10, 80, 70)
    calls = []
    mask.apply(image, rect=rect, device=device,
               progress=lambda stage, fraction: calls.append((stage, fraction)) or True)
    assert calls and all(isinstance(s, str) and 0.0 <= f <= 1.0 for s, f in calls)
    with pytest.raises(megavox.CancelledError):
        mask.apply(image, rect=rect, device=device, progress=lambda stage, fraction: False)
    raised = Stop()

    def fail(stage, fraction):
        raise raised

    with pytest.raises(Stop) as e:
        mask.apply(image, rect=rect, device=device, progress=fail)
    assert e.value is raised


def test_device_released_before_its_scene(selector, sphere):
    v, t = sphere
    origins, directions = helpers_geometry.rays_at(CENTRE, 3.0, 200)
    device = megavox.Device(selector)
    scene = device.build((v, t), resolution=64)
    want = scene.trace(origins, directions).tobytes()
    del device
    gc.collect()
    assert scene.trace(origins, directions).tobytes() == want
    assert scene.render(32, 24).shape == (24, 32, 4)
    assert scene.device.info["selector"] == selector
    del scene
    gc.collect()


def test_scene_released_before_its_device(selector, sphere):
    v, t = sphere
    device = megavox.Device(selector)
    scene = device.build((v, t), resolution=64)
    voxels = scene.info["voxels"]
    del scene
    gc.collect()
    assert device.build((v, t), resolution=64).info["voxels"] == voxels
    del device
    gc.collect()


def test_opened_scene_and_hierarchy_outlive_their_device(selector, sphere, tmp_path):
    v, t = sphere
    device = megavox.Device(selector)
    device.build((v, t), resolution=64, output=str(tmp_path / "s.mvx"))
    xyz, _ = helpers_geometry.cloud(1000)
    points.build(xyz, str(tmp_path / "p.mvx"), device=device)
    scene = device.open(str(tmp_path / "s.mvx"))
    hierarchy = points.open(str(tmp_path / "p.mvx"), device=device)
    del device
    gc.collect()
    origins, directions = helpers_geometry.rays_at(CENTRE, 3.0, 50)
    assert np.isfinite(scene.trace(origins, directions)["t"]).any()
    assert len(hierarchy.xyz) == 1000 and len(hierarchy) >= 1
    nodes = hierarchy.nodes
    del hierarchy
    gc.collect()
    assert int(nodes["point_count"].sum()) == 1000  # the arrays handed out are the caller's


def test_results_outlive_everything(selector, sphere):
    v, t = sphere
    device = megavox.Device(selector)
    scene = device.build((v, t), resolution=64)
    origins, directions = helpers_geometry.rays_at(CENTRE, 3.0, 50)
    hits, rgba = scene.trace(origins, directions, colours=True)
    image = scene.render(16, 16)
    copy_hits, copy_image = hits.copy(), image.copy()
    del scene, device
    gc.collect()
    assert hits.tobytes() == copy_hits.tobytes() and image.tobytes() == copy_image.tobytes()
    assert rgba.shape == (50, 4)


def test_threads_trace_one_scene(device, sphere):
    v, t = sphere
    scene = device.build((v, t), resolution=128)
    batches = [helpers_geometry.rays_at(CENTRE, 3.0, 2000, seed=s) for s in range(4)]
    want = [scene.trace(o, d).tobytes() for o, d in batches]
    results, errors = {}, []

    def work(k):
        try:
            for i in range(3):
                o, d = batches[(k + i) % len(batches)]
                results[(k, i)] = (k + i) % len(batches), scene.trace(o, d).tobytes()
        except BaseException as e:  # noqa: B902 (reported below)
            errors.append(e)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(6)]
    for th in threads:
        th.start()
    for th in threads:
        th.join(timeout=120)
    assert not any(th.is_alive() for th in threads)
    assert errors == []
    assert len(results) == 18
    for batch, got in results.values():
        assert got == want[batch]


def test_threads_build_on_their_own_devices(selector, sphere, tmp_path):
    v, t = sphere
    want = megavox.Device(selector).build((v, t), resolution=64, output=str(tmp_path / "want.mvx"))
    del want
    errors = []

    def work(k):
        try:
            megavox.Device(selector).build((v, t), resolution=64, output=str(tmp_path / ("t%d.mvx" % k)))
        except BaseException as e:  # noqa: B902
            errors.append(e)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(3)]
    for th in threads:
        th.start()
    for th in threads:
        th.join(timeout=120)
    assert errors == []
    want_bytes = (tmp_path / "want.mvx").read_bytes()
    for k in range(3):
        assert (tmp_path / ("t%d.mvx" % k)).read_bytes() == want_bytes


def test_trace_releases_the_gil(device, sphere):
    """While one thread traces a large batch, another runs Python: its loop never stalls for the whole trace."""
    v, t = sphere
    scene = device.build((v, t), resolution=128)
    origins, directions = helpers_geometry.rays_at(CENTRE, 3.0, 1000000)
    span = []

    def work():
        start = time.perf_counter()
        scene.trace(origins, directions)
        span.append(time.perf_counter() - start)

    stamps = []
    th = threading.Thread(target=work)
    th.start()
    while th.is_alive():
        stamps.append(time.perf_counter())
    th.join()
    longest_stall = float(np.diff(stamps).max()) if len(stamps) > 1 else span[0]
    assert longest_stall < 0.5 * span[0], "the main thread stalled %.3f s of a %.3f s trace" % (longest_stall, span[0])
