"""Files for the CLI and back: binary PLY meshes and clouds, PPM / PGM images, and a small PNG reader."""
import struct
import zlib

import numpy as np


def write_ply_mesh(path, vertices, triangles, colours=None):
    """A binary little-endian PLY: float x, y, z (uchar red, green, blue), faces as list uchar uint."""
    vertices = np.asarray(vertices, np.float32)
    triangles = np.asarray(triangles, np.uint32)
    header = "ply\nformat binary_little_endian 1.0\nelement vertex %d\n" % len(vertices)
    header += "property float x\nproperty float y\nproperty float z\n"
    if colours is not None:
        header += "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        vdt = np.dtype([("p", "<f4", (3,)), ("c", "u1", (3,))])
        body = np.empty(len(vertices), vdt)
        body["p"] = vertices
        body["c"] = np.asarray(colours, np.uint8)[:, :3]
    else:
        body = vertices.astype("<f4")
    header += "element face %d\nproperty list uchar uint vertex_indices\nend_header\n" % len(triangles)
    faces = np.empty(len(triangles), np.dtype([("n", "u1"), ("i", "<u4", (3,))]))
    faces["n"] = 3
    faces["i"] = triangles
    with open(path, "wb") as f:
        f.write(header.encode("ascii") + body.tobytes() + faces.tobytes())


def write_ply_cloud(path, xyz, rgb=None, intensity=None, double=False):
    """A binary little-endian PLY point cloud: float (double) x, y, z, uchar (ushort) red, green, blue as rgb's
    dtype, ushort intensity."""
    coord = "double" if double else "float"
    xyz = np.asarray(xyz, "<f8" if double else "<f4")
    header = "ply\nformat binary_little_endian 1.0\nelement vertex %d\n" % len(xyz)
    header += "property %s x\nproperty %s y\nproperty %s z\n" % (coord, coord, coord)
    fields = [("p", xyz.dtype, (3,))]
    if rgb is not None:
        rgb = np.asarray(rgb)
        kind = "uchar" if rgb.dtype == np.uint8 else "ushort"
        header += "property %s red\nproperty %s green\nproperty %s blue\n" % (kind, kind, kind)
        fields.append(("c", rgb.dtype.newbyteorder("<"), (3,)))
    if intensity is not None:
        header += "property ushort intensity\n"
        fields.append(("i", "<u2"))
    header += "end_header\n"
    body = np.empty(len(xyz), np.dtype(fields))
    body["p"] = xyz
    if rgb is not None:
        body["c"] = rgb
    if intensity is not None:
        body["i"] = intensity
    with open(path, "wb") as f:
        f.write(header.encode("ascii") + body.tobytes())


def write_pnm(path, image):
    """(H, W) or (H, W, 3) uint8 / uint16 as a binary PGM (P5) or PPM (P6), 16-bit samples big-endian."""
    image = np.asarray(image)
    if image.dtype not in (np.uint8, np.uint16) or image.ndim not in (2, 3) or (image.ndim == 3 and image.shape[2] != 3):
        raise ValueError("write_pnm takes (H, W) or (H, W, 3) uint8 or uint16")
    h, w = image.shape[:2]
    magic = b"P5" if image.ndim == 2 else b"P6"
    maxval = 255 if image.dtype == np.uint8 else 65535
    data = np.ascontiguousarray(image, np.uint8 if maxval == 255 else ">u2").tobytes()
    with open(path, "wb") as f:
        f.write(b"%s\n%d %d\n%d\n" % (magic, w, h, maxval) + data)


def write_ppm(path, image):
    """(H, W, 3) uint8 as a binary PPM (P6)."""
    assert np.asarray(image).ndim == 3
    write_pnm(path, np.asarray(image, np.uint8))


def write_pgm(path, image):
    """(H, W) uint8 as a binary PGM (P5)."""
    assert np.asarray(image).ndim == 2
    write_pnm(path, np.asarray(image, np.uint8))


def _paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def read_png(path):
    """An 8-bit, non-interlaced grey (H, W), grey+alpha / RGB / RGBA (H, W, C) PNG as uint8."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("%s: not a PNG" % path)
    pos, idat, ihdr = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        chunk = data[pos + 8:pos + 8 + length]
        crc = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])[0]
        if zlib.crc32(kind + chunk) & 0xFFFFFFFF != crc:
            raise ValueError("%s: bad CRC in %r" % (path, kind))
        if kind == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", chunk)
        elif kind == b"IDAT":
            idat.append(chunk)
        elif kind == b"IEND":
            break
        pos += 12 + length
    width, height, depth, colour_type, _, _, interlace = ihdr
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(colour_type)
    if depth != 8 or channels is None or interlace != 0:
        raise ValueError("%s: unsupported PNG (depth %d, colour type %d, interlace %d)"
                         % (path, depth, colour_type, interlace))
    raw = zlib.decompress(b"".join(idat))
    stride = width * channels
    if len(raw) != height * (stride + 1):
        raise ValueError("%s: PNG data of the wrong size" % path)
    bpp = channels
    out = bytearray()
    prev = bytearray(stride)
    for y in range(height):
        ftype = raw[y * (stride + 1)]
        cur = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if ftype == 1:  # Sub
            for x in range(bpp, stride):
                cur[x] = (cur[x] + cur[x - bpp]) & 0xFF
        elif ftype == 2:  # Up
            for x in range(stride):
                cur[x] = (cur[x] + prev[x]) & 0xFF
        elif ftype == 3:  # Average
            for x in range(stride):
                left = cur[x - bpp] if x >= bpp else 0
                cur[x] = (cur[x] + ((left + prev[x]) >> 1)) & 0xFF
        elif ftype == 4:  # Paeth
            for x in range(stride):
                left = cur[x - bpp] if x >= bpp else 0
                upleft = prev[x - bpp] if x >= bpp else 0
                cur[x] = (cur[x] + _paeth(left, prev[x], upleft)) & 0xFF
        elif ftype != 0:
            raise ValueError("%s: bad filter type %d in row %d" % (path, ftype, y))
        out += cur
        prev = cur
    pixels = np.frombuffer(bytes(out), np.uint8)
    return pixels.reshape(height, width) if channels == 1 else pixels.reshape(height, width, channels)


def read_ppm(path):
    """A binary 8-bit PPM (P6) as (H, W, 3) uint8 (comment lines allowed)."""
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    if fields[0] != b"P6" or int(fields[3]) != 255:
        raise ValueError("%s: not an 8-bit binary PPM" % path)
    w, h = int(fields[1]), int(fields[2])
    return np.frombuffer(data, np.uint8, w * h * 3, pos + 1).reshape(h, w, 3)
