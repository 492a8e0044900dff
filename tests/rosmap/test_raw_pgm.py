"""A binary 8-bit PGM without comments is read straight from its bytes (a 100 M-cell map: one copy, not
Pillow's three); every reader gets the grid Pillow's decode gives, and any other PGM goes Pillow's way."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pmk_nb.errors import MapLoadError
from pmk_nb.rosmap import image as rosmap_image
from pmk_nb.rosmap import read_map


def _map(tmp_path: Path, header: bytes, pixels: bytes, name: str = "m.pgm") -> Path:
    (tmp_path / name).write_bytes(header + pixels)
    yaml = tmp_path / (name + ".yaml")
    yaml.write_text(
        f"image: {name}\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    return yaml


def _by_pillow(monkeypatch: pytest.MonkeyPatch, yaml: Path, reader: str) -> np.ndarray:
    with monkeypatch.context() as m:
        m.setattr(rosmap_image, "_raw_gray_pgm", lambda path, max_pixels: None)
        return read_map(yaml, reader=reader).data


@pytest.mark.parametrize("reader", ["ros1", "nav2_humble", "nav2_jazzy"])
@pytest.mark.parametrize("shape", [(3, 5), (300, 257)])  # below and above the gray lookup's size
def test_the_bytes_read_as_pillow_decodes_them(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, reader: str, shape: tuple[int, int]
) -> None:
    h, w = shape
    values = np.random.default_rng(h).integers(0, 256, size=(h, w), dtype=np.uint8)
    yaml = _map(tmp_path, f"P5\n{w} {h}\n255\n".encode(), values.tobytes())
    seen: list[object] = []
    real = rosmap_image._raw_gray_pgm
    monkeypatch.setattr(rosmap_image, "_raw_gray_pgm", lambda p, c: seen.append(real(p, c)) or seen[-1])
    grid = read_map(yaml, reader=reader)
    assert seen and seen[0] is not None  # read from its bytes
    assert grid.data.shape == (h, w) and np.array_equal(grid.data, _by_pillow(monkeypatch, yaml, reader))


def test_a_pgm_with_a_comment_or_another_maxval_goes_pillows_way(tmp_path: Path) -> None:
    pixels = bytes(range(12))
    commented = _map(tmp_path, b"P5\n# CREATOR: map_saver.cpp 0.050 m/pix\n4 3\n255\n", pixels, "a.pgm")
    assert rosmap_image._raw_gray_pgm(commented.with_suffix(""), None) is None
    assert read_map(commented).data.shape == (3, 4)
    other = _map(tmp_path, b"P5\n4 3\n15\n", pixels, "b.pgm")
    assert rosmap_image._raw_gray_pgm(other.with_suffix(""), None) is None


def test_a_truncated_pgm_is_refused_as_before(tmp_path: Path) -> None:
    yaml = _map(tmp_path, b"P5\n40 30\n255\n", b"\x00" * 100)
    assert rosmap_image._raw_gray_pgm(yaml.with_suffix(""), None) is None
    with pytest.raises(MapLoadError):
        read_map(yaml)
