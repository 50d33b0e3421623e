#!/usr/bin/python3
"""The SymPy half of `hybridtest check-model`: an independent reading of a model file.

Reads the model file (docs/model-files.md) with PyYAML, builds the same model with
sympy.physics.mechanics (ReferenceFrame.orient_axis / orient_body_fixed / orient_explicit,
Point.locatenew, Particle, RigidBody) and derives Kane's equations with KanesMethod, sharing no
code with the C++ engine. Then evaluates the mass matrix M and the forcing g (SymPy's
convention M u' = forcing, the engine's too) at the states given in a JSON file:

    [{"t": 0.3, "q": [...], "u": [...], "r": [...], "z": [...]}, ...]

(z: the extra first-order states of `states:`, in the file's order) and prints one JSON object
{"M": [n x n per state], "g": [n per state], "qdot": [n per state], "zdot": [nz per state]}
(q̇ = W(q) u, ż the states' rates) on stdout. Any failure: a message on stderr and exit
status 3.

Usage: check_model_sympy.py MODEL.yaml STATES.json
The file is assumed valid (the C++ reader checked it first); parameters take their values
from the file.
"""

import json
import pathlib
import re
import sys

import sympy as sp
import yaml
from sympy.parsing.sympy_parser import (convert_xor, parse_expr,
                                        standard_transformations)
from sympy.physics import mechanics as me

TRANSFORMS = standard_transformations + (convert_xor,)


def _if(cond, a, b):
    return sp.Piecewise((a, cond), (b, True))


FUNCTIONS = {'sin': sp.sin, 'cos': sp.cos, 'tan': sp.tan, 'exp': sp.exp, 'log': sp.log,
             'sqrt': sp.sqrt, 'abs': sp.Abs, 'pow': sp.Pow, 'min': sp.Min, 'max': sp.Max,
             'atan2': sp.atan2, 'tanh': sp.tanh, 'asin': sp.asin, 'acos': sp.acos,
             'atan': sp.atan, 'sign': sp.sign, 'if_': _if, 'pi': sp.pi}

# Units to SI, written out here again (not read from the C++ table): factor of each unit name.
UNIT = {'m': 1, 'mm': sp.Rational(1, 1000), 'cm': sp.Rational(1, 100), 'km': 1000,
        'µm': sp.Rational(1, 10**6), 'um': sp.Rational(1, 10**6),
        'kg': 1, 'g': sp.Rational(1, 1000), 't': 1000,
        's': 1, 'ms': sp.Rational(1, 1000), 'min': 60, 'h': 3600,
        'N': 1, 'mN': sp.Rational(1, 1000), 'kN': 1000, 'MN': 10**6,
        'Pa': 1, 'kPa': 1000, 'MPa': 10**6, 'GPa': 10**9, 'bar': 10**5,
        'J': 1, 'kJ': 1000, 'W': 1, 'kW': 1000, 'MW': 10**6, 'Hz': 1,
        'rad': 1, 'deg': sp.pi / 180, '°': sp.pi / 180, 'rev': 2 * sp.pi,
        'rpm': 2 * sp.pi / 60, '1': 1, '-': 1}
# A number followed by a unit: the longest run without spaces that is a unit, else its first
# word if that is one (the C++ reader's rule).
WORD = r'(?:[^\W\d]|[°µ])[\w°µ²³]*'
SUFFIX = re.compile(r'(?<![\w.])(\d+\.?\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?)(\s*)(' +
                    WORD + r'(?:[/*·^\-\w°µ²³]*))')


def _suffix(m):
    number, space, run = m.group(1), m.group(2), m.group(3)
    first = re.match(WORD, run).group(0)
    for unit in (run, first):
        try:
            factor = unit_factor(unit)
        except (KeyError, ValueError):
            continue
        return f'({number}*({factor}))' + run[len(unit):]
    return number + space + run


def unit_factor(text):
    """SI factor of a unit such as 'N·m/rad', 'kN/mm', 'kg·m²', 'm/s^2'."""
    num, _, den = str(text).partition('/')
    factor = sp.Integer(1)
    for part, sign in ((num, 1), (den, -1)):
        for f in re.split(r'[·*. ]+', part):
            if not f:
                continue
            power = 1
            m = re.fullmatch(r'(.+?)(²|³|\^-?\d+)', f)
            if m:
                f, p = m.group(1), m.group(2)
                power = 2 if p == '²' else 3 if p == '³' else int(p[1:])
            factor *= sp.sympify(UNIT[f]) ** (sign * power)
    return factor


LIST_SECTIONS = ('coordinates', 'speeds', 'frames', 'points', 'particles', 'bodies', 'slots',
                 'forces', 'torques')


def substitute(node, var, value):
    """$var and ${var} replaced by value in every string under node."""
    if isinstance(node, str):
        return re.sub(r'\$\{' + re.escape(var) + r'\}|\$' + re.escape(var) + r'(?!\w)',
                      lambda m: value, node)
    if isinstance(node, list):
        return [substitute(v, var, value) for v in node]
    if isinstance(node, dict):
        return {k: substitute(v, var, value) for k, v in node.items()}
    return node


def expand_repeats(doc):
    """The file with every `repeat: {var: [values]}, items: [...]` block expanded in place."""
    for key in LIST_SECTIONS:
        items = doc.get(key)
        if not isinstance(items, list):
            continue
        out = []
        for item in items:
            if isinstance(item, dict) and 'repeat' in item:
                (var, values), = item['repeat'].items()
                for v in values:
                    text = v if isinstance(v, str) else yaml.safe_dump(v).split('\n')[0]
                    out.extend(substitute(e, var, text) for e in item['items'])
            else:
                out.append(item)
        doc[key] = out
    return doc


def is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def read_csv(path):
    """Rows of cells (strings) of a CSV table, comments (#) and blank lines dropped."""
    rows = []
    with open(path, encoding='utf-8') as f:
        for line in f:
            line = line.split('#', 1)[0].strip()
            if line.strip(',; \t'):
                rows.append([c.strip() for c in re.split(r'[,;\t]', line)])
    return rows


class Reader:
    def __init__(self, doc, directory=pathlib.Path('.')):
        self.doc = doc
        self.directory = directory
        self.t = me.dynamicsymbols._t
        self.names = dict(FUNCTIONS)
        self.names['t'] = self.t
        for name, p in (doc.get('parameters') or {}).items():
            value = p['value'] if isinstance(p, dict) else p
            unit = p.get('unit') if isinstance(p, dict) else None
            factor = unit_factor(unit) if unit else 1
            self.names[name] = sp.Float(float(value) * float(factor))
        coords = doc['coordinates']
        n = len(coords)
        self.q = list(me.dynamicsymbols(f'qq0:{n}')) if n > 1 else [me.dynamicsymbols('qq0')]
        self.u = list(me.dynamicsymbols(f'uu0:{n}')) if n > 1 else [me.dynamicsymbols('uu0')]
        for k, c in enumerate(coords):
            self.names[c['name']] = self.q[k]
        speeds = doc.get('speeds') or [{'name': f'u{k + 1}'} for k in range(n)]
        for k, s in enumerate(speeds):
            self.names[s['name']] = self.u[k]
        slots = doc.get('slots') or []
        self.r = [sp.Symbol(f'rr{k}') for k in range(len(slots))]
        for k, s in enumerate(slots):
            self.names[s['name']] = self.r[k]
        # Extra states: plain symbols (their rates are read in build(), after velocity()).
        states = doc.get('states') or {}
        self.z = [sp.Symbol(f'zz{k}') for k in range(len(states))]
        for k, name in enumerate(states):
            self.names[name] = self.z[k]
        for name, table in (doc.get('tables') or {}).items():
            if 'csv' in table or 'csv_grid' in table:
                rows = read_csv(self.directory / table.get('csv', table.get('csv_grid')))
                if 'csv' in table:
                    rows = [r for r in rows if all(is_number(c) for c in r)]
                    xs = [sp.Float(r[0]) for r in rows]
                    ys = [sp.Float(r[1]) for r in rows]
                    self.names[name] = self.table(xs, ys)
                else:
                    ys = [sp.Float(c) for c in rows[0][1:]]
                    xs = [sp.Float(r[0]) for r in rows[1:]]
                    zs = [[sp.Float(c) for c in r[1:]] for r in rows[1:]]
                    self.names[name] = self.table2(xs, ys, zs)
                continue
            xs = [self.expr(v) for v in table['x']]
            ys = [self.expr(v) for v in table['y']]
            if 'z' in table:
                zs = [[self.expr(v) for v in row] for row in table['z']]
                self.names[name] = self.table2(xs, ys, zs)
            else:
                self.names[name] = self.table(xs, ys)
        for name, text in (doc.get('time_functions') or {}).items():
            self.names[name] = self.expr(text)

    @staticmethod
    def table(xs, ys):
        """Piecewise-linear y(x), constant beyond the ends."""
        def lookup(a):
            pieces = [(ys[0], a < xs[0])]
            for k in range(len(xs) - 1):
                slope = (ys[k + 1] - ys[k]) / (xs[k + 1] - xs[k])
                pieces.append((ys[k] + slope * (a - xs[k]), a < xs[k + 1]))
            pieces.append((ys[-1], True))
            return sp.Piecewise(*pieces)
        return lookup

    @staticmethod
    def table2(xs, ys, zs):
        """Bilinear z(x, y) in each cell of the grid, clamped to the grid beyond its edges."""
        def cells(grid, a):
            # (cell index, fraction across it, condition), the first that holds wins.
            out = [(0, sp.S.Zero, a < grid[0])]
            for k in range(len(grid) - 1):
                out.append((k, (a - grid[k]) / (grid[k + 1] - grid[k]), a < grid[k + 1]))
            out.append((len(grid) - 2, sp.S.One, True))
            return out

        def lookup(a, b):
            outer = []
            for i, s, ci in cells(xs, a):
                inner = []
                for j, r, cj in cells(ys, b):
                    z00, z10, z01, z11 = zs[i][j], zs[i + 1][j], zs[i][j + 1], zs[i + 1][j + 1]
                    inner.append((z00 * (1 - s) * (1 - r) + z10 * s * (1 - r) + z01 * (1 - s) * r
                                  + z11 * s * r, cj))
                outer.append((sp.Piecewise(*inner), ci))
            return sp.Piecewise(*outer)
        return lookup

    def expr(self, text):
        text = str(text)
        text = SUFFIX.sub(_suffix, text)
        text = re.sub(r'\bif\s*\(', 'if_(', text)
        text = re.sub(r'\b(velocity|angular_velocity)\s*\(\s*(\w+)\s*,\s*(\w+)\s*\)\s*\.\s*([xyz])',
                      r"\1_('\2', '\3', '\4')", text)
        return parse_expr(text, local_dict=dict(self.names), transformations=TRANSFORMS)

    def vector(self, frame, components):
        units = (frame.x, frame.y, frame.z)
        return sum((self.expr(c) * e for c, e in zip(components, units)), me.Vector(0))

    def build(self):
        doc = self.doc
        N = me.ReferenceFrame('N')
        O = me.Point('O')
        O.set_vel(N, 0)
        frames = {'N': N}
        points = {'O': O}
        for f in doc.get('frames') or []:
            parent = frames[f.get('parent', 'N')]
            F = me.ReferenceFrame('F_' + str(len(frames)))
            if 'angle' in f:
                axis = f.get('axis', 'z')
                if isinstance(axis, str):
                    vec = {'x': parent.x, 'y': parent.y, 'z': parent.z}[axis.lower()]
                else:
                    vec = self.vector(parent, axis)
                F.orient_axis(parent, vec, self.expr(f['angle']))
            elif 'euler' in f:
                angles = [self.expr(a) for a in f['euler']['angles']]
                F.orient_body_fixed(parent, angles, f['euler']['sequence'].upper())
            else:
                R = sp.Matrix([[self.expr(c) for c in row] for row in f['dcm']])
                # R's columns are F's unit vectors in the parent: parent.dcm(F) == R.
                F.orient_explicit(parent, R)
                if any(abs(float(v)) > 1e-12 for v in (parent.dcm(F) - R)):
                    F.orient_explicit(parent, R.T)
            frames[f['name']] = F
        for p in doc.get('points') or []:
            base = points[p.get('from', 'O')]
            frame = frames[p.get('frame', 'N')]
            r = self.vector(frame, p['position'])
            P = base.locatenew(p['name'], r)
            P.set_vel(N, base.vel(N) + r.dt(N))
            points[p['name']] = P
        bodies = []
        for p in doc.get('particles') or []:
            bodies.append(me.Particle(p['name'], points[p['point']], self.expr(p['mass'])))
        for b in doc.get('bodies') or []:
            frame = frames[b['frame']]
            I = b['inertia']
            if not isinstance(I[0], list):
                I = [[I[0], 0, 0], [0, I[1], 0], [0, 0, I[2]]]
            I = [[self.expr(c) for c in row] for row in I]
            dyadic = me.inertia(frame, I[0][0], I[1][1], I[2][2], I[0][1], I[1][2], I[2][0])
            center = points[b['mass_center']]
            bodies.append(me.RigidBody(b['name'], center, frame, self.expr(b['mass']),
                                       (dyadic, center)))
        # velocity(P, F).x and angular_velocity(A, F).z in loads: SymPy's own P.vel(N) and
        # A.ang_vel_in(N), with q̇ = W(q) u substituted.
        n = len(self.q)
        W_doc = doc.get('kinematical_equations')
        W_kin = sp.Matrix([[self.expr(c) for c in row] for row in W_doc]) if W_doc else sp.eye(n)
        qdot_sub = {qk.diff(self.t): wk for qk, wk in zip(self.q, W_kin * sp.Matrix(self.u))}

        def velocity(point, frame, axis):
            return points[point].vel(N).dot(getattr(frames[frame], axis)).subs(qdot_sub)

        def angular_velocity(of, frame, axis):
            return frames[of].ang_vel_in(N).dot(getattr(frames[frame], axis)).subs(qdot_sub)

        self.names['velocity_'] = velocity
        self.names['angular_velocity_'] = angular_velocity
        self.zdot = sp.Matrix([self.expr(st['rate']) for st in (doc.get('states') or {}).values()])
        loads = []
        for f in doc.get('forces') or []:
            loads.append((points[f['point']],
                          self.vector(frames[f.get('expressed_in', 'N')], f['value'])))
        for f in doc.get('torques') or []:
            loads.append((frames[f['frame']],
                          self.vector(frames[f.get('expressed_in', 'N')], f['value'])))
        n = len(self.q)
        W = doc.get('kinematical_equations')
        if W:
            W = sp.Matrix([[self.expr(c) for c in row] for row in W])
        else:
            W = sp.eye(n)
        qd = sp.Matrix([qk.diff(self.t) for qk in self.q])
        kd = list(qd - W * sp.Matrix(self.u))
        # Kept for other readers (tests/oracle/constraints_oracle.py adds constraint rows).
        self.N, self.frames, self.points = N, frames, points
        self.bodies, self.loads, self.kd = bodies, loads, kd
        kane = me.KanesMethod(N, q_ind=self.q, u_ind=self.u, kd_eqs=kd)
        kane.kanes_equations(bodies, loads)
        # q' may remain in the forcing: eliminate it through the kinematical equations.
        kdd = kane.kindiffdict()
        self.qdot = W * sp.Matrix(self.u)
        # sign(x)' = 2 δ(x): zero wherever it is evaluated (the engine's derivative of sign).
        def no_delta(e):
            return e.replace(sp.DiracDelta, lambda *a: sp.S.Zero)
        return no_delta(me.msubs(kane.mass_matrix, kdd)), no_delta(me.msubs(kane.forcing, kdd))


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        return run()
    except Exception as e:  # reported to check-model with its type, exit status 3
        print(f'check_model_sympy.py: {type(e).__name__}: {e}', file=sys.stderr)
        return 3


def run():
    with open(sys.argv[1], encoding='utf-8') as f:
        doc = yaml.safe_load(f)
    with open(sys.argv[2], encoding='utf-8') as f:
        states = json.load(f)
    reader = Reader(expand_repeats(doc), pathlib.Path(sys.argv[1]).parent)
    M, F = reader.build()
    n = len(reader.q)
    Q = sp.symbols(f'Q0:{n}')
    U = sp.symbols(f'U0:{n}')
    plain = {**dict(zip(reader.q, Q)), **dict(zip(reader.u, U))}
    M = me.msubs(M, plain)
    F = me.msubs(F, plain)
    args = [reader.t, *Q, *U, *reader.r, *reader.z]
    fM = sp.lambdify(args, M.tolist(), 'math')
    fF = sp.lambdify(args, list(F), 'math')
    fQ = sp.lambdify(args, list(me.msubs(reader.qdot, plain)), 'math')
    fZ = sp.lambdify(args, list(me.msubs(reader.zdot, plain)), 'math')
    out = {'M': [], 'g': [], 'qdot': [], 'zdot': []}
    for s in states:
        values = [s['t'], *s['q'], *s['u'], *s['r'], *s.get('z', [])]
        out['M'].append([[float(v) for v in row] for row in fM(*values)])
        out['g'].append([float(v) for v in fF(*values)])
        out['qdot'].append([float(v) for v in fQ(*values)])
        out['zdot'].append([float(v) for v in fZ(*values)])
    print(json.dumps(out))
    return 0


if __name__ == '__main__':
    sys.exit(main())
