"""numpy record types laid out exactly as the C API's structs, so results come back without a copy."""
import numpy as np

#: One ray's hit, MvTraceHit (32 bytes): t (inf: a miss; NaN: gave up after max_steps), the level of the cell hit
#: (0: a voxel), the cell at that level (its first voxel is cell << level) and the face entered.
HIT_DTYPE = np.dtype([("t", "<f4"), ("level", "<u4"), ("cell", "<u4", (3,)), ("normal", "<i4", (3,))])

#: One node of a point hierarchy, MvPointNode (40 bytes, as .mvx stores it). code: the Morton code with a sentinel
#: bit (the root is 1; child o of c is (c << 3) | o); a node's points are [first_point, first_point + point_count).
NODE_DTYPE = np.dtype([("code", "<u8"), ("first_point", "<u8"), ("subtree_points", "<u8"), ("point_count", "<u4"),
                       ("first_child", "<u4"), ("child_mask", "u1"), ("level", "u1"), ("pad", "<u2"),
                       ("reserved", "<u4")])

assert HIT_DTYPE.itemsize == 32 and NODE_DTYPE.itemsize == 40
