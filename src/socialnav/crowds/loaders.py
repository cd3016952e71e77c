"""Loaders for recorded pedestrian trajectories, read with pandas into a :class:`Recording`.

Formats and their documented frame periods (seconds per frame *number*):

- ``obsmat`` — ETH (BIWI Walking Pedestrians, Pellegrini et al. ICCV 2009) and UCY
  (Crowds-by-Example, Lerner et al. 2007) as collected by OpenTraj: one row per (frame, person)
  ``frame id pos_x pos_z pos_y v_x v_z v_y``, metres and m/s on the ground plane ``(x, y)``,
  ``z`` unused. Frame numbers count video frames at 25 fps, annotated every 10 frames:
  default period :data:`OBSMAT_FRAME_PERIOD` = 0.04 s (0.4 s between annotations).
- ``four_column`` — ``frame id x y`` separated by whitespace, tabs or commas, as in the ETH
  "univ" sequence and most trajectory-prediction repositories (Social-GAN's ``datasets``):
  the same ETH/UCY video frame numbers, default :data:`FOUR_COLUMN_FRAME_PERIOD` = 0.04 s.
- ``trajnet`` — Trajnet++ ``ndjson`` (vita-epfl/trajnetplusplustools): one JSON object per line,
  ``{"scene": {"id", "p", "s", "e", "fps"?, "tag"?}}`` or ``{"track": {"f", "p", "x", "y"}}``.
  Frame numbers are not renumbered by Trajnet++; rows come ``fps`` times a second (2.5 by
  default). The default period is therefore ``1 / (fps · median frame step)`` (0.04 s for the
  ETH/UCY-derived files, whose frames step by 10 at 2.5 rows/s).

``groups.txt`` (OpenTraj): one group per line, the ids of people who walk together separated by
spaces. Every error names the file and the line.
"""

from __future__ import annotations

import io
import json
import math
import re
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from socialnav.core.errors import ConfigurationError
from socialnav.crowds.recording import DEFAULT_MAX_GAP, Recording, Track

OBSMAT_FRAME_PERIOD = 0.04
FOUR_COLUMN_FRAME_PERIOD = 0.04
TRAJNET_FPS = 2.5
FORMATS = ("obsmat", "four_column", "trajnet")
#: ids and frame numbers beyond this are not exact as the floats they are read as
_LARGEST_INTEGER = 2**53
OBSMAT_COLUMNS = ("frame", "id", "x", "z", "y", "vx", "vz", "vy")


class RecordingFormatError(ConfigurationError):
    """A recording file that cannot be read; the message names the file and the line."""


def _require_file(path: Path) -> None:
    if path.is_dir():
        raise RecordingFormatError(f"{path}: is a directory, not a recording file")
    if not path.is_file():
        raise RecordingFormatError(f"{path}: no such file")


def _period(frame_period: float | None, default: float, path: Path) -> float:
    period = default if frame_period is None else float(frame_period)
    if not (math.isfinite(period) and period > 0):
        raise RecordingFormatError(f"{path}: frame_period must be positive, got {frame_period}")
    return period


def _read_text(path: Path) -> str:
    """The file's text (UTF-8, a byte-order mark dropped). Raises
    :class:`RecordingFormatError` for a missing file, a folder, or bytes that are not text."""
    _require_file(path)
    data = path.read_bytes()
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise RecordingFormatError(
            f"{path}: line {line}: not a text file (byte {exc.start} is not UTF-8)"
        ) from exc
    if "\x00" in text:
        line = text[: text.index("\x00")].count("\n") + 1
        raise RecordingFormatError(f"{path}: line {line}: not a text file (a NUL byte)")
    # every line ending as one: CRLF (Windows) and a lone CR (classic Mac OS) read as LF
    return text.replace("\r\n", "\n").replace("\r", "\n")


def _read_table(path: Path, columns: Sequence[str], sep: str) -> pd.DataFrame:
    """Numeric columns of a text table; ``line`` (1-based) kept for error messages."""
    text = _read_text(path)
    # pandas infers the width from the first line (a blank first line would make it 1, and
    # a longer row later a parser error): give it the widest line's field count instead
    width = max(
        (len(re.split(sep, line.split("#", 1)[0])) for line in text.splitlines()), default=0
    )
    try:
        raw = pd.read_csv(
            io.StringIO(text),
            sep=sep,
            header=None,
            names=range(max(width, 1)),
            dtype=str,
            skip_blank_lines=False,
            engine="python",
            comment="#",
            # Only an empty field is missing: a literal "nan" is a value (and not finite).
            keep_default_na=False,
            na_values=[""],
        )
    except pd.errors.ParserError as exc:
        raise RecordingFormatError(f"{path}: {exc}") from exc
    except pd.errors.EmptyDataError as exc:
        raise RecordingFormatError(f"{path}: the file is empty") from exc
    # Leading whitespace makes an empty first field with a regex separator.
    raw = raw.loc[:, ~(raw.isna() | (raw == "")).all(axis=0)]
    raw.columns = range(raw.shape[1])
    raw["line"] = np.arange(1, len(raw) + 1)
    raw = raw[~raw.drop(columns="line").isna().all(axis=1)]
    if raw.empty:
        raise RecordingFormatError(f"{path}: no data rows")
    n = len(columns)
    values = raw.drop(columns="line")
    if values.shape[1] < n:
        raise RecordingFormatError(
            f"{path}: line {int(raw['line'].iloc[0])}: expected {n} columns "
            f"({' '.join(columns)}), found {values.shape[1]}"
        )
    if values.shape[1] > n:
        extra = values.iloc[:, n:].notna().any(axis=1)
        line = int(raw["line"][extra].iloc[0])
        raise RecordingFormatError(
            f"{path}: line {line}: expected {n} columns ({' '.join(columns)}), found more"
        )
    numeric = values.apply(pd.to_numeric, errors="coerce")
    bad = numeric.isna().any(axis=1) | ~np.isfinite(numeric.to_numpy(dtype=float)).all(axis=1)
    if bad.any():
        line = int(raw["line"][bad].iloc[0])
        row = values[bad].iloc[0]
        col = int(
            np.flatnonzero(numeric[bad].iloc[0].isna() | ~np.isfinite(numeric[bad].iloc[0]))[0]
        )
        if pd.isna(row.iloc[col]):  # a short row (a file cut mid-line), not a bad number
            raise RecordingFormatError(
                f"{path}: line {line}: {int(row.notna().sum())} columns; expected {n} "
                f"({' '.join(columns)})"
            )
        raise RecordingFormatError(
            f"{path}: line {line}: column {col + 1} ({columns[col]}) is not a finite number: "
            f"{row.iloc[col]!r}"
        )
    numeric.columns = list(columns)
    numeric["line"] = raw["line"].to_numpy()
    return numeric


def _tracks(df: pd.DataFrame, period: float, path: Path) -> tuple[Track, ...]:
    """Tracks from rows ``frame, id, x, y, line``; ids and frames must be integers."""
    for col in ("frame", "id"):
        frac = (df[col] - np.round(df[col])).abs() > 1e-6
        if frac.any():
            line = int(df["line"][frac].iloc[0])
            raise RecordingFormatError(f"{path}: line {line}: {col} must be an integer")
        huge = df[col].abs() > _LARGEST_INTEGER
        if huge.any():
            line = int(df["line"][huge].iloc[0])
            raise RecordingFormatError(f"{path}: line {line}: {col} is too large an integer")
    df = df.assign(
        frame=np.round(df["frame"]).astype(np.int64), id=np.round(df["id"]).astype(np.int64)
    )
    dup = df.duplicated(["id", "frame"], keep="first")
    if dup.any():
        first = df[dup].iloc[0]
        raise RecordingFormatError(
            f"{path}: line {int(first['line'])}: person {int(first['id'])} appears twice in "
            f"frame {int(first['frame'])}"
        )
    df = df.sort_values(["id", "frame"], kind="stable")
    tracks = []
    for pid, rows in df.groupby("id", sort=True):
        tracks.append(
            Track(
                int(pid),
                rows["frame"].to_numpy(dtype=float) * period,
                rows[["x", "y"]].to_numpy(dtype=float),
            )
        )
    return tuple(tracks)


def load_groups(path: str | Path) -> tuple[tuple[int, ...], ...]:
    """Groups of ids that walk together from an OpenTraj ``groups.txt`` (one group per line,
    ids separated by whitespace or commas; blank lines skipped). Raises
    :class:`RecordingFormatError` naming the line for an id that is not an integer or is
    listed twice in one group."""
    p = Path(path)
    _require_file(p)
    groups = []
    for number, line in enumerate(_read_text(p).splitlines(), start=1):
        fields = line.replace(",", " ").split()
        if not fields:
            continue
        ids: list[int] = []
        for field in fields:
            try:
                value = float(field)
            except ValueError:
                value = math.nan
            if not (math.isfinite(value) and value == round(value)):
                raise RecordingFormatError(
                    f"{p}: line {number}: person ids must be integers, got {field!r}"
                )
            if int(value) in ids:
                raise RecordingFormatError(f"{p}: line {number}: person {int(value)} listed twice")
            ids.append(int(value))
        groups.append(tuple(ids))
    return tuple(groups)


def _with_groups(
    tracks: tuple[Track, ...],
    spec: str | Path | Sequence[Sequence[int]] | None,
    period: float,
    path: Path,
    fmt: str,
    max_gap: float,
) -> Recording:
    """The recording of ``tracks`` with the group list ``spec`` (a file or id lists)."""
    groups = _groups(spec)
    source = str(spec) if isinstance(spec, str | Path) else "group list"
    known = {t.id for t in tracks}
    # Group lists may name people the file never shows (a slice of a recording keeps its
    # list): keep only those present. A group only partly present is said: people who walk
    # together appear together, so it hints at another recording's list.
    partial = [g for g in groups if 0 < sum(i in known for i in g) < len(g)]
    if partial:
        absent = sorted({i for g in partial for i in g} - known)
        shown = ", ".join(map(str, absent[:10])) + (", ..." if len(absent) > 10 else "")
        warnings.warn(
            f"{source}: {len(partial)} group(s) name people who never appear in {path} "
            f"(ids {shown}); those groups keep only the people present (a group left with "
            "fewer than two is dropped)",
            stacklevel=3,
        )
    kept = tuple(g2 for g in groups if len(g2 := tuple(i for i in g if i in known)) >= 2)
    return Recording(tracks, period, kept, path, fmt, max_gap)


def load_obsmat(
    path: str | Path,
    frame_period: float | None = None,
    groups: str | Path | Sequence[Sequence[int]] | None = None,
    max_gap: float = DEFAULT_MAX_GAP,
) -> Recording:
    """An ETH/UCY ``obsmat`` file (default ``frame_period`` 0.04 s, see the module docstring).

    ``groups``: a ``groups.txt`` path or id lists. Raises :class:`RecordingFormatError`.
    """
    p = Path(path)
    period = _period(frame_period, OBSMAT_FRAME_PERIOD, p)
    df = _read_table(p, OBSMAT_COLUMNS, r"[\s,]+")
    return _with_groups(_tracks(df, period, p), groups, period, p, "obsmat", max_gap)


def load_four_column(
    path: str | Path,
    frame_period: float | None = None,
    groups: str | Path | Sequence[Sequence[int]] | None = None,
    max_gap: float = DEFAULT_MAX_GAP,
) -> Recording:
    """A ``frame id x y`` text file (whitespace, tab or comma separated; default
    ``frame_period`` 0.04 s). Raises :class:`RecordingFormatError`."""
    p = Path(path)
    period = _period(frame_period, FOUR_COLUMN_FRAME_PERIOD, p)
    df = _read_table(p, ("frame", "id", "x", "y"), r"[\s,]+")
    return _with_groups(_tracks(df, period, p), groups, period, p, "four_column", max_gap)


def load_trajnet(
    path: str | Path,
    frame_period: float | None = None,
    groups: str | Path | Sequence[Sequence[int]] | None = None,
    max_gap: float = DEFAULT_MAX_GAP,
) -> Recording:
    """A Trajnet++ ``ndjson`` file: its track records (scenes only give the frame rate).

    Default ``frame_period``: ``1 / (fps · median frame step)`` with the scenes' ``fps``
    (2.5 when absent). Raises :class:`RecordingFormatError`.
    """
    p = Path(path)
    _require_file(p)
    rows: list[tuple[int, int, float, float, int]] = []
    fps: list[float] = []
    for number, line in enumerate(_read_text(p).splitlines(), start=1):
        if not line.strip():
            continue
        try:
            obj = json.loads(line)
        except json.JSONDecodeError as exc:
            raise RecordingFormatError(f"{p}: line {number}: not JSON: {exc.msg}") from exc
        if not isinstance(obj, dict) or not ({"scene", "track"} & obj.keys()):
            raise RecordingFormatError(f"{p}: line {number}: expected a 'scene' or 'track' record")
        if "scene" in obj:
            scene = obj["scene"]
            if not isinstance(scene, dict):
                raise RecordingFormatError(f"{p}: line {number}: 'scene' must be an object")
            if "fps" in scene:
                rate = _number(scene["fps"], p, number, "scene.fps")
                if rate <= 0:
                    raise RecordingFormatError(
                        f"{p}: line {number}: scene.fps must be positive, got {rate:g}"
                    )
                fps.append(rate)
            continue
        track = obj["track"]
        if not isinstance(track, dict):
            raise RecordingFormatError(f"{p}: line {number}: 'track' must be an object")
        values = []
        for key in ("f", "p", "x", "y"):
            if key not in track:
                raise RecordingFormatError(f"{p}: line {number}: track record has no {key!r}")
            values.append(_number(track[key], p, number, f"track.{key}"))
        rows.append((values[0], values[1], values[2], values[3], number))  # type: ignore[arg-type]
    if not rows:
        raise RecordingFormatError(f"{p}: no track records")
    df = pd.DataFrame(rows, columns=["frame", "id", "x", "y", "line"])
    # Trajnet++ files list a track row once per scene that contains it: same row, same data.
    df = df.drop_duplicates(["frame", "id", "x", "y"], keep="first")
    if frame_period is None:
        rate = float(np.median(fps)) if fps else TRAJNET_FPS
        steps = df.sort_values(["id", "frame"]).groupby("id")["frame"].diff().dropna()
        steps = steps[steps > 0]
        step = float(np.median(steps)) if len(steps) else 1.0
        frame_period = 1.0 / (rate * step)
    period = _period(frame_period, TRAJNET_FPS, p)
    return _with_groups(_tracks(df, period, p), groups, period, p, "trajnet", max_gap)


def _number(value: object, path: Path, line: int, field: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise RecordingFormatError(f"{path}: line {line}: {field} must be a finite number")
    if field in ("track.f", "track.p") and abs(value) > _LARGEST_INTEGER:
        raise RecordingFormatError(f"{path}: line {line}: {field} {value} is too large an integer")
    return float(value)


def _groups(
    groups: str | Path | Sequence[Sequence[int]] | None,
) -> tuple[tuple[int, ...], ...]:
    if groups is None:
        return ()
    if isinstance(groups, str | Path):
        return load_groups(groups)
    return tuple(tuple(int(i) for i in g) for g in groups)


def sibling_groups_file(path: Path) -> Path | None:
    """The group list next to a recording, as OpenTraj lays them out: ``X_groups.txt`` beside
    ``X_obsmat.txt`` (or ``X.txt``), or ``groups.txt`` in the same folder."""
    stem = path.stem
    for suffix in ("_obsmat", ""):
        if suffix and stem.endswith(suffix):
            candidate = path.with_name(stem[: -len(suffix)] + "_groups.txt")
            if candidate.is_file():
                return candidate
    candidate = path.with_name(stem + "_groups.txt")
    if candidate.is_file():
        return candidate
    candidate = path.with_name("groups.txt")
    return candidate if candidate.is_file() and candidate != path else None


def detect_format(path: str | Path) -> str:
    """``trajnet`` for ``.ndjson``/``.json`` files, else ``obsmat`` for 8 columns and
    ``four_column`` for 4 (the first data line decides)."""
    p = Path(path)
    if p.suffix.lower() in (".ndjson", ".json", ".jsonl"):
        return "trajnet"
    for number, line in enumerate(_read_text(p).splitlines(), start=1):
        fields = [f for f in line.replace(",", " ").split() if f]
        if not fields or fields[0].startswith("#"):
            continue
        if line.lstrip().startswith("{"):
            return "trajnet"
        if len(fields) == 8:
            return "obsmat"
        if len(fields) == 4:
            return "four_column"
        raise RecordingFormatError(
            f"{p}: line {number}: {len(fields)} columns; expected 8 (obsmat) or 4 "
            "(frame id x y), or a .ndjson Trajnet++ file"
        )
    raise RecordingFormatError(f"{p}: no data rows")


def load_recording(
    path: str | Path,
    format: str = "auto",
    frame_period: float | None = None,
    groups: str | Path | Sequence[Sequence[int]] | bool | None = True,
    max_gap: float = DEFAULT_MAX_GAP,
) -> Recording:
    """Any supported file. ``format``: ``auto`` (:func:`detect_format`) or one of
    :data:`FORMATS`; ``frame_period`` ``None`` = the format's default; ``groups``: ``True`` =
    the sibling group list if there is one (:func:`sibling_groups_file`), ``False``/``None`` =
    none, or a path / id lists. Raises :class:`RecordingFormatError`."""
    p = Path(path)
    fmt = detect_format(p) if format == "auto" else format
    if fmt not in FORMATS:
        raise RecordingFormatError(f"{p}: unknown format {format!r}; use auto or {FORMATS}")
    if groups is True:
        found = sibling_groups_file(p)
        group_spec: str | Path | Sequence[Sequence[int]] | None = found
    elif groups is False:
        group_spec = None
    else:
        group_spec = groups
    loader = {"obsmat": load_obsmat, "four_column": load_four_column, "trajnet": load_trajnet}[fmt]
    return loader(p, frame_period, group_spec, max_gap)
