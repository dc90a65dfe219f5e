"""The worked example of docs/python.md: a numpy mesh to a voxel DAG, rays back as arrays, a picture saved.

    PYTHONPATH=build/python python3 python/examples/torus.py [OUT_DIR]
"""
import os
import sys

import numpy as np

import megavox


def torus(major=1.0, minor=0.35, u_steps=96, v_steps=48):
    """A torus around +Z as (vertices float32 (n, 3), triangles uint32 (m, 3), colours uint8 (n, 3))."""
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, u_steps, endpoint=False),
                       np.linspace(0, 2 * np.pi, v_steps, endpoint=False), indexing="ij")
    x = (major + minor * np.cos(v)) * np.cos(u)
    y = (major + minor * np.cos(v)) * np.sin(u)
    z = minor * np.sin(v)
    vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(np.float32)
    i, j = np.meshgrid(np.arange(u_steps), np.arange(v_steps), indexing="ij")
    a, b = i * v_steps + j, ((i + 1) % u_steps) * v_steps + j
    c, d = ((i + 1) % u_steps) * v_steps + (j + 1) % v_steps, i * v_steps + (j + 1) % v_steps
    triangles = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    hue = (u.reshape(-1) / (2 * np.pi))  # colour by angle around the ring
    colours = np.stack([255 * hue, 128 + 100 * np.sin(2 * np.pi * hue), 255 * (1 - hue)], axis=1).astype(np.uint8)
    return vertices, triangles.astype(np.uint32), colours


def main(out_dir):
    os.makedirs(out_dir, exist_ok=True)
    device = megavox.Device()  # the CLI's default device; megavox.devices() lists them all
    print("device:", device.info["name"])

    vertices, triangles, colours = torus()
    scene = device.build((vertices, triangles, colours), resolution=512, format="ssvdag",
                         output=os.path.join(out_dir, "torus.mvx"),
                         progress=lambda stage, fraction: print(f"  {stage} {fraction:4.0%}   ", end="\r"))
    info = scene.info
    print(f"\n{info['voxels']} voxels in {info['bytes']} bytes ({info['encoding']}, {info['resolution']}^3)")

    # A fan of rays from above, straight down: the hits come back as one structured array.
    xs = np.linspace(-1.5, 1.5, 7, dtype=np.float32)
    origins = np.stack([xs, np.zeros_like(xs), np.full_like(xs, 2.0)], axis=1)
    directions = np.tile(np.array([[0, 0, -1]], np.float32), (len(xs), 1))
    hits, rgba = scene.trace(origins, directions, colours=True)
    for x, hit, colour in zip(xs, hits, rgba):
        where = "miss" if np.isinf(hit["t"]) else f"z = {2.0 - hit['t']:+.3f}, voxel {hit['cell'].tolist()}"
        print(f"  x = {x:+.2f}: {where}, colour {colour[:3].tolist()}")

    picture = scene.render(640, 480, view="iso")
    path = os.path.join(out_dir, "torus.png")
    megavox.write_image(path, picture)
    print("picture:", os.path.abspath(path))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else ".")
