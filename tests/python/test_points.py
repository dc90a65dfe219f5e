"""megavox.points: build from arrays (the CLI's bytes for the same PLY), open, 3D Tiles, attributes."""
import json
import os

import numpy as np
import pytest

import megavox
from megavox import points

import helpers_files
import helpers_geometry

N = 5000


def read(path):
    with open(path, "rb") as f:
        return f.read()


def grid_codes(xyz, info):
    """Each position's integer cell on the hierarchy's grid (world = offset + scale * X)."""
    scale = np.broadcast_to(np.asarray(info["scale"], np.float64), (3,))
    offset = np.broadcast_to(np.asarray(info["offset"], np.float64), (3,))
    q = (np.asarray(xyz, np.float64) - offset) / scale
    return (np.sign(q) * np.floor(np.abs(q) + 0.5)).astype(np.int64)  # llround: halves away from zero


def assert_same_hierarchy(ours, theirs, device, from_arrays=True):
    """The two point .mvx files hold the same hierarchy (nodes, points, attributes, grid). The files record what
    was read ("float32 arrays", "PLY binary_little_endian"), so built from arrays their bytes differ by that text
    alone; built from the same file, they are the same bytes."""
    a, b = points.open(str(ours), device=device), points.open(str(theirs), device=device)
    assert a.nodes.tobytes() == b.nodes.tobytes()
    assert a.xyz.tobytes() == b.xyz.tobytes()
    for name in ("rgb", "intensity", "extra"):
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None) == (y is None), name
        assert x is None or x.tobytes() == y.tobytes(), name
    for key in ("points_in", "points_kept", "points_dropped", "depth", "scale", "offset", "crs"):
        assert a.info[key] == b.info[key], key
    if from_arrays:
        assert a.info["format"].endswith("arrays") and b.info["format"].startswith("PLY")
    else:
        assert read(ours) == read(theirs)


def sorted_rows(codes, *columns):
    """codes (P, 3) and each column (P, ...) in the lexicographic order of the codes."""
    order = np.lexsort((codes[:, 2], codes[:, 1], codes[:, 0]))
    return [codes[order]] + [np.asarray(c)[order] for c in columns]


@pytest.mark.parametrize("max_node_points", [None, 512])
def test_build_from_arrays_equals_cli(selector, device, cli, tmp_path, max_node_points):
    xyz, rgb = helpers_geometry.cloud(N)
    ply = tmp_path / "cloud.ply"
    helpers_files.write_ply_cloud(ply, xyz, rgb)
    ours, theirs = tmp_path / "py.mvx", tmp_path / "cli.mvx"
    extra = {} if max_node_points is None else {"max_node_points": max_node_points}
    result = points.build(xyz, str(ours), rgb=rgb, device=device, **extra)
    assert result is None
    args = [] if max_node_points is None else ["--max-node-points", max_node_points]
    cli("points", "build", ply, "-o", theirs, "-q", *args, device=selector)
    assert_same_hierarchy(ours, theirs, device)


def test_build_from_float64_equals_cli_of_a_double_ply(selector, device, cli, tmp_path):
    xyz, _ = helpers_geometry.cloud(N, seed=2)
    xyz = xyz.astype(np.float64) + np.random.default_rng(0).uniform(0, 1e-5, xyz.shape)
    ply = tmp_path / "cloud.ply"
    helpers_files.write_ply_cloud(ply, xyz, double=True)
    points.build(xyz, str(tmp_path / "py.mvx"), max_node_points=1000, device=device)
    cli("points", "build", ply, "-o", tmp_path / "cli.mvx", "--max-node-points", 1000, "-q", device=selector)
    assert_same_hierarchy(tmp_path / "py.mvx", tmp_path / "cli.mvx", device)


def test_build_from_path_equals_cli(selector, device, cli, tmp_path):
    xyz, rgb = helpers_geometry.cloud(N, seed=3)
    ply = tmp_path / "cloud.ply"
    helpers_files.write_ply_cloud(ply, xyz, rgb)
    points.build(str(ply), str(tmp_path / "py.mvx"), depth=4, device=device)
    cli("points", "build", ply, "-o", tmp_path / "cli.mvx", "--depth", 4, "-q", device=selector)
    assert_same_hierarchy(tmp_path / "py.mvx", tmp_path / "cli.mvx", device, from_arrays=False)


def test_open_single_node(device, tmp_path):
    xyz, rgb = helpers_geometry.cloud(N)
    out = tmp_path / "one.mvx"
    points.build(xyz, str(out), rgb=rgb, device=device)
    h = points.open(str(out), device=device)
    assert len(h) == 1
    assert int(h.nodes["point_count"].sum()) == N
    assert h.xyz.shape == (N, 3) and h.xyz.dtype == np.float64
    assert h.rgb.shape == (N, 3) and h.rgb.dtype == np.uint16
    assert h.intensity is None and h.extra is None


def test_open_hierarchy(selector, device, tmp_path):
    xyz, rgb = helpers_geometry.cloud(N)
    out = tmp_path / "cloud.mvx"
    points.build(xyz, str(out), rgb=rgb, max_node_points=512, device=device)
    h = points.open(str(out), device=device)
    nodes = h.nodes
    assert nodes.dtype.itemsize == 40
    assert nodes.dtype == megavox.NODE_DTYPE
    assert set(nodes.dtype.names) >= {"code", "first_point", "subtree_points", "point_count", "first_child",
                                      "child_mask", "level", "pad", "reserved"}
    assert len(h) == len(nodes) > 1
    info = h.info
    assert info["points_in"] == N and info["points_kept"] == N and info["points_dropped"] == 0
    assert info["depth"] >= 1
    # Every stored point belongs to one node; the root's subtree holds every input point.
    assert int(nodes["point_count"].sum()) == len(h.xyz)
    assert int(nodes["subtree_points"][0]) == N
    leaves = np.flatnonzero(nodes["child_mask"] == 0)
    assert int(nodes["point_count"][leaves].sum()) == N
    # World coordinates within the grid's scale of the inputs.
    scale = float(np.max(info["scale"]))
    assert scale > 0
    assert (h.xyz.min(axis=0) >= xyz.min(axis=0) - scale).all()
    assert (h.xyz.max(axis=0) <= xyz.max(axis=0) + scale).all()
    # The leaves hold every input point, each once, with its colour.
    parts = [h.node_points(int(i)) for i in leaves]
    assert all(isinstance(p, slice) for p in parts)
    leaf_xyz = np.concatenate([h.xyz[p] for p in parts])
    leaf_rgb = np.concatenate([h.rgb[p] for p in parts])
    got_codes, got_rgb = sorted_rows(grid_codes(leaf_xyz, info), leaf_rgb)
    want_codes, want_rgb = sorted_rows(grid_codes(xyz, info), rgb)
    assert np.array_equal(got_codes, want_codes)
    assert np.array_equal(got_rgb, want_rgb.astype(np.uint16))  # a uchar colour stays 0-255
    np.testing.assert_allclose(np.sort(leaf_xyz, axis=0), np.sort(xyz.astype(np.float64), axis=0),
                               atol=scale, rtol=0)
    # node_points(i) is [first_point, first_point + point_count).
    for i in range(len(h)):
        p = h.node_points(i)
        assert (p.start, p.stop) == (int(nodes["first_point"][i]),
                                     int(nodes["first_point"][i]) + int(nodes["point_count"][i]))


def test_3dtiles(selector, device, cli, tmp_path):
    xyz, rgb = helpers_geometry.cloud(N)
    folder = tmp_path / "tiles"
    points.build(xyz, str(folder), format="3dtiles", rgb=rgb, max_node_points=1000, device=device)
    tileset = folder / "tileset.json"
    assert tileset.is_file()
    with open(tileset) as f:
        assert "root" in json.load(f)
    # The same folder as the CLI's.
    ply = tmp_path / "cloud.ply"
    helpers_files.write_ply_cloud(ply, xyz, rgb)
    theirs = tmp_path / "cli_tiles"
    cli("points", "build", ply, "--format", "3dtiles", "--max-node-points", 1000, "-o", theirs, "-q",
        device=selector)

    def files(root):
        return {os.path.relpath(os.path.join(d, f), root) for d, _, fs in os.walk(root) for f in fs}

    assert files(folder) == files(theirs)
    for name in sorted(files(folder), key=lambda n: n == "tileset.json"):  # the tiles first, then the tileset
        if name == "tileset.json":  # the same but for the input it names (asset.extras.source)
            x, y = json.loads(read(folder / name)), json.loads(read(theirs / name))
            assert x["asset"]["extras"].pop("source").endswith("arrays")
            y["asset"]["extras"].pop("source")
            assert x == y
        else:
            assert read(folder / name) == read(theirs / name), name


def test_intensity_and_classification(device, tmp_path):
    xyz, rgb = helpers_geometry.cloud(N)
    rng = np.random.default_rng(4)
    intensity = rng.integers(0, 65536, N, dtype=np.uint16)
    classification = rng.integers(0, 32, N, dtype=np.uint8)
    out = tmp_path / "attrs.mvx"
    points.build(xyz, str(out), rgb=rgb, intensity=intensity, classification=classification, max_node_points=700,
                 device=device)
    h = points.open(str(out), device=device)
    assert h.intensity is not None and h.intensity.dtype == np.uint16 and h.intensity.shape == (len(h.xyz),)
    assert h.extra is not None and h.extra.dtype == np.uint8 and h.extra.shape == (len(h.xyz), 1)
    leaves = np.flatnonzero(h.nodes["child_mask"] == 0)
    idx = np.concatenate([np.arange(len(h.xyz))[h.node_points(int(i))] for i in leaves])
    got = sorted_rows(grid_codes(h.xyz[idx], h.info), h.intensity[idx], h.extra[idx, 0])
    want = sorted_rows(grid_codes(xyz, h.info), intensity, classification)
    assert np.array_equal(got[0], want[0])
    assert np.array_equal(got[1], want[1])
    assert np.array_equal(got[2], want[2])


def test_uint16_rgb_and_intensity_equal_cli(selector, device, cli, tmp_path):
    xyz, rgb8 = helpers_geometry.cloud(N, seed=6)
    rgb = rgb8.astype(np.uint16) * 257
    intensity = (np.arange(N) * 13 % 65536).astype(np.uint16)
    ply = tmp_path / "cloud.ply"
    helpers_files.write_ply_cloud(ply, xyz, rgb, intensity=intensity)
    points.build(xyz, str(tmp_path / "py.mvx"), rgb=rgb, intensity=intensity, device=device)
    cli("points", "build", ply, "-o", tmp_path / "cli.mvx", "-q", device=selector)
    assert_same_hierarchy(tmp_path / "py.mvx", tmp_path / "cli.mvx", device)


def test_default_device(tmp_path):
    xyz, _ = helpers_geometry.cloud(1000)
    out = tmp_path / "default.mvx"
    points.build(xyz, str(out))
    h = points.open(str(out))
    assert h.info["points_kept"] == 1000
    assert h.rgb is None


def _shared_data(relative):
    root = os.environ.get("MEGAVOX_TEST_DATA") or os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data")
    path = os.path.join(root, relative)
    if not os.path.exists(path):
        pytest.skip(f"shared data not found: {path} (stage ../shared/data or set MEGAVOX_TEST_DATA)")
    return path


def test_las_fields_travel_by_name(tmp_path, device):
    laz = _shared_data("pointcloud_laz/autzen_trim.laz")
    las = _shared_data("pointcloud_autzen/autzen_trim.las")
    out = tmp_path / "autzen.mvx"
    points.build(laz, str(out), device=device)
    h = points.open(out, device=device)
    names = [f["name"] for f in h.info["fields"]]
    assert names[:3] == ["return_number", "number_of_returns", "classification"] and "gps_time" in names
    leaves = np.concatenate([np.arange(len(h.xyz))[h.node_points(i)] for i in h.leaves()])
    classes = h.field("classification")[leaves]
    gps = h.field("gps_time")[leaves]
    assert classes.dtype == np.uint8 and gps.dtype == np.float64
    # The uncompressed twin's records, read with numpy: classification (low 5 bits of byte 15), GPS time at 20.
    raw = np.fromfile(las, dtype=np.uint8)
    offset = int(raw[96:100].view("<u4")[0])
    count = int(raw[107:111].view("<u4")[0])
    records = raw[offset:offset + 34 * count].reshape(count, 34)
    assert np.array_equal(np.sort(classes), np.sort(records[:, 15] & 31))
    assert np.array_equal(np.sort(gps), np.sort(np.ascontiguousarray(records[:, 20:28]).view("<f8")[:, 0]))
    with pytest.raises(KeyError, match="no field 'colour'"):
        h.field("colour")


def test_tiles_version_crs_and_bounds(tmp_path, device):
    laz = _shared_data("pointcloud_laz/autzen_trim.laz")
    for version in ("1.1", "1.0"):
        out = tmp_path / f"t{version}"
        points.build(laz, str(out), format="3dtiles", tiles_version=version, device=device)
        tileset = json.loads((out / "tileset.json").read_text())
        assert tileset["asset"]["version"] == version
        assert ("transform" in tileset["root"]) == (version == "1.1")  # 1.1 placed through the file's CRS
    with pytest.raises(megavox.Error, match="EPSG:999999"):
        points.build(laz, str(tmp_path / "bad"), format="3dtiles", crs="EPSG:999999", device=device)
    assert not (tmp_path / "bad").exists()
    # A box over the western half: fewer points, all inside it.
    whole = points.open(_build(laz, tmp_path / "whole.mvx", device), device=device)
    x0, x1 = whole.xyz[:, 0].min(), whole.xyz[:, 0].max()
    box = (x0, -1e12, -1e12, (x0 + x1) / 2, 1e12, 1e12)
    part = points.open(_build(laz, tmp_path / "part.mvx", device, bounds=box), device=device)
    assert 0 < part.info["points_kept"] < whole.info["points_kept"]
    assert (part.xyz[:, 0] <= box[3]).all()
    with pytest.raises(ValueError, match="six numbers"):
        points.build(laz, str(tmp_path / "x.mvx"), bounds=(1, 2, 3), device=device)


def _build(source, out, device, **options):
    points.build(source, str(out), device=device, **options)
    return out
