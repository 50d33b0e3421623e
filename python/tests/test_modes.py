"""hybridtest.modes: the same analysis as `hybridtest modes` (one C++ implementation), against
the command line's --json, Meijaard et al.'s Table 2 (the benchmark bicycle at v = 5 m/s), the
governor's analytic steady angle arccos(g / (l Ω²)) and nutation frequency about it, the driven
rotor's blade balance, and the errors."""
import cmath
import json
import math
import subprocess

import numpy as np
import pytest

import hybridtest as ht
from conftest import ROOT

BICYCLE = ROOT / "examples/models/whipple_bicycle.yaml"
GOVERNOR = ROOT / "tests/modelfile/data/governor.yaml"
PENDULUM = ROOT / "tests/modelfile/data/sprung_pendulum.yaml"
FOUR_BAR = ROOT / "examples/models/four_bar.yaml"


def cli_json(cli, *args):
    done = subprocess.run([cli, "modes", *map(str, args), "--json"], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def test_bicycle_equals_the_command_line_and_table_2(cli):
    got = ht.modes(BICYCLE, set={"v": 5.0})
    want = cli_json(cli, BICYCLE, "--set", "v=5")
    # The same implementation: equal to the last bit (JSON round-trips doubles).
    assert got.model == want["model"] == "whipple_bicycle"
    assert got.states == want["states"]
    np.testing.assert_array_equal(got.A, np.array(want["state_matrix"]))
    np.testing.assert_array_equal(got.x, np.array(want["operating_point"]))
    assert len(got.modes) == len(want["modes"]) == 10
    for mode, w in zip(got.modes, want["modes"]):
        assert mode.eigenvalue == complex(w["real"], w["imag"])
        assert mode.frequency_hz == w["frequency_hz"]
        assert mode.damped_frequency_hz == w["damped_frequency_hz"]
        assert mode.damping_ratio == w["damping_ratio"]
        np.testing.assert_array_equal(mode.shape,
                                      np.array(w["shape_real"]) + 1j * np.array(w["shape_imag"]))
    # Meijaard, Papadopoulos, Ruina and Schwab (2007), Table 2, v = 5 m/s.
    table = [complex(-0.77534188219585, 4.46486771378823),
             complex(-0.77534188219585, -4.46486771378823),
             -0.32286642900409, -14.07838969279820]
    for w in table:
        assert np.min(np.abs(got.eigenvalues - w)) <= 1e-9 * abs(w), w
    assert np.sum(np.abs(got.eigenvalues) < 1e-9) == 6
    assert got.steady is None
    weave = max(got.modes, key=lambda m: m.eigenvalue.imag)
    assert weave.frequency_hz == pytest.approx(abs(table[0]) / (2 * math.pi), rel=1e-9)
    assert weave.damping_ratio == pytest.approx(0.77534188219585 / abs(table[0]), rel=1e-9)


@pytest.mark.parametrize("omega", [7.5, 10.0, 25.0])
def test_governor_steady_angle(omega):
    a = ht.modes(GOVERNOR, set={"Omega": omega}, steady="theta")
    theta = math.acos(9.81 / (0.2 * omega ** 2))
    assert a.steady.coordinates == ["theta"]
    assert a.steady.values[0] == pytest.approx(theta, abs=1e-10)
    assert a.steady.converged and a.steady.iterations > 0
    assert a.steady.residual <= 1e-10 and a.steady.residual_unit == "rad/s²"
    assert a.x[1] == a.steady.values[0] and a.x[2] == omega
    assert a.start[1] == 1.2  # the model's initial angle, where the search began
    # The nutation about the steady cone, with the angular momentum h about the shaft kept:
    # m l² θ̈ = m l² f(θ), f = sin θ cos θ ψ̇(θ)² − (g/l) sin θ, ψ̇ = h / (J + m l² sin² θ);
    # ω² = −f'(θ*) (a complex-step derivative: exact to rounding, no engine code).
    m, l, inertia, g = 0.5, 0.2, 0.01, 9.81
    h = (inertia + m * l * l * math.sin(theta) ** 2) * omega

    def f(t):
        rate = h / (inertia + m * l * l * cmath.sin(t) ** 2)
        return cmath.sin(t) * cmath.cos(t) * rate ** 2 - g / l * cmath.sin(t)
    nutation = math.sqrt(-f(theta + 1e-30j).imag / 1e-30)
    assert max(ev.imag for ev in a.eigenvalues) == pytest.approx(nutation, rel=1e-10)
    assert np.max(np.abs(a.eigenvalues.real)) <= 1e-9


def test_steady_state_from_a_given_start_and_the_forms_of_steady(cli):
    # Below sqrt(g/l) only the hanging state is steady; from either side it is found.
    for start in (-0.8, 0.8):
        a = ht.modes(GOVERNOR, set={"Omega": 5.0}, at={"q": [0.0, start]}, steady=["theta"])
        assert abs(a.steady.values[0]) <= 1e-10
    by_list = ht.modes(PENDULUM, steady=["q"])
    by_text = ht.modes(PENDULUM, steady="q")
    np.testing.assert_array_equal(by_list.x, by_text.x)
    want = cli_json(cli, PENDULUM, "--steady", "q")
    assert want["steady"]["values"][0] == by_list.steady.values[0]
    assert want["steady"]["iterations"] == by_list.steady.iterations


def test_four_bar_static_equilibrium_through_the_constraints():
    a = ht.modes(FOUR_BAR, at={"u": [0.0, 0.0, 0.0]}, steady="q1")
    assert a.states == ["q1", "u1"]
    assert a.steady.residual <= 1e-10
    # Independent: the four-bar test (tests/modelfile/steady_state_test.cc) minimises the
    # potential energy; here a looser check that every speed rate vanishes there.
    model = ht.Model.from_file(str(FOUR_BAR))
    xdot = model.state_derivative(0.0, a.x)
    assert np.max(np.abs(xdot)) <= 1e-9


def test_errors():
    with pytest.raises(ht.ModelError, match=r"no steady state found for q .*4\.38 rad/s².*"
                                            r"Try another start"):
        ht.modes(PENDULUM, set={"k": 0.0, "T": 6.0}, steady="q")
    with pytest.raises(ht.ModelError, match="no speed rate depends on coordinate psi"):
        ht.modes(GOVERNOR, steady="psi")
    with pytest.raises(ht.ModelError, match="coordinate q2 is dependent"):
        ht.modes(FOUR_BAR, at={"u": [0, 0, 0]}, steady="q2")
    with pytest.raises(ht.ConfigError, match="'phi' is not a coordinate.*psi, theta"):
        ht.modes(GOVERNOR, steady="phi")
    with pytest.raises(ht.ConfigError, match="q has 3 values; the model has n = 2"):
        ht.modes(GOVERNOR, at={"q": [0, 1, 2]})
    with pytest.raises(ht.ConfigError, match="unknown key 'x'"):
        ht.modes(GOVERNOR, at={"x": [0, 1, 2, 3]})
    with pytest.raises(ht.ConfigError, match="Omegaa"):
        ht.modes(GOVERNOR, set={"Omegaa": 3.0})
    with pytest.raises(ht.ConfigError,
                       match=r"no_such_model\.yaml: cannot open this YAML file \(no such file\)"):
        ht.modes(ROOT / "no_such_model.yaml")
    with pytest.raises(ht.ModelError, match="the constraints cannot be met"):
        ht.modes(FOUR_BAR, at={"q": [0.0, 0.0, 0.0]})


def test_a_run_config_gives_its_model_files_operating_point():
    config = ROOT / "examples/09_closed_loops/four_bar.yaml"
    by_config = ht.modes(config, set={"k": 30.0})
    by_file = ht.modes(FOUR_BAR, set={"k": 30.0})
    np.testing.assert_array_equal(by_config.A, by_file.A)
    np.testing.assert_array_equal(by_config.x, by_file.x)


def test_a_driven_rotor_balances_its_blade_tips():
    # q_i = ramp (f_w − m g sin θ_i) / (k − m Ω²): the tip balance along b̂_iy at u̇ = 0.
    omega, t, q4 = 20.0, 3.0, 0.3
    a = ht.modes(ROOT / "examples/models/rotor.yaml", time=t, at={"q": [0, 0, 0, q4],
                 "u": [0, 0, 0, omega]}, steady="q1,q2,q3", driven="u4")
    ramp = 1 - math.exp(-t / 0.5)
    want = [ramp * (100.0 - 1.96 * 9.82 * math.sin(q4 + 2 * math.pi * i / 3)) /
            (7.2e3 - 1.96 * omega ** 2) for i in range(3)]
    np.testing.assert_allclose(a.steady.values, want, rtol=0, atol=1e-15)
    assert a.steady.driven == ["u4"]
    with pytest.raises(ht.ModelError, match="u̇ of speed 'u4'"):
        ht.modes(ROOT / "examples/models/rotor.yaml", time=t, at={"u": [0, 0, 0, omega]},
                 steady="q1,q2,q3")


def test_modes_takes_the_iteration_bound_of_the_command_line():
    """Issue 45: one bound for `modes --steady-iterations` and modes(max_iterations=)."""
    with pytest.raises(ht.ConfigError, match=r"max_iterations=100000\): expected 1 to 10000, "
                                             r"as `hybridtest modes --steady-iterations`"):
        ht.modes(GOVERNOR, set={"Omega": 5.0}, steady="theta", max_iterations=10**5)


def test_modes_are_named_marked_and_an_equilibrium_is_checked():
    """Issue 50: the same readout as the command line (labels, unstable, equilibrium)."""
    slow = ht.modes(BICYCLE, set={"v": 3.0})
    assert slow.equilibrium
    weave = [m for m in slow.modes if m.label == "weave"]
    assert len(weave) == 2 and all(m.unstable for m in weave)
    capsize = [m for m in slow.modes if m.label == "capsize"]
    assert len(capsize) == 1 and not capsize[0].unstable and capsize[0].dominant[0] == "q4"
    fast = ht.modes(BICYCLE, set={"v": 5.0})
    assert not any(m.unstable for m in fast.modes)
    turning = ht.modes(ROOT / "examples/models/slider_crank.yaml", at={"u": [3.0, 0.0, 0.0]})
    assert not turning.equilibrium and turning.residual > 1e-3
