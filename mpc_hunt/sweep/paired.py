"""Two strategies told apart on the same hunts (``mpc-hunt sweep-report --versus A B``).

A sweep runs every strategy on the same hunts (the same draws, the same seeds), so two strategies are compared
hunt by hunt: of the hunts both ran, ``both`` captured by both, ``first`` by the first alone, ``second`` by the
second alone, ``neither``. The difference of their capture rates is (first − second) / hunts, and its 95 %
interval is Newcombe's for paired proportions (method 10 of Newcombe, Stat. Med. 17, 2635–2650, 1998: the two
rates' Wilson intervals combined with the correlation of the pairs, continuity-corrected). Pairing removes what
the hunts share (a hard draw is hard for both), so it tells apart what two rates with intervals of their own
cannot; unlike the normal approximation on the differences, the interval stays wide where few hunts differ (no
discordant hunt among 7 is not a certainty of no difference) and within [−1, 1].

On the hunts both captured, the first's capture time minus the second's is summarised by its median and the
sign test's exact 95 % interval for the median (order statistics of the differences: no assumption on their
distribution, none of the normal approximation), which needs at least six such hunts.
"""

from __future__ import annotations

import math
import statistics
from dataclasses import asdict, dataclass

from mpc_hunt import markdown
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.sweep.summary import Z95, combination, wilson


@dataclass(frozen=True)
class PairedCounts:
    """The hunts two strategies both ran, by who captured them."""

    both: int
    first: int  # captured by the first strategy alone
    second: int  # by the second alone
    neither: int

    @classmethod
    def of(cls, pairs) -> PairedCounts:
        """The counts of ``pairs``: (captured by the first, captured by the second), one per hunt."""
        pairs = [(bool(x), bool(y)) for x, y in pairs]
        return cls(
            sum(x and y for x, y in pairs),
            sum(x and not y for x, y in pairs),
            sum(y and not x for x, y in pairs),
            sum(not (x or y) for x, y in pairs),
        )

    @property
    def hunts(self) -> int:
        return self.both + self.first + self.second + self.neither

    @property
    def difference(self) -> float:
        """The first's capture rate minus the second's (0 with no hunt)."""
        return (self.first - self.second) / self.hunts if self.hunts else 0.0


def newcombe(counts: PairedCounts, z: float = Z95) -> tuple[float, float]:
    """Newcombe's interval (method 10, the module's docstring) for the difference of paired capture rates;
    (−1, 1) with no hunt."""
    a, b, c, d, n = counts.both, counts.first, counts.second, counts.neither, counts.hunts
    if n == 0:
        return (-1.0, 1.0)
    p1, p2 = (a + b) / n, (a + c) / n
    l1, u1 = wilson(a + b, n, z)
    l2, u2 = wilson(a + c, n, z)
    product = (a + b) * (c + d) * (a + c) * (b + d)
    cross = a * d - b * c
    corrected = cross - n / 2 if cross > n / 2 else cross if cross < 0 else 0.0  # the continuity correction
    phi = corrected / math.sqrt(product) if product else 0.0
    lower = math.sqrt(max((p1 - l1) ** 2 - 2 * phi * (p1 - l1) * (u2 - p2) + (u2 - p2) ** 2, 0.0))
    upper = math.sqrt(max((u1 - p1) ** 2 - 2 * phi * (u1 - p1) * (p2 - l2) + (p2 - l2) ** 2, 0.0))
    difference = p1 - p2
    return (max(-1.0, difference - lower), min(1.0, difference + upper))


def median_interval(values: list[float], level: float = 0.95) -> tuple[float, float, float]:
    """The median of ``values`` and the sign test's exact interval for it at ``level`` (at least that coverage):
    [x_(k), x_(n−k+1)] of the sorted values, k the largest with P(Bin(n, ½) < k) ≤ (1 − level) / 2; (−∞, ∞)
    where no k is (five values or fewer at 95 %)."""
    x, n = sorted(values), len(values)
    if not n:
        raise ValueError("median_interval: no values")
    tail, k, below = (1 - level) / 2, 0, 0.0
    while below + math.comb(n, k) / 2**n <= tail:
        below += math.comb(n, k) / 2**n
        k += 1
    median = statistics.median(x)
    return (median, -math.inf, math.inf) if k == 0 else (median, x[k - 1], x[n - k])


def hunt_of(row: dict) -> tuple:
    """The hunt a row ran, whichever strategy ran it: (attacker, belief, seed, draw)."""
    return (*combination(row)[1:], row["seed"], row["index"])


def time_summary(rows: list[dict], first: str, second: str, where=lambda row: True) -> dict:
    """The first strategy's capture time minus the second's on the hunts both captured among the ``rows`` kept by
    ``where``: how many, the median difference (s), its interval (:func:`median_interval`) and what it tells."""
    times: dict[str, dict[tuple, float]] = {first: {}, second: {}}
    for r in rows:
        if r["strategy"] in times and r["outcome"] == "captured" and where(r):
            times[r["strategy"]][hunt_of(r)] = r["capture_time_s"]
    differences = [times[first][h] - times[second][h] for h in times[first].keys() & times[second].keys()]
    if not differences:
        return {"hunts": 0, "median_difference_s": None, "ci95_s": None, "verdict": "none captured by both"}
    median, lo, hi = median_interval(differences)
    verdict = "quicker" if hi < 0 else "slower" if lo > 0 else "not told apart"
    return {
        "hunts": len(differences),
        "median_difference_s": median,
        "ci95_s": None if math.isinf(lo) else [lo, hi],
        "verdict": verdict if math.isfinite(lo) else "too few",
    }


def told(interval: tuple[float, float]) -> str:
    """What a difference's interval tells of the first strategy against the second."""
    lo, hi = interval
    return "ahead" if lo > 0 else "behind" if hi < 0 else "not told apart"


def paired_counts(rows: list[dict], first: str, second: str, where=lambda row: True) -> PairedCounts:
    """The hunts (attacker, belief, seed, draw) both strategies ran among the ``rows`` kept by ``where``."""
    won: dict[str, dict[tuple, bool]] = {first: {}, second: {}}
    for r in rows:
        if r["strategy"] in won and where(r):
            won[r["strategy"]][hunt_of(r)] = r["outcome"] == "captured"
    return PairedCounts.of((won[first][h], won[second][h]) for h in won[first].keys() & won[second].keys())


def versus(rows: list[dict], first: str, second: str) -> list[dict]:
    """Per attacker and belief where both strategies ran a hunt: their paired counts on every hunt both ran and on
    the comfortable ones, each with the difference, its interval and what it tells; and their capture times on
    the hunts both captured (:func:`time_summary`). A strategy the rows do not
    hold, or two that ran no hunt in common, is refused."""
    held = sorted({r["strategy"] for r in rows})
    for name in (first, second):
        if name not in held:
            raise MpcHuntError(f"{name}: not a strategy of this file (it holds {', '.join(held) or 'no hunt'})")
    if first == second:
        raise MpcHuntError(f"{first} {second}: give two different strategies")
    out = []
    by_cell: dict[tuple, list[dict]] = {}
    for r in rows:  # one pass: the rows of each attacker and belief
        by_cell.setdefault(combination(r)[1:], []).append(r)
    for (attacker, belief), mine in by_cell.items():
        entry: dict = {"first": first, "second": second, "attacker": attacker, "belief": belief}
        for kind, where in (("all", lambda r: True), ("comfortable", lambda r: bool(r.get("comfortable")))):
            entry[kind] = summary(paired_counts(mine, first, second, where))
        entry["capture_time"] = time_summary(mine, first, second)
        if entry["all"]["hunts"]:
            out.append(entry)
    if not out:
        raise MpcHuntError(f"{first} {second}: no hunt of this file was run by both")
    return out


def summary(counts: PairedCounts) -> dict:
    """``counts`` as plain data, with the difference, its interval (:func:`newcombe`) and what it tells."""
    interval = newcombe(counts)
    return asdict(counts) | {
        "hunts": counts.hunts,
        "difference": counts.difference,
        "ci95": list(interval),
        "verdict": told(interval),
    }


def cell(entry: dict) -> str:
    """One comparison (:func:`summary`) as a table cell: the difference in points, its interval, the hunts, the
    verdict."""
    if not entry["hunts"]:
        return "–"
    lo, hi = (_points(x) for x in entry["ci95"])
    return f"{_points(entry['difference'])} ({lo} to {hi}), {entry['hunts']}: {entry['verdict']}"


def _points(share: float) -> str:
    """A share as signed whole points; one decimal where that would print a difference of a few hunts in hundreds
    as 0 (−1 of 200 hunts is −0.5, not −0)."""
    points = 100 * share
    return f"{points:+.1f}" if points and round(points) == 0 else f"{points:+.0f}"


def time_cell(entry: dict) -> str:
    """A :func:`time_summary` as a table cell."""
    if not entry["hunts"]:
        return "–"
    if entry["ci95_s"] is None:
        return f"{entry['median_difference_s']:+.1f} s, {entry['hunts']}: too few"
    lo, hi = entry["ci95_s"]
    return f"{entry['median_difference_s']:+.1f} s ({lo:+.1f} to {hi:+.1f}), {entry['hunts']}: {entry['verdict']}"


def versus_table(entries: list[dict]) -> str:
    """:func:`versus` as a markdown table."""
    first, second = entries[0]["first"], entries[0]["second"]
    return "\n".join(
        markdown.table(
            [
                "attacker",
                "belief",
                f"{first} − {second}, every hunt both ran",
                "on the comfortable ones",
                "capture time on the hunts both captured, median",
            ],
            "lllll",
            (
                [e["attacker"], e["belief"], cell(e["all"]), cell(e["comfortable"]), time_cell(e["capture_time"])]
                for e in entries
            ),
        )
    )
