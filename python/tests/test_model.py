"""hybridtest.Model against independent oracles: the rotor derived with SymPy's KanesMethod,
finite differences for the Jacobians, and the model's own structure (g affine in r)."""
import numpy as np
import pytest

import hybridtest as ht
import rotor_sympy
from conftest import ROOT


@pytest.fixture(scope="module")
def rotor():
    return ht.Model.from_file(str(ROOT / "examples/models/rotor.yaml"))


@pytest.fixture(scope="module")
def sympy_rotor(rotor):
    return rotor_sympy.mass_and_forcing({k: v[0] for k, v in rotor.parameters.items()})


def states(count, seed=3):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        q = np.r_[rng.uniform(-0.1, 0.1, 3), rng.uniform(-3, 3)]
        yield rng.uniform(0, 2), q, rng.uniform(-1, 1, 4), rng.uniform(-100, 100, 3)


def test_mass_matrix_and_forcing_match_sympy(rotor, sympy_rotor):
    M_ref, g_ref = sympy_rotor
    for t, q, u, r in states(10):
        x = np.r_[q, u]
        np.testing.assert_allclose(rotor.mass_matrix(t, x), M_ref(q), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(rotor.forcing(t, x, r=r), g_ref(t, q, u, r), rtol=1e-11,
                                   atol=1e-10)


def test_builtin_rotor_equals_the_model_file(rotor):
    builtin = ht.Model.builtin("rotor", blades=3)
    for t, q, u, r in states(5):
        x = np.r_[q, u]
        np.testing.assert_allclose(builtin.mass_matrix(t, x), rotor.mass_matrix(t, x),
                                   rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(builtin.forcing(t, x, r=r), rotor.forcing(t, x, r=r),
                                   rtol=1e-11, atol=1e-10)


def test_state_derivative_solves_m_udot_equals_g(rotor):
    for t, q, u, r in states(5):
        x = np.r_[q, u]
        xdot = rotor.state_derivative(t, x, r=r)
        np.testing.assert_allclose(xdot[:4], u, rtol=0, atol=0)
        np.testing.assert_allclose(rotor.mass_matrix(t, x) @ xdot[4:], rotor.forcing(t, x, r=r),
                                   rtol=1e-10, atol=1e-9)


def test_coupling_matrix_is_the_slope_of_g_in_r(rotor):
    t, q, u, r = next(states(1))
    x = np.r_[q, u]
    B = rotor.coupling_matrix(t, x)
    assert B.shape == (4, 3)
    for s in range(3):
        e = np.zeros(3)
        e[s] = 1.0
        np.testing.assert_allclose(rotor.forcing(t, x, r=r + e) - rotor.forcing(t, x, r=r),
                                   B[:, s], rtol=1e-9, atol=1e-9)


def test_state_jacobian_matches_central_differences(rotor):
    t, q, u, r = next(states(1, seed=5))
    x = np.r_[q, u]
    J = rotor.state_jacobian(t, x, r=r)
    h = 1e-6
    for k in range(8):
        dx = np.zeros(8)
        dx[k] = h
        column = (rotor.state_derivative(t, x + dx, r=r)
                  - rotor.state_derivative(t, x - dx, r=r)) / (2 * h)
        np.testing.assert_allclose(J[:, k], column, rtol=1e-5, atol=1e-5)


def test_default_r_is_the_slot_springs(rotor):
    t, q, u, _ = next(states(1))
    x = np.r_[q, u]
    d = rotor.slot_displacements(t, x)
    np.testing.assert_array_equal(d, q[:3])
    np.testing.assert_allclose(rotor.forcing(t, x), rotor.forcing(t, x, r=7200.0 * d))


def test_parameters_override_by_name():
    m = ht.Model.from_file(str(ROOT / "examples/models/rotor.yaml"), parameters={"m_b": 3.0})
    x = np.zeros(8)
    assert m.parameters["m_b"] == (3.0, "kg", "blade tip mass")
    assert m.mass_matrix(0.0, x)[0, 0] == 3.0


def test_inputs_are_read_in_place_and_results_are_numpy(rotor):
    x = np.zeros(8)
    M = rotor.mass_matrix(0.0, x)
    assert isinstance(M, np.ndarray) and M.dtype == np.float64 and M.flags.owndata is False


def test_check_reports_a_positive_definite_mass_matrix(rotor):
    report = rotor.check(states=10)
    assert report["mass_matrix_positive_definite"] and report["worst_condition_number"] >= 1


def test_errors_are_the_hierarchy_with_the_library_messages(rotor):
    assert issubclass(ht.ConfigError, ht.Error) and issubclass(ht.Error, RuntimeError)
    for cls in (ht.ModelError, ht.TransferError, ht.IoError, ht.SafetyStop):
        assert issubclass(cls, ht.Error)
    with pytest.raises(ht.ConfigError, match="x has 3 values; the rotor model needs 8"):
        rotor.mass_matrix(0.0, np.zeros(3))
    with pytest.raises(ht.ConfigError, match="r has 2 values"):
        rotor.forcing(0.0, np.zeros(8), r=np.zeros(2))
    with pytest.raises(ht.ConfigError, match="k_bee"):
        ht.Model.from_file(str(ROOT / "examples/models/rotor.yaml"), parameters={"k_bee": 1.0})
    with pytest.raises(ht.ConfigError, match="no_such_model"):
        ht.Model.builtin("no_such_model")
    with pytest.raises(ht.ConfigError, match="missing.yaml"):
        ht.Model.from_file("missing.yaml")


@pytest.mark.parametrize("blades", [10**9, 0, 2.5, 32])
def test_builtin_rotor_takes_the_blade_bound_of_a_run_config(blades):
    """Model.builtin and a run config's model.blades are bounded by one rule, with one message
    (issue 45: blades=10**9 used to take 24 GB before the kernel killed it)."""
    expected = (rf"blades = {blades:.15g}: expected a whole number of blades from 1 to 31 "
                r"\(the Kane engine takes at most 32 coordinates")
    with pytest.raises(ht.ConfigError, match=expected):
        ht.Model.builtin("rotor", blades=blades)
    config = {"model": {"name": "rotor", "blades": blades},
              "integrator": {"tableau": "heun", "dt": 0.001}, "duration": 0.01}
    from_config = r"model\.blades[^=]* = " + expected.split(" = ", 1)[1]
    with pytest.raises(ht.ConfigError, match=from_config):
        ht.Session(config, command="simulate")
    assert ht.Model.builtin("rotor", blades=31).num_coordinates == 32
