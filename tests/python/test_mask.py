"""megavox.mask: apply (the CLI's masks of the same pixels), seeds, train + model, refused images."""
import numpy as np
import pytest

import megavox
from megavox import mask

import helpers_files
import helpers_geometry

RECT = (20, 10, 80, 70)


@pytest.fixture
def cli_mask(cli, tmp_path):
    """cli_mask(image, *args, device=SEL): `megavox mask apply` of the pixels (written as PPM / PGM) -> (H, W)."""

    def run(image, *args, device=None):
        path = tmp_path / ("cli_in.ppm" if image.ndim == 3 else "cli_in.pgm")
        helpers_files.write_pnm(path, image)
        out = tmp_path / "cli_masks"
        cli("mask", "apply", path, "-o", out, "-q", *args, device=device)
        return helpers_files.read_png(out / "cli_in.png")

    return run


def rect_arg(rect):
    return ",".join(str(v) for v in rect)


def seed_map(disc):
    seeds = np.full(disc.shape, 128, np.uint8)
    seeds[:3, :] = 0
    seeds[-3:, :] = 0
    cy, cx = disc.shape[0] // 2, disc.shape[1] // 2
    seeds[cy - 5:cy + 5, cx - 5:cx + 5] = 255
    return seeds


def test_rect_equals_cli(selector, device, cli_mask):
    image, disc = helpers_geometry.disc_image()
    got = mask.apply(image, rect=RECT, device=device)
    assert got.shape == image.shape[:2] and got.dtype == np.uint8
    assert set(np.unique(got)) <= {0, 255}
    fg = got == 255
    assert (fg & disc).sum() / (fg | disc).sum() > 0.7  # the disc, eroded
    assert np.array_equal(got, cli_mask(image, "--rect", rect_arg(RECT), device=selector))


def test_options_equal_cli(selector, device, cli_mask):
    image, _ = helpers_geometry.disc_image(seed=5)
    got = mask.apply(image, rect=RECT, iterations=1, erode=0, device=device)
    assert np.array_equal(got, cli_mask(image, "--rect", rect_arg(RECT), "--iterations", 1, "--erode", 0,
                                        device=selector))


def test_seeds_equal_cli(selector, device, cli_mask, tmp_path):
    image, disc = helpers_geometry.disc_image(seed=9)
    seeds = seed_map(disc)
    got = mask.apply(image, seeds=seeds, device=device)
    seeds_path = tmp_path / "seeds.pgm"
    helpers_files.write_pgm(seeds_path, seeds)
    assert np.array_equal(got, cli_mask(image, "--seeds", seeds_path, device=selector))
    assert (got[seeds == 255] == 255).all()
    assert (got[seeds == 0] == 0).all()
    # Seeds and a box together.
    both = mask.apply(image, rect=RECT, seeds=seeds, device=device)
    assert np.array_equal(both, cli_mask(image, "--rect", rect_arg(RECT), "--seeds", seeds_path, device=selector))


def test_grey_and_16_bit_images_equal_cli(selector, device, cli_mask):
    image, _ = helpers_geometry.disc_image(seed=6)
    grey = image.mean(axis=2).astype(np.uint8)
    got = mask.apply(grey, rect=RECT, device=device)
    assert np.array_equal(got, cli_mask(grey, "--rect", rect_arg(RECT), device=selector))
    assert np.array_equal(mask.apply(grey[:, :, None], rect=RECT, device=device), got)
    deep = (grey.astype(np.uint16) * 251 + np.arange(grey.size, dtype=np.uint16).reshape(grey.shape) % 200)
    got16 = mask.apply(deep, rect=RECT, device=device)
    assert np.array_equal(got16, cli_mask(deep, "--rect", rect_arg(RECT), device=selector))
    rgb16 = image.astype(np.uint16) * 257
    assert np.array_equal(mask.apply(rgb16, rect=RECT, device=device),
                          cli_mask(rgb16, "--rect", rect_arg(RECT), device=selector))


def test_train_then_apply_equals_cli(selector, device, cli, tmp_path):
    images, masks = [], []
    (tmp_path / "images").mkdir()
    (tmp_path / "masks").mkdir()
    for i, seed in enumerate((3, 4)):
        image, disc = helpers_geometry.disc_image(seed=seed)
        m = np.where(disc, 255, 0).astype(np.uint8)
        m[:5, :] = 128  # skipped
        images.append(image)
        masks.append(m)
        helpers_files.write_ppm(tmp_path / "images" / ("im%d.ppm" % i), image)
        helpers_files.write_pgm(tmp_path / "masks" / ("im%d.pgm" % i), m)
    model = tmp_path / "py.mvm"
    assert mask.train(images, masks, str(model)) is None
    assert model.is_file()
    cli_model = tmp_path / "cli.mvm"
    cli("mask", "train", "--images", tmp_path / "images", "--masks", tmp_path / "masks", "-o", cli_model)
    assert model.read_bytes() == cli_model.read_bytes()

    test, disc = helpers_geometry.disc_image(seed=9)
    got = mask.apply(test, model=str(model), device=device)
    fg = got == 255
    assert (fg & disc).sum() / (fg | disc).sum() > 0.7
    test_path = tmp_path / "test.ppm"
    helpers_files.write_ppm(test_path, test)
    cli("mask", "apply", test_path, "--model", model, "-o", tmp_path / "out", "-q", device=selector)
    assert np.array_equal(got, helpers_files.read_png(tmp_path / "out" / "test.png"))


def test_default_device():
    image, disc = helpers_geometry.disc_image()
    got = mask.apply(image, rect=RECT)
    assert got.shape == disc.shape


@pytest.mark.parametrize("shape", [(90, 120, 2), (90, 120, 4), (90,), (2, 90, 120, 3)])
def test_wrong_image_shapes_refused(device, shape):
    image = np.zeros(shape, np.uint8)
    with pytest.raises(ValueError, match="image"):
        mask.apply(image, rect=(0, 0, 10, 10), device=device)


@pytest.mark.parametrize("dtype", [np.float32, np.float64, np.int8, np.int32])
def test_wrong_image_dtypes_refused(device, dtype):
    image, _ = helpers_geometry.disc_image()
    with pytest.raises(ValueError, match="image"):
        mask.apply(image.astype(dtype), rect=RECT, device=device)


def test_wrong_seeds_refused(device):
    image, disc = helpers_geometry.disc_image()
    with pytest.raises(ValueError, match="seeds"):
        mask.apply(image, seeds=seed_map(disc)[:-1], device=device)
    with pytest.raises(ValueError, match="seeds"):
        mask.apply(image, seeds=seed_map(disc).astype(np.uint16), device=device)


def test_no_start_refused(device):
    image, _ = helpers_geometry.disc_image()
    with pytest.raises(megavox.InvalidArgumentError):
        mask.apply(image, device=device)


def test_rect_outside_refused(device):
    image, _ = helpers_geometry.disc_image()
    with pytest.raises(megavox.Error) as e:
        mask.apply(image, rect=(100, 10, 80, 70), device=device)
    assert e.value.code in ("MV_ERROR_INVALID_ARGUMENT", "MV_ERROR_INPUT")
    assert "box" in str(e.value) or "rect" in str(e.value)


def test_train_refuses_mismatched_lists(tmp_path):
    image, disc = helpers_geometry.disc_image()
    m = np.where(disc, 255, 0).astype(np.uint8)
    with pytest.raises(ValueError):
        mask.train([image, image], [m], str(tmp_path / "m.mvm"))
    with pytest.raises(ValueError, match="mask"):
        mask.train([image], [m[:-1]], str(tmp_path / "m.mvm"))
    assert not (tmp_path / "m.mvm").exists()
