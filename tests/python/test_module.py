"""Module level: __version__, devices() (the CLI's list), the default Device(), constants."""
import json
import os
import subprocess
import sys

import numpy as np

import megavox
from megavox import mask, points

import helpers_files
import helpers_geometry


def test_version_equals_cli(cli):
    first = cli("--version").stdout.splitlines()[0]  # "megavox X.Y.Z"; what MPI it has follows
    assert isinstance(megavox.__version__, str)
    assert first.split()[-1].lstrip("v") == megavox.__version__


def test_devices_equal_cli(cli):
    ours = megavox.devices()
    theirs = json.loads(cli("devices", "--json").stdout)
    assert [d["selector"] for d in ours] == [d["selector"] for d in theirs]
    for d, c in zip(ours, theirs):
        assert set(d) >= {"selector", "name", "backend", "type", "platform", "memory_bytes", "default"}
        assert d["name"] == c["name"]
        assert d["backend"] == c["backend"]
        assert d["type"] == c["type"]
        assert d["platform"] == c["platform"]
        assert isinstance(d["memory_bytes"], int) and d["memory_bytes"] == c["global_memory_bytes"]
        assert d["default"] is c["selected"]


def test_default_device(selectors):
    defaults = [d for d in megavox.devices() if d["default"]]
    assert len(defaults) == 1
    assert megavox.Device().info["selector"] == defaults[0]["selector"]
    assert defaults[0]["selector"] in selectors


def test_device_by_selector(selector):
    assert megavox.Device(selector).info["selector"] == selector


def test_constants():
    assert isinstance(megavox.IN_CORE, int)
    assert megavox.HIT_DTYPE.itemsize == 32


def test_paths_take_os_pathlike(device, sphere, tmp_path):
    """Every path argument takes a str or an os.PathLike, as Device.build's source does."""
    v, t = sphere
    scene = device.build((v, t), resolution=32, output=tmp_path / "a.mvx")
    scene.save(tmp_path / "b.mvx")
    assert device.open(tmp_path / "b.mvx").info["voxels"] == scene.info["voxels"]
    megavox.write_image(tmp_path / "p.png", scene.render(16, 16))
    assert helpers_files.read_png(tmp_path / "p.png").shape == (16, 16, 3)
    xyz, _ = helpers_geometry.cloud(500)
    points.build(xyz, tmp_path / "c.mvx", device=device)
    helpers_files.write_ply_cloud(tmp_path / "c.ply", xyz)
    points.build(tmp_path / "c.ply", tmp_path / "d.mvx", device=device)
    assert len(points.open(tmp_path / "d.mvx", device=device).xyz) == 500
    image, disc = helpers_geometry.disc_image()
    mask.train([image], [np.where(disc, 255, 0).astype(np.uint8)], tmp_path / "m.mvm")
    assert mask.apply(image, model=tmp_path / "m.mvm", device=device).shape == disc.shape


def test_device_by_name(selector):
    """A selector may be (part of) the device's name, as the CLI's --device."""
    listed = megavox.devices()
    name = next(d["name"] for d in listed if d["selector"] == selector)
    part = name.split(" ")[0].split(",")[0]  # a config value cannot hold a comma ("llvmpipe (LLVM 15.0.6, 256 bits)")
    candidates = [d["selector"] for d in listed if part.lower() in d["name"].lower()]
    got = megavox.Device(part).info["selector"]
    assert got in candidates
    if len(candidates) == 1:
        assert got == selector


def test_default_follows_megavox_device(selector):
    """Device() and devices()' default follow $MEGAVOX_DEVICE, as the CLI does."""
    code = ("import megavox; d = [x['selector'] for x in megavox.devices() if x['default']]; "
            "print(megavox.Device().info['selector'], *d)")
    env = dict(os.environ, MEGAVOX_DEVICE=selector)
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == [selector, selector]
