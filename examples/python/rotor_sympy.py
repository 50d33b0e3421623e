"""The paper's rotor derived by hand with SymPy's KanesMethod (independent of hybridtest).

Three blades, each a tip mass m_b at P_i = O + l_b b_ix + q_i b_iy in the blade frame B_i
(azimuth q4 + 2π(i−1)/3 about z), on a hub of inertia I_g about z with generator damping d_g.
At each tip: the blade's static restoring force r_i and mass-proportional damping ζ_b m_b u_i
against b_iy, the wind ρ f_w along b_iy, gravity m_b ρ g along n_x; on the hub the blades'
root reactions l_b Σ(r_i + ζ_b m_b u_i) and −d_g u4; ρ(t) = 1 − exp(−t/t0) (Eq. 12).

mass_and_forcing(parameters) returns numpy functions M(q) and g(t, q, u, r) in SymPy's
convention M u̇ = forcing (hybridtest's too).
"""
import sympy as sp
from sympy.physics import mechanics as me


def derive(blades=3):
    """(q, u, r, t, symbols, M, forcing) of the rotor, symbolic."""
    q = me.dynamicsymbols(f"q1:{blades + 2}")
    u = me.dynamicsymbols(f"u1:{blades + 2}")
    r = sp.symbols(f"r1:{blades + 1}")
    t = me.dynamicsymbols._t
    l_b, m_b, zeta_b, f_w, I_g, d_g, g, t0 = sp.symbols("l_b m_b zeta_b f_w I_g d_g g t0")
    ramp = 1 - sp.exp(-t / t0)

    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    H = N.orientnew("H", "Axis", (q[blades], N.z))
    H.set_ang_vel(N, u[blades] * N.z)
    hub = me.RigidBody("hub", O, H, 0, (me.inertia(H, I_g / 2, I_g / 2, I_g), O))

    bodies, loads = [hub], []
    reaction = 0
    for i in range(blades):
        B = H.orientnew(f"B{i + 1}", "Axis", (2 * sp.pi * i / blades, H.z))
        P = O.locatenew(f"P{i + 1}", l_b * B.x + q[i] * B.y)
        P.set_vel(N, P.pos_from(O).dt(N).subs({sp.diff(qk, t): uk for qk, uk in zip(q, u)}))
        bodies.append(me.Particle(f"tip{i + 1}", P, m_b))
        loads.append((P, (-(r[i] + zeta_b * m_b * u[i]) + ramp * f_w) * B.y
                      + m_b * g * ramp * N.x))
        reaction += r[i] + zeta_b * m_b * u[i]
    loads.append((H, (-d_g * u[blades] + reaction * l_b) * N.z))

    kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=[sp.diff(a, t) - b for a, b in zip(q, u)])
    kane.kanes_equations(bodies, loads)
    symbols = dict(l_b=l_b, m_b=m_b, zeta_b=zeta_b, f_w=f_w, I_g=I_g, d_g=d_g, g=g, t0=t0)
    return q, u, r, t, symbols, kane.mass_matrix, kane.forcing


def mass_and_forcing(parameters, blades=3):
    """Numpy functions M(q) and g(t, q, u, r) for {name: value} parameters (SI)."""
    import numpy as np

    q, u, r, t, symbols, M, F = derive(blades)
    values = {symbols[name]: value for name, value in parameters.items() if name in symbols}
    qs, us = sp.symbols(f"qs0:{len(q)}"), sp.symbols(f"us0:{len(u)}")
    ts = sp.Symbol("ts")
    plain = dict(zip(q, qs)) | dict(zip(u, us)) | {t: ts}
    M_num = sp.lambdify([qs], M.subs(values).subs(plain), "numpy")
    F_num = sp.lambdify([ts, qs, us, r], F.subs(values).subs(plain), "numpy")
    return (lambda q_: np.array(M_num(q_), dtype=float),
            lambda t_, q_, u_, r_: np.array(F_num(t_, q_, u_, r_), dtype=float).ravel())
