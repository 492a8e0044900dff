"""Issue 30: map servers read only their maps folder (the image too), and check an image's size from
its header before decoding it (a 165 KB PNG of 12000 x 12000 took 1.9 GB)."""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

import pytest

from pmk_nb.errors import INVALID_MAP_DATA, MAP_DOES_NOT_EXIST, MapImageTooLarge, MapLoadError, MapOutsideFolder
from pmk_nb.robot.mapstore import MapStore
from pmk_nb.rosmap.files import read_map
from pmk_nb.rosmap.guard import MAX_MAP_PIXELS
from pmk_nb.rosmap.header import header_size
from tests.fixtures_sim import room_grid, write_test_map

SIDE = 12000  # 144 M pixels, over the 100 M cap


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def bomb_png(path: Path, side: int = SIDE) -> Path:
    """A real, valid gray PNG of side x side white pixels: ~140 KB on disk for 144 M pixels."""
    packer = zlib.compressobj(9)
    row = b"\x00" + b"\xff" * side
    body = b"".join(packer.compress(row) for _ in range(side)) + packer.flush()
    ihdr = struct.pack(">IIBBBBB", side, side, 8, 0, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", ihdr) + _chunk(b"IDAT", body) + _chunk(b"IEND", b""))
    return path


@pytest.fixture(scope="module")
def bomb(tmp_path_factory: pytest.TempPathFactory) -> bytes:
    return bomb_png(tmp_path_factory.mktemp("bomb") / "bomb.png").read_bytes()


def _yaml(folder: Path, name: str, image: str) -> Path:
    path = folder / f"{name}.yaml"
    path.write_text(
        f"image: {image}\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    return path


@pytest.fixture
def maps(tmp_path: Path) -> Path:
    """A maps folder with a good map, and beside it (outside) a good map and an image."""
    folder = tmp_path / "ALMA_MAPS"
    write_test_map(room_grid(), folder, "room")
    write_test_map(room_grid(), tmp_path / "elsewhere", "secret")
    outside_image = tmp_path / "elsewhere" / "secret.pgm"
    _yaml(folder, "absolute", str(outside_image))
    _yaml(folder, "dotdot", "../elsewhere/secret.pgm")
    (folder / "link.pgm").symlink_to(outside_image)
    _yaml(folder, "linked", "link.pgm")
    return folder


@pytest.mark.parametrize("name", ["absolute", "dotdot", "linked"])
def test_the_chairs_map_server_refuses_an_image_outside_its_folder(maps: Path, name: str) -> None:
    store = MapStore(maps)
    assert store.load("room.yaml")[0] == 0
    code, text = store.load(f"{name}.yaml")
    assert code == INVALID_MAP_DATA and "outside the maps folder" in text and "image" in text
    assert store.current is not None and store.current.path.name == "room.yaml"  # the old map kept


def test_read_map_names_the_image_and_the_folder(maps: Path) -> None:
    with pytest.raises(MapOutsideFolder) as info:
        read_map(maps / "linked.yaml", within=maps)
    err = info.value
    assert (err.what, err.folder, err.path) == ("image", str(maps.resolve()), str(maps / "link.pgm"))
    with pytest.raises(MapOutsideFolder) as info:
        read_map(maps.parent / "elsewhere" / "secret.yaml", within=maps)
    assert info.value.what == "YAML" and info.value.code == MAP_DOES_NOT_EXIST
    assert read_map(maps / "linked.yaml").width == 120  # without a folder (the dashboard's own files): read


@pytest.mark.parametrize("name", ["absolute", "dotdot", "linked"])
def test_the_simulator_refuses_an_image_outside_its_folder(sim_factory, maps: Path, name: str) -> None:
    sim = sim_factory(maps_dir=maps, grid=room_grid(8.0, 8.0), start_pose=(1.0, 1.0, 0.0))
    before = sim.grid
    assert sim.load_map(maps / f"{name}.yaml") == INVALID_MAP_DATA
    assert sim.grid is before


def test_the_simulator_refuses_a_yaml_outside_its_folder(sim_factory, maps: Path) -> None:
    sim = sim_factory(maps_dir=maps, grid=room_grid(8.0, 8.0), start_pose=(1.0, 1.0, 0.0))
    before = sim.grid
    assert sim.load_map(maps.parent / "elsewhere" / "secret.yaml") == MAP_DOES_NOT_EXIST
    assert sim.grid is before
    assert sim.load_map(maps / "room.yaml") == 0 and sim.grid is not before  # inside: loaded


def _no_decoding(monkeypatch: pytest.MonkeyPatch) -> None:
    """Pillow may open (read a header) but decodes no pixel."""
    from PIL import Image, ImageFile

    def refuse(self: Image.Image) -> None:
        raise AssertionError(f"{getattr(self, 'filename', self)} was decoded")

    monkeypatch.setattr(ImageFile.ImageFile, "load", refuse)
    monkeypatch.setattr(Image.Image, "load", refuse)


@pytest.mark.slow
def test_a_png_bomb_is_refused_from_its_header(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, bomb: bytes) -> None:
    png = tmp_path / "bomb.png"
    png.write_bytes(bomb)
    assert png.stat().st_size < 200_000 and header_size(png) == (SIDE, SIDE)
    yaml = _yaml(tmp_path, "bomb", "bomb.png")
    _no_decoding(monkeypatch)
    with pytest.raises(MapImageTooLarge) as info:
        read_map(yaml)
    err = info.value
    assert (err.width, err.height, err.limit, err.code) == (SIDE, SIDE, MAX_MAP_PIXELS, INVALID_MAP_DATA)
    assert "12000x12000 pixels" in str(err)
    monkeypatch.setenv("PMK_MAP_MAX_PIXELS", str(SIDE * SIDE))  # a site with the memory may raise the cap
    with pytest.raises(MapLoadError) as raised:
        read_map(yaml)
    assert "was decoded" in str(raised.value.__cause__)  # past the check, at the (stubbed) decoder


@pytest.mark.slow
def test_the_map_servers_refuse_a_png_bomb(
    sim_factory, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, bomb: bytes
) -> None:
    folder = tmp_path / "maps"
    folder.mkdir()
    (folder / "bomb.png").write_bytes(bomb)
    _yaml(folder, "bomb", "bomb.png")
    _no_decoding(monkeypatch)
    code, text = MapStore(folder).load("bomb.yaml")
    assert code == INVALID_MAP_DATA and "12000x12000" in text
    sim = sim_factory(maps_dir=folder, grid=room_grid(), start_pose=(1.0, 1.0, 0.0))
    assert sim.load_map(folder / "bomb.yaml") == INVALID_MAP_DATA


@pytest.mark.parametrize("fmt", ["BMP", "GIF"])
def test_other_formats_are_measured_before_decoding(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fmt: str) -> None:
    """The cap applies to the size Pillow opened, whatever the format (GIF: no header parser of ours)."""
    from PIL import Image

    image = tmp_path / f"m.{fmt.lower()}"
    Image.new("L", (80, 60), 254).save(image, fmt)
    with Image.open(image) as im:
        assert im.size == (80, 60)
    yaml = _yaml(tmp_path, "m", image.name)
    assert read_map(yaml).width == 80
    _no_decoding(monkeypatch)
    with pytest.raises(MapImageTooLarge, match="80x60 pixels"):
        read_map(yaml, max_pixels=80 * 60 - 1)
