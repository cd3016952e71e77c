"""Whom the robot touches in the recorded crowds, and how long it had seen them.

Run: ``.venv/bin/python benchmarks/crowd_contacts.py --results DIR [--seen 2.0]`` on the folder
of ``socialnav compare --suite crowds … --out DIR``. It reads every episode folder under
``DIR/runs`` (earlier calls into the same folder included, while the report covers the latest
call) and prints two Markdown tables to stdout.

A replayed pedestrian appears where their track begins — inside the annotated area as well as at
its border — and does not react to the robot; someone already walking 1–2 m from the start (the
suite keeps only the first metre clear) can reach the robot in its first second. Some passive
contacts (:mod:`socialnav.metrics.crowd`: the robot stopped or moving away) are therefore with
people the robot had little time to avoid. For each contact event this script takes the time the
person had been *in view* when it began: present in the episode's record without a gap (a track
that drops out and comes back counts from its return), at most since the episode's start — the
robot's warning time, not the planner's sensing (the baselines sense 8 m; with ``--context
detected`` the planner sees noisy tracks).

1. Per report section (recording, people replayed or handed to HL within a distance, context
   given or detected) × robot × planner: episodes; with any contact; with a passive contact;
   with a passive contact with someone in view at least ``--seen`` s; and those whose passive
   contacts are all with people in view for less, split by whether one of them appeared during
   the episode or all were in view from its start.
2. Passive contact *events* per report section × planner (robots pooled) by the controller's
   status at the first contact sample and the time in view. The status is the planner's own:
   socialnav's control loop reports ``WAITING``, ``EVADING`` and the like, the baselines only
   ``OK`` and ``GOAL_REACHED``.

The crowd suite's target counts every passive contact; this split says how many of them came
with less warning than ``--seen`` s, it does not redefine the target. Unreadable episode
folders (and folders under ``runs`` without an ``episode.json``) are listed on stderr (exit
status 1 after the tables).
"""

from __future__ import annotations

import argparse
import math
import sys
from collections import Counter
from pathlib import Path
from typing import NamedTuple

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.experiments.crowd import recording_name
from socialnav.experiments.storage import EPISODE_FILE, load_episode
from socialnav.metrics.crowd import contact_events


class Contact(NamedTuple):
    """One contact event: ``active`` (the robot closed on the person), ``seen`` (s in view when
    it began), ``appeared`` (the person came into view after the episode's first sample) and
    the controller ``status`` at that sample."""

    active: bool
    seen: float
    appeared: bool
    status: str


def in_view_since(record: EpisodeRecord, person: int, sample: int) -> int:
    """First sample of the run of samples, ending at ``sample``, in which person ``person``
    (column of ``people_positions``) is present; 0 when present from the episode's start."""
    present = np.isfinite(record.people_positions[: sample + 1, person, 0])
    absent = np.flatnonzero(~present)
    return int(absent[-1]) + 1 if absent.size else 0


def contacts(record: EpisodeRecord) -> list[Contact]:
    """Every contact event of ``record`` (:func:`~socialnav.metrics.crowd.contact_events`)."""
    status = record.status if record.status is not None else np.full(len(record.times), "OK")
    out = []
    for k, first, _last, active in contact_events(record):
        since = in_view_since(record, k, first)
        seen = float((first - since) * record.dt)
        out.append(Contact(active, seen, since > 0, str(status[first])))
    return out


def section(record: EpisodeRecord) -> str:
    """The report section an episode belongs to: recording, people, context."""
    meta = record.meta
    source = meta.get("recording") or str(record.scenario).split("@", 1)[0]
    name = recording_name(str(source))
    humans = str(meta.get("humans", "replayed"))
    if humans != "replayed":
        name += f", {humans}"
    if meta.get("context", "given") != "given":
        name += f", context {meta['context']}"
    return name


def episode_folders(ap: argparse.ArgumentParser, results: Path) -> list[Path]:
    """The folders under ``results/runs``; a clear error for a wrong folder."""
    if not results.exists():
        ap.error(f"{results} does not exist")
    if not results.is_dir():
        ap.error(f"{results} is a file; pass the folder given to compare --out")
    if (results / EPISODE_FILE).is_file():
        ap.error(f"{results} is one episode's folder; pass the compare --out folder above runs/")
    if results.name == "runs" and any(results.glob(f"*/{EPISODE_FILE}")):
        ap.error(f"{results} is the runs folder itself; pass the folder above it")
    if not (results / "runs").is_dir():
        ap.error(f"{results} has no runs folder; pass the folder given to compare --out")
    folders = sorted(p for p in (results / "runs").iterdir() if p.is_dir())
    if not folders:
        ap.error(f"{results / 'runs'} holds no episode folders (run compare with --out)")
    return folders


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--results", type=Path, required=True, help="a compare --out folder")
    ap.add_argument(
        "--seen",
        type=float,
        default=2.0,
        help="seconds a person must have been in the record before a contact (default 2)",
    )
    args = ap.parse_args()
    if not (math.isfinite(args.seen) and args.seen > 0):
        ap.error(f"--seen must be a positive number of seconds, got {args.seen}")
    seen = f"{args.seen:g} s"
    columns = [
        "episodes",
        "any contact",
        "passive",
        f"passive, one in view >= {seen}",
        f"passive, all in view < {seen}: one appeared in the episode",
        f"passive, all in view < {seen}: all in view from its start",
    ]
    episodes: Counter[tuple[str, str, str, str]] = Counter()
    events: Counter[tuple[str, str, str, str]] = Counter()
    unreadable: list[str] = []
    for folder in episode_folders(ap, args.results):
        try:
            record = load_episode(folder)
            if record.family != "crowd":
                continue
            found = contacts(record)
        except (OSError, ValueError) as exc:
            unreadable.append(str(exc) if str(folder) in str(exc) else f"{folder}: {exc}")
            continue
        key = (section(record), str(record.meta.get("robot")), str(record.meta.get("planner")))
        passive = [c for c in found if not c.active]
        late = [c for c in passive if c.seen >= args.seen]
        counts = (
            True,
            bool(found),
            bool(passive),
            bool(late),
            bool(passive) and not late and any(c.appeared for c in passive),
            bool(passive) and not late and not any(c.appeared for c in passive),
        )
        for column, hit in zip(columns, counts, strict=True):
            episodes[(*key, column)] += hit
        for c in passive:
            when = "long" if c.seen >= args.seen else "appeared" if c.appeared else "start"
            events[(key[0], key[2], c.status, when)] += 1
    if not episodes:
        ap.error(
            f"{args.results / 'runs'} holds no crowd-suite episodes (family 'crowd'); "
            "run compare --suite crowds … --out"
        )
    total = sum(v for k, v in episodes.items() if k[3] == "episodes")
    print(
        f"{total} crowd episodes under {args.results / 'runs'} (every call into the folder; "
        "its report covers the latest).\n"
    )
    print("| section | robot | planner | " + " | ".join(columns) + " |")
    print("|---" * (3 + len(columns)) + "|")
    for key in sorted({k[:3] for k in episodes}):
        cells = " | ".join(str(episodes[(*key, c)]) for c in columns)
        print(f"| {key[0]} | {key[1]} | {key[2]} | {cells} |")
    print(
        f'\nEpisodes; "in view": present in the episode\'s record (since its start at most); '
        f'"one in view >= {seen}": at least one of the people touched; "its start": the '
        "episode's.\n"
    )
    print(
        "Passive contact events, robots pooled:\n\n"
        f"| section | planner | status at contact | in view < {seen}, appeared in the episode | "
        f"in view < {seen}, in view from its start | in view >= {seen} |"
    )
    print("|---|---|---|---|---|---|")
    for name, planner, status in sorted({k[:3] for k in events}):
        cells = " | ".join(
            str(events[(name, planner, status, w)]) for w in ("appeared", "start", "long")
        )
        print(f"| {name} | {planner} | {status} | {cells} |")
    if not events:
        print("| (no passive contact) | | | | | |")
    if unreadable:
        print(f"{len(unreadable)} episode folder(s) could not be read:", file=sys.stderr)
        for line in unreadable:
            print(f"  {line}", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
