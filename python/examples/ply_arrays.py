"""A small numpy reader of triangle-mesh PLY files (ASCII or binary little-endian; x, y, z of any float or int type;
faces as lists of 3), enough to hand a scan to megavox as arrays. Other elements and properties are skipped."""
import numpy as np

_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2", "ushort": "u2",
          "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4", "float": "f4", "float32": "f4",
          "double": "f8", "float64": "f8"}


def read_ply(path):
    """(vertices float32 (n, 3), triangles uint32 (m, 3)) of the PLY at path."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            raise ValueError(f"{path}: not a PLY file")
        fmt, elements = None, []
        while True:
            words = f.readline().decode("ascii").split()
            if not words or words[0] in ("comment", "obj_info"):
                continue
            if words[0] == "end_header":
                break
            if words[0] == "format":
                fmt = words[1]
            elif words[0] == "element":
                elements.append((words[1], int(words[2]), []))
            elif words[0] == "property":
                elements[-1][2].append(words[1:])
        body = f.read()
    if fmt not in ("ascii", "binary_little_endian"):
        raise ValueError(f"{path}: format {fmt} is not read by this example")
    vertices = triangles = None
    at = 0
    tokens = body.split() if fmt == "ascii" else None
    for name, count, props in elements:
        if fmt == "ascii":
            width = sum(1 for p in props if p[0] != "list") + sum(1 + 3 for p in props if p[0] == "list")
            table = np.array(tokens[at:at + width * count], dtype=np.float64).reshape(count, width)
            at += width * count
            names = []
            for p in props:
                names += [p[-1]] if p[0] != "list" else ["n", p[-1] + "0", p[-1] + "1", p[-1] + "2"]
            columns = {n: table[:, i] for i, n in enumerate(names)}
            if name == "vertex":
                vertices = np.stack([columns["x"], columns["y"], columns["z"]], axis=1).astype(np.float32)
            elif name == "face":
                key = [p[-1] for p in props if p[0] == "list"][0]
                triangles = np.stack([columns[key + str(k)] for k in range(3)], axis=1).astype(np.uint32)
            continue
        fields = []
        for p in props:
            if p[0] == "list":
                fields += [("n", "<" + _TYPES[p[1]]), (p[-1], "<" + _TYPES[p[2]], (3,))]
            else:
                fields.append((p[-1], "<" + _TYPES[p[0]]))
        rec = np.dtype(fields)
        table = np.frombuffer(body, dtype=rec, count=count, offset=at)
        at += rec.itemsize * count
        if name == "vertex":
            vertices = np.stack([table["x"], table["y"], table["z"]], axis=1).astype(np.float32)
        elif name == "face":
            if (table["n"] != 3).any():
                raise ValueError(f"{path}: a face that is not a triangle")
            key = [p[-1] for p in props if p[0] == "list"][0]
            triangles = np.ascontiguousarray(table[key]).astype(np.uint32)
    return vertices, triangles
