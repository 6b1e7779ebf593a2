"""Python's Model.simulate takes the automatic tolerance of `mbd simulate` (issue 42,
docs/user-guide.md "The automatic choice"): without tol, book Ex. 5.6 (v_s = 1e-9 m/s) runs at
v_s / 10 and its block comes to rest where the book says, -(0.03 - 15 * 2 F_f / k) = -5.70e-4 m;
a given tol too coarse for the stiction velocity is kept and warned of, by element."""

import mbd
from conftest import scene

EX_5_6 = "extreme/friction-oscillator-ex5-6.yaml"


def test_book_example_5_6_without_tol_comes_to_rest_where_the_book_says():
    result = mbd.load(scene(EX_5_6)).simulate(2.0)
    rest = -(0.03 - 15 * 2 * (0.1 * 5 * 9.81) / 5000)
    assert abs(rest - (-5.70e-4)) < 1e-12
    assert abs(result["block.x"][-1] - rest) < 1e-5, result["block.x"][-1]
    assert result.stats.integrator == "cvode"
    assert abs(result.stats.tolerance * (1 + 1e-9) - 1e-10) < 1e-22
    assert any("tolerance 1e-10 (automatic: force 'dry'" in m for m in result.messages), result.messages


def test_a_given_tol_too_coarse_for_a_stiction_velocity_is_warned_of():
    result = mbd.load(scene(EX_5_6)).simulate(0.05, tol=1e-6)
    assert result.stats.tolerance == 1e-6
    warnings = [m for m in result.messages if m.startswith("warning: force 'dry' has stiction velocity 1e-09")]
    assert len(warnings) == 1, result.messages
    assert "at most 1e-10" in warnings[0]
