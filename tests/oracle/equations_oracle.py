#!/usr/bin/python3
"""Contract tests of `hybridtest equations` (issue 36; docs/equations.md).

    equations_oracle.py --binary B --model rotor|MODEL.yaml [--states 25] [--seed 1]
        The `sympy` output, executed, equals SymPy's KanesMethod M and forcing at random
        states: the rotor against oracle_models.derive_rotor (paper Table 1 values), a model
        file against check-model's independent SymPy reader (check_model_sympy.py). Entry a
        passes against b if |a - b| <= 1e-12 * max(1, max|B|) (B: the oracle's whole array).
    equations_oracle.py --binary B --constrained MODEL.yaml [--states 25] [--seed 1]
        A constrained model (issue 47 item 2): the `sympy` output's reduced equations
        M_reduced u' = f_reduced (A's symbols solved from A_d A = -A_i at the state), its tree M
        and f, and its constraint rows A_d u_d + A_i u_i + b = 0 equal `eom --assemble --json` at
        random consistent states, entry a against b within 1e-12 * max(1, max|B|); u' solved
        from both reduced systems agrees as well.
    equations_oracle.py --binary B --chains 3,6,12 [--states 10] [--seed 1]
        Issue 47's contract on the n-link pendulums of bench/equations_vs_sympy.py (each N
        links, with the pivot fixed and on a cart): the `sympy` output, evaluated at random states (its
        own common subexpressions kept, parameters at their values), equals `eom --json` of
        the numeric engine, M and f entry by entry within 1e-12 * max(1, max|eom's array|).
    equations_oracle.py --binary B --latex
        The `latex` output of the rotor and of the four-bar (constrained) compiles with
        pdflatex (exit 77, skipped, if pdflatex is absent: scripts/install-deps.sh installs
        texlive-latex-base).
    equations_oracle.py --binary B --stable
        Two runs of `equations` print the same bytes (the rotor and example model files), no
        number with float noise (issue 47).
    equations_oracle.py --binary B --cli
        Bad input exits with status 2 and a message naming the problem; --out and
        --overwrite guard an existing file.
    equations_oracle.py --binary B --compiled CONFIG
        `simulate CONFIG` with `compiled: true` added to its model section equals `simulate
        CONFIG` within 1e-12 of each column's largest value (1e-12 m for q); `compile-model`
        finds the library the run compiled in the cache ($HYBRIDTEST_CACHE_DIR, a temporary
        directory here).
"""
import argparse
import json
import math
import pathlib
import random
import runpy
import shutil
import subprocess
import sys
import tempfile

import sympy as sp

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE))

TOLERANCE = 1e-12


def run(binary, *args, check=True):
    p = subprocess.run([binary, *args], capture_output=True, text=True)
    if check and p.returncode != 0:
        sys.exit(f'FAIL: {binary} {" ".join(args)} exited {p.returncode}:\n{p.stderr}')
    return p


def load_module(binary, model, workdir):
    out = pathlib.Path(workdir) / 'equations.py'
    run(binary, 'equations', model, '--format', 'sympy', '--out', str(out))
    mod = runpy.run_path(str(out))
    for name in ('q', 'u', 'r', 't', 'M', 'f', 'parameters'):
        if name not in mod:
            sys.exit(f'FAIL: the sympy module of {model} does not define `{name}`')
    n = len(mod['q'])
    if not isinstance(mod['M'], sp.MatrixBase) or mod['M'].shape != (n, n):
        sys.exit(f'FAIL: M is not a {n} x {n} sympy.Matrix')
    if not isinstance(mod['f'], sp.MatrixBase) or mod['f'].shape != (n, 1):
        sys.exit(f'FAIL: f is not a {n} x 1 sympy.Matrix')
    if not isinstance(mod['parameters'], dict) or not mod['parameters']:
        sys.exit('FAIL: `parameters` is not a non-empty dict')
    return mod


def random_states(mod, count, seed):
    rng = random.Random(seed)
    n, ns, nz = len(mod['q']), len(mod['r']), len(mod.get('z', []))
    states = []
    for i in range(count):
        scale = [0.1, 5.0, 50.0][i % 3]
        states.append({
            't': 0.0 if i == 0 else rng.uniform(0.0, 5.0),
            'q': [rng.uniform(-1.1, 1.1) for _ in range(n)],
            'u': [rng.uniform(-scale, scale) for _ in range(n)],
            'r': [rng.uniform(-2000.0, 2000.0) for _ in range(ns)],
            'z': [rng.uniform(-1.0, 1.0) for _ in range(nz)],
        })
    return states


def ours(mod, states):
    args = [mod['t'], *mod['q'], *mod['u'], *mod['r'], *mod.get('z', [])]
    # The parameters are symbols (where the engine's number is their product): their values.
    M, f = mod['M'].subs(mod['parameters']), mod['f'].subs(mod['parameters'])
    free = (M.free_symbols | f.free_symbols) - set(args)
    if free:
        sys.exit(f'FAIL: M or f has symbols that are neither state nor parameters: {free}')
    # cse: a large model's M and f share their subexpressions (printed once, docs/equations.md).
    fM = sp.lambdify(args, M.tolist(), 'math', cse=True)
    ff = sp.lambdify(args, list(f), 'math', cse=True)
    out = []
    for s in states:
        a = [s['t'], *s['q'], *s['u'], *s['r'], *s['z']]
        out.append((fM(*a), ff(*a)))
    return out


def oracle_rotor(states):
    import oracle_models  # noqa: E402  (tests/oracle, SymPy's KanesMethod)
    model = oracle_models.derive_rotor(3)
    p = model.resolve({})
    out = []
    for s in states:
        m, f, _ = model.evaluate(s['t'], s['q'], s['u'], s['r'], p)
        out.append((m.tolist(), f.tolist()))
    return out


def oracle_model_file(path, states, workdir):
    reader = ROOT / 'apps' / 'hybridtest' / 'check_model_sympy.py'
    sfile = pathlib.Path(workdir) / 'states.json'
    sfile.write_text(json.dumps(states))
    p = subprocess.run([sys.executable, str(reader), path, str(sfile)], capture_output=True,
                       text=True)
    if p.returncode != 0:
        sys.exit(f'FAIL: check_model_sympy.py {path}:\n{p.stderr}')
    data = json.loads(p.stdout)
    return list(zip(data['M'], data['g']))


def compare(name, a, b, state, what, oracle='KanesMethod'):
    flat_b = [x for row in b for x in (row if isinstance(row, list) else [row])]
    flat_a = [x for row in a for x in (row if isinstance(row, list) else [row])]
    scale = max([1.0] + [abs(x) for x in flat_b])
    worst = 0.0
    for i, (x, y) in enumerate(zip(flat_a, flat_b)):
        err = abs(float(x) - float(y))
        worst = max(worst, err / scale)
        if not math.isfinite(float(x)) or err > TOLERANCE * scale:
            sys.exit(f'FAIL: {name}: {what} entry {i} at state {state}: equations {x}, '
                     f'{oracle} {y} (tolerance {TOLERANCE} x {scale})')
    return worst


def check_model(binary, model, count, seed):
    with tempfile.TemporaryDirectory() as workdir:
        mod = load_module(binary, model, workdir)
        states = random_states(mod, count, seed)
        mine = ours(mod, states)
        if model == 'rotor':
            theirs = oracle_rotor(states)
        else:
            theirs = oracle_model_file(model, states, workdir)
    worst = 0.0
    for i, ((Ma, fa), (Mb, fb)) in enumerate(zip(mine, theirs)):
        worst = max(worst, compare(model, Ma, Mb, states[i], 'M'))
        worst = max(worst, compare(model, fa, fb, states[i], 'f'))
    print(f'{model}: M and f equal KanesMethod at {count} states '
          f'(largest relative difference {worst:.2e})')


class NumericSympy:
    """A stand-in for `sp` that evaluates a printed module in floats at one state: a symbol is
    its value, sp.Matrix its list. The module's own common subexpressions stay shared (a
    large model's M is a DAG that sympy.lambdify's cse takes a minute to rediscover)."""
    def __init__(self, values):
        self.values = values
        for name in ('sin', 'cos', 'tan', 'exp', 'log', 'atan', 'asin', 'acos', 'tanh',
                     'atan2', 'sqrt'):
            setattr(self, name, getattr(math, name))
        self.pi, self.Abs = math.pi, abs
        self.sign = lambda x: (x > 0) - (x < 0)

    def Symbol(self, name, real=True):
        return self.values[name]

    @staticmethod
    def Rational(p, q):
        return p / q

    @staticmethod
    def Matrix(rows):
        return [list(row) if isinstance(row, list) else row for row in rows]


def evaluate(code, values):
    """The printed module executed on NumericSympy at `values` (symbol name -> float)."""
    scope = {'sp': NumericSympy(values)}
    exec(code, scope)
    return scope


def check_constrained(binary, model, count, seed):
    sys.path.insert(0, str(ROOT / 'apps' / 'hybridtest'))
    from check_constraints_sympy import solve  # noqa: E402  (Gaussian elimination)
    model = str(pathlib.Path(model).resolve())
    with tempfile.TemporaryDirectory() as workdir:
        mod = load_module(binary, model, workdir)  # runs under SymPy itself
        for name in ('dependent', 'A_d', 'A_i', 'b', 'bias', 'A', 'M_reduced', 'f_reduced'):
            if name not in mod:
                sys.exit(f'FAIL: the sympy module of {model} does not define `{name}`')
        text = (pathlib.Path(workdir) / 'equations.py').read_text(encoding='utf-8')
        code = compile(text.replace('import sympy as sp\n', ''), 'equations.py', 'exec')
        n = len(mod['q'])
        fixed = {str(k): float(v) for k, v in mod['parameters'].items()}
        fixed.update({str(s): 0.0 for s in mod['udot']})
        names = [str(s) for s in (mod['t'], *mod['q'], *mod['u'], *mod['r'], *mod.get('z', []))]
        a_names = [str(s) for s in mod['A']]
        dependent = [list(mod['u']).index(s) for s in mod['dependent']]
        config = pathlib.Path(workdir) / 'config.yaml'
        config.write_text(f'model: {{file: {model}}}\nintegrator: {{tableau: rk4, dt: 0.001}}\n'
                          'duration: 1.0\n', encoding='utf-8')
        x0 = json.loads(run(binary, 'modes', model, '--json').stdout)['operating_point']
        rng = random.Random(seed)
        worst = 0.0
        for trial in range(count):
            x = list(x0)
            for k in range(n):
                x[k] += rng.uniform(-0.2, 0.2)
                x[n + k] = rng.uniform(-3.0, 3.0)
            t = rng.uniform(0.0, 1.0)
            out = json.loads(run(binary, 'eom', str(config), '--time', repr(t), '--state',
                                 ','.join(repr(v) for v in x), '--assemble', '--json').stdout)
            xs = out['state']
            values = dict(fixed)
            values.update(zip(names, [t, *xs[:2 * n], *out['restoring'], *xs[2 * n:]]))
            values.update({a: 0.0 for a in a_names})
            Ad, Ai = (evaluate(code, values)[k] for k in ('A_d', 'A_i'))
            A = [[-v for v in row] for row in solve(Ad, Ai)]
            values.update(zip(a_names, [v for row in A for v in row]))
            ev = evaluate(code, values)
            Mr, fr = ev['M_reduced'], ev['f_reduced']
            state = f'trial {trial} (t = {t})'
            worst = max(worst, compare(model, ev['M'], out['mass_matrix'], state, 'M'))
            worst = max(worst, compare(model, ev['f'], out['forcing'], state, 'f'))
            if out['dependent_speeds'] == dependent:
                worst = max(worst, compare(model, Mr, out['reduced_mass_matrix'], state, 'M_reduced'))
                worst = max(worst, compare(model, fr, out['reduced_forcing'], state, 'f_reduced'))
            ours_udot = [row[0] for row in solve(Mr, [[v] for v in fr])]
            eom_udot = [row[0] for row in solve(out['reduced_mass_matrix'],
                                                [[v] for v in out['reduced_forcing']])]
            worst = max(worst, compare(model, ours_udot, eom_udot, state, "u'"))
            # The printed rows vanish at the assembled state: A_d u_d + A_i u_i + b = 0.
            independent = [j for j in range(n) if j not in dependent]
            bv = ev['b']
            u = xs[n:2 * n]
            for s_ in range(len(bv)):
                row = (sum(Ad[s_][k] * u[j] for k, j in enumerate(dependent)) +
                       sum(Ai[s_][k] * u[j] for k, j in enumerate(independent)) + bv[s_])
                if abs(row) > 1e-9 * max(1.0, max(abs(v) for v in u)):
                    sys.exit(f'FAIL: {model}: constraint row {s_ + 1} is {row} at the assembled '
                             f'state of {state}')
    print(f'{model}: the reduced equations equal eom --assemble at {count} consistent states '
          f'(largest relative difference {worst:.2e})')
    return 0


def bench_module():
    """bench/equations_vs_sympy.py, the generator of the n-link pendulums."""
    import importlib.util
    spec = importlib.util.spec_from_file_location('equations_vs_sympy',
                                                  ROOT / 'bench' / 'equations_vs_sympy.py')
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    return bench


def check_chain(binary, links, base, count, seed):
    """The printed equations of an n-link pendulum against the numeric engine (`eom`)."""
    with tempfile.TemporaryDirectory() as workdir:
        work = pathlib.Path(workdir)
        model = work / f'pendulum{links}{"_base" if base else ""}.yaml'
        model.write_text(bench_module().pendulum(links, base), encoding='utf-8')
        mod = load_module(binary, str(model), workdir)
        text = (work / 'equations.py').read_text(encoding='utf-8')
        code = compile(text.replace('import sympy as sp\n', ''), 'equations.py', 'exec')
        n = len(mod['q'])
        fixed = {str(k): float(v) for k, v in mod['parameters'].items()}
        fixed.update({str(s): 0.0 for s in mod['udot']})
        names = [str(s) for s in (*mod['q'], *mod['u'])]
        config = work / 'config.yaml'
        config.write_text(f'model: {{file: {model}}}\nintegrator: {{tableau: rk4, dt: 0.001}}\n'
                          'duration: 1.0\n', encoding='utf-8')
        rng = random.Random(seed)
        worst = 0.0
        for trial in range(count):
            scale = [0.1, 5.0, 50.0][trial % 3]
            x = ([rng.uniform(-1.1, 1.1) for _ in range(n)] +
                 [rng.uniform(-scale, scale) for _ in range(n)])
            t = rng.uniform(0.0, 5.0)
            out = json.loads(run(binary, 'eom', str(config), '--time', repr(t), '--state',
                                 ','.join(repr(v) for v in x), '--json').stdout)
            values = dict(fixed)
            values['t'] = t
            values.update(zip(names, x))
            ev = evaluate(code, values)
            state = f'trial {trial} (t = {t})'
            for what, ours_, theirs in (('M', ev['M'], out['mass_matrix']),
                                        ('f', ev['f'], out['forcing'])):
                worst = max(worst, compare(model.name, ours_, theirs, state, what, 'eom'))
    print(f'{model.name}: M and f equal eom at {count} states '
          f'(largest relative difference {worst:.2e})')
    return 0


def check_latex(binary):
    pdflatex = shutil.which('pdflatex')
    if pdflatex is None:
        print('SKIP: pdflatex is absent (scripts/install-deps.sh installs texlive-latex-base)')
        return 77
    # The rotor, and a constrained model (its constraint section).
    for name, model in (('rotor', 'rotor'),
                        ('four_bar', str(ROOT / 'examples' / 'models' / 'four_bar.yaml'))):
        with tempfile.TemporaryDirectory() as workdir:
            tex = pathlib.Path(workdir) / f'{name}.tex'
            run(binary, 'equations', model, '--format', 'latex', '--paper-form', '--out', str(tex))
            p = subprocess.run([pdflatex, '-interaction=nonstopmode', '-halt-on-error', tex.name],
                               cwd=workdir, capture_output=True, text=True)
            pdf = pathlib.Path(workdir) / f'{name}.pdf'
            if p.returncode != 0 or not pdf.exists() or pdf.stat().st_size == 0:
                sys.exit(f'FAIL: pdflatex {name}.tex exited {p.returncode}:\n{p.stdout[-3000:]}')
        print(f'{name}: latex output compiles with pdflatex')
    return 0


def check_cli(binary):
    def expect2(args, words):
        p = run(binary, *args, check=False)
        if p.returncode != 2 or not all(w in p.stderr for w in words):
            sys.exit(f'FAIL: {" ".join(args)}: expected exit 2 and a message with {words}, got '
                     f'{p.returncode}:\n{p.stderr}')
    with tempfile.TemporaryDirectory() as workdir:
        out = pathlib.Path(workdir) / 'eq.md'
        expect2(['equations', 'rotor', '--format', 'html'], ['--format html', 'markdown'])
        expect2(['equations', str(pathlib.Path(workdir) / 'missing.yaml')], ['no such file'])
        bad = pathlib.Path(workdir) / 'bad.yaml'
        bad.write_text('coordinates: [unclosed\n')
        expect2(['equations', str(bad)], ['bad.yaml'])
        run(binary, 'equations', 'rotor', '--out', str(out))
        first = out.read_text()
        if 'M[1,1]' not in first or 'Fr' not in first:
            sys.exit('FAIL: the markdown output has no M[1,1] or Fr section')
        expect2(['equations', 'rotor', '--out', str(out)], ['exists', '--overwrite'])
        run(binary, 'equations', 'rotor', '--out', str(out), '--overwrite')
        model = ROOT / 'examples' / 'models' / 'rotor.yaml'
        expect2(['equations', str(model), '--out', str(model)], ['--out'])
    print('equations: bad input exits 2 with a clear message; --out is guarded')
    return 0


def read_csv(path):
    rows = [line.split(',') for line in pathlib.Path(path).read_text().splitlines()
            if line and not line.startswith('#')]
    return rows[0], [[float(x) for x in row] for row in rows[1:]]


def check_compiled(binary, config):
    import yaml
    config = pathlib.Path(config).resolve()
    with tempfile.TemporaryDirectory() as workdir:
        work = pathlib.Path(workdir)
        doc = yaml.safe_load(config.read_text())
        if 'file' in doc['model']:
            doc['model']['file'] = str((config.parent / doc['model']['file']).resolve())
        doc.pop('output', None)
        plain, compiled = work / 'plain.yaml', work / 'compiled.yaml'
        plain.write_text(yaml.safe_dump(doc))
        doc['model']['compiled'] = True
        compiled.write_text(yaml.safe_dump(doc))
        env_cache = str(work / 'cache')
        import os
        os.environ['HYBRIDTEST_CACHE_DIR'] = env_cache
        run(binary, 'simulate', str(plain), '--out', str(work / 'plain.csv'))
        run(binary, 'simulate', str(compiled), '--out', str(work / 'compiled.csv'))
        libraries = list(pathlib.Path(env_cache).glob('*.so'))
        if len(libraries) != 1:
            sys.exit(f'FAIL: expected one compiled library in the cache, found {libraries}')
        p = run(binary, 'compile-model', str(compiled))
        if str(libraries[0]) not in p.stdout or 'found in the cache' not in p.stdout:
            sys.exit(f'FAIL: compile-model did not find {libraries[0]} in the cache:\n{p.stdout}')
        head_a, a = read_csv(work / 'compiled.csv')
        head_b, b = read_csv(work / 'plain.csv')
    if head_a != head_b or len(a) != len(b) or len(b) < 2:
        sys.exit(f'FAIL: the runs differ in shape: {len(a)} and {len(b)} rows')
    worst = 0.0
    for c, name in enumerate(head_b):
        scale = max([1.0] + [abs(row[c]) for row in b])
        diff = max(abs(ra[c] - rb[c]) for ra, rb in zip(a, b))
        worst = max(worst, diff / scale)
        if diff > TOLERANCE * scale:
            sys.exit(f'FAIL: column {name}: compiled and numeric runs differ by {diff:.3g} '
                     f'(tolerance {TOLERANCE} x {scale})')
    print(f'{config.name}: simulate with the compiled model equals the numeric engine over '
          f'{len(b)} rows (largest relative difference {worst:.2e})')
    return 0


def check_stable(binary):
    """Issue 47: runs print the same bytes (the rotor, every model file under examples/models/,
    and a 6-link pendulum on a cart printed with common subexpressions; Markdown, SymPy and C),
    and no number printed in Markdown or SymPy carries float noise (more than 15 significant
    digits, such as 1.5699999999999998). Four runs each (each its own process, so GiNaC's address-dependent term order differs): a model that
    printed one of four texts at random (spinning_top did) passes two runs one time in four."""
    import re
    models = ['rotor'] + [str(p) for p in sorted((ROOT / 'examples/models').glob('*.yaml'))]
    # A model printed with common subexpressions (too large to expand): the pendulum of the
    # benchmark (bench/equations_vs_sympy.py), 6 links on a cart.
    bench = bench_module()
    workdir = tempfile.TemporaryDirectory()
    chain = pathlib.Path(workdir.name) / 'pendulum6_base.yaml'
    chain.write_text(bench.pendulum(6, True), encoding='utf-8')
    models.append(str(chain))
    for model in models:
        for fmt in ('sympy', 'markdown', 'c'):
            a = run(binary, 'equations', model, '--format', fmt).stdout
            for _ in range(3):
                if run(binary, 'equations', model, '--format', fmt).stdout != a:
                    sys.exit(f'FAIL: two runs of equations {model} --format {fmt} differ')
            if fmt == 'c':
                continue  # C literals carry 17 digits: C reads them back exactly
            for number in re.findall(r'(?<![\w.])\d+\.\d+(?:e[-+]?\d+)?', a):
                digits = re.sub(r'e.*', '', number).replace('.', '').lstrip('0')
                if len(digits) > 15:
                    sys.exit(f'FAIL: equations {model} --format {fmt} prints {number}')
            if model == str(chain) and fmt == 'sympy' and 'cse1 = ' not in a:
                sys.exit(f'FAIL: equations {model} has no common subexpressions: not a large model')
    check_one_naming(binary)
    print('equations: byte-identical runs, no float noise; a run config prints its model\'s '
          'equations')
    return 0


def check_one_naming(binary):
    """Issue 47 item 3: the rotor's run config (built-in model, a substructure per blade, the
    blade parameters blade1.m_b, ... following the shared m_b) prints the equations the model
    file prints, symbol for symbol, and lists an instance's parameter only where instances
    differ (the azimuths blade<i>.psi)."""
    model = run(binary, 'equations', str(ROOT / 'examples/models/rotor.yaml'),
                '--format', 'sympy').stdout
    config = run(binary, 'equations', str(ROOT / 'examples/rotor/numerical.yaml'),
                 '--format', 'sympy').stdout
    def lines(text, prefix):
        return [line for line in text.splitlines() if line.startswith(prefix)]
    for prefix in ('M = ', 'f = ', 'Fr = ', 'Fr_star = ', 'qdot = '):
        if lines(model, prefix) != lines(config, prefix):
            sys.exit(f'FAIL: examples/rotor/numerical.yaml prints {prefix}... differently from '
                     f'examples/models/rotor.yaml')
    instances = {line.split(' = ')[0] for line in lines(config, 'blade')}
    expected = {'blade1_psi', 'blade2_psi', 'blade3_psi'}
    if instances != expected:
        sys.exit(f'FAIL: the run config declares the instance parameters {sorted(instances)}; '
                 f'expected only the azimuths {sorted(expected)} (the others follow m_b, l_b, ...)')


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--binary', required=True)
    ap.add_argument('--model')
    ap.add_argument('--states', type=int, default=25)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--latex', action='store_true')
    ap.add_argument('--cli', action='store_true')
    ap.add_argument('--compiled', metavar='CONFIG')
    ap.add_argument('--stable', action='store_true')
    ap.add_argument('--constrained', metavar='MODEL')
    ap.add_argument('--chains', metavar='N,N,...')
    a = ap.parse_args()
    if a.chains:
        for links in (int(n) for n in a.chains.split(',')):
            for base in (False, True):
                check_chain(a.binary, links, base, a.states, a.seed)
        return 0
    if a.constrained:
        return check_constrained(a.binary, a.constrained, a.states, a.seed)
    if a.stable:
        return check_stable(a.binary)
    if a.compiled:
        return check_compiled(a.binary, a.compiled)
    if a.latex:
        return check_latex(a.binary)
    if a.cli:
        return check_cli(a.binary)
    check_model(a.binary, a.model, a.states, a.seed)
    return 0


if __name__ == '__main__':
    sys.exit(main())
