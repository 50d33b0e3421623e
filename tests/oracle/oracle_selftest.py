"""Self-test of the SymPy side of the Kane oracle (no hybridtest binary needed).

Checks the KanesMethod derivations in oracle_models.py against results obtained another way:
- rotor (N = 3 and N = 4): M is exactly the hand-derived arrow matrix (m_b on the diagonal,
  m_b l_b couplings to the hub, I_g + sum m_b (l_b^2 + q_i^2) in the corner) and F is exactly
  the hand-derived forcing; the hub's steady-state torque balance gives u_hub = N f_w l_b / d_g
  (1.5 rad/s for the paper's 3 blades);
- double pendulum and spinning top: power balance. With u' = M^-1 F, a conservative system
  satisfies u^T F + (1/2) u^T M' u + dV/dt = 0 (M' the time derivative of M along the motion,
  V the potential energy written independently from the geometry); checked at random states.
"""

import math

import numpy as np
import sympy as sm

import oracle_models as om


def _rotor_exact(nb):
    model = om.derive_rotor(nb)
    t = sm.Symbol('t')
    q = sm.symbols(f'qq0:{nb + 1}')
    u = sm.symbols(f'uu0:{nb + 1}')
    r = sm.symbols(f'r1:{nb + 1}')
    # blade<i>.key is the symbol key_i in the derivation.
    b = [{key: sm.Symbol(f'{key}_{i}', real=True) for key in om.ROTOR_BLADE_KEYS}
         for i in range(1, nb + 1)]
    i_g, d_g, g, t0 = sm.symbols('I_g d_g g t0', positive=True)
    rho = 1 - sm.exp(-t / t0)
    mass = sm.zeros(nb + 1, nb + 1)
    forcing = sm.zeros(nb + 1, 1)
    mass[nb, nb] = i_g
    forcing[nb] = -d_g * u[nb]
    for i in range(nb):
        m, l, theta = b[i]['m_b'], b[i]['l_b'], b[i]['psi'] + q[nb]
        mass[i, i] = m
        mass[i, nb] = mass[nb, i] = m * l
        mass[nb, nb] += m * (l**2 + q[i]**2)
        forcing[i] = (rho * b[i]['f_w'] - r[i] - b[i]['zeta_b'] * m * u[i] + m * q[i] * u[nb]**2
                      - rho * m * g * sm.sin(theta))
        forcing[nb] += (rho * b[i]['f_w'] * l - rho * m * g * (l * sm.sin(theta)
                        + q[i] * sm.cos(theta)) - 2 * m * q[i] * u[i] * u[nb])
    ok = True
    if sm.simplify(model.mass_matrix_sym - mass) != sm.zeros(nb + 1, nb + 1):
        print(f'FAIL rotor N={nb}: mass matrix differs from the arrow matrix')
        ok = False
    if sm.simplify(model.forcing_sym - forcing) != sm.zeros(nb + 1, 1):
        print(f'FAIL rotor N={nb}: forcing differs from the hand derivation')
        ok = False
    # Steady state: zero deflections and blade speeds, ramp finished, hub at N f_w l_b / d_g.
    p = model.resolve({})
    u_hub = nb * 100.0 * 0.5 / 100.0
    for hub_angle in (0.0, 0.7, -2.3):
        qv = [0.0] * nb + [hub_angle]
        uv = [0.0] * nb + [u_hub]
        _, f, _ = model.evaluate(200.0, qv, uv, [0.0] * nb, p)
        if abs(f[nb]) > 1e-10:
            print(f'FAIL rotor N={nb}: hub torque {f[nb]!r} != 0 at u_hub = {u_hub}')
            ok = False
    if nb == 3 and not math.isclose(u_hub, 1.5):
        ok = False
    print(f'rotor N={nb}: arrow mass matrix, hand forcing, steady hub speed {u_hub} rad/s: '
          f'{"ok" if ok else "FAILED"}')
    return ok


def _power_balance(model, potential, q_syms, rng, q_sampler):
    """Checks u^T F + 1/2 u^T M' u + V' = 0 at random states."""
    n = model.n
    u = sm.symbols(f'uu0:{n}')
    qdot = model.qdot_sym
    mdot = sm.zeros(n, n)
    for j in range(n):
        mdot += model.mass_matrix_sym.diff(q_syms[j]) * qdot[j]
    uvec = sm.Matrix(u)
    vdot = sum(potential.diff(q_syms[j]) * qdot[j] for j in range(n))
    power = (uvec.T * model.forcing_sym)[0] + (uvec.T * mdot * uvec)[0] / 2 + vdot
    params = [sm.Symbol(k, real=True) if k not in ('m1', 'm2', 'l1', 'l2', 'g')
              else sm.Symbol(k, positive=True) for k in model.param_keys]
    fn = sm.lambdify([list(q_syms), list(u), params], power, modules='numpy')
    p = model.resolve({})
    worst = 0.0
    for _ in range(50):
        qv = q_sampler(rng)
        uv = rng.uniform(-50.0, 50.0, n)
        _, f, _ = model.evaluate(1.0, qv, uv, [], p)
        scale = max(1.0, float(np.max(np.abs(f * uv))))
        worst = max(worst, abs(fn(list(qv), list(uv), p)) / scale)
    ok = worst < 1e-12
    print(f'{model.name}: power balance at 50 random states, worst relative residual '
          f'{worst:.2e}: {"ok" if ok else "FAILED"}')
    return ok


def _pendulum(rng):
    model = om.derive_double_pendulum()
    q = sm.symbols('qq0:2')
    m1, m2, l1, l2, g = sm.symbols('m1 m2 l1 l2 g', positive=True)
    # n_x points down, so the height is -x and V = -g sum m_i x_i.
    x1 = l1 * sm.cos(q[0])
    x2 = x1 + l2 * sm.cos(q[0] + q[1])
    potential = -g * (m1 * x1 + m2 * x2)
    return _power_balance(model, potential, q, rng,
                          lambda r: r.uniform(-2 * math.pi, 2 * math.pi, 2))


def _top(rng):
    model = om.derive_spinning_top()
    q = sm.symbols('qq0:3')
    p = {k: sm.Symbol(k, real=True) for k in om.TOP_DEFAULTS}
    # Height of G: n_z . R_x(q1) R_y(q2) R_z(q3) c, with elementary rotation matrices.
    c1, s1, c2, s2, c3, s3 = (sm.cos(q[0]), sm.sin(q[0]), sm.cos(q[1]), sm.sin(q[1]),
                              sm.cos(q[2]), sm.sin(q[2]))
    rx = sm.Matrix([[1, 0, 0], [0, c1, -s1], [0, s1, c1]])
    ry = sm.Matrix([[c2, 0, s2], [0, 1, 0], [-s2, 0, c2]])
    rz = sm.Matrix([[c3, -s3, 0], [s3, c3, 0], [0, 0, 1]])
    height = (rx * ry * rz * sm.Matrix([p['cx'], p['cy'], p['cz']]))[2]
    potential = p['m'] * p['g'] * height
    return _power_balance(model, potential, q, rng,
                          lambda r: np.array([r.uniform(-math.pi, math.pi),
                                              r.uniform(-1.2, 1.2),
                                              r.uniform(-math.pi, math.pi)]))


def run():
    rng = np.random.default_rng(7)
    results = [_rotor_exact(3), _rotor_exact(4), _pendulum(rng), _top(rng)]
    print('PASSED' if all(results) else 'FAILED')
    return 0 if all(results) else 1
