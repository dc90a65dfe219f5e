"""Masks of photographs and range maps: GrabCut on the device, and the histogram models that start it."""
from . import _default
from ._megavox import _mask_apply, _mask_train


def apply(image, *, rect=None, seeds=None, model=None, iterations=5, erode=2, device=None, progress=None):
    """The mask of `image` ((h, w), (h, w, 1) or (h, w, 3); uint8 or uint16) as a (h, w) uint8 array, 0 or 255:
    GrabCut, then a 5x5 median and an erosion of `erode` pixels, as `megavox mask apply`.

    Starts (at least one): rect (x, y, width, height: outside sure background); seeds, a (h, w) uint8 map of
    0 / 64 / 128 / 192 / 255 (sure bg, probable bg, unknown, probable fg, sure fg); model, a .mvm path.
    """
    return _mask_apply(_default.device(device), image, rect, seeds, model, iterations, erode, progress)


def train(images, masks, out, *, device=None):
    """Trains a histogram model on images and their (h, w) uint8 masks (255 foreground, 0 background, anything
    else skipped) and writes it to `out` (.mvm), as `megavox mask train`."""
    _mask_train(_default.device(device), list(images), list(masks), out)
