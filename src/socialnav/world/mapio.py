"""ROS ``map_server`` map files: a YAML description plus a PGM/PNG image.

Semantics follow ROS 1 ``map_server`` (``image_loader.cpp``, noetic) and ``map_saver``:

- YAML keys ``image`` (absolute, or relative to the YAML's folder), ``resolution`` (m/pixel),
  ``origin`` ``[x, y, yaw]`` of the lower-left pixel, ``occupied_thresh``, ``free_thresh``,
  ``negate`` (0/1 or bool), optional ``mode`` (``trinary`` default, ``scale``, ``raw``).
- Colour pixels are averaged over their channels (in *trinary* mode ROS 1 averages the alpha
  channel in as well; in scale/raw mode alpha is excluded). After ``negate``
  (``avg := 255 - avg``) the occupancy probability is ``p = (255 - avg) / 255``.
- trinary: ``p > occupied_thresh`` → 100, ``p < free_thresh`` → 0, otherwise -1 (unknown).
- scale: as trinary outside the thresholds; a fully transparent pixel (alpha 0) → -1;
  in between → ``99 (p - free) / (occ - free)`` (kept as a float here; ROS truncates to int8,
  see :meth:`OccupancyMap.to_ros_data`).
- raw: the (negated) average value itself, 0..255 (ROS stores it in an int8, so 255 reads -1).
- Image row 0 is the top of the picture; rows are flipped so that grid row 0 is the bottom.

Origin yaw: it is recorded in ``meta["origin"]`` but the grid stays axis-aligned at
``(x, y)`` — exactly what costmap_2d and most of the ROS stack do ("many parts of the system
ignore yaw"). Pass ``allow_yaw=False`` to :func:`load_map` to refuse maps with a non-zero yaw.

Saving follows ``map_saver``: trinary images hold 0 (occupied), 254 (free), 205 (unknown), and
the YAML is written with ``negate: 0``. Scale and raw maps are saved so that loading them back
reproduces the values (scale: the inverse of the loading map; unknown cells need PNG alpha).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import yaml
from numpy.typing import NDArray
from PIL import Image, UnidentifiedImageError

from socialnav.core.errors import InvalidInputError
from socialnav.world.grid import GridGeometry

MapMode = Literal["trinary", "scale", "raw"]
MODES: tuple[str, ...] = ("trinary", "scale", "raw")
OCCUPIED = 100
FREE_VALUE = 0
UNKNOWN_VALUE = -1
# map_saver pixel values for trinary maps
PIXEL_OCCUPIED = 0
PIXEL_FREE = 254
PIXEL_UNKNOWN = 205
_DEFAULT_OCC = 0.65
_DEFAULT_FREE = 0.196


class MapFileError(InvalidInputError):
    """A map YAML or image is missing, unreadable or malformed (message names file and field)."""


@dataclass(frozen=True)
class OccupancyMap:
    """An occupancy grid as ``map_server`` publishes it.

    ``occupancy`` is ``(rows, cols)``, row 0 at the bottom: int8 {-1 unknown, 0 free, 100
    occupied} for trinary maps, float64 for scale (-1 unknown, else 0..100) and raw (0..255)
    maps. ``meta`` holds ``mode``, ``negate``, ``occupied_thresh``, ``free_thresh``,
    ``origin`` ``[x, y, yaw]`` and, when loaded from disk, ``image`` and ``yaml_path``.
    """

    occupancy: NDArray[Any]
    geometry: GridGeometry
    meta: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.occupancy.shape != self.geometry.shape:
            raise InvalidInputError(
                f"occupancy shape {self.occupancy.shape} != geometry shape {self.geometry.shape}"
            )
        mode = self.meta.get("mode", "trinary")
        if mode not in MODES:
            raise InvalidInputError(f"map mode must be one of {MODES}, got {mode!r}")

    @property
    def mode(self) -> str:
        """The map's ``mode`` (trinary, scale or raw; ROS map_server)."""
        return str(self.meta.get("mode", "trinary"))

    @classmethod
    def from_masks(
        cls,
        occupied: NDArray[np.bool_],
        geometry: GridGeometry,
        unknown: NDArray[np.bool_] | None = None,
    ) -> OccupancyMap:
        """Trinary map from boolean ``(rows, cols)`` masks (occupied wins over unknown)."""
        occ = np.where(np.asarray(occupied, dtype=bool), OCCUPIED, FREE_VALUE).astype(np.int8)
        if unknown is not None:
            occ[np.asarray(unknown, dtype=bool) & (occ == FREE_VALUE)] = UNKNOWN_VALUE
        meta = {
            "mode": "trinary",
            "negate": 0,
            "occupied_thresh": _DEFAULT_OCC,
            "free_thresh": _DEFAULT_FREE,
            "origin": [float(geometry.origin[0]), float(geometry.origin[1]), 0.0],
        }
        return cls(occ, geometry, meta)

    def to_ros_data(self) -> NDArray[np.int8]:
        """``(rows, cols)`` int8 values as in ``nav_msgs/OccupancyGrid.data`` (C truncation)."""
        v = np.trunc(np.asarray(self.occupancy, dtype=float)).astype(np.int64)
        return (v & 0xFF).astype(np.uint8).view(np.int8)

    def unknown_mask(self) -> NDArray[np.bool_]:
        """Cells costmap_2d's static layer reads as NO_INFORMATION (data == -1)."""
        return self.to_ros_data() == UNKNOWN_VALUE

    def occupied_mask(self, lethal_threshold: int = OCCUPIED) -> NDArray[np.bool_]:
        """Cells costmap_2d's static layer marks LETHAL: unsigned value >= ``lethal_threshold``.

        The static layer compares the *unsigned* byte, so raw values 100..254 are lethal and
        255 (-1) is unknown.
        """
        u = self.to_ros_data().view(np.uint8)
        return (u >= lethal_threshold) & (u != 255)


def _field(doc: dict[str, Any], key: str, path: Path) -> Any:
    if key not in doc:
        raise MapFileError(f"{path}: missing required field '{key}'")
    return doc[key]


def _float_field(doc: dict[str, Any], key: str, path: Path) -> float:
    raw = _field(doc, key, path)
    try:
        value = float(raw)
    except (TypeError, ValueError):
        raise MapFileError(f"{path}: field '{key}' must be a number, got {raw!r}") from None
    if not math.isfinite(value):
        raise MapFileError(f"{path}: field '{key}' must be finite, got {raw!r}")
    return value


def _parse_negate(raw: Any, path: Path) -> bool:
    if isinstance(raw, bool):
        return raw
    if isinstance(raw, int | float) and raw in (0, 1):
        return bool(raw)
    raise MapFileError(f"{path}: field 'negate' must be 0, 1, true or false, got {raw!r}")


def _read_pixels(
    image_path: Path, yaml_path: Path, mode: str
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Channel average ``(H, W)`` float and alpha ``(H, W)`` (255 when the image has none)."""
    img: Image.Image
    try:
        with Image.open(image_path) as im:
            im.load()
            img = im
    except FileNotFoundError:
        raise MapFileError(f"{yaml_path}: field 'image': file not found: {image_path}") from None
    except (UnidentifiedImageError, OSError, SyntaxError, ValueError) as exc:
        raise MapFileError(
            f"{yaml_path}: field 'image': cannot read image {image_path}: {exc}"
        ) from None
    if img.mode == "P":
        img = img.convert("RGBA" if "transparency" in img.info else "RGB")
    if img.mode == "1":
        img = img.convert("L")
    if img.mode not in ("L", "LA", "RGB", "RGBA"):
        raise MapFileError(
            f"{yaml_path}: field 'image': unsupported pixel format {img.mode!r} in {image_path}"
            " (8-bit grey, grey+alpha, RGB or RGBA expected)"
        )
    px = np.asarray(img, dtype=np.float64)
    if px.ndim == 2:
        px = px[..., None]
    has_alpha = img.mode in ("LA", "RGBA")
    alpha = px[..., -1] if has_alpha else np.full(px.shape[:2], 255.0)
    # ROS 1 quirk kept on purpose: trinary mode averages the alpha channel in too.
    avg_channels = px.shape[-1] if (mode == "trinary" or not has_alpha) else px.shape[-1] - 1
    # Integer average as in image_loader.cpp (an int sum divided by an int channel count).
    avg = np.floor(px[..., :avg_channels].sum(axis=-1) / avg_channels)
    return avg, alpha


def load_map(yaml_path: str | Path, *, allow_yaw: bool = True) -> OccupancyMap:
    """Load a ``map_server`` YAML + image pair.

    Raises :class:`MapFileError` (a ``ValueError``) naming the file and field on a missing or
    malformed field, an unreadable image or an unknown ``mode``.
    """
    path = Path(yaml_path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise MapFileError(f"{path}: cannot read map YAML: {exc}") from None
    try:
        doc = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise MapFileError(f"{path}: invalid YAML: {exc}") from None
    if not isinstance(doc, dict):
        raise MapFileError(f"{path}: map YAML must be a mapping of fields")

    image = _field(doc, "image", path)
    if not isinstance(image, str) or not image:
        raise MapFileError(f"{path}: field 'image' must be a file name, got {image!r}")
    resolution = _float_field(doc, "resolution", path)
    if resolution <= 0:
        raise MapFileError(f"{path}: field 'resolution' must be positive, got {resolution}")
    origin_raw = _field(doc, "origin", path)
    try:
        origin = [float(v) for v in origin_raw]
    except (TypeError, ValueError):
        raise MapFileError(
            f"{path}: field 'origin' must be [x, y, yaw], got {origin_raw!r}"
        ) from None
    if len(origin) != 3 or not all(math.isfinite(v) for v in origin):
        raise MapFileError(f"{path}: field 'origin' must be 3 finite numbers, got {origin_raw!r}")
    if not allow_yaw and origin[2] != 0.0:
        raise MapFileError(f"{path}: field 'origin' has yaw {origin[2]} but allow_yaw=False")
    occ_th = _float_field(doc, "occupied_thresh", path)
    free_th = _float_field(doc, "free_thresh", path)
    if not (0.0 <= free_th <= occ_th <= 1.0):
        raise MapFileError(
            f"{path}: fields 'free_thresh' ({free_th}) and 'occupied_thresh' ({occ_th}) must "
            "satisfy 0 <= free_thresh <= occupied_thresh <= 1"
        )
    negate = _parse_negate(_field(doc, "negate", path), path)
    mode = doc.get("mode", "trinary")
    if mode not in MODES:
        raise MapFileError(f"{path}: field 'mode' must be one of {MODES}, got {mode!r}")

    image_path = Path(image)
    if not image_path.is_absolute():
        image_path = path.parent / image_path
    avg, alpha = _read_pixels(image_path, path, mode)
    if negate:
        avg = 255.0 - avg
    # Flip: image row 0 is the top, grid row 0 is the bottom.
    avg, alpha = avg[::-1], alpha[::-1]

    if mode == "raw":
        occupancy: NDArray[Any] = avg.copy()
    else:
        p = (255.0 - avg) / 255.0
        if mode == "trinary":
            occupancy = np.full(p.shape, UNKNOWN_VALUE, dtype=np.int8)
        else:
            span = occ_th - free_th
            ratio = (p - free_th) / span if span > 0 else np.zeros_like(p)
            occupancy = np.where(alpha < 1.0, float(UNKNOWN_VALUE), 99.0 * ratio)
        occupancy[p > occ_th] = OCCUPIED
        occupancy[p < free_th] = FREE_VALUE

    geometry = GridGeometry(
        shape=(int(avg.shape[0]), int(avg.shape[1])),
        resolution=resolution,
        origin=(origin[0], origin[1]),
    )
    meta = {
        "image": image,
        "yaml_path": str(path),
        "mode": mode,
        "negate": int(negate),
        "occupied_thresh": occ_th,
        "free_thresh": free_th,
        "origin": origin,
    }
    return OccupancyMap(occupancy, geometry, meta)


def _image_pixels(omap: OccupancyMap) -> tuple[NDArray[np.uint8], NDArray[np.uint8] | None]:
    """Grey pixels ``(rows, cols)`` in grid order (row 0 bottom) and optional alpha."""
    occ = np.asarray(omap.occupancy, dtype=float)
    mode = omap.mode
    if mode == "trinary":
        # map_saver thresholds, expressed on the 0..100 scale of the YAML thresholds.
        occ_t = 100.0 * float(omap.meta.get("occupied_thresh", _DEFAULT_OCC))
        free_t = 100.0 * float(omap.meta.get("free_thresh", _DEFAULT_FREE))
        grey = np.full(occ.shape, PIXEL_UNKNOWN, dtype=np.uint8)
        grey[(occ >= 0) & (occ <= free_t)] = PIXEL_FREE
        grey[occ >= occ_t] = PIXEL_OCCUPIED
        return grey, None
    if mode == "raw":
        return np.clip(np.rint(occ), 0, 255).astype(np.uint8), None
    occ_th = float(omap.meta.get("occupied_thresh", _DEFAULT_OCC))
    free_th = float(omap.meta.get("free_thresh", _DEFAULT_FREE))
    unknown = occ < 0
    # Invert the loader: value v in [0, 99] came from p = free + v/99 (occ - free).
    p = np.where(occ >= OCCUPIED, 1.0, free_th + np.clip(occ, 0, 99) / 99.0 * (occ_th - free_th))
    p = np.where(occ <= 0, 0.0, p)
    # Unknown needs a grey between the thresholds: ROS applies the thresholds before alpha.
    p = np.where(unknown, 0.5 * (free_th + occ_th), p)
    grey = np.clip(np.rint(255.0 - 255.0 * p), 0, 255).astype(np.uint8)
    alpha = np.where(unknown, 0, 255).astype(np.uint8) if unknown.any() else None
    return grey, alpha


def save_map(
    omap: OccupancyMap,
    yaml_path: str | Path,
    image_format: Literal["pgm", "png"] = "pgm",
) -> Path:
    """Write ``omap`` as ``<yaml stem>.<image_format>`` beside ``yaml_path``; return the image path.

    The YAML names the image by its file name (relative to the YAML's folder), with
    ``negate: 0``, the map's thresholds, ``mode`` and ``origin`` (yaw kept).
    Scale maps with unknown cells need ``image_format="png"`` (unknown = transparent pixel).
    """
    if image_format not in ("pgm", "png"):
        raise InvalidInputError(f"image_format must be 'pgm' or 'png', got {image_format!r}")
    path = Path(yaml_path)
    grey, alpha = _image_pixels(omap)
    if alpha is not None and image_format == "pgm":
        raise InvalidInputError(
            f"{path}: a scale-mode map with unknown cells needs image_format='png' (alpha)"
        )
    image_path = path.with_suffix(f".{image_format}")
    top_first = grey[::-1]
    if alpha is None:
        img = Image.fromarray(np.ascontiguousarray(top_first))
    else:
        la = np.stack([top_first, alpha[::-1]], axis=-1)
        img = Image.fromarray(np.ascontiguousarray(la))
    img.save(image_path, format="PPM" if image_format == "pgm" else "PNG")

    yaw = float(omap.meta.get("origin", [0.0, 0.0, 0.0])[2])
    origin = [float(omap.geometry.origin[0]), float(omap.geometry.origin[1]), yaw]
    doc = {
        "image": image_path.name,
        "mode": omap.mode,
        "resolution": float(omap.geometry.resolution),
        "origin": origin,
        "negate": 0,
        "occupied_thresh": float(omap.meta.get("occupied_thresh", _DEFAULT_OCC)),
        "free_thresh": float(omap.meta.get("free_thresh", _DEFAULT_FREE)),
    }
    path.write_text(yaml.safe_dump(doc, sort_keys=False, default_flow_style=None))
    return image_path
