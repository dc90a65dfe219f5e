"""Calls in awkward company: a property read while another thread's build waits in its progress callback, a cancel
at the write, callbacks that answer oddly, messages that are not UTF-8, arguments of the wrong type or layout."""
import threading

import numpy as np
import pytest

import megavox


def test_reading_properties_while_a_build_reports_progress_does_not_hang(selector, cube):
    device = megavox.Device(selector)
    scene = device.build(cube, resolution=32)
    v, t = cube
    done = threading.Event()
    errors = []

    def build_often():
        try:
            for _ in range(4):
                device.build((v, t), resolution=128, progress=lambda s, f: None)
        except Exception as e:  # noqa: BLE001  (reported below)
            errors.append(e)
        done.set()

    worker = threading.Thread(target=build_often)
    worker.start()
    while not done.is_set():  # each read needs the device the build holds while it calls back
        assert device.info["selector"] == selector
        assert scene.stats["passes"] >= 0
        assert scene.colour_entries == 0
        repr(device)
    worker.join(timeout=120)
    assert not worker.is_alive() and not errors


def test_a_cancel_when_the_write_starts_leaves_no_file(selector, cube, tmp_path):
    device = megavox.Device(selector)
    out = tmp_path / "cancelled.mvx"
    with pytest.raises(megavox.CancelledError):
        device.build(cube, resolution=32, output=out, progress=lambda s, f: s != "write")
    assert not out.exists()
    xyz = np.random.default_rng(1).random((500, 3)).astype(np.float32)
    with pytest.raises(megavox.CancelledError):
        megavox.points.build(xyz, tmp_path / "p.mvx", device=device, progress=lambda s, f: s != "write")
    assert not (tmp_path / "p.mvx").exists()


def test_a_callback_answer_without_a_truth_value_is_raised(selector, cube):
    device = megavox.Device(selector)
    with pytest.raises(ValueError, match="truth value"):
        device.build(cube, resolution=32, progress=lambda s, f: np.array([1, 2]))


def test_a_message_quoting_bytes_that_are_not_utf8_still_raises_the_input_error(selector, tmp_path):
    device = megavox.Device(selector)
    bad = tmp_path / "bad.ply"
    bad.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty flo\xffat x\nend_header\n0\n")
    with pytest.raises(megavox.Error) as e:
        device.build(bad, resolution=32)
    assert str(bad) in str(e.value)


def test_paths_that_are_not_utf8_are_file_system_bytes(selector, cube, tmp_path):
    device = megavox.Device(selector)
    name = bytes(tmp_path) + b"/\xff\xfe.mvx"
    device.build(cube, resolution=32, output=name)
    assert device.open(name).info["voxels"] > 0


@pytest.mark.parametrize("call", [
    lambda s, o, d: s.trace(o, d, [1, 2, 3]),
    lambda s, o, d: s.trace(o, d, max_steps=-1),
    lambda s, o, d: s.trace(o, d, max_steps=2**40),
    lambda s, o, d: s.render(8, 8, camera={"eye": (0, 0, 5), "target": "origin"}),
    lambda s, o, d: s.view_camera("iso", fov="wide"),
    lambda s, o, d: s.device.build((np.zeros((3, 3), np.float32), np.array([[0, 1, 2**63]], np.uint64))),
    lambda s, o, d: megavox.mask.apply(np.zeros((8, 8), np.uint8), rect=(1.0, 1, 4, 4), device=s.device),
    lambda s, o, d: megavox.mask.apply(np.zeros((8, 8), np.uint8), rect=5, device=s.device),
    lambda s, o, d: megavox.Device(0),
    lambda s, o, d: megavox.Device(memory=-5),
])
def test_arguments_of_the_wrong_type_or_range_are_value_errors(selector, cube, call):
    device = megavox.Device(selector)
    scene = device.build(cube, resolution=32)
    o = np.zeros((2, 3), np.float32)
    d = np.ones((2, 3), np.float32)
    with pytest.raises((ValueError, TypeError)) as e:
        call(scene, o, d)
    assert not isinstance(e.value, RuntimeError)


def test_a_size_past_the_device_is_refused_by_the_device_config():
    with pytest.raises(megavox.Error):
        megavox.Device(memory=2**70)


def test_misaligned_and_strided_arrays_give_the_hits_of_packed_ones(selector, cube):
    device = megavox.Device(selector)
    scene = device.build(cube, resolution=32)
    rng = np.random.default_rng(3)
    o = (rng.random((50, 3)) * 4 - 2).astype(np.float32)
    o[:, 2] = 5
    d = np.tile(np.array([[0, 0, -1]], np.float32), (50, 1))
    expected = scene.trace(o, d)
    raw = np.zeros(o.nbytes + 1, np.uint8)
    shifted = np.frombuffer(raw.data, dtype=np.float32, count=o.size, offset=1).reshape(50, 3)
    assert not shifted.flags.aligned
    shifted[...] = o
    wide = np.zeros((50, 6), np.float32)
    wide[:, ::2] = d
    assert scene.trace(shifted, wide[:, ::2]).tobytes() == expected.tobytes()
