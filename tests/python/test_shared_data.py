"""Real data from the shared staging folder (${MEGAVOX_TEST_DATA:-<source>/../shared/data}): a scanned mesh, a
LAS cloud and a photograph, each against the CLI. Skipped where that data is not staged."""
import os

import numpy as np
import pytest

from megavox import mask, points

import helpers_files

DATA = os.environ.get("MEGAVOX_TEST_DATA") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared", "data")


def staged(relative):
    path = os.path.join(DATA, relative)
    if not os.path.isfile(path):
        pytest.skip("shared data not staged: %s" % os.path.normpath(path))
    return path


def read(path):
    with open(path, "rb") as f:
        return f.read()


def test_bunny_equals_cli(selector, device, cli, tmp_path):
    ply = staged("meshes_stanford/stanford_bunny.ply")
    scene = device.build(ply, resolution=128, format="ssvdag", output=str(tmp_path / "py.mvx"))
    cli("build", ply, "--resolution", 128, "--format", "ssvdag", "-o", tmp_path / "cli.mvx", "-q", device=selector)
    assert read(tmp_path / "py.mvx") == read(tmp_path / "cli.mvx")
    assert scene.info["voxels"] > 10000
    image = scene.render(64, 48)
    assert image.shape == (48, 64, 4)


def test_autzen_las_equals_cli(selector, device, cli, tmp_path):
    las = staged("pointcloud_autzen/autzen_trim.las")
    points.build(las, str(tmp_path / "py.mvx"), device=device)
    cli("points", "build", las, "-o", tmp_path / "cli.mvx", "-q", device=selector)
    assert read(tmp_path / "py.mvx") == read(tmp_path / "cli.mvx")
    h = points.open(tmp_path / "py.mvx", device=device)
    assert h.info["points_kept"] == 110000
    assert h.rgb is not None and h.intensity is not None
    assert "NAD83" in h.info["crs"]
    leaves = np.flatnonzero(h.nodes["child_mask"] == 0)
    assert int(h.nodes["point_count"][leaves].sum()) == 110000


def test_photo_crop_mask_equals_cli(selector, device, cli, tmp_path):
    photo = helpers_files.read_ppm(staged("grabcut/images/106024.ppm"))
    crop = np.ascontiguousarray(photo[100:196, 180:308])  # 128 x 96 of real pixels
    rect = (16, 12, 96, 72)
    got = mask.apply(crop, rect=rect, device=device)
    path = tmp_path / "crop.ppm"
    helpers_files.write_ppm(path, crop)
    cli("mask", "apply", path, "--rect", ",".join(map(str, rect)), "-o", tmp_path / "out", "-q", device=selector)
    assert np.array_equal(got, helpers_files.read_png(tmp_path / "out" / "crop.png"))


def test_vdb_grid_equals_cli(selector, device, cli, tmp_path):
    vdb = staged("openvdb_samples/sphere.vdb")
    scene = device.build(vdb, grid="ls_sphere", resolution=64, output=str(tmp_path / "py.mvx"))
    cli("build", vdb, "--grid", "ls_sphere", "--resolution", 64, "-o", tmp_path / "cli.mvx", "-q", device=selector)
    assert read(tmp_path / "py.mvx") == read(tmp_path / "cli.mvx")
    assert scene.info["resolution"] == 64
