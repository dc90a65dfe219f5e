# trace_mvx.py FILE.mvx: the installed Python module's twin of consumer/trace_mvx.c: the same 16 x 16 grid of
# rays straight down through the model's bounds; prints "hits N".
import sys

import numpy as np

import megavox

scene = megavox.Device().open(sys.argv[1])
info = scene.info
lo, hi = np.array(info["lower"]), np.array(info["upper"])
i = np.arange(256)
origins = np.stack([lo[0] + (hi[0] - lo[0]) * ((i % 16) + 0.5) / 16, lo[1] + (hi[1] - lo[1]) * ((i // 16) + 0.5) / 16,
                    np.full(256, hi[2] + 1)], axis=1).astype(np.float32)
directions = np.tile(np.array([[0, 0, -1]], np.float32), (256, 1))
hits = scene.trace(origins, directions)
print("hits", int(np.isfinite(hits["t"]).sum()))
