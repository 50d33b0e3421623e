"""Independent SymPy derivations of hybridtest's built-in models (the Kane oracle).

Each model is derived from its physical description with
``sympy.physics.mechanics.KanesMethod`` and turned into fast numeric functions with
``lambdify``. Nothing here is taken from the C++ engine.

Convention (SymPy's): ``M(q) u' = F(t, q, u, r)`` with ``M = KanesMethod.mass_matrix`` and
``F = KanesMethod.forcing`` (q' eliminated through the kinematical equations), and
``x = [q; u]``, ``x' = [q'; u']``.

Every model is a :class:`DerivedModel`. Its parameters are SymPy symbols keyed by the name the
config file uses (``k_b``, ``blade2.m_b``, ``Ixy``, ...); :meth:`DerivedModel.resolve` turns a
dict of config overrides into the numeric parameter vector, applying the same precedence the
config documents (a per-blade key beats a model-wide key beats the default).
"""

import math

import numpy as np
import sympy as sm
import sympy.physics.mechanics as me


class DerivedModel:
    """A model derived symbolically, with numeric evaluators.

    Attributes:
      name: model name as in the config (``model.name``).
      n: number of generalized speeds (= number of coordinates here).
      num_slots: number of restoring-force slots r (0 if none).
      param_keys: list of config keys, in the order of the numeric parameter vector.
      defaults: dict config key -> default value (SI).
      blade_keys: for the rotor, the per-blade key stems (``l_b``, ...), else [].
      num_blades: for the rotor, N, else 0.
      mass_matrix_sym, forcing_sym, qdot_sym: the symbolic results (plain symbols).
    """

    def __init__(self, name, q, u, r, params, defaults, mass_matrix, forcing, qdot,
                 num_blades=0, blade_keys=()):
        self.name = name
        self.n = len(u)
        self.num_slots = len(r)
        self.num_blades = num_blades
        self.blade_keys = list(blade_keys)
        self.param_keys = list(params.keys())
        self.defaults = dict(defaults)
        t = sm.Symbol('t')
        # Replace dynamicsymbols by plain symbols so lambdify sees only symbols.
        qs = sm.symbols(f'qq0:{len(q)}')
        us = sm.symbols(f'uu0:{len(u)}')
        sub = dict(zip(q, qs))
        sub.update(dict(zip(u, us)))
        sub[me.dynamicsymbols._t] = t
        self.mass_matrix_sym = mass_matrix.xreplace(sub)
        self.forcing_sym = forcing.xreplace(sub)
        self.qdot_sym = qdot.xreplace(sub)
        args = [t, list(qs), list(us), list(r), [params[k] for k in self.param_keys]]
        self._mass = sm.lambdify(args, self.mass_matrix_sym, modules='numpy', cse=True)
        self._forcing = sm.lambdify(args, self.forcing_sym, modules='numpy', cse=True)
        self._qdot = sm.lambdify(args, self.qdot_sym, modules='numpy', cse=True)

    def resolve(self, overrides):
        """Numeric parameter vector from config overrides (dict key -> value).

        A rotor key without a blade prefix applies to every blade unless that blade has its
        own ``blade<i>.<key>``.
        """
        values = []
        for key in self.param_keys:
            if key in overrides:
                values.append(float(overrides[key]))
                continue
            stem = key.split('.', 1)[1] if key.startswith('blade') and '.' in key else None
            if stem is not None and stem in overrides:
                values.append(float(overrides[stem]))
            else:
                values.append(float(self.defaults[key]))
        return values

    def evaluate(self, t, q, u, r, p):
        """Returns (M (n x n), F (n,), xdot (2n,)) as float arrays."""
        a = (float(t), list(q), list(u), list(r), list(p))
        m = np.array(self._mass(*a), dtype=float).reshape(self.n, self.n)
        f = np.array(self._forcing(*a), dtype=float).reshape(self.n)
        qd = np.array(self._qdot(*a), dtype=float).reshape(len(q))
        ud = np.linalg.solve(m, f)
        return m, f, np.concatenate([qd, ud])


def _kane(frame, q, u, kd, bodies, loads):
    """Runs KanesMethod; returns (M, F, qdot(q, u)) with q' eliminated."""
    kane = me.KanesMethod(frame, q_ind=q, u_ind=u, kd_eqs=kd)
    kane.kanes_equations(bodies, loads)
    kdd = kane.kindiffdict()
    mass = me.msubs(kane.mass_matrix, kdd)
    forcing = me.msubs(kane.forcing, kdd)
    # trigsimp removes spurious 1/cos factors that the linear solve leaves behind (they would
    # cost accuracy where the factor is near zero although q' itself is regular there).
    qdot = sm.Matrix([sm.trigsimp(sm.together(kdd[sm.diff(qi, me.dynamicsymbols._t)]))
                      for qi in q])
    return mass, forcing, qdot


ROTOR_GLOBAL_DEFAULTS = {  # paper Table 1
    'l_b': 0.5, 'm_b': 1.96, 'zeta_b': 1.0, 'k_b': 7200.0, 'f_w': 100.0,
    'I_g': 0.1, 'd_g': 100.0, 'g': 9.82, 't0': 0.5,
}
ROTOR_BLADE_KEYS = ('l_b', 'm_b', 'zeta_b', 'k_b', 'f_w', 'psi')


def derive_rotor(num_blades):
    """The paper's rotor with N blades: q1..qN tip deflections, q_{N+1} hub angle, u = q'."""
    nb = num_blades
    t = me.dynamicsymbols._t
    q = me.dynamicsymbols(f'q1:{nb + 2}')
    u = me.dynamicsymbols(f'u1:{nb + 2}')
    r = list(sm.symbols(f'r1:{nb + 1}'))
    i_g, d_g, g, t0 = sm.symbols('I_g d_g g t0', positive=True)
    params = {}
    defaults = {}
    blade = []
    for i in range(1, nb + 1):
        syms = {}
        for key in ROTOR_BLADE_KEYS:
            s = sm.Symbol(f'{key}_{i}', real=True)
            syms[key] = s
            params[f'blade{i}.{key}'] = s
            defaults[f'blade{i}.{key}'] = (2 * math.pi * (i - 1) / nb if key == 'psi'
                                           else ROTOR_GLOBAL_DEFAULTS[key])
        blade.append(syms)
    for key, s in (('I_g', i_g), ('d_g', d_g), ('g', g), ('t0', t0)):
        params[key] = s
        defaults[key] = ROTOR_GLOBAL_DEFAULTS[key]

    n_frame = me.ReferenceFrame('N')
    hub = n_frame.orientnew('H', 'Axis', [q[nb], n_frame.z])
    hub.set_ang_vel(n_frame, u[nb] * n_frame.z)
    origin = me.Point('O')
    origin.set_vel(n_frame, 0)
    rho = 1 - sm.exp(-t / t0)

    bodies = [me.RigidBody('Hub', origin, hub, 1, (me.inertia(hub, 0, 0, i_g), origin))]
    loads = []
    hub_torque = -d_g * u[nb]
    for i in range(nb):
        b = blade[i]
        bf = hub.orientnew(f'B{i + 1}', 'Axis', [b['psi'], hub.z])
        tip = origin.locatenew(f'P{i + 1}', b['l_b'] * bf.x + q[i] * bf.y)
        tip.set_vel(n_frame, tip.pos_from(origin).dt(n_frame).subs(
            {sm.diff(qj, t): uj for qj, uj in zip(q, u)}))
        bodies.append(me.Particle(f'tip{i + 1}', tip, b['m_b']))
        restoring = r[i] + b['zeta_b'] * b['m_b'] * u[i]
        loads.append((tip, -restoring * bf.y + b['m_b'] * rho * g * n_frame.x
                      + rho * b['f_w'] * bf.y))
        hub_torque += restoring * b['l_b']
    loads.append((hub, hub_torque * n_frame.z))
    kd = [ui - sm.diff(qi, t) for qi, ui in zip(q, u)]
    mass, forcing, qdot = _kane(n_frame, q, u, kd, bodies, loads)
    return DerivedModel('rotor', q, u, r, params, defaults, mass, forcing, qdot,
                        num_blades=nb, blade_keys=ROTOR_BLADE_KEYS)


def derive_double_pendulum():
    """Planar double pendulum, absolute angle q1 and relative angle q2, n_x down."""
    t = me.dynamicsymbols._t
    q = me.dynamicsymbols('q1:3')
    u = me.dynamicsymbols('u1:3')
    m1, m2, l1, l2, g = sm.symbols('m1 m2 l1 l2 g', positive=True)
    params = {'m1': m1, 'm2': m2, 'l1': l1, 'l2': l2, 'g': g}
    defaults = {'m1': 1.0, 'm2': 1.0, 'l1': 1.0, 'l2': 1.0, 'g': 9.81}
    n_frame = me.ReferenceFrame('N')
    a = n_frame.orientnew('A', 'Axis', [q[0], n_frame.z])
    b = a.orientnew('B', 'Axis', [q[1], a.z])
    a.set_ang_vel(n_frame, u[0] * n_frame.z)
    b.set_ang_vel(a, u[1] * a.z)
    origin = me.Point('O')
    origin.set_vel(n_frame, 0)
    p1 = origin.locatenew('P1', l1 * a.x)
    p2 = p1.locatenew('P2', l2 * b.x)
    p1.v2pt_theory(origin, n_frame, a)
    p2.v2pt_theory(p1, n_frame, b)
    bodies = [me.Particle('pa', p1, m1), me.Particle('pb', p2, m2)]
    loads = [(p1, m1 * g * n_frame.x), (p2, m2 * g * n_frame.x)]
    kd = [ui - sm.diff(qi, t) for qi, ui in zip(q, u)]
    mass, forcing, qdot = _kane(n_frame, q, u, kd, bodies, loads)
    return DerivedModel('double_pendulum', q, u, [], params, defaults, mass, forcing, qdot)


TOP_DEFAULTS = {
    'm': 1.0, 'cx': 0.02, 'cy': -0.01, 'cz': 0.1,
    'Ixx': 0.012, 'Iyy': 0.010, 'Izz': 0.006, 'Ixy': 0.001, 'Ixz': -0.0008, 'Iyz': 0.0005,
    'g': 9.81,
}


def derive_spinning_top():
    """Rigid body about a fixed pivot, body-fixed x-y-z angles, u = body-frame omega."""
    t = me.dynamicsymbols._t
    q = me.dynamicsymbols('q1:4')
    u = me.dynamicsymbols('u1:4')
    params = {k: sm.Symbol(k, real=True) for k in TOP_DEFAULTS}
    p = params
    n_frame = me.ReferenceFrame('N')
    a = n_frame.orientnew('A', 'Axis', [q[0], n_frame.x])
    bp = a.orientnew('Bp', 'Axis', [q[1], a.y])
    c = bp.orientnew('C', 'Axis', [q[2], bp.z])
    # Kinematical equations from the orientation chain, before omega is re-expressed in u.
    omega_q = c.ang_vel_in(n_frame)
    kd = [u[0] - omega_q.dot(c.x), u[1] - omega_q.dot(c.y), u[2] - omega_q.dot(c.z)]
    c.set_ang_vel(n_frame, u[0] * c.x + u[1] * c.y + u[2] * c.z)
    origin = me.Point('O')
    origin.set_vel(n_frame, 0)
    mc = origin.locatenew('G', p['cx'] * c.x + p['cy'] * c.y + p['cz'] * c.z)
    mc.v2pt_theory(origin, n_frame, c)
    inertia = me.inertia(c, p['Ixx'], p['Iyy'], p['Izz'], p['Ixy'], p['Iyz'], p['Ixz'])
    body = me.RigidBody('top', mc, c, p['m'], (inertia, mc))
    loads = [(mc, -p['m'] * p['g'] * n_frame.z)]
    mass, forcing, qdot = _kane(n_frame, q, u, kd, [body], loads)
    return DerivedModel('spinning_top', q, u, [], params, TOP_DEFAULTS, mass, forcing, qdot)
