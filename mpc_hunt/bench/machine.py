"""The machine a benchmark ran on: CPU, cores, load, Python and package versions (written next to results)."""

from __future__ import annotations

import os
import platform
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

PACKAGES = ("mpc-hunt", "numpy", "numba", "scipy", "casadi", "osqp", "clarabel", "cvxpy", "daqp")


def cpu_model() -> str:
    """The CPU's model name from /proc/cpuinfo, else what :mod:`platform` knows."""
    try:
        for line in Path("/proc/cpuinfo").read_text(encoding="utf-8").splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


# OpenBLAS's kernel families (the names OPENBLAS_CORETYPE takes), each with the CPU flag it needs, widest first.
KERNEL_FAMILIES = (("avx512f", "SkylakeX"), ("avx2", "Haswell"), ("avx", "Sandybridge"), ("pni", "Prescott"))


def blas_kernel_families() -> list[str]:
    """The OpenBLAS kernel families this CPU can run (none where /proc/cpuinfo cannot be read)."""
    try:
        text = Path("/proc/cpuinfo").read_text(encoding="utf-8")
    except OSError:
        return []
    flags = next((set(line.split(":", 1)[1].split()) for line in text.splitlines() if line.startswith("flags")), set())
    return [family for flag, family in KERNEL_FAMILIES if flag in flags]


def _version(package: str) -> str | None:
    try:
        return version(package)
    except PackageNotFoundError:
        return None


def load_average() -> list[float] | None:
    """The 1, 5 and 15 minute load averages (other work on the machine), where the OS reports them."""
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except (AttributeError, OSError):
        return None


def describe_machine() -> dict:
    """Plain data: CPU model, logical cores (and those this process may use), OS, Python, package versions, load."""
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return {
        "cpu": cpu_model(),
        "cores": os.cpu_count(),
        "usable_cores": usable,
        "system": f"{platform.system()} {platform.release()} {platform.machine()}",
        "python": platform.python_version(),
        "packages": {p: _version(p) for p in PACKAGES},
        "load_average": load_average(),
    }


def machine_lines(machine: dict) -> list[str]:
    """The description as Markdown bullet lines, for reports."""
    packages = ", ".join(f"{p} {v}" for p, v in machine["packages"].items() if v)
    lines = [
        f"- CPU: {machine['cpu']}, {machine['cores']} logical cores ({machine['usable_cores']} usable)",
        f"- System: {machine['system']}, Python {machine['python']}",
        f"- Packages: {packages}",
    ]
    for key, label in (("load_average", "at the start"), ("load_average_end", "at the end")):
        if machine.get(key):
            lines.append(f"- Load average (1, 5, 15 min) {label}: {', '.join(map(str, machine[key]))}")
    return lines
