"""An engine's cost at a target error, read off its own work-precision curves (bench_report.py).

A series (one formulation x integrator, or one peer integrator) is a curve of points (error, CPU
time) ordered by its setting, loosest first. Its cost at a target error is read by linear
interpolation of log(CPU time) against log(error) between the two consecutive points whose errors
bracket the target: on a power law cpu = c * error^-1/p (an integrator of order p in its asymptotic
range) this is exact, so a grid's spacing does not quantize the ratio of two engines. An engine's
cost is the least over its series. A series that never reaches the target gives nothing; one whose
every point is already more accurate gives its cheapest point, an upper bound (marked).
"""
import math


def usable(row):
    return (row["status"] == "ok" and row["error"] is not None and math.isfinite(row["error"])
            and row["error"] > 0 and row["cpu_s"] is not None and row["cpu_s"] > 0)


def setting_of(row):
    """The grid setting of a row: its tolerance (adaptive) or its step."""
    return row["tolerance"] if row["tolerance"] else row["step"]


def series_cost_at(points, target):
    """points: (setting, error, cpu) of one series. Returns (cpu, exact) or None.

    exact is False when every point is more accurate than the target (cpu is then the cheapest
    point's, an upper bound on the cost at the target)."""
    if not points:
        return None
    curve = sorted(points, key=lambda p: -p[0])  # loosest setting first
    best = None
    for (_, e0, c0), (_, e1, c1) in zip(curve, curve[1:]):
        lo, hi = min(e0, e1), max(e0, e1)
        if not (lo <= target <= hi):
            continue
        if e0 == e1:
            cost = min(c0, c1)
        else:
            w = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            cost = math.exp(math.log(c0) + w * (math.log(c1) - math.log(c0)))
        best = cost if best is None else min(best, cost)
    for _, e, c in curve:  # a single point exactly at the target
        if e == target:
            best = c if best is None else min(best, c)
    if best is not None:
        return best, True
    if all(e < target for _, e, _ in curve):
        return min(c for _, _, c in curve), False
    return None


def engine_cost_at(rows, target, key):
    """The least cost at `target` over the series of `rows` (grouped by key(row)).

    Returns (cpu, exact, series name) or None when no series reaches the target."""
    groups = {}
    for r in rows:
        if usable(r):
            groups.setdefault(key(r), []).append((setting_of(r), r["error"], r["cpu_s"]))
    found = None
    for name, points in groups.items():
        got = series_cost_at(points, target)
        if got is None:
            continue
        cpu, exact = got
        # an interpolated cost beats an upper bound of the same size
        rank = (cpu, not exact)
        if found is None or rank < (found[0], not found[1]):
            found = (cpu, exact, name)
    return found
