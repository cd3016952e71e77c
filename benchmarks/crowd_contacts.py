"""Whom the robot touches in the recorded crowds, and how long it had seen them.

Run: ``.venv/bin/python benchmarks/crowd_contacts.py --results DIR [--seen 2.0]`` on the folder
of ``socialnav compare --suite crowds …`` (its ``runs/`` subfolders, written with the runs).

A replayed pedestrian appears where their track begins — at a door or a tram stop inside the
annotated area as often as at its border — and does not react to the robot. Some passive
contacts (:mod:`socialnav.metrics.crowd`: the robot stopped or moving away) are therefore with
someone the robot could hardly have avoided. For every run this script lists each contact
event with the time the person had been in view when it began (since their latest
appearance: a track that drops out and comes back counts from its return) and prints:

1. per recording × robot × planner: episodes, episodes with any contact, with a passive
   contact, with a passive contact with someone in view at least ``--seen`` s, and with
   passive contacts only with people in view for less than that;
2. per planner: passive contact events by the robot's controller status at the first contact
   sample and by the time in view (shorter or longer than ``--seen``).

The crowd suite's target counts every passive contact; this split says how many of them came
with less warning than ``--seen`` s, it does not redefine the target.
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.experiments.storage import EPISODE_FILE, load_episode
from socialnav.metrics.crowd import contact_events


def time_in_view(record: EpisodeRecord, person: int, sample: int) -> float:
    """Seconds person ``person`` (column of ``people_positions``) had been in view without a
    gap at ``sample`` (0 when they appear at that sample)."""
    present = np.isfinite(record.people_positions[: sample + 1, person, 0])
    absent = np.flatnonzero(~present)
    first = int(absent[-1]) + 1 if absent.size else 0
    return float((sample - first) * record.dt)


def contacts(record: EpisodeRecord) -> list[tuple[bool, float, str]]:
    """``(active, seconds in view, status)`` of each contact event of ``record``."""
    status = record.status if record.status is not None else np.full(len(record.times), "OK")
    return [
        (active, time_in_view(record, k, first), str(status[first]))
        for k, first, _last, active in contact_events(record)
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--results", type=Path, required=True, help="a compare --out folder")
    ap.add_argument("--seen", type=float, default=2.0, help="seconds in view (default 2)")
    args = ap.parse_args()
    folders = sorted(p.parent for p in (args.results / "runs").glob(f"*/{EPISODE_FILE}"))
    if not folders:
        ap.error(f"{args.results / 'runs'} holds no episode folders (run compare with --out)")
    episodes: Counter[tuple[str, str, str, str]] = Counter()
    events: Counter[tuple[str, str, str]] = Counter()
    for folder in folders:
        record = load_episode(folder)
        if record.family != "crowd":
            continue
        recording = Path(str(record.meta.get("recording", record.scenario))).stem
        key = (recording, str(record.meta["robot"]), str(record.meta["planner"]))
        found = contacts(record)
        passive = [seen for active, seen, _ in found if not active]
        episodes[(*key, "episodes")] += 1
        episodes[(*key, "any contact")] += bool(found)
        episodes[(*key, "passive")] += bool(passive)
        late = any(seen >= args.seen for seen in passive)
        episodes[(*key, f"passive, seen >= {args.seen:g} s")] += late
        episodes[(*key, f"passive, only seen < {args.seen:g} s")] += bool(passive) and not late
        for active, seen, status in found:
            if not active:
                events[(key[2], status, "seen" if seen >= args.seen else "new")] += 1
    columns = [
        "episodes",
        "any contact",
        "passive",
        f"passive, seen >= {args.seen:g} s",
        f"passive, only seen < {args.seen:g} s",
    ]
    keys = sorted({k[:3] for k in episodes})
    print("| recording | robot | planner | " + " | ".join(columns) + " |")
    print("|---" * (3 + len(columns)) + "|")
    for key in keys:
        cells = " | ".join(str(episodes[(*key, c)]) for c in columns)
        print(f"| {key[0]} | {key[1]} | {key[2]} | {cells} |")
    print()
    print(f"| planner | status at contact | passive events seen < {args.seen:g} s | seen longer |")
    print("|---|---|---|---|")
    for planner, status in sorted({k[:2] for k in events}):
        new, seen = events[(planner, status, "new")], events[(planner, status, "seen")]
        print(f"| {planner} | {status} | {new} | {seen} |")


if __name__ == "__main__":
    main()
