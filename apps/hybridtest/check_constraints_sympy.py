#!/usr/bin/python3
"""SymPy cross-check of the constrained Kane equations (decision 0023): the second half of
`hybridtest check-model` on a model with constraints, shipped beside the binary as
hybridtest_check_constraints_sympy.py (tests/oracle/ runs it on the example models too).

    check_constraints_sympy.py --binary B --model MODEL.yaml [--states 25] [--seed 1]
                               [--tolerance 1e-11] [--kanes]

At random consistent states (random independent coordinates and speeds, the dependent ones
solved by `hybridtest eom --assemble`), the engine's reduced equations

    [Cᵀ M; B] u̇ = [Cᵀ g; −(Ḃ u + ċ)],   C = [I; A], A = −B_d⁻¹ B_i

(`eom --json`: reduced_mass_matrix, reduced_forcing) equal an independent derivation: M and g
from check-model's SymPy reader (check_model_sympy.py, KanesMethod over all speeds), the
constraint rows B, c and Ḃ u + ċ from SymPy's own point velocities and accelerations (P.vel,
P.pos_from, .dt), and the reduction done here in floating point with the dependent speeds the
engine used at that state (the file's `dependent_speeds`, or the engine's pivoted choice). The
SymPy side also checks that the engine's state meets the constraints (|f|, |B u + c| <= 1e-11). With --kanes, SymPy's
KanesMethod(u_dependent=..., velocity_constraints=..., configuration_constraints=...) is
formed too and its mass_matrix and forcing must equal the same (a check of the reduction
itself; small models with `dependent_speeds:` only: SymPy 1.11 inverts B_d symbolically).
Entry a passes against b if |a - b| <= tolerance * max(1, max|b|) over the oracle's whole
array. Exit status 0: all agree; 1: a difference (printed); 2: bad arguments.
"""
import argparse
import json
import pathlib
import random
import subprocess
import sys
import tempfile

import sympy as sp
import sympy.physics.mechanics as me
import yaml

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
try:  # beside the binary (the build tree, an installation)
    import hybridtest_check_model_sympy as reader_module  # noqa: E402
except ImportError:  # in the source tree
    import check_model_sympy as reader_module  # noqa: E402


def constraint_rows(reader, doc):
    """(velocity-level rows g(q, u, t) = B u + c, holonomic rows f(q, t) or None), in the
    engine's row order."""
    frames, points, N = reader.frames, reader.points, reader.N
    qd_sub = {qk.diff(reader.t): uk for qk, uk in zip(reader.q, reader.u)}
    rows = []
    for c in doc['constraints']:
        E = frames[c.get('expressed_in', 'N')]
        comps = c.get('components', ['x', 'y', 'z'])
        if 'holonomic' in c:
            f = reader.expr(c['holonomic'])
            rows.append((f.diff(reader.t).subs(qd_sub), f))
        elif 'nonholonomic' in c:
            rows.append((reader.expr(c['nonholonomic']), None))
        elif 'coincide' in c:
            P, Q = (points[name] for name in c['coincide'])
            d = P.pos_from(Q)
            for comp in comps:
                f = d.dot(getattr(E, comp))
                rows.append((f.diff(reader.t).subs(qd_sub), f))
        else:
            P = points[c['velocity_zero']]
            if 'of_body' in c:
                C = points[c['through']]
                v = C.vel(N) + frames[c['of_body']].ang_vel_in(N).cross(P.pos_from(C))
            else:
                v = P.vel(N)
            for comp in comps:
                rows.append((v.dot(getattr(E, comp)).subs(qd_sub), None))
    return rows


def run(binary, *args):
    p = subprocess.run([binary, *args], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f'FAIL: {binary} {" ".join(args)} exited {p.returncode}:\n{p.stderr}')
    return p.stdout


def flat(a):
    return [float(v) for row in a for v in (row if isinstance(row, (list, tuple)) else [row])]


def worst(a, b):
    a, b = flat(a), flat(b)
    scale = max(1.0, max(abs(v) for v in b))
    return max(abs(x - y) for x, y in zip(a, b)) / scale


def solve(A, B):
    """X with A X = B (lists of rows), Gaussian elimination with partial pivoting."""
    n = len(A)
    M = [list(map(float, A[i])) + list(map(float, B[i])) for i in range(n)]
    for c in range(n):
        p = max(range(c, n), key=lambda i: abs(M[i][c]))
        M[c], M[p] = M[p], M[c]
        for i in range(c + 1, n):
            f = M[i][c] / M[c][c]
            M[i] = [x - f * y for x, y in zip(M[i], M[c])]
    X = [[0.0] * len(B[0]) for _ in range(n)]
    for i in reversed(range(n)):
        for k in range(len(B[0])):
            s = M[i][n + k] - sum(M[i][j] * X[j][k] for j in range(i + 1, n))
            X[i][k] = s / M[i][i]
    return X


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--binary', required=True)
    ap.add_argument('--model', required=True)
    ap.add_argument('--states', type=int, default=25)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--tolerance', type=float, default=1e-11)
    ap.add_argument('--kanes', action='store_true')
    a = ap.parse_args()
    if 'constraints' not in yaml.safe_load(pathlib.Path(a.model).read_text(encoding='utf-8')):
        print(f'{a.model}: the model has no constraints: nothing to check here', file=sys.stderr)
        return 2
    model = pathlib.Path(a.model).resolve()
    doc = reader_module.expand_repeats(yaml.safe_load(model.read_text(encoding='utf-8')))
    reader = reader_module.Reader(doc, model.parent)
    M, F = reader.build()
    n = len(reader.q)
    rows = constraint_rows(reader, doc)
    g = sp.Matrix([r[0] for r in rows])
    B = g.jacobian(reader.u)
    # Ḃ u + ċ: the time derivative of B u + c with u̇ = 0 and q̇ = u.
    udot_zero = {uk.diff(reader.t): 0 for uk in reader.u}
    qd_sub = {qk.diff(reader.t): uk for qk, uk in zip(reader.q, reader.u)}
    bias = g.diff(reader.t).subs(udot_zero).subs(qd_sub)
    f = sp.Matrix([r[1] for r in rows if r[1] is not None])
    Q = sp.symbols(f'Q0:{n}')
    U = sp.symbols(f'U0:{n}')
    plain = {**dict(zip(reader.q, Q)), **dict(zip(reader.u, U))}
    args = [reader.t, *Q, *U, *reader.r]
    lam = {name: sp.lambdify(args, me.msubs(expr, plain).tolist(), 'math')
           for name, expr in (('M', M), ('F', F), ('B', B), ('bias', bias), ('g', g), ('f', f))}
    kanes = None
    if a.kanes and 'dependent_speeds' not in doc:
        print('--kanes needs the file\'s dependent_speeds: (SymPy\'s KanesMethod takes a fixed '
              'choice)', file=sys.stderr)
        return 2
    if a.kanes:
        dependent = [[s['name'] for s in doc['speeds']].index(name)
                     for name in doc['dependent_speeds']]
        independent = [j for j in range(n) if j not in dependent]
        order = independent + dependent
        kane = me.KanesMethod(reader.N, q_ind=reader.q, u_ind=[reader.u[j] for j in independent],
                              u_dependent=[reader.u[j] for j in dependent],
                              kd_eqs=[qk.diff(reader.t) - uk for qk, uk in zip(reader.q, reader.u)],
                              velocity_constraints=list(g))
        kane.kanes_equations(reader.bodies, reader.loads)
        kdd = kane.kindiffdict()
        def plain_of(e):  # q' through the kinematical equations, then plain symbols
            return me.msubs(me.msubs(e, kdd), plain).tolist()
        kanes = (sp.lambdify(args, plain_of(kane.mass_matrix), 'math'),
                 sp.lambdify(args, plain_of(kane.forcing), 'math'), order)
    with tempfile.TemporaryDirectory() as tmp:
        config = pathlib.Path(tmp) / 'config.yaml'
        config.write_text(f'model: {{file: {model}}}\nintegrator: {{tableau: rk4, dt: 0.001}}\n'
                          'duration: 1.0\n', encoding='utf-8')
        rng = random.Random(a.seed)
        x0 = None
        failures = 0
        largest = {}
        for trial in range(a.states):
            if x0 is None:  # the model's initial state, assembled
                x0 = json.loads(run(a.binary, 'modes', str(model), '--json'))['operating_point']
            x = list(x0)
            for k in range(n):
                x[k] += rng.uniform(-0.2, 0.2)
                x[n + k] = rng.uniform(-3.0, 3.0)
            t = rng.uniform(0.0, 1.0)
            out = json.loads(run(a.binary, 'eom', str(config), '--time', repr(t), '--state',
                                 ','.join(repr(v) for v in x), '--assemble', '--json'))
            xs = out['state']
            # The dependent speeds the engine reduced with at this state.
            dependent = list(out['dependent_speeds'])
            independent = [j for j in range(n) if j not in dependent]
            values = [t, *xs[:n], *xs[n:2 * n], *out['restoring']]
            Mv = [list(map(float, row)) for row in lam['M'](*values)]
            Fv = flat(lam['F'](*values))
            Bv = [list(map(float, row)) for row in lam['B'](*values)]
            bv = flat(lam['bias'](*values))
            residual = max([abs(v) for v in flat(lam['g'](*values))] +
                           ([abs(v) for v in flat(lam['f'](*values))] if f.shape[0] else []))
            m = len(Bv)
            X = solve([[row[j] for j in dependent] for row in Bv],
                      [[row[j] for j in independent] for row in Bv])
            A = [[-v for v in row] for row in X]  # (m x p): u_dep = A u_ind
            Mr = [[Mv[i][k] + sum(A[s][c] * Mv[dependent[s]][k] for s in range(m))
                   for k in range(n)] for c, i in enumerate(independent)] + Bv
            Fr = [Fv[i] + sum(A[s][c] * Fv[dependent[s]] for s in range(m))
                  for c, i in enumerate(independent)] + [-v for v in bv]
            errors = {'constraints at the state': residual,
                      'reduced M': worst(out['reduced_mass_matrix'], Mr),
                      'reduced forcing': worst(out['reduced_forcing'], Fr)}
            if kanes is not None:
                order = kanes[2]
                Mk = [list(map(float, row)) for row in kanes[0](*values)]
                Fk = flat(kanes[1](*values))
                unorder = [[0.0] * n for _ in range(n)]  # SymPy's columns are [u_ind, u_dep]
                for i in range(n):
                    for c, j in enumerate(order):
                        unorder[i][j] = Mk[i][c]
                errors['KanesMethod M'] = worst(Mr, unorder)
                errors['KanesMethod forcing'] = worst(Fr, Fk)
            for name, e in errors.items():
                largest[name] = max(largest.get(name, 0.0), e)
                if not e <= a.tolerance:
                    failures += 1
                    print(f'FAIL: {model.name} state {trial}: {name}: {e:.3g} > {a.tolerance:g}')
        print(f'{model.name}: reduced equations with dependent speeds at {a.states} consistent '
              f'states, {failures} failures (tolerance {a.tolerance:g}); largest relative '
              'difference: ' + ', '.join(f'{k} {v:.2g}' for k, v in largest.items()))
        return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
