"""Point clouds: LOD point hierarchies (OMiCroN's bottom-up build) from a file or from numpy arrays, and read back."""
import os

import numpy as np

from . import _default
from ._megavox import _points_build, _points_open


def build(source, out, *, format="mvx", depth=0, max_node_points=16384, rgb=None, intensity=None,
          classification=None, tiles_version="1.1", crs=None, bounds=None, device=None, progress=None):
    """Builds a point hierarchy at `out` (a .mvx file, or with format="3dtiles" a 3D Tiles folder).

    source: a PLY or LAS path, or positions as a float32 or float64 (n, 3) array in world units. Arrays go onto
    the grid a PLY of the same values gets (float32 as float, float64 as double), so they build what that PLY
    builds. With arrays: rgb uint8 or uint16 (n, 3), intensity uint16 (n,), classification uint8 (n,) (kept as one
    extra byte per point). format="3dtiles": tiles_version "1.1" (glTF tiles, placed on the globe when the cloud
    has a CRS; crs="EPSG:N" or WKT overrides the input's) or "1.0" (.pnts). bounds=(min x, y, z, max x, y, z):
    only a LAS or LAZ file's points in that box (a COPC file decodes only the chunks that meet it).
    progress(stage, fraction) may return False to cancel.
    """
    _points_build(_default.device(device), source, out, format, depth, max_node_points, rgb, intensity,
                  classification, progress, tiles_version, crs, bounds)


class PointHierarchy:
    """A .mvx point hierarchy read whole: nodes breadth-first (root first, each node's children contiguous in
    octant order) and the points of every node in node order."""

    def __init__(self, info, nodes, xyz, rgb, intensity, extra, normal):
        self.info = info            #: dict: points_in, points_kept, points_dropped, depth, scale, offset, crs, format, fields
        self.nodes = nodes          #: structured array of megavox.NODE_DTYPE
        self.xyz = xyz              #: float64 (p, 3), world units
        self.rgb = rgb              #: uint16 (p, 3), or None
        self.intensity = intensity  #: uint16 (p,), or None
        self.extra = extra          #: uint8 (p, extra bytes): the record info["fields"] lays out, or None (arrays: unnamed)
        self.normal = normal        #: float32 (p, 3), or None

    def __len__(self):
        return len(self.nodes)

    def node_points(self, i):
        """The slice of node i's points in xyz and the other columns."""
        n = self.nodes[i]
        first = int(n["first_point"])
        return slice(first, first + int(n["point_count"]))

    def field(self, name):
        """One named field of every point (a LAS file's "classification", "gps_time", "return_number", its typed
        extra bytes, ...) as an array of its own type: (p,) or (p, count). Scale and add are not applied."""
        for f in self.info.get("fields", []):
            if f["name"] == name:
                dtype = np.dtype(f["dtype"])
                start = f["offset"]
                raw = np.ascontiguousarray(self.extra[:, start:start + dtype.itemsize * f["count"]])
                values = raw.view(dtype)
                return values[:, 0] if f["count"] == 1 else values
        names = ", ".join(f["name"] for f in self.info.get("fields", [])) or "none"
        raise KeyError(f"no field {name!r} (fields: {names})")

    def leaves(self):
        """Indices of the leaf nodes (they hold every point kept, once)."""
        return (self.nodes["child_mask"] == 0).nonzero()[0]

    def __repr__(self):
        return f"<megavox.points.PointHierarchy {len(self.nodes)} nodes, {len(self.xyz)} points>"


def open(path, device=None):
    """Reads the .mvx point hierarchy at `path`."""
    return PointHierarchy(*_points_open(_default.device(device), os.fspath(path)))
