"""ROS map_server YAML + PGM/PNG loading and map_saver-style saving."""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

import numpy as np
import pytest

from socialnav.world.grid import GridGeometry
from socialnav.world.mapio import MapFileError, OccupancyMap, load_map, save_map

# A 3-row × 4-col picture, top row first (as stored in the file).
PIXELS_TOP_FIRST = np.array(
    [
        [0, 254, 205, 255],
        [10, 100, 150, 200],
        [254, 254, 0, 0],
    ],
    dtype=np.uint8,
)


def pgm_p5(pixels: np.ndarray) -> bytes:
    h, w = pixels.shape
    return f"P5\n# hand-made\n{w} {h}\n255\n".encode() + pixels.astype(np.uint8).tobytes()


def pgm_p2(pixels: np.ndarray) -> bytes:
    h, w = pixels.shape
    body = "\n".join(" ".join(str(int(v)) for v in row) for row in pixels)
    return f"P2\n# ascii\n{w} {h}\n255\n{body}\n".encode()


def png_bytes(pixels: np.ndarray, color_type: int) -> bytes:
    """Minimal PNG writer (8-bit, no filtering): color_type 0 grey, 2 RGB, 4 grey+alpha, 6 RGBA."""
    h, w = pixels.shape[:2]
    raw = b"".join(b"\x00" + pixels[r].astype(np.uint8).tobytes() for r in range(h))

    def chunk(kind: bytes, data: bytes) -> bytes:
        crc = zlib.crc32(kind + data) & 0xFFFFFFFF
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)

    ihdr = struct.pack(">IIBBBBB", w, h, 8, color_type, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", ihdr)
        + chunk(b"IDAT", zlib.compress(raw))
        + chunk(b"IEND", b"")
    )


def write_yaml(folder: Path, image: str, **over: object) -> Path:
    fields = {
        "image": image,
        "resolution": 0.05,
        "origin": "[-1.0, 2.0, 0.0]",
        "occupied_thresh": 0.65,
        "free_thresh": 0.196,
        "negate": 0,
    }
    fields.update(over)
    text = "".join(f"{k}: {v}\n" for k, v in fields.items() if v is not None)
    path = folder / "map.yaml"
    path.write_text(text)
    return path


def expected_trinary(pixels_top_first: np.ndarray, negate: bool = False) -> np.ndarray:
    v = pixels_top_first.astype(float)
    if negate:
        v = 255 - v
    p = (255 - v) / 255
    out = np.full(v.shape, -1, dtype=np.int8)
    out[p > 0.65] = 100
    out[p < 0.196] = 0
    return out[::-1]


@pytest.mark.parametrize("writer", [pgm_p5, pgm_p2], ids=["P5", "P2"])
@pytest.mark.parametrize("negate", [0, 1])
def test_trinary_pgm_matches_ros_thresholds_and_flips_rows(tmp_path, writer, negate):
    (tmp_path / "m.pgm").write_bytes(writer(PIXELS_TOP_FIRST))
    omap = load_map(write_yaml(tmp_path, "m.pgm", negate=negate))
    assert omap.occupancy.dtype == np.int8
    np.testing.assert_array_equal(omap.occupancy, expected_trinary(PIXELS_TOP_FIRST, bool(negate)))
    assert omap.geometry.shape == (3, 4)
    assert omap.geometry.resolution == 0.05
    assert omap.geometry.origin == (-1.0, 2.0)
    # Bottom-left pixel of the picture (254, free when not negated) is cell (0, 0).
    assert omap.occupancy[0, 0] == (100 if negate else 0)
    # map_saver's trinary values read back as occupied / free / unknown.
    if not negate:
        top = omap.occupancy[2]
        assert list(top[:3]) == [100, 0, -1]


def test_png_grey_and_rgb_average_channels(tmp_path):
    (tmp_path / "g.png").write_bytes(png_bytes(PIXELS_TOP_FIRST, 0))
    grey = load_map(write_yaml(tmp_path, "g.png"))
    np.testing.assert_array_equal(grey.occupancy, expected_trinary(PIXELS_TOP_FIRST))
    # An RGB pixel (0, 30, 255): integer mean 95 → p = 0.627 → unknown; (250, 255, 255) → free.
    rgb = np.array([[[0, 30, 255], [250, 255, 255]]], dtype=np.uint8)
    (tmp_path / "c.png").write_bytes(png_bytes(rgb, 2))
    colour = load_map(write_yaml(tmp_path, "c.png"))
    np.testing.assert_array_equal(colour.occupancy, [[-1, 0]])


def test_scale_mode_interpolates_and_alpha_zero_is_unknown(tmp_path):
    grey = np.array([[0, 255, 128, 128]], dtype=np.uint8)
    alpha = np.array([[255, 255, 255, 0]], dtype=np.uint8)
    (tmp_path / "s.png").write_bytes(png_bytes(np.stack([grey, alpha], axis=-1), 4))
    omap = load_map(write_yaml(tmp_path, "s.png", mode="scale"))
    p = (255 - 128) / 255
    expected_mid = 99 * (p - 0.196) / (0.65 - 0.196)
    np.testing.assert_allclose(omap.occupancy, [[100, 0, expected_mid, -1]])
    # ROS stores the truncated int8.
    np.testing.assert_array_equal(omap.to_ros_data(), [[100, 0, int(expected_mid), -1]])


def test_raw_mode_keeps_values_and_negate(tmp_path):
    px = np.array([[0, 7, 100, 255]], dtype=np.uint8)
    (tmp_path / "r.pgm").write_bytes(pgm_p5(px))
    raw = load_map(write_yaml(tmp_path, "r.pgm", mode="raw"))
    np.testing.assert_array_equal(raw.occupancy, [[0, 7, 100, 255]])
    np.testing.assert_array_equal(raw.to_ros_data(), [[0, 7, 100, -1]])
    np.testing.assert_array_equal(raw.unknown_mask(), [[False, False, False, True]])
    np.testing.assert_array_equal(raw.occupied_mask(), [[False, False, True, False]])
    neg = load_map(write_yaml(tmp_path, "r.pgm", mode="raw", negate=1))
    np.testing.assert_array_equal(neg.occupancy, [[255, 248, 155, 0]])


@pytest.mark.parametrize("fmt", ["pgm", "png"])
def test_trinary_round_trip_writes_map_saver_values(tmp_path, fmt):
    occ = np.array([[100, 0, -1], [0, 0, 100]], dtype=np.int8)
    geo = GridGeometry((2, 3), 0.1, (3.0, -4.0))
    omap = OccupancyMap(
        occ,
        geo,
        {"mode": "trinary", "occupied_thresh": 0.65, "free_thresh": 0.196, "origin": [3, -4, 0.5]},
    )
    sub = tmp_path / "maps"
    sub.mkdir()
    image_path = save_map(omap, sub / "saved.yaml", image_format=fmt)
    assert image_path.name == f"saved.{fmt}"
    # map_saver pixel values, picture top row = grid top row.
    from PIL import Image

    with Image.open(image_path) as im:
        np.testing.assert_array_equal(np.asarray(im), [[254, 254, 0], [0, 254, 205]])
    back = load_map(sub / "saved.yaml")
    np.testing.assert_array_equal(back.occupancy, occ)
    assert back.geometry == geo
    assert back.meta["origin"] == [3.0, -4.0, 0.5]
    assert back.meta["image"] == f"saved.{fmt}"  # relative to the YAML's folder


def test_scale_round_trip_png_with_unknown(tmp_path):
    occ = np.array([[100.0, 0.0, 50.0, -1.0]])
    geo = GridGeometry((1, 4), 0.05)
    omap = OccupancyMap(occ, geo, {"mode": "scale", "occupied_thresh": 0.65, "free_thresh": 0.2})
    with pytest.raises(ValueError, match="png"):
        save_map(omap, tmp_path / "s.yaml", image_format="pgm")
    save_map(omap, tmp_path / "s.yaml", image_format="png")
    back = load_map(tmp_path / "s.yaml")
    assert back.mode == "scale"
    # One grey level spans 99 / (255 · 0.45) ≈ 0.86 of the 0..99 scale.
    np.testing.assert_allclose(back.occupancy, occ, atol=0.9)
    assert back.occupancy[0, 3] == -1


def test_raw_round_trip(tmp_path):
    occ = np.array([[0.0, 1.0, 99.0, 254.0]])
    omap = OccupancyMap(occ, GridGeometry((1, 4), 0.05), {"mode": "raw"})
    save_map(omap, tmp_path / "r.yaml", image_format="pgm")
    np.testing.assert_array_equal(load_map(tmp_path / "r.yaml").occupancy, occ)


def test_from_masks_and_static_layer_masks():
    geo = GridGeometry((2, 2), 0.1)
    omap = OccupancyMap.from_masks(
        np.array([[True, False], [False, False]]), geo, np.array([[True, True], [False, False]])
    )
    np.testing.assert_array_equal(omap.occupancy, [[100, -1], [0, 0]])
    np.testing.assert_array_equal(omap.occupied_mask(), [[True, False], [False, False]])
    np.testing.assert_array_equal(omap.unknown_mask(), [[False, True], [False, False]])


def test_absolute_image_path_and_nonzero_yaw(tmp_path):
    (tmp_path / "m.pgm").write_bytes(pgm_p5(PIXELS_TOP_FIRST))
    other = tmp_path / "elsewhere"
    other.mkdir()
    path = write_yaml(other, str(tmp_path / "m.pgm"), origin="[0, 0, 1.5707963]")
    omap = load_map(path)
    assert omap.meta["origin"][2] == pytest.approx(np.pi / 2)
    assert omap.geometry.origin == (0.0, 0.0)  # axis-aligned grid; yaw recorded only
    with pytest.raises(MapFileError, match="origin"):
        load_map(path, allow_yaw=False)


@pytest.mark.parametrize(
    ("over", "match"),
    [
        ({"resolution": None}, "missing required field 'resolution'"),
        ({"resolution": -0.1}, "'resolution' must be positive"),
        ({"resolution": "abc"}, "'resolution' must be a number"),
        ({"mode": "fancy"}, "'mode' must be one of"),
        ({"negate": 3}, "'negate'"),
        ({"origin": "[1, 2]"}, "'origin'"),
        ({"occupied_thresh": 0.1}, "free_thresh"),
        ({"image": "missing.pgm"}, "field 'image': file not found"),
    ],
)
def test_errors_name_file_and_field(tmp_path, over, match):
    (tmp_path / "m.pgm").write_bytes(pgm_p5(PIXELS_TOP_FIRST))
    over = dict(over)
    path = write_yaml(tmp_path, str(over.pop("image", "m.pgm")), **over)
    with pytest.raises(MapFileError, match=match) as info:
        load_map(path)
    assert str(path) in str(info.value)
    assert isinstance(info.value, ValueError)


def test_unreadable_image_and_yaml(tmp_path):
    (tmp_path / "bad.pgm").write_bytes(b"not an image at all")
    path = write_yaml(tmp_path, "bad.pgm")
    with pytest.raises(MapFileError, match="field 'image': cannot read image"):
        load_map(path)
    with pytest.raises(MapFileError, match="cannot read map YAML"):
        load_map(tmp_path / "nope.yaml")
    (tmp_path / "list.yaml").write_text("- 1\n- 2\n")
    with pytest.raises(MapFileError, match="mapping"):
        load_map(tmp_path / "list.yaml")
