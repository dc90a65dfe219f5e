#!/usr/bin/env python3
"""Gives a binary little-endian PLY mesh (float x, y, z vertices, then faces) smooth vertex colours from position,
for the mesh rows of `megavox bench attributes`: each channel is 255 * (0.5 + 0.5 sin(6 pi t)), t the vertex's
place along x, y or z in the mesh's bounding box, rounded. The faces are copied as they are.

Usage: scripts/colour_ply.py IN.ply OUT.ply
"""
import math
import struct
import sys


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    src, dst = sys.argv[1], sys.argv[2]
    with open(src, "rb") as f:
        data = f.read()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        print(f"{src}: not a PLY file", file=sys.stderr)
        return 1
    header = data[:end].decode("ascii", "replace").splitlines()
    body = end + len(b"end_header\n")
    vertices, props, element = 0, [], None
    for line in header:
        words = line.split()
        if words[:1] == ["format"] and words[1:2] != ["binary_little_endian"]:
            print(f"{src}: {line}: only binary_little_endian is read", file=sys.stderr)
            return 1
        if words[:1] == ["element"]:
            element = words[1]
            if element == "vertex":
                vertices = int(words[2])
        elif words[:1] == ["property"] and element == "vertex":
            props.append((words[1], words[2]))
    if props != [("float", "x"), ("float", "y"), ("float", "z")]:
        print(f"{src}: vertices must be exactly float x, y, z (found {props})", file=sys.stderr)
        return 1
    xyz = struct.unpack_from(f"<{3 * vertices}f", data, body)
    lo = [min(xyz[k::3]) for k in range(3)]
    span = [max(max(xyz[k::3]) - lo[k], 1e-30) for k in range(3)]
    out = bytearray()
    for v in range(vertices):
        p = xyz[3 * v:3 * v + 3]
        rgb = [round(255 * (0.5 + 0.5 * math.sin(6 * math.pi * (p[k] - lo[k]) / span[k]))) for k in range(3)]
        out += struct.pack("<3f3B", *p, *rgb)
    lines = []
    for line in header:
        lines.append(line)
        if line.strip() == "property float z":
            lines += ["property uchar red", "property uchar green", "property uchar blue"]
    with open(dst, "wb") as f:
        f.write(("\n".join(lines) + "\nend_header\n").encode("ascii"))
        f.write(out)
        f.write(data[body + 12 * vertices:])
    return 0


if __name__ == "__main__":
    sys.exit(main())
