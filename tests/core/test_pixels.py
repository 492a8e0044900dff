"""The access check's pixel tools after the speed work of issue 31: narrow wrapped row counts in the
erosion and a sort-based unique give exactly what scipy's distance transform and numpy's unique give."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from pmk_nb.pixels import erode, erode_rows, least_roots, regions, shift_bits, sorted_unique


@pytest.mark.parametrize("radius", [1.0, 2.5, 7.000000001, 27.34, 127.5, 130.2])
def test_erode_matches_distance_transform(radius: float) -> None:
    """Radii whose windows fit one-byte counts (2r + 1 < 256) and wider ones (two-byte counts)."""
    rng = np.random.default_rng(int(radius * 10))
    mask = rng.random((600, 900)) > 2e-5
    mask[:, :1] = mask[:, -1:] = mask[:1] = mask[-1:] = False  # outside the grid is not free
    want = ndimage.distance_transform_edt(mask) > radius
    assert want.any() and not want.all()
    assert np.array_equal(erode(mask, radius), want)


def test_erode_rows_strips_agree_with_whole() -> None:
    """Strips of any height give the rows of the whole erosion (wrapped counts restart per strip)."""
    rng = np.random.default_rng(3)
    mask = rng.random((97, 300)) > 0.01
    whole = erode(mask, 6.5)
    for step in (1, 7, 40):
        got = np.zeros_like(whole)
        for a, rows in erode_rows(lambda lo, hi: mask[lo:hi], *mask.shape, 6.5, step=step):
            got[a : a + len(rows)] = rows
        assert np.array_equal(got, whole)


@pytest.mark.parametrize("n", [0, 1, 2, 1000])
def test_sorted_unique_is_numpy_unique(n: int) -> None:
    values = np.random.default_rng(n).integers(-50, 50, size=n)
    assert np.array_equal(sorted_unique(values), np.unique(values))


def test_region_edges_sorted_unique_pairs() -> None:
    """Touching regions of different owners: each pair once, sorted, as np.unique(axis=0) gave."""
    rng = np.random.default_rng(5)
    mask = rng.random((60, 80)) > 0.3
    owner = (np.arange(80)[None, :] // 9 + np.arange(60)[:, None] // 7).astype(np.int32)
    labels, label_owner, edges = regions(mask, owner)
    assert len(edges) > 10
    assert np.array_equal(edges, np.unique(edges, axis=0))
    for u, v in edges.tolist():
        assert label_owner[u] != label_owner[v]
        a, b = labels == u, labels == v
        across = (a[:, :-1] & b[:, 1:]).any() or (a[:, 1:] & b[:, :-1]).any()
        assert across or (a[:-1] & b[1:]).any() or (a[1:] & b[:-1]).any()


@pytest.mark.parametrize("k", [0, 1, 5, 63, 64, 65, 130, 200, 400])
def test_shift_bits_moves_packed_columns(k: int) -> None:
    """Packed rows moved k columns: bit x of the result is column x + k of the rows, zeros past the end
    (across word boundaries and by more than a word)."""
    rng = np.random.default_rng(k)
    rows = rng.random((5, 200)) > 0.5
    words = np.zeros((5, 4 * 8), dtype=np.uint8)
    words[:, :25] = np.packbits(rows, axis=1, bitorder="little")
    got = np.unpackbits(shift_bits(words.view("<u8"), k).view(np.uint8), axis=1, count=200, bitorder="little")
    want = np.zeros_like(rows)
    want[:, : max(0, 200 - k)] = rows[:, k:]
    assert np.array_equal(got.view(bool), want)


@pytest.mark.parametrize("seed", range(6))
def test_union_gives_each_item_the_least_item_of_its_component(seed: int) -> None:
    """Chains (each item joined to one later item and it to no other earlier one), pairs in both orders,
    repeated pairs and self pairs: every item's root is the least item of its component."""
    rng = np.random.default_rng(seed)
    n = 400
    a = rng.integers(0, n, 300)
    b = np.where(rng.random(300) < 0.7, np.minimum(a + rng.integers(1, 4, 300), n - 1), rng.integers(0, n, 300))
    a, b = np.concatenate([a, a[:20]]), np.concatenate([b, b[:20]])  # some pairs twice
    want = np.arange(n)
    for _ in range(n):  # plain relaxation to the fixed point: the least item reachable
        low = np.minimum(want[a], want[b])
        np.minimum.at(want, a, low)
        np.minimum.at(want, b, low)
    assert np.array_equal(least_roots(n, a, b), want)
    assert len(set(want.tolist())) > 10
