"""Issue 38: the pixel cap is checked on what Pillow will decode, priced by the pixel mode, and a Netpbm
header is read by its grammar (a comment ended by CR made a 4000 x 4000 PGM read as 1x1, so it was
decoded under a 1 M cap)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image, ImageFile

from pmk_nb.errors import INVALID_MAP_DATA, MalformedImageHeader, MapImageTooLarge
from pmk_nb.rosmap import header_size, read_map
from pmk_nb.rosmap import image as rosmap_image
from pmk_nb.rosmap.guard import GRAY8_BYTES, decode_bytes, pixels_allowed

CAP = 1_000_000
REPO = Path(__file__).resolve().parents[2]


def _yaml(folder: Path, image: str) -> Path:
    path = folder / "m.yaml"
    path.write_text(
        f"image: {image}\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    return path


@pytest.fixture
def no_decoding(monkeypatch: pytest.MonkeyPatch) -> None:
    """Any pixel decoded fails the test: only headers may be read."""

    def refuse(self: Image.Image) -> None:
        raise AssertionError(f"{getattr(self, 'filename', self)} was decoded")

    monkeypatch.setattr(ImageFile.ImageFile, "load", refuse)
    monkeypatch.setattr(Image.Image, "load", refuse)


def cr_comment_pgm(path: Path, side: int = 4000) -> Path:
    """The issue's file: the header's comment ends in CR, and the raster starts with the bytes "1 1\\n"
    (valid pixels), which a line-by-line reader took for the size."""
    header = f"P5 # made by hand\r{side} {side} 255\n".encode("ascii")
    raster = b"1 1\n" + b"\xfe" * (side * side - 4)
    path.write_bytes(header + raster)
    return path


def test_a_comment_ended_by_cr_does_not_shrink_the_image(tmp_path: Path, no_decoding: None) -> None:
    pgm = cr_comment_pgm(tmp_path / "cr.pgm")
    assert header_size(pgm) == (4000, 4000)
    with Image.open(pgm) as im:  # the decoder's own reading agrees
        assert im.size == (4000, 4000)
    with pytest.raises(MapImageTooLarge) as info:
        read_map(_yaml(tmp_path, "cr.pgm"), max_pixels=CAP)
    err = info.value
    assert (err.width, err.height, err.limit, err.mode, err.code) == (4000, 4000, CAP, "L", INVALID_MAP_DATA)
    assert err.path == str(pgm)


def test_the_cap_is_checked_on_the_decoders_size_not_on_a_second_reading(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, no_decoding: None
) -> None:
    """Whatever a header parser of ours says (here: a lying one), the size Pillow opened is priced."""
    cr_comment_pgm(tmp_path / "cr.pgm", side=1200)
    monkeypatch.setattr(rosmap_image, "header_size", lambda path: (1, 1))
    with pytest.raises(MapImageTooLarge) as info:
        read_map(_yaml(tmp_path, "cr.pgm"), max_pixels=CAP)
    assert (info.value.width, info.value.height) == (1200, 1200)


def test_a_header_the_decoder_reads_otherwise_is_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    cr_comment_pgm(tmp_path / "small.pgm", side=40)
    monkeypatch.setattr(rosmap_image, "header_size", lambda path: (1, 1))
    with pytest.raises(MalformedImageHeader) as info:
        read_map(_yaml(tmp_path, "small.pgm"))
    assert info.value.path == str(tmp_path / "small.pgm") and "40x40" in info.value.reason


@pytest.mark.parametrize(
    ("header", "size"),
    [
        (b"P5\n4 3\n255\n", (4, 3)),
        (b"P5 # a comment\r4 3\r255\r", (4, 3)),  # CR ends comments and separates tokens
        (b"P5\t4\x0b3\x0c255 ", (4, 3)),  # every whitespace byte of the spec
        (b"P5\n#one\n#two\r\n  4\n3\n255\n", (4, 3)),
        (b"P5\n4#a comment splits no token: it is dropped whole\n0 3 255\n", (40, 3)),
        (b"P5\n4 3 255#after the maxval\n\n", (4, 3)),
        (b"P2\n4 3\n255\n", (4, 3)),
        (b"P6 #colour\r4 3 255\n", (4, 3)),
        (b"P4\n# bits: no maxval\r16 3\n", (16, 3)),
    ],
)
def test_the_netpbm_header_follows_the_grammar_as_pillow_does(tmp_path: Path, header: bytes, size: tuple) -> None:
    cells = size[0] * size[1]
    rasters = {b"P2": b"1 " * cells, b"P6": b"\x80" * cells * 3, b"P4": b"\x0f" * (size[0] // 8 * size[1])}
    raster = rasters.get(header[:2], b"\x80" * cells)
    path = tmp_path / "m.pgm"
    path.write_bytes(header + raster)
    assert header_size(path) == size
    with Image.open(path) as im:
        assert im.size == size
    assert read_map(_yaml(tmp_path, "m.pgm")).width == size[0]


@pytest.mark.parametrize(
    ("header", "why"),
    [
        (b"P5\n4 x3\n255\n", "decimal number"),
        (b"P5\n4 -3\n255\n", "decimal number"),
        (b"P5\n4 3", "it ends after 1 of its 3 numbers"),  # "3" has no whitespace after it
        (b"P5\n# never ends", "comment runs past the end"),
        (b"P5\n0 3\n255\n", "side of 0 pixels"),
        (b"P5\n4 3\n70000\n", "maxval 70000"),
        (b"P5\n4 3\n0\n", "maxval 0"),
        (b"P54 3 255\n", "no whitespace after the magic"),
        (b"P5\n12345678901 3\n255\n", "longer than 10 digits"),
    ],
)
def test_a_malformed_netpbm_header_is_a_typed_error_naming_the_file(tmp_path: Path, header: bytes, why: str) -> None:
    path = tmp_path / "bad.pgm"
    path.write_bytes(header + (b"\x80" * 12 if header.endswith(b"\n") else b""))  # a raster after a whole header
    with pytest.raises(MalformedImageHeader) as info:
        header_size(path)
    assert info.value.path == str(path) and why in info.value.reason and str(path) in str(info.value)
    with pytest.raises(MalformedImageHeader) as again:
        read_map(_yaml(tmp_path, "bad.pgm"))
    assert again.value.path == str(path) and again.value.code == INVALID_MAP_DATA


def test_a_malformed_header_is_a_broken_map_in_the_listing(tmp_path: Path) -> None:
    from pmk_nb.library.scan import _image_size

    path = tmp_path / "bad.pgm"
    path.write_bytes(b"P5\n4 x3\n255\n")
    width, height, broken = _image_size(path)
    assert (width, height) == (0, 0) and str(path) in broken


def _save(path: Path, mode: str, side: int, **kw: object) -> Path:
    if mode == "I;16":  # a 16-bit PGM (Pillow opens it as "I")
        values = np.full((side, side), 50000, dtype=">u2")
        path.write_bytes(f"P5\n{side} {side}\n65535\n".encode() + values.tobytes())
        return path
    Image.new(mode, (side, side), 200).save(path, **kw)
    return path


@pytest.mark.parametrize(
    ("name", "mode", "kw"),
    [
        ("g16.pgm", "I;16", {}),
        ("rgba.png", "RGBA", {}),
        ("rgb.png", "RGB", {}),
        ("pal.png", "P", {}),
        ("trns.png", "L", {"transparency": 0}),
    ],
)
def test_a_16_bit_or_colour_image_is_priced_by_what_it_costs_to_decode(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, name: str, mode: str, kw: dict
) -> None:
    """An 8-bit gray image of 1000 x 1000 passes a 1 M cap; the same size in a costlier mode does not."""
    assert read_map(_yaml(tmp_path, _save(tmp_path / "gray.pgm", "L", 1000).name), max_pixels=CAP).width == 1000
    image = _save(tmp_path / name, mode, 1000, **kw)
    with Image.open(image) as im:
        opened, transparent = im.mode, "transparency" in im.info
    assert decode_bytes(opened, transparent) > GRAY8_BYTES
    allowed = pixels_allowed(CAP, opened, transparent)
    assert allowed == CAP * GRAY8_BYTES // decode_bytes(opened, transparent) < 1000 * 1000
    with pytest.raises(MapImageTooLarge) as info:
        read_map(_yaml(tmp_path, name), max_pixels=CAP)
    assert (info.value.mode, info.value.limit, info.value.width) == (opened, allowed, 1000)
    assert read_map(_yaml(tmp_path, name), max_pixels=CAP * 6).width == 1000  # with the memory: read


PEAK_SCRIPT = """
import sys
from pathlib import Path
from pmk_nb.rosmap import read_map

def status(key):  # kB
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(key + ":"):
            return int(line.split()[1]) * 1024
    raise SystemExit("no " + key + " in /proc/self/status")

image = Path(sys.argv[1])
def yaml(name, mode):
    path = image.with_name(name + "." + mode + ".yaml")
    path.write_text("image: " + name + "\\nmode: " + mode + "\\nresolution: 0.05\\norigin: [0, 0, 0]\\n"
                    "negate: 0\\noccupied_thresh: 0.65\\nfree_thresh: 0.196\\n")
    return path
tiny = image.with_name("tiny.pgm")
tiny.write_bytes(b"P5\\n300 300\\n255\\n" + bytes(range(256)) * 351 + b"\\x80" * 144)
for reader in ("ros1", "nav2_humble", "nav2_jazzy"):  # every module and code path loaded first
    read_map(yaml("tiny.pgm", "scale"), reader=reader)
Path("/proc/self/clear_refs").write_text("5")  # the peak (VmHWM) starts again from here
base = status("VmRSS")
for mode in ("trinary", "scale", "raw"):
    for reader in ("ros1", "nav2_humble", "nav2_jazzy"):
        read_map(yaml(image.name, mode), reader=reader, max_pixels=10**9)
print(status("VmHWM") - base)
"""


@pytest.mark.slow
@pytest.mark.parametrize("name", ["L.pgm", "I16.pgm", "I16.png", "RGBA.png"])
def test_the_decoding_prices_cover_what_decoding_takes(tmp_path: Path, name: str) -> None:
    """Peak memory of every reader in every map mode, in a process of its own, stays within the price
    (10 % slack for the allocator's rounding) of the mode Pillow opens."""
    import os
    import subprocess
    import sys

    side = 1500
    rng = np.random.default_rng(38)
    gray = rng.integers(0, 256, (side, side), dtype=np.uint8)
    path = tmp_path / name
    if name == "L.pgm":
        Image.fromarray(gray).save(path)
    elif name == "I16.pgm":
        path.write_bytes(f"P5\n{side} {side}\n65535\n".encode() + (gray.astype(">u2") * 257).tobytes())
    elif name == "I16.png":
        Image.fromarray(gray.astype(np.uint16) * 257).save(path)
    else:
        colour = rng.integers(0, 256, (side, side, 3), dtype=np.uint8)
        Image.fromarray(np.concatenate([colour, gray[..., None]], axis=2), "RGBA").save(path)
    with Image.open(path) as im:
        price = decode_bytes(im.mode, "transparency" in im.info)
    env = {**os.environ, "PYTHONPATH": str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    run = subprocess.run(
        [sys.executable, "-c", PEAK_SCRIPT, str(path)],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
        env=env,
    )
    assert run.returncode == 0, run.stderr
    per_pixel = int(run.stdout.strip()) / (side * side)
    print(f"{name}: {per_pixel:.1f} bytes a pixel at peak, priced {price}")
    assert per_pixel <= price * 1.1, f"{name}: {per_pixel:.1f} bytes a pixel at peak, priced {price}"
