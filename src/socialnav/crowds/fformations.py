"""F-formation datasets in the MATLAB layout of Cristani et al. (Synth, CoffeeBreak, ...).

A dataset folder holds three files (read with :func:`scipy.io.loadmat`):

- ``features.mat``: ``features`` (1 × F cell array), one ``(K, 4)`` matrix per frame with rows
  ``[person_id, x, y, body_orientation]``; positions in the dataset's ground-plane unit
  (centimetres for the Cristani et al. sets), the orientation in radians, counter-clockwise
  from the +x axis (checked on the data by :func:`facing_offsets`); ``timestamp`` (1 × F).
- ``groundtruth.mat``: ``GTgroups`` (1 × G cell array), per annotated frame a cell array of
  id vectors (people alone are not listed); ``GTtimestamp`` (1 × G), the ``timestamp`` of the
  feature frame each annotates (frames are matched by that value, never by position).
- ``settings.mat``: ``params``, the parameters the dataset's authors published for their Hough
  voting method (HFF: M. Cristani et al., "Social interaction discovery by statistical
  analysis of F-formations", BMVC 2011): ``radius`` (the stride, person to o-space centre),
  ``covmat`` (3 × 3 covariance of the samples drawn around each person's ``x, y, θ``),
  ``nsamples``, ``quant`` (the vote grid's cell size), ``empty`` (HFF's empty-o-space weight).

Errors: :class:`FFormationFormatError`, naming the file and the field.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.crowds.loaders import RecordingFormatError

#: Centimetres, the length unit of the Cristani et al. files (``settings.mat``'s 60-unit stride).
CENTIMETRE = 0.01


class FFormationFormatError(RecordingFormatError):
    """An F-formation dataset file that cannot be read; the message names the file and field."""


@dataclass(frozen=True)
class FFormationFrame:
    """One annotated frame: ``ids (K,)``, ``positions (K, 2)`` in metres, ``yaws (K,)`` in
    radians (counter-clockwise from +x), and the true ``groups`` (id lists, singletons not
    listed) at feature ``timestamp``."""

    timestamp: int
    ids: np.ndarray
    positions: FloatArray
    yaws: FloatArray
    groups: list[list[int]]


@dataclass(frozen=True)
class FFormationSettings:
    """``settings.mat`` in SI units: ``stride`` (m), ``covariance`` ``(3, 3)`` of ``x, y, θ``
    (m², m², rad²), ``nsamples``, ``quant`` (m), ``empty`` (HFF's weight, unitless)."""

    stride: float
    covariance: FloatArray
    nsamples: int
    quant: float
    empty: float

    @property
    def position_sigma(self) -> float:
        """Standard deviation (m) of a person's position in the published sampling model."""
        return float(np.sqrt(0.5 * (self.covariance[0, 0] + self.covariance[1, 1])))

    @property
    def heading_sigma(self) -> float:
        """Standard deviation (rad) of a person's orientation in the published sampling model."""
        return float(np.sqrt(self.covariance[2, 2]))


def _loadmat(path: Path, fields: Sequence[str]) -> dict[str, Any]:
    from scipy.io import loadmat
    from scipy.io.matlab import MatReadError

    if not path.is_file():
        raise FFormationFormatError(f"{path}: no such file")
    try:
        data = loadmat(path)
    except (MatReadError, OSError, ValueError, TypeError, NotImplementedError) as exc:
        raise FFormationFormatError(f"{path}: not a readable MATLAB file ({exc})") from exc
    for f in fields:
        if f not in data:
            raise FFormationFormatError(f"{path}: field '{f}' is missing")
    return data


def _scalar(path: Path, name: str, value: Any) -> float:
    arr = np.asarray(value, dtype=object).ravel()
    try:
        x = float(np.asarray(arr[0] if arr.size == 1 else value, dtype=float).ravel()[0])
    except (TypeError, ValueError, IndexError) as exc:
        raise FFormationFormatError(f"{path}: field 'params.{name}' is not a number") from exc
    if arr.size != 1 or not np.isfinite(x):
        raise FFormationFormatError(f"{path}: field 'params.{name}' must be one finite number")
    return x


def load_fformation_settings(
    path: str | Path, length_unit: float = CENTIMETRE
) -> FFormationSettings:
    """``settings.mat`` (module docstring), lengths converted to metres by ``length_unit``
    (metres per file unit). Raises :class:`FFormationFormatError` naming the file and field
    (missing, not a number, a non-positive stride, a covariance that is not 3 × 3 and
    positive semi-definite)."""
    p = Path(path)
    params = _loadmat(p, ["params"])["params"]
    names = params.dtype.names or ()
    for f in ("radius", "covmat", "nsamples", "quant", "empty"):
        if f not in names:
            raise FFormationFormatError(f"{p}: field 'params.{f}' is missing")
    s = params.ravel()[0]
    stride = _scalar(p, "radius", s["radius"]) * length_unit
    if stride <= 0:
        raise FFormationFormatError(f"{p}: field 'params.radius' must be positive")
    try:
        cov = np.array(s["covmat"], dtype=float)
    except (TypeError, ValueError) as exc:
        raise FFormationFormatError(f"{p}: field 'params.covmat' is not numeric") from exc
    if cov.shape != (3, 3) or not np.all(np.isfinite(cov)):
        raise FFormationFormatError(f"{p}: field 'params.covmat' must be a finite 3 x 3 matrix")
    if np.linalg.eigvalsh(0.5 * (cov + cov.T)).min() < -1e-9 * max(1.0, abs(cov).max()):
        raise FFormationFormatError(f"{p}: field 'params.covmat' is not positive semi-definite")
    scale = np.diag([length_unit, length_unit, 1.0])
    return FFormationSettings(
        stride=stride,
        covariance=scale @ cov @ scale,
        nsamples=int(_scalar(p, "nsamples", s["nsamples"])),
        quant=_scalar(p, "quant", s["quant"]) * length_unit,
        empty=_scalar(p, "empty", s["empty"]),
    )


def _cells(path: Path, name: str, value: Any) -> list[Any]:
    arr = np.asarray(value, dtype=object)
    if arr.ndim != 2 or 1 not in arr.shape:
        raise FFormationFormatError(f"{path}: field '{name}' must be a 1 x N cell array")
    return list(arr.ravel())


def _stamps(path: Path, name: str, value: Any) -> list[int]:
    try:
        out = [int(v) for v in np.asarray(value, dtype=float).ravel()]
    except (TypeError, ValueError) as exc:
        raise FFormationFormatError(f"{path}: field '{name}' is not numeric") from exc
    if len(set(out)) != len(out):
        raise FFormationFormatError(f"{path}: field '{name}' repeats a timestamp")
    return out


def _groups(path: Path, index: int, cell: Any) -> list[list[int]]:
    arr = np.asarray(cell, dtype=object)
    if arr.size == 0:
        return []
    try:
        return [[int(i) for i in np.asarray(g, dtype=float).ravel()] for g in arr.ravel()]
    except (TypeError, ValueError) as exc:
        raise FFormationFormatError(
            f"{path}: field 'GTgroups{{{index + 1}}}' must hold id vectors"
        ) from exc


def _feature_rows(path: Path, index: int, cell: Any) -> FloatArray:
    field = f"features{{{index + 1}}}"
    m = np.asarray(cell)
    if m.size == 0:
        return np.zeros((0, 4))
    if m.ndim != 2 or m.shape[1] != 4:
        raise FFormationFormatError(f"{path}: field '{field}' must be a K x 4 matrix")
    try:
        rows = m.astype(float)
    except (TypeError, ValueError) as exc:
        raise FFormationFormatError(f"{path}: field '{field}' is not numeric") from exc
    if not np.all(np.isfinite(rows)):
        raise FFormationFormatError(f"{path}: field '{field}' is not finite")
    return rows


def load_fformation_frames(
    folder: str | Path, length_unit: float = CENTIMETRE
) -> list[FFormationFrame]:
    """The annotated frames of a dataset folder (module docstring), in ``GTtimestamp`` order,
    positions converted to metres by ``length_unit``. Raises :class:`FFormationFormatError`
    naming the file and field: a missing field, a feature matrix that is not ``(K, 4)`` or not
    finite, an annotated timestamp without a feature frame, or a true group naming someone
    absent from its frame."""
    d = Path(folder)
    fpath, gpath = d / "features.mat", d / "groundtruth.mat"
    feats = _loadmat(fpath, ["features", "timestamp"])
    gt = _loadmat(gpath, ["GTgroups", "GTtimestamp"])
    matrices = _cells(fpath, "features", feats["features"])
    stamps = _stamps(fpath, "timestamp", feats["timestamp"])
    if len(stamps) != len(matrices):
        raise FFormationFormatError(
            f"{fpath}: field 'timestamp' has {len(stamps)} entries for {len(matrices)} frames"
        )
    gt_groups = _cells(gpath, "GTgroups", gt["GTgroups"])
    gt_stamps = _stamps(gpath, "GTtimestamp", gt["GTtimestamp"])
    if len(gt_stamps) != len(gt_groups):
        raise FFormationFormatError(
            f"{gpath}: field 'GTtimestamp' has {len(gt_stamps)} entries "
            f"for {len(gt_groups)} annotated frames"
        )
    where = {s: i for i, s in enumerate(stamps)}
    out = []
    for k, (stamp, cell) in enumerate(zip(gt_stamps, gt_groups, strict=True)):
        if stamp not in where:
            raise FFormationFormatError(
                f"{gpath}: field 'GTtimestamp' names frame {stamp}, which {fpath.name} lacks"
            )
        i = where[stamp]
        rows = _feature_rows(fpath, i, matrices[i])
        ids = rows[:, 0].astype(int)
        groups = _groups(gpath, k, cell)
        absent = sorted({m for g in groups for m in g} - set(ids.tolist()))
        if absent:
            raise FFormationFormatError(
                f"{gpath}: field 'GTgroups{{{k + 1}}}' names {absent}, absent from frame {stamp}"
            )
        out.append(FFormationFrame(stamp, ids, rows[:, 1:3] * length_unit, rows[:, 3], groups))
    return out


def heading_step(yaws: FloatArray, finest: float = float(np.radians(1.0))) -> float:
    """The quantisation step (rad) of a set of headings: the largest ``2π/n`` of which every
    heading is a multiple (to 1e-6 rad), or ``0.0`` (continuous) when only steps finer than
    ``finest`` fit. CoffeeBreak's four head-pose classes give π/2; Synth's π/12."""
    y = np.asarray(yaws, dtype=float).ravel()
    if y.size == 0:
        return 0.0
    n = 1
    while 2 * np.pi / n >= finest:
        step = 2 * np.pi / n
        if np.all(np.abs(y / step - np.round(y / step)) * step < 1e-6):
            return float(step)
        n += 1
    return 0.0


#: Candidate readings of a file's orientation column, as maps from the stored angle to the
#: heading counter-clockwise from +x: the convention of the files and four mix-ups (an axis
#: mirrored, the angle measured clockwise from +y as in image-style compass bearings, the
#: direction reversed).
HEADING_CONVENTIONS: dict[str, Callable[[FloatArray], FloatArray]] = {
    "counter-clockwise from +x": lambda t: t,
    "y mirrored (-θ)": lambda t: -t,
    "x mirrored (π - θ)": lambda t: np.pi - t,
    "clockwise from +y (π/2 - θ)": lambda t: np.pi / 2 - t,
    "reversed (θ + π)": lambda t: t + np.pi,
}


def facing_offsets(
    frames: Sequence[FFormationFrame], convention: Callable[[FloatArray], FloatArray]
) -> FloatArray:
    """Unsigned angle (rad) between each grouped person's heading, read with ``convention``
    (a map of :data:`HEADING_CONVENTIONS`), and the direction from them to the mean position
    of the rest of their true group, over all frames: small under the right reading, since an
    F-formation's members face its o-space (Kendon 1990)."""
    out: list[float] = []
    for fr in frames:
        index = {int(i): k for k, i in enumerate(fr.ids)}
        yaw = convention(fr.yaws)
        for g in fr.groups:
            members = [index[m] for m in g]
            for k in members:
                rest = [j for j in members if j != k]
                if not rest:
                    continue
                d = fr.positions[rest].mean(axis=0) - fr.positions[k]
                off = np.arctan2(d[1], d[0]) - yaw[k]
                out.append(abs(float(np.arctan2(np.sin(off), np.cos(off)))))
    return np.array(out)


def front_share(
    scenes: Iterable[tuple[FloatArray, FloatArray]], max_range: float = 1.5
) -> tuple[float, int]:
    """How often people's headings agree with who stands next to them, without any labels:
    over every pair of *mutual* nearest neighbours at most ``max_range`` (m) apart, the share
    of the pair's people whose heading (rad, CCW from +x) has the other strictly in front
    (positive dot product), with the number of people counted. ``scenes`` yields
    ``(positions (K, 2) m, yaws (K,) rad)`` per frame.

    Members of an F-formation face its o-space, so a neighbour in their circle stands in
    front of them (Kendon 1990: in a vis-à-vis pair straight ahead, in a circle of ``k`` at
    ``90° − 180°/k`` off the heading); a heading drawn at random has them in front half the
    time. A source whose share is lower than clean headings give for the same kind of scene
    has that many more wrong headings, which is what ``benchmarks/bench_context.py`` uses to
    calibrate a detector to a heading source. The default range is the chord between
    neighbours of a six-person circle of radius 1.5 m (the widest the project's group
    scenarios use). Returns ``(nan, 0)`` when no pair qualifies."""
    people = front = 0
    for positions, yaws in scenes:
        pos = np.asarray(positions, dtype=float)
        yaw = np.asarray(yaws, dtype=float)
        who, other, _ = mutual_neighbours(pos, max_range)
        rel = pos[other] - pos[who]
        ahead = rel[:, 0] * np.cos(yaw[who]) + rel[:, 1] * np.sin(yaw[who]) > 0
        people += int(who.size)
        front += int(ahead.sum())
    return (front / people if people else float("nan")), people


def mutual_neighbours(
    positions: FloatArray, max_range: float = np.inf
) -> tuple[np.ndarray, np.ndarray, FloatArray]:
    """The people of ``positions (K, 2)`` (m) whose nearest neighbour has them as nearest too,
    at most ``max_range`` m away: ``(who (M,), their neighbour (M,), distance (M,) m)``, each
    pair listed from both sides. Empty for fewer than two people."""
    pos = np.asarray(positions, dtype=float)
    if pos.shape[0] < 2:
        empty = np.zeros(0, dtype=np.intp)
        return empty, empty, np.zeros(0)
    d = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
    np.fill_diagonal(d, np.inf)
    nearest = d.argmin(axis=1)
    mine = np.arange(pos.shape[0])
    gap = d[mine, nearest]
    ok = (nearest[nearest] == mine) & (gap <= max_range)
    return mine[ok], nearest[ok], gap[ok]
