"""Small meshes, point clouds and images made with numpy (no data files needed)."""
import numpy as np


def cube_mesh():
    """The cube [-1, 1]^3 as 8 vertices and 12 triangles (float32, uint32)."""
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], np.float32)
    # vertex index = 4 * (x > 0) + 2 * (y > 0) + (z > 0)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    t = []
    for a, b, c, d in quads:
        t += [(a, b, c), (a, c, d)]
    return v, np.array(t, np.uint32)


def icosphere(subdivisions):
    """A unit sphere: 20 * 4^subdivisions triangles (float32 vertices, uint32 triangles)."""
    g = (1 + 5 ** 0.5) / 2
    verts = [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g), (0, -1, -g), (0, 1, -g),
             (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, np.float64) / np.linalg.norm(p) for p in verts]
    for _ in range(subdivisions):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                middle[key] = len(verts) - 1
            return middle[key]

        new_faces = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new_faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new_faces
    return np.array(verts, np.float32), np.array(faces, np.uint32)


def vertex_colours(vertices):
    """A colour per vertex from its position (uint8 (N, 3)), never black."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    return (32 + (vertices - lo) / (hi - lo) * 200).astype(np.uint8)


def cloud(n, seed=1):
    """n points in a 10 x 5 x 2 box away from the origin (float32), with uint8 colours."""
    rng = np.random.default_rng(seed)
    xyz = (rng.random((n, 3)) * np.array([10.0, 5.0, 2.0]) + np.array([100.0, 200.0, 3.0])).astype(np.float32)
    rgb = rng.integers(0, 256, (n, 3), dtype=np.uint8)
    return xyz, rgb


def disc_image(width=120, height=90, seed=3):
    """A bright disc on a dark noisy background: uint8 (H, W, 3), and the disc's boolean map."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:height, 0:width]
    image = rng.integers(20, 70, (height, width, 3)).astype(np.uint8)
    disc = (xx - width // 2) ** 2 + (yy - height // 2) ** 2 < (min(width, height) * 0.28) ** 2
    image[disc] = (np.array([230, 200, 60]) + rng.integers(-15, 15, (int(disc.sum()), 3))).astype(np.uint8)
    return image, disc


def rays_at(centre, radius, n, seed=7):
    """n rays from a sphere of the radius around the centre towards points near the centre (some miss)."""
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    origins = np.asarray(centre) + radius * d
    targets = np.asarray(centre) + rng.uniform(-0.7, 0.7, (n, 3)) * radius
    directions = targets - origins
    return origins.astype(np.float32), directions.astype(np.float32)
