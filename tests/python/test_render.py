"""Scene.render: (H, W, 4) uint8 pictures equal to `megavox render`'s, view_camera, write_image."""
import numpy as np
import pytest

import megavox

import helpers_files

W, H = 96, 64


@pytest.fixture
def built(device, sphere, tmp_path):
    v, t = sphere
    path = tmp_path / "sphere.mvx"
    return device.build((v, t), resolution=128, output=str(path)), path


def test_shape_dtype_alpha(built):
    scene, _ = built
    image = scene.render(W, H)
    assert image.shape == (H, W, 4)
    assert image.dtype == np.uint8
    assert (image[..., 3] == 255).all()
    rgb = image[..., :3].reshape(-1, 3)
    assert len(np.unique(rgb, axis=0)) > 10  # the model is in the picture, shaded
    assert scene.render(W, H).tobytes() == image.tobytes()  # the same picture again


@pytest.mark.parametrize("view,shading", [("iso", "shaded"), ("front", "normal"), ("top", "depth")])
def test_equals_cli(selector, built, cli, tmp_path, view, shading):
    scene, path = built
    image = scene.render(W, H, view=view, shading=shading)
    png = tmp_path / "cli.png"
    cli("render", path, "-o", png, "--width", W, "--height", H, "--view", view, "--shading", shading, "-q",
        device=selector)
    assert np.array_equal(image[..., :3], helpers_files.read_png(png))


def test_lod_and_ao_equal_cli(selector, built, cli, tmp_path):
    scene, path = built
    image = scene.render(W, H, lod_pixels=4.0, ao_samples=2)
    png = tmp_path / "cli.png"
    cli("render", path, "-o", png, "--width", W, "--height", H, "--lod-pixels", 4, "--ao-samples", 2, "-q",
        device=selector)
    assert np.array_equal(image[..., :3], helpers_files.read_png(png))


def test_view_camera(built):
    scene, _ = built
    cam = scene.view_camera("front")
    assert set(cam) >= {"eye", "target", "up", "fov"}
    assert len(cam["eye"]) == 3 and len(cam["target"]) == 3 and len(cam["up"]) == 3
    assert cam["fov"] == pytest.approx(40.0)  # MV_DEFAULT_FOV
    assert scene.view_camera("front", fov=25)["fov"] == pytest.approx(25.0)
    assert scene.view_camera("iso") != cam
    # The preset view's camera renders the preset view.
    iso = scene.view_camera()
    assert scene.render(W, H, camera=iso).tobytes() == scene.render(W, H, view="iso").tobytes()


def test_camera_equals_cli(selector, built, cli, tmp_path):
    scene, path = built
    cam = scene.view_camera("left", fov=30)
    eye = tuple(cam["eye"])
    cam = dict(cam, eye=(eye[0] * 0.8, eye[1] + 0.3, eye[2] * 0.8))  # off the preset: a camera of our own
    image = scene.render(W, H, camera=cam)
    png = tmp_path / "cli.png"

    def xyz(v):
        return ",".join(repr(float(c)) for c in v)

    cli("render", path, "-o", png, "--width", W, "--height", H, "--eye", xyz(cam["eye"]), "--target",
        xyz(cam["target"]), "--up", xyz(cam["up"]), "--fov", repr(float(cam["fov"])), "-q", device=selector)
    assert np.array_equal(image[..., :3], helpers_files.read_png(png))


def test_write_image_png(built, tmp_path):
    scene, _ = built
    image = scene.render(W, H, shading="normal")
    path = tmp_path / "picture.png"
    megavox.write_image(str(path), image)
    assert np.array_equal(helpers_files.read_png(path), image[..., :3])
    # Any (H, W, 4) uint8 array, not only renders.
    rng = np.random.default_rng(0)
    noise = rng.integers(0, 256, (17, 23, 4), dtype=np.uint8)
    megavox.write_image(str(tmp_path / "noise.png"), noise)
    assert np.array_equal(helpers_files.read_png(tmp_path / "noise.png"), noise[..., :3])


def test_write_image_rgb(built, tmp_path):
    """(H, W, 3) is taken too (the module's docstring): the same PNG as with alpha."""
    scene, _ = built
    image = scene.render(W, H, shading="normal")
    megavox.write_image(str(tmp_path / "rgba.png"), image)
    megavox.write_image(str(tmp_path / "rgb.png"), np.ascontiguousarray(image[..., :3]))
    assert (tmp_path / "rgba.png").read_bytes() == (tmp_path / "rgb.png").read_bytes()


def test_write_image_jpeg(built, tmp_path):
    scene, _ = built
    path = tmp_path / "picture.jpg"
    megavox.write_image(str(path), scene.render(W, H))
    with open(path, "rb") as f:
        assert f.read(3) == b"\xff\xd8\xff"
