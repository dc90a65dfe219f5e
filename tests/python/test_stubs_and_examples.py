"""The typed stubs name what the module has, and the examples in python/examples run as docs/python.md says."""
import ast
import os
import subprocess
import sys

import numpy as np

import helpers_capi
import megavox

PACKAGE = os.path.dirname(megavox.__file__)
EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python", "examples")


def stub_names(name):
    """Top-level names and, per class, method and property names of a .pyi in the built package."""
    with open(os.path.join(PACKAGE, name)) as f:
        tree = ast.parse(f.read())
    top, classes = set(), {}
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            top.add(node.name)
        if isinstance(node, ast.ClassDef):
            classes[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)} | \
                                 {n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
        if isinstance(node, ast.AnnAssign):
            top.add(node.target.id)
        if isinstance(node, ast.ImportFrom):
            top.update(a.asname or a.name for a in node.names)
        if isinstance(node, ast.Assign):
            top.update(t.id for t in node.targets if isinstance(t, ast.Name))
    return top, classes


def public(obj):
    return {n for n in dir(obj) if not n.startswith("_")}


def test_the_package_stub_names_every_public_name_and_method():
    top, classes = stub_names("__init__.pyi")
    assert set(megavox.__all__) <= top
    for cls in (megavox.Device, megavox.Scene):
        assert public(cls) <= classes[cls.__name__], cls.__name__
    assert "__init__" in classes["Device"]


def test_the_points_and_mask_stubs_name_their_functions():
    top, classes = stub_names("points.pyi")
    assert {"build", "open", "PointHierarchy"} <= top
    assert public(megavox.points.PointHierarchy) <= classes["PointHierarchy"] | {"info", "nodes", "xyz", "rgb",
                                                                               "intensity", "extra", "normal"}
    top, _ = stub_names("mask.pyi")
    assert {"apply", "train"} <= top


def run_example(args, cwd):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([os.path.dirname(PACKAGE), EXAMPLES]))
    return subprocess.run([sys.executable] + args, cwd=cwd, env=env, capture_output=True, text=True, timeout=600)


def test_the_worked_example_writes_its_picture(tmp_path):
    r = run_example([os.path.join(EXAMPLES, "torus.py"), str(tmp_path)], tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "torus.png").stat().st_size > 1000
    assert (tmp_path / "torus.mvx").is_file()
    assert "voxels in" in r.stdout


def test_the_scan_check_agrees_with_the_cli_and_the_c_api(tmp_path, cli_path):
    library_path = helpers_capi.library_path()
    sys.path.insert(0, EXAMPLES)
    import torus  # noqa: E402
    vertices, triangles, _ = torus.torus(u_steps=40, v_steps=20)
    ply = tmp_path / "ring.ply"
    with open(ply, "wb") as f:
        f.write(b"ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                b"property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
                % (len(vertices), len(triangles)))
        f.write(vertices.astype("<f4").tobytes())
        faces = np.zeros(len(triangles), dtype=[("n", "u1"), ("i", "<i4", (3,))])
        faces["n"], faces["i"] = 3, triangles
        f.write(faces.tobytes())
    r = run_example([os.path.join(EXAMPLES, "scan_check.py"), str(ply), "--cli", os.path.abspath(cli_path), "--library",
                     os.path.abspath(library_path),
                     "--resolution", "128", "--rays", "3000", "--repeats", "1"], tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert '"same_mvx_bytes_as_cli": true' in r.stdout and '"same_hits_as_c_api": true' in r.stdout
