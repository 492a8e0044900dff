"""map_server reader/writer against the upstream fixtures in shared/data/map_server."""

from __future__ import annotations

import csv
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from pmk_nb.errors import MapFormatError
from pmk_nb.grid import OccupancyGrid
from pmk_nb.rosmap import files as rosmap
from pmk_nb.rosmap.files import MapLoadError, grid_to_gray, read_map, read_map_yaml, write_map
from pmk_nb.rosmap.image import decode_image, image_to_data
from tests.shared_data import MAP_SERVER_DATA

DATA = MAP_SERVER_DATA
ROS1 = DATA / "ros1_map_server"
NAV2 = DATA / "nav2_map_server"
READERS = ["ros1", "nav2_humble", "nav2_jazzy"]
SPECTRUM_CSV = {
    "ros1": ROS1 / "expected" / "spectrum_{}_occ0.65_free0.1_derived_ros1.csv",
    "nav2_humble": NAV2 / "expected" / "spectrum_{}_occ0.65_free0.1_derived_nav2_humble.csv",
    "nav2_jazzy": NAV2 / "expected" / "spectrum_{}_occ0.65_free0.1_derived_nav2_jazzy_eigen.csv",
}


def csv_grid(path: Path) -> np.ndarray:
    """Fixture CSV: first line = grid row 0 (bottom)."""
    rows = [[int(v) for v in line.split(",")] for line in path.read_text().split()]
    return np.array(rows, dtype=np.int16).astype(np.int8)


def load(
    path: Path, reader: str, mode: str = "trinary", negate: bool = False, occ: float = 0.65, free: float = 0.196
) -> np.ndarray:
    """Grid rows (row 0 = bottom) for an image loaded with explicit parameters (like loadMapFromFile)."""
    img = decode_image(path)
    data = image_to_data(img, reader=reader, mode=mode, negate=negate, occupied_thresh=occ, free_thresh=free)
    return data[::-1]


# --- 1. testmap.yaml ------------------------------------------------------------------------------


@pytest.mark.parametrize("reader", READERS)
@pytest.mark.parametrize("yaml_path", [ROS1 / "testmap.yaml", NAV2 / "testmap.yaml"])
def test_testmap_yaml_matches_upstream_array(yaml_path: Path, reader: str) -> None:
    grid = read_map(yaml_path, reader=reader)
    expected = csv_grid(ROS1 / "expected" / "testmap_g_valid_image_content.csv")
    assert (grid.width, grid.height) == (10, 10)
    assert grid.resolution == pytest.approx(0.1)
    assert grid.origin == (2.0, 3.0, 1.0)
    assert grid.frame_id == "map"
    np.testing.assert_array_equal(grid.data, expected)
    np.testing.assert_array_equal(expected, csv_grid(NAV2 / "expected" / "testmap_g_valid_image_content.csv"))


@pytest.mark.parametrize("reader", READERS)
@pytest.mark.parametrize(
    "image",
    [ROS1 / "testmap.png", ROS1 / "testmap.bmp", NAV2 / "testmap.png", NAV2 / "testmap.bmp", NAV2 / "testmap.pgm"],
)
@pytest.mark.parametrize("free", [0.1, 0.196])
def test_testmap_images_load_same_grid(image: Path, reader: str, free: float) -> None:
    expected = csv_grid(ROS1 / "expected" / "testmap_g_valid_image_content.csv")
    np.testing.assert_array_equal(load(image, reader, free=free), expected)


def test_pillow_decodes_png_and_bmp_to_identical_bytes() -> None:
    png, bmp = decode_image(ROS1 / "testmap.png"), decode_image(ROS1 / "testmap.bmp")
    np.testing.assert_array_equal(png.rgba, bmp.rgba)
    assert set(np.unique(png.rgba[..., :3]).tolist()) == {0, 255}
    pgm = decode_image(NAV2 / "testmap.pgm")
    np.testing.assert_array_equal(pgm.rgba[..., 0] == 0, png.rgba[..., 0] == 0)
    assert set(np.unique(pgm.rgba[..., 0]).tolist()) == {0, 254}
    # SDL gives ROS 1 a BGR surface for BMP: same bytes reversed per pixel
    np.testing.assert_array_equal(bmp.sdl, png.sdl[..., ::-1])


# --- 2. testmap2 (negate 1) ----------------------------------------------------------------------


@pytest.mark.parametrize("reader", READERS)
def test_testmap2_negate(reader: str) -> None:
    grid = read_map(ROS1 / "testmap2.yaml", reader=reader)
    assert (grid.width, grid.height) == (12, 12)
    assert grid.origin == (-2.0, -3.0, -1.0)
    np.testing.assert_array_equal(grid.data, csv_grid(ROS1 / "expected" / "testmap2_tmap2_g_valid_image_content.csv"))


# --- 3. spectrum.png ------------------------------------------------------------------------------


@pytest.mark.parametrize("reader", READERS)
@pytest.mark.parametrize("mode", ["trinary", "scale", "raw"])
def test_spectrum_per_cell(reader: str, mode: str) -> None:
    data = load(ROS1 / "spectrum.png", reader, mode=mode, free=0.1)
    np.testing.assert_array_equal(data, csv_grid(Path(str(SPECTRUM_CSV[reader]).format(mode))))


@pytest.mark.parametrize("reader", READERS)
def test_spectrum_counts(reader: str) -> None:
    spectrum = ROS1 / "spectrum.png"
    tri = load(spectrum, reader, free=0.1)
    assert (np.sum(tri == 100), np.sum(tri == 0), np.sum(tri == -1)) == (90, 26, 140)
    scale = load(spectrum, reader, mode="scale", free=0.1)
    mid = np.sum((scale >= 1) & (scale <= 99))
    if reader == "ros1":
        assert (np.sum(scale == 100), np.sum(scale == 0), mid) == (90, 26, 140)
    else:
        assert (np.sum(scale == 100), np.sum(scale == 0), mid) == (90, 27, 139)
    raw = load(spectrum, reader, mode="raw", free=0.1).reshape(-1)
    if reader == "ros1":
        np.testing.assert_array_equal(raw.view(np.uint8), np.arange(256))
    else:
        np.testing.assert_array_equal(raw[:101], np.arange(101))
        assert np.all(raw[101:] == -1)
    scale_ros1 = load(spectrum, "ros1", mode="scale", free=0.1).astype(int)
    assert np.abs(scale.astype(int) - scale_ros1).max() <= 2


# --- 4. every gray value --------------------------------------------------------------------------

GRAY_COLUMNS = [
    ("ros1_trinary_occ.65_free.196", "ros1", "trinary", 0.196),
    ("nav2humble_trinary_occ.65_free.196", "nav2_humble", "trinary", 0.196),
    ("nav2jazzy+_trinary_occ.65_free.196", "nav2_jazzy", "trinary", 0.196),
    ("ros1_trinary_occ.65_free.25", "ros1", "trinary", 0.25),
    ("nav2humble_trinary_occ.65_free.25", "nav2_humble", "trinary", 0.25),
    ("nav2jazzy+_trinary_occ.65_free.25", "nav2_jazzy", "trinary", 0.25),
    ("ros1_scale_occ.65_free.196", "ros1", "scale", 0.196),
    ("nav2humble_scale_occ.65_free.196", "nav2_humble", "scale", 0.196),
    ("nav2jazzy+_scale_occ.65_free.196", "nav2_jazzy", "scale", 0.196),
    ("ros1_raw", "ros1", "raw", 0.196),
    ("nav2_raw_humble_and_jazzy+", "nav2_humble", "raw", 0.196),
    ("nav2_raw_humble_and_jazzy+", "nav2_jazzy", "raw", 0.196),
]


@pytest.fixture(scope="module")
def gray_table() -> dict[str, list[int]]:
    with (DATA / "expected_by_gray_value_derived.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [int(r["gray"]) for r in rows] == list(range(256))
    return {key: [int(r[key]) for r in rows] for key in rows[0]}


@pytest.mark.parametrize(("column", "reader", "mode", "free"), GRAY_COLUMNS)
@pytest.mark.parametrize("fmt", ["png", "pgm", "bmp"])
def test_every_gray_value(
    tmp_path: Path, gray_table: dict[str, list[int]], column: str, reader: str, mode: str, free: float, fmt: str
) -> None:
    pixels = np.arange(256, dtype=np.uint8).reshape(1, 256)
    path = tmp_path / f"gray.{fmt}"
    image = (
        Image.fromarray(pixels, mode="L")
        if fmt != "bmp"
        else Image.fromarray(np.repeat(pixels[..., None], 3, axis=2), mode="RGB")
    )
    image.save(path)
    got = load(path, reader, mode=mode, free=free).reshape(-1).astype(int).tolist()
    assert got == gray_table[column]


def test_gray_205_is_free_with_free_thresh_025(gray_table: dict[str, list[int]]) -> None:
    assert gray_table["ros1_trinary_occ.65_free.25"][205] == 0
    assert gray_table["ros1_trinary_occ.65_free.196"][205] == -1


# --- 5. errors with Nav2 LoadMap codes --------------------------------------------------------------


@pytest.mark.parametrize("reader", READERS)
def test_invalid_image_yaml_is_code_2(reader: str) -> None:
    with pytest.raises(MapLoadError) as info:
        read_map(NAV2 / "invalid_image.yaml", reader=reader)
    assert info.value.code == rosmap.INVALID_MAP_DATA == 2
    assert "invalid.png" in str(info.value)
    assert isinstance(info.value, MapFormatError)


def test_missing_yaml_is_code_3(tmp_path: Path) -> None:
    with pytest.raises(MapLoadError) as info:
        read_map(tmp_path / "invalid_file.yaml")
    assert info.value.code == 3
    assert "invalid_file.yaml" in str(info.value)


def test_empty_path_is_code_1() -> None:
    with pytest.raises(MapLoadError) as info:
        read_map_yaml("")
    assert info.value.code == 1


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("image: [unclosed", "not valid YAML"),
        ("- just a list", "mapping"),
        ("resolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", "image"),
        ("image: a.png\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", "resolution"),
        (
            "image: a.png\nresolution: 0.1\norigin: [0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.2\n",
            "origin",
        ),
        ("image: a.png\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", "negate"),
        (
            "image: a.png\nresolution: .nan\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.2\n",
            "finite",
        ),
        (
            "image: a.png\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.2\n"
            "mode: fancy\n",
            "mode",
        ),
    ],
)
def test_unparsable_yaml_is_code_3(tmp_path: Path, text: str, fragment: str) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(MapLoadError) as info:
        read_map(path)
    assert info.value.code == 3
    assert fragment in str(info.value)


def test_corrupt_image_is_code_2(tmp_path: Path) -> None:
    (tmp_path / "m.png").write_bytes(b"not a png at all")
    (tmp_path / "m.yaml").write_text(
        "image: m.png\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.2\n"
    )
    with pytest.raises(MapLoadError) as info:
        read_map(tmp_path / "m.yaml")
    assert info.value.code == 2


def test_map_yaml_gives_the_image_as_written_and_resolved(tmp_path: Path) -> None:
    shutil.copy(NAV2 / "testmap.png", tmp_path / "img.png")
    (tmp_path / "elsewhere").mkdir()
    shutil.copy(NAV2 / "testmap.png", tmp_path / "elsewhere" / "img.png")
    (tmp_path / "link.png").symlink_to(tmp_path / "elsewhere" / "img.png")
    rest = "resolution: 0.1\norigin: [1, 2, 0.5]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\nstorey: F1\n"
    cases = {"img.png": True, "elsewhere/img.png": False, "../x/img.png": False, "link.png": False}
    for written, beside in cases.items():
        (tmp_path / "m.yaml").write_text(f"image: {written}\n{rest}")
        doc = read_map_yaml(tmp_path / "m.yaml")
        assert doc.image_text == written and doc.image == tmp_path / written
        assert doc.image_is_beside is beside, written
    fields = doc.fields(image="new.png")
    assert list(fields)[:7] == ["image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh", "mode"]
    assert fields["image"] == "new.png" and fields["origin"] == [1.0, 2.0, 0.5] and fields["storey"] == "F1"
    assert doc.fields()["image"] == "link.png"


def test_a_dot_dot_in_the_yamls_own_path_keeps_its_image_beside(tmp_path: Path) -> None:
    """Issue 40, item 8: `pmk send maps/../maps/m.yaml` was refused, 'image not in the YAML's folder'."""
    (tmp_path / "maps").mkdir()
    (tmp_path / "other").mkdir()
    shutil.copy(NAV2 / "testmap.png", tmp_path / "maps" / "img.png")
    rest = "resolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    (tmp_path / "maps" / "m.yaml").write_text(f"image: img.png\n{rest}")
    assert read_map_yaml(tmp_path / "other" / ".." / "maps" / "m.yaml").image_is_beside
    (tmp_path / "maps" / "m.yaml").write_text(f"image: ../maps/img.png\n{rest}")  # the YAML's own '..' still is not
    assert not read_map_yaml(tmp_path / "other" / ".." / "maps" / "m.yaml").image_is_beside


def test_image_path_relative_and_absolute(tmp_path: Path) -> None:
    info = read_map_yaml(NAV2 / "testmap.yaml")
    assert info.image == NAV2 / "testmap.png"
    assert (info.negate, info.mode, info.occupied_thresh, info.free_thresh) == (False, "trinary", 0.65, 0.196)
    shutil.copy(NAV2 / "testmap.png", tmp_path / "img.png")
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "abs.yaml").write_text(
        f"image: {tmp_path / 'img.png'}\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: true\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\nlla_origin: [1.5, 2.5, 3.0]\n"
    )
    grid = read_map(sub / "abs.yaml")
    expected = csv_grid(ROS1 / "expected" / "testmap_g_valid_image_content.csv")
    np.testing.assert_array_equal(grid.data == 100, expected == 0)  # negate: white is occupied
    assert grid.meta["lla_origin"] == [1.5, 2.5, 3.0]


def test_alpha_semantics_per_reader(tmp_path: Path) -> None:
    # one white pixel fully transparent, one white opaque, one black half transparent
    rgba = np.array([[[255, 255, 255, 0], [255, 255, 255, 255], [0, 0, 0, 128]]], dtype=np.uint8)
    path = tmp_path / "a.png"
    Image.fromarray(rgba, mode="RGBA").save(path)
    # trinary: ROS 1 and Humble average alpha in: (3*255+0)/4 = 191.25 -> occ 0.25 -> unknown
    assert load(path, "ros1").tolist() == [[-1, 0, 100]]
    assert load(path, "nav2_humble").tolist() == [[-1, 0, 100]]
    # Jazzy: any alpha < 255 is unknown
    assert load(path, "nav2_jazzy").tolist() == [[-1, 0, -1]]
    # scale: ROS 1 only alpha == 0 is unknown (alpha ignored in the mean); Nav2 any transparency
    assert load(path, "ros1", mode="scale").tolist() == [[0, 0, 100]]
    assert load(path, "nav2_humble", mode="scale").tolist() == [[-1, 0, -1]]


# --- 6. writer ------------------------------------------------------------------------------------


def make_grid(data: np.ndarray, **meta: object) -> OccupancyGrid:
    return OccupancyGrid(data=data.astype(np.int8), resolution=0.05, origin=(-1.25, 3.5, 0.0), meta=dict(meta))


def test_grid_to_gray_values_and_orientation() -> None:
    grid = make_grid(np.array([[0, 100, -1], [50, 1, 99]]))
    gray = grid_to_gray(grid)
    assert gray.dtype == np.uint8
    assert gray.tolist() == [[127, 251, 3], [254, 0, 205]]  # row 0 = top = grid's last row


def test_write_read_round_trip_and_files(tmp_path: Path) -> None:
    data = np.full((40, 60), -1, dtype=np.int8)
    data[5:35, 5:55] = 0
    data[5, 5:55] = 100
    data[10:20, 30] = 100
    grid = make_grid(
        data,
        storey="F1",
        source="/x/y.gml",
        translation=(1.0, 2.0),
        rotation=0.1 + 0.2,
        lla_origin=(45.801324, 9.092891, -151.3),
        unit="cm",
        wall_thickness=0.1,
    )
    files = write_map(grid, tmp_path, "house")
    assert files.yaml == tmp_path / "house.yaml"
    assert files.image == tmp_path / "house.pgm"
    assert files.preview == tmp_path / "house-visualization.png"
    raw = files.image.read_bytes()
    assert raw.startswith(b"P5\n60 40\n255\n")
    assert len(raw) == len(b"P5\n60 40\n255\n") + 60 * 40
    assert set(raw[len(b"P5\n60 40\n255\n") :]) == {0, 254, 205}
    text = files.yaml.read_text()
    keys = [line.split(":")[0] for line in text.splitlines() if line and not line.startswith(" ")]
    assert keys[:7] == ["image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh", "mode"]
    doc = yaml.safe_load(text)
    assert doc["image"] == "house.pgm" and doc["origin"] == [-1.25, 3.5, 0.0] and doc["negate"] == 0
    assert doc["rotation"] == 0.1 + 0.2  # floats read back bit-for-bit
    assert doc["lla_origin"] == [45.801324, 9.092891, -151.3]
    assert doc["generator"].startswith("pmk_nb ")
    assert doc["preview"] == "house-visualization.png" and doc["preview_px_per_m"] == pytest.approx(10.0)
    for reader in READERS:
        back = read_map(files.yaml, reader=reader)
        np.testing.assert_array_equal(back.data, grid.data)
        assert back.resolution == grid.resolution and back.origin == grid.origin
        assert back.meta["storey"] == "F1"
    with Image.open(files.preview) as pv:
        assert pv.size == (30, 20)  # 3 m x 2 m at 10 px/m
        assert pv.mode in ("L", "RGBA")


def test_write_png_format(tmp_path: Path) -> None:
    data = np.array([[0, 100], [-1, 0]], dtype=np.int8)
    files = write_map(make_grid(data), tmp_path, "m", image_format="png", preview=False)
    assert files.image.name == "m.png" and files.preview is None
    with Image.open(files.image) as im:
        assert im.mode == "L"
    np.testing.assert_array_equal(read_map(files.yaml, reader="nav2_jazzy").data, data)


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(
    data=st.integers(1, 25).flatmap(
        lambda h: st.integers(1, 25).flatmap(
            lambda w: st.lists(st.sampled_from([-1, 0, 100]), min_size=h * w, max_size=h * w).map(
                lambda v: np.array(v, dtype=np.int8).reshape(h, w)
            )
        )
    ),
    fmt=st.sampled_from(["pgm", "png"]),
    resolution=st.floats(0.001, 2.0),
)
def test_round_trip_random_grids(
    tmp_path_factory: pytest.TempPathFactory, data: np.ndarray, fmt: str, resolution: float
) -> None:
    folder = tmp_path_factory.mktemp("rt")
    grid = OccupancyGrid(data=data, resolution=resolution, origin=(resolution * 3.3, -7.1, 0.0))
    files = write_map(grid, folder, "r", image_format=fmt)
    for reader in READERS:
        back = read_map(files.yaml, reader=reader)
        np.testing.assert_array_equal(back.data, data)
        assert back.resolution == resolution
        assert back.origin == grid.origin


def test_preview_is_capped_for_huge_maps(tmp_path: Path) -> None:
    grid = OccupancyGrid(data=np.zeros((100, 9000), dtype=np.int8), resolution=0.1)  # 900 m wide
    files = write_map(grid, tmp_path, "wide")
    with Image.open(files.preview) as pv:
        assert max(pv.size) <= rosmap.PREVIEW_MAX_SIDE
    doc = yaml.safe_load(files.yaml.read_text())
    assert doc["preview_px_per_m"] == pytest.approx(4096 / 900.0)


def test_writer_refuses_nav2_oversize(tmp_path: Path) -> None:
    grid = OccupancyGrid(data=np.zeros((1, 32768), dtype=np.int8), resolution=0.01)
    with pytest.raises(MapFormatError) as info:
        write_map(grid, tmp_path, "big", preview=False)
    assert "32767" in str(info.value) and "0.011" in str(info.value)
    assert list(tmp_path.iterdir()) == []
    files = write_map(grid, tmp_path, "big", preview=False, allow_large=True)
    assert files.image.exists()


def test_failed_write_leaves_previous_set_untouched(tmp_path: Path) -> None:
    first = make_grid(np.zeros((4, 4), dtype=np.int8))
    files = write_map(first, tmp_path, "m")
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    files.preview.unlink()
    files.preview.mkdir()  # a folder where the preview must go: the write fails
    before.pop("m-visualization.png")
    with pytest.raises(MapFormatError):
        write_map(make_grid(np.full((4, 4), 100, dtype=np.int8)), tmp_path, "m")
    after = {p.name: p.read_bytes() for p in tmp_path.iterdir() if p.is_file()}
    assert after == before  # no temp files left, old files unchanged


def test_failure_while_writing_temps_cleans_up(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    write_map(make_grid(np.zeros((4, 4), dtype=np.int8)), tmp_path, "m")
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}

    real_fsync = __import__("os").fsync
    calls = {"n": 0}

    def fsync_second_fails(fd: int) -> None:
        calls["n"] += 1
        if calls["n"] == 2:  # the preview temp file: the image temp already exists
            raise OSError(28, "No space left on device")
        real_fsync(fd)

    monkeypatch.setattr("os.fsync", fsync_second_fails)
    with pytest.raises(MapFormatError, match="No space left"):
        write_map(make_grid(np.full((4, 4), 100, dtype=np.int8)), tmp_path, "m")
    monkeypatch.undo()
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before


@pytest.mark.parametrize("name", ["", "a/b", ".."])
def test_writer_rejects_bad_names(tmp_path: Path, name: str) -> None:
    with pytest.raises(MapFormatError):
        write_map(make_grid(np.zeros((2, 2))), tmp_path, name)


def test_streamed_pgm_equals_one_shot_encoding() -> None:
    import io

    from pmk_nb.rosmap.image import pgm_bytes, write_pgm

    rng = np.random.default_rng(7)
    grid = make_grid(rng.choice(np.array([-1, 0, 100, 42], dtype=np.int8), size=(37, 11)))
    buf = io.BytesIO()
    write_pgm(grid, buf, rows_per_chunk=5)
    assert buf.getvalue() == pgm_bytes(grid_to_gray(grid))


def test_palette_png_ros1_reads_indices_nav2_reads_colours(tmp_path: Path) -> None:
    img = Image.fromarray(np.array([[0, 1]], dtype=np.uint8), mode="P")
    img.putpalette([255, 255, 255, 0, 0, 0] + [0, 0, 0] * 254)  # index 0 = white, 1 = black
    path = tmp_path / "p.png"
    img.save(path)
    assert load(path, "ros1").tolist() == [[100, 100]]  # SDL hands ROS 1 the indices 0 and 1: dark
    assert load(path, "nav2_humble").tolist() == [[0, 100]]
    assert load(path, "nav2_jazzy").tolist() == [[0, 100]]


def test_storey_file_names() -> None:
    from pmk_nb.library import safe_file_part, storey_map_names

    assert storey_map_names("house", ["F1"]) == {"F1": "house"}
    assert storey_map_names("house", ["2"], several=True) == {"2": "house_2"}
    names = storey_map_names("house", ["F 1", "F_1", "../x", ""])
    assert names == {"F 1": "house_F_1", "F_1": "house_F_1-2", "../x": "house_x", "": "house_storey"}
    assert all("/" not in n for n in names.values())
    assert safe_file_part("Erdgeschoß (EG)") == "Erdgescho_EG"


def test_rewriting_a_read_map_keeps_extras_but_not_stale_preview(tmp_path: Path) -> None:
    grid = make_grid(np.zeros((5, 5), dtype=np.int8), storey="F2", lla_origin=None, generator="someone else")
    first = write_map(grid, tmp_path / "a", "m")
    back = read_map(first.yaml)
    assert back.meta["storey"] == "F2" and "lla_origin" not in back.meta
    second = write_map(back, tmp_path / "b", "m", preview=False)
    doc = yaml.safe_load(second.yaml.read_text())
    assert "preview" not in doc and "preview_px_per_m" not in doc
    assert doc["generator"].startswith("pmk_nb ") and doc["storey"] == "F2"
