"""scripts/work_precision.py: an engine's cost at a target error, on synthetic curves whose cost
at any error is known in closed form."""
import math
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))
from work_precision import engine_cost_at, series_cost_at  # noqa: E402


def power_law(c, p, tolerances, error_per_tol=1.0):
    """A series of order p: error = error_per_tol * tol, cpu = c * error^(-1/p)."""
    return [(tol, error_per_tol * tol, c * (error_per_tol * tol) ** (-1.0 / p)) for tol in tolerances]


def row(engine, name, tol, error, cpu, status="ok"):
    return {"engine": engine, "formulation": name, "integrator": "x", "tolerance": tol, "step": None,
            "error": error, "cpu_s": cpu, "status": status}


def test_a_power_law_is_read_exactly_between_coarse_grid_points():
    for p in (4.0, 5.0, 8.0):
        points = power_law(2e-3, p, [1e-3, 1e-6, 1e-9, 1e-12], error_per_tol=3.7)
        for target in (1e-6, 1e-9, 2.5e-7):
            cpu, exact = series_cost_at(points, target)
            assert exact
            assert math.isclose(cpu, 2e-3 * target ** (-1.0 / p), rel_tol=1e-12)


def test_the_order_of_the_points_is_the_settings_not_the_input():
    points = power_law(1.0, 5.0, [1e-4, 1e-6, 1e-8, 1e-10])
    cpu, _ = series_cost_at(list(reversed(points)), 1e-7)
    assert math.isclose(cpu, 1e-7 ** (-0.2), rel_tol=1e-12)


def test_a_curve_that_never_reaches_the_target_gives_nothing_and_one_always_below_an_upper_bound():
    assert series_cost_at(power_law(1.0, 4.0, [1e-2, 1e-3, 1e-4]), 1e-9) is None
    cpu, exact = series_cost_at(power_law(1.0, 4.0, [1e-10, 1e-11]), 1e-6)
    assert not exact and math.isclose(cpu, 1e-10 ** -0.25)


def test_a_non_monotone_curve_takes_its_cheapest_crossing():
    # error rises again at the tight end (round-off): two crossings of 1e-6, the cheaper counts
    points = [(1e-4, 1e-4, 1.0), (1e-6, 1e-7, 2.0), (1e-8, 1e-5, 4.0)]
    cpu, exact = series_cost_at(points, 1e-6)
    expected = 2.0 ** (2.0 / 3.0)  # 1e-6 lies 2/3 of the way from 1e-4 to 1e-7 in log error
    assert exact and math.isclose(cpu, expected, rel_tol=1e-12)


def test_an_engine_costs_its_cheapest_series_and_ignores_failed_runs():
    rows = []
    for tol, e, c in power_law(1e-3, 5.0, [1e-4, 1e-6, 1e-8]):
        rows.append(row("mbd", "slow", tol, e, 10 * c))
    for tol, e, c in power_law(1e-3, 5.0, [1e-4, 1e-6, 1e-8]):
        rows.append(row("mbd", "fast", tol, e, c))
    rows.append(row("mbd", "broken", 1e-4, float("nan"), 1e-9, status="step-size collapse"))
    rows.append(row("mbd", "broken", 1e-6, 1e-6, 1e-12, status="max steps"))
    cpu, exact, name = engine_cost_at(rows, 3e-7, key=lambda r: r["formulation"])
    assert name == "fast" and exact
    assert math.isclose(cpu, 1e-3 * 3e-7 ** -0.2, rel_tol=1e-12)
