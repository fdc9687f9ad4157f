"""Small scenario files as TOML text, for the tests that feed files to the command line."""

from __future__ import annotations


def scenario_toml(name: str, defenders, *, time_limit: float, arena=None, obstacles=()) -> str:
    """A scenario with the paper's attacker at (5, 5), ``defenders`` (x, y) starts at 0.08 m/s, and
    ``obstacles`` ((x, y), radius)."""
    parts = [f'name = "{name}"\n' + (f"arena = {[float(v) for v in arena]}\n" if arena else ""),
             "[attacker]\nstart = [5.0, 5.0]\nnominal_velocity = [0.03, 0.0]\nmax_speed = 0.03\n"
             "perception_radius = 1.0\n"]
    parts += [f"[[defenders]]\nstart = [{float(x)}, {float(y)}]\nmax_speed = 0.08\n" for x, y in defenders]
    parts += [f"[[obstacles]]\ncentre = [{float(x)}, {float(y)}]\nradius = {float(r)}\n" for (x, y), r in obstacles]
    parts.append(f"[hunt]\ntime_limit = {float(time_limit)}\n")
    return "\n".join(parts)
