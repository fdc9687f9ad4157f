"""Two strategies told apart on the same hunts: the paired difference of their captures, with its 95 % interval.

Every sweep study runs each strategy on the same hunts (same draws, same seeds), so two strategies are compared
hunt by hunt: one's capture (1 or 0) minus the other's, averaged, with the normal approximation's interval on
those paired differences. Pairing removes what the hunts share (a hard draw is hard for both), so it tells apart
differences that two unpaired capture rates with their own intervals cannot.
"""

from __future__ import annotations

import statistics

from mpc_hunt import markdown
from mpc_hunt.sweep.summary import Z95

EXACT = "exact"


def paired_interval(differences: list[int]) -> tuple[float, float, float]:
    """The mean of paired differences (each −1, 0 or 1: one controller's capture minus another's on the same hunt)
    and its 95 % interval by the normal approximation."""
    mean = statistics.fmean(differences)
    half = Z95 * (statistics.stdev(differences) / len(differences) ** 0.5 if len(differences) > 1 else 1.0)
    return mean, mean - half, mean + half


def paired_difference(rows: list[dict], attacker: str, mine: str, other: str,
                      comfortable: bool = True) -> tuple[int, float, float, float]:
    """``mine``'s captures minus ``other``'s on the hunts against ``attacker`` that both ran (exact belief; the
    comfortable ones only, if ``comfortable``): (hunts, mean difference, its 95 % interval), as shares."""
    def won(strategy: str) -> dict[int, int]:
        return {r["index"]: int(r["outcome"] == "captured") for r in rows if r["strategy"] == strategy
                and r["attacker"] == attacker and r["belief"] == EXACT and (r["comfortable"] or not comfortable)}
    ours, theirs = won(mine), won(other)
    common = sorted(set(ours) & set(theirs))
    if not common:
        return 0, 0.0, 0.0, 0.0
    return (len(common), *paired_interval([ours[i] - theirs[i] for i in common]))


def told(lo: float, hi: float) -> str:
    """What a paired difference's 95 % interval ``lo`` to ``hi`` tells."""
    return "ahead" if lo > 0 else "behind" if hi < 0 else "not told apart"


def then_and_now(rows: list[dict], previous: list[dict], pairs: list[tuple[str, str]], attackers,
                 comfortable: bool = True) -> list[str]:
    """Markdown: per attacker, each pair's (mine, other) paired difference on the last run's rows (``previous``)
    and on this run's, in points with the 95 % interval and the hunts paired: what the rerun tells apart."""
    body = []
    for attacker in attackers:
        cells = []
        for mine, other in pairs:
            for run in (previous, rows):
                n, mean, lo, hi = paired_difference(run, attacker, mine, other, comfortable)
                cells.append(f"{100 * mean:+.0f} ({100 * lo:+.0f} to {100 * hi:+.0f}), {n}: {told(lo, hi)}"
                             if n else "–")
        body.append([attacker, *cells])
    return markdown.table(["attacker", *(f"`{mine}` − `{other}`, {when}" for mine, other in pairs
                                         for when in ("last run", "now"))], "l" * (1 + 2 * len(pairs)), body) + [""]
