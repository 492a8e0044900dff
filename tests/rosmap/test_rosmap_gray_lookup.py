"""The big-gray-map lookup in ``rosmap.image`` gives exactly what each reader's own maths gives.

The map server node reads 4000x4000 maps on every deploy (issue 9: deploy + confirm <= 3 s), so 8-bit
gray images of 65536 pixels or more go through a 256-entry table built with the readers' own functions.
"""

from __future__ import annotations

import numpy as np
import pytest

from pmk_nb.rosmap import image as im


def _gray(values: np.ndarray) -> im.DecodedImage:
    rgba = np.stack([values, values, values, np.full_like(values, 255)], axis=2)
    return im.DecodedImage(rgba=rgba, has_alpha=False, sdl=values[..., None].copy(), sdl_alpha_mask=False)


DIRECT = {"ros1": im._ros1, "nav2_humble": im._nav2_humble, "nav2_jazzy": im._nav2_jazzy}


@pytest.mark.parametrize("reader", sorted(DIRECT))
@pytest.mark.parametrize("mode", ["trinary", "scale", "raw"])
@pytest.mark.parametrize("negate", [False, True])
@pytest.mark.parametrize("thresholds", [(0.65, 0.196), (0.9, 0.1), (0.6, 0.55)])
def test_lookup_equals_the_readers_maths(reader: str, mode: str, negate: bool, thresholds: tuple[float, float]) -> None:
    values = np.random.default_rng(7).integers(0, 256, size=(300, 300), dtype=np.uint8)
    img = _gray(values)
    assert im._plain_gray(img) is not None  # big enough, plain gray: the lookup is taken
    occ, free = thresholds
    kw = dict(mode=mode, negate=negate, occupied_thresh=occ, free_thresh=free)
    got = im.image_to_data(img, reader=reader, **kw)
    want = DIRECT[reader](img, mode, negate, occ, free)
    assert got.dtype == np.int8 and np.array_equal(got, want)


def test_not_plain_gray_keeps_the_readers_maths() -> None:
    values = np.random.default_rng(8).integers(0, 256, size=(300, 300), dtype=np.uint8)
    img = _gray(values)
    img.rgba[5, 5, 0] ^= 1  # one coloured pixel
    assert im._plain_gray(img) is None
    small = _gray(values[:100, :100])
    assert im._plain_gray(small) is None  # small maps: not worth a table
    alpha = _gray(values)
    alpha.has_alpha = True
    assert im._plain_gray(alpha) is None


@pytest.mark.parametrize("reader", sorted(DIRECT))
@pytest.mark.parametrize("mode", ["trinary", "scale", "raw"])
def test_a_gray_only_image_reads_as_its_expanded_self(reader: str, mode: str) -> None:
    """An opaque 8-bit gray file keeps no RGBA copy (``rgba=None``): every reader sees the same grid,
    looked up or by its own maths, as from the RGBA Pillow would have made, in either row order."""
    values = np.random.default_rng(9).integers(0, 256, size=(300, 300), dtype=np.uint8)
    lean = im.DecodedImage(rgba=None, has_alpha=False, sdl=values[..., None].copy(), sdl_alpha_mask=False)
    kw = dict(mode=mode, negate=False, occupied_thresh=0.65, free_thresh=0.196)
    want = DIRECT[reader](_gray(values), mode, False, 0.65, 0.196)
    assert np.array_equal(im.image_to_data(lean, reader=reader, **kw), want)
    assert np.array_equal(im.image_to_data(lean, reader=reader, bottom_up=True, **kw), want[::-1])
    small = im.DecodedImage(rgba=None, has_alpha=False, sdl=values[:50, :50, None].copy(), sdl_alpha_mask=False)
    assert np.array_equal(im.image_to_data(small, reader=reader, **kw), want[:50, :50])  # by the maths
    assert np.array_equal(lean.rgba, _gray(values).rgba)
