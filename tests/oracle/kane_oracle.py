#!/usr/bin/python3
"""Kane oracle: compares `hybridtest eom` with SymPy's KanesMethod at random states.

For each model (the rotor with N = 3 and N = 2 blades) the equations of motion are derived independently with
sympy.physics.mechanics.KanesMethod (oracle_models.py). 100 states per case (--states) are drawn with a fixed seed:
random coordinates, speeds up to |u| = 50 (rad/s or m/s), random times, random restoring
forces (rotor) and random parameter overrides written into a temporary YAML config
(model-wide and, for the rotor, per-blade keys; a few states keep the defaults). For each state
the binary is run as

    hybridtest eom CONFIG --time T --state x1,...,x2n [--restoring r1,...,rN] --json

and its JSON {"mass_matrix", "forcing", "xdot"} is compared with the oracle's
M = KanesMethod.mass_matrix, F = KanesMethod.forcing and xdot = [q'; M^-1 F].

Tolerance (relative 1e-10): an entry a of the engine's array passes against the oracle's entry
b if |a - b| <= 1e-10 * max(1, ||B||_inf), where ||B||_inf is the largest absolute entry of the
oracle's whole array (mass_matrix, forcing and xdot each taken separately).

The script also checks that the CLI rejects a state vector of the wrong length (2n - 1 and
2n + 1 entries) with a non-zero exit status and a message that names the expected length 2n,
and (rotor) a --restoring list with N - 1 entries with a message that names N.

On failure it prints the model, the state index, t, x, r, the config overrides, the array, the
entry, both values and the tolerance; the temporary directory with the configs is kept.
Exit status: 0 if everything passed, 1 on a mismatch or a malformed answer, 2 on usage errors.

Usage:
  /usr/bin/python3 kane_oracle.py --binary build/release/apps/hybridtest/hybridtest --model rotor
  /usr/bin/python3 kane_oracle.py --self-test      # SymPy side only, no binary needed
"""

import argparse
import math
import os
import shutil
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import oracle_models  # noqa: E402
import oracle_cli  # noqa: E402

REL_TOL = 1e-10
MAX_SPEED = 50.0

# Plausible positive ranges for random parameter overrides (SI).
ROTOR_GLOBAL_RANGES = {
    'l_b': (0.3, 1.2), 'm_b': (0.5, 4.0), 'zeta_b': (0.2, 3.0), 'k_b': (1e3, 2e4),
    'f_w': (10.0, 300.0), 'I_g': (0.05, 1.0), 'd_g': (10.0, 300.0), 'g': (9.0, 10.5),
    't0': (0.1, 2.0),
}
ROTOR_BLADE_RANGES = {
    'l_b': (0.3, 1.2), 'm_b': (0.5, 4.0), 'zeta_b': (0.2, 3.0), 'k_b': (1e3, 2e4),
    'f_w': (10.0, 300.0), 'psi': (-math.pi, 2 * math.pi),
}
PENDULUM_RANGES = {'m1': (0.3, 3.0), 'm2': (0.3, 3.0), 'l1': (0.3, 2.0), 'l2': (0.3, 2.0),
                   'g': (9.0, 10.5)}
TOP_RANGES = {
    'm': (0.3, 3.0), 'cx': (-0.05, 0.05), 'cy': (-0.05, 0.05), 'cz': (0.02, 0.3),
    'Ixx': (0.008, 0.012), 'Iyy': (0.008, 0.012), 'Izz': (0.006, 0.010),
    'Ixy': (-0.0015, 0.0015), 'Ixz': (-0.0015, 0.0015), 'Iyz': (-0.0015, 0.0015),
    'g': (9.0, 10.5),
}
NUM_DEFAULT_STATES = 3  # the first states of each case use the config's defaults


def random_overrides(model, rng):
    """A random subset of parameter overrides for the model (dict config key -> value)."""
    if model.name == 'rotor':
        ranges = dict(ROTOR_GLOBAL_RANGES)
        for i in range(1, model.num_blades + 1):
            for key, rg in ROTOR_BLADE_RANGES.items():
                ranges[f'blade{i}.{key}'] = rg
    elif model.name == 'double_pendulum':
        ranges = PENDULUM_RANGES
    else:
        ranges = TOP_RANGES
    keys = sorted(ranges)
    chosen = [k for k in keys if rng.random() < 0.5]
    return {k: float(rng.uniform(*ranges[k])) for k in chosen}


def random_state(model, rng, index):
    """Returns (t, q, u, r) for state number index."""
    n = model.n
    speed = [0.1, 5.0, MAX_SPEED][index % 3]
    u = rng.uniform(-speed, speed, n)
    if model.name == 'rotor':
        q = np.concatenate([rng.uniform(-0.5, 0.5, n - 1), rng.uniform(-20.0, 20.0, 1)])
    elif model.name == 'double_pendulum':
        q = rng.uniform(-2 * math.pi, 2 * math.pi, n)
    else:
        q = np.array([rng.uniform(-math.pi, math.pi), rng.uniform(-1.2, 1.2),
                      rng.uniform(-math.pi, math.pi)])
    r = rng.uniform(-2000.0, 2000.0, model.num_slots)
    t = 0.0 if index == 0 else float(rng.uniform(0.0, 5.0))
    return t, q, u, r


def compare(name, engine, oracle, worst):
    """List of (array name, entry index, engine value, oracle value, tolerance) that fail.

    worst[name] is raised to the largest |a - b| / max(1, ||B||_inf) seen."""
    scale = max(1.0, float(np.max(np.abs(oracle))) if oracle.size else 1.0)
    tol = REL_TOL * scale
    bad = []
    for idx in np.ndindex(oracle.shape):
        a, b = float(engine[idx]), float(oracle[idx])
        if not (abs(a - b) <= tol):
            bad.append((name, idx, a, b, tol))
        elif abs(a - b) / scale > worst.get(name, 0.0):
            worst[name] = abs(a - b) / scale
    return bad


def fmt_vec(v):
    return '[' + ', '.join(repr(float(x)) for x in v) + ']'


def run_case(binary, model, rng, num_states, workdir, label):
    """Compares num_states random states; returns the number of failing states."""
    failures = 0
    worst = {}
    for k in range(num_states):
        overrides = {} if k < NUM_DEFAULT_STATES else random_overrides(model, rng)
        t, q, u, r = random_state(model, rng, k)
        params = model.resolve(overrides)
        m_o, f_o, xd_o = model.evaluate(t, q, u, r, params)
        config = oracle_cli.write_config(workdir, f'{label}_{k:03d}.yaml', model, overrides)
        x = np.concatenate([q, u])
        try:
            m_e, f_e, xd_e = oracle_cli.run_eom(binary, config, t, x, r, model.n)
        except oracle_cli.CliFailure as err:
            print(f'FAIL {label} state {k}: {err}\n  t = {t!r}\n  x = {fmt_vec(x)}\n'
                  f'  r = {fmt_vec(r)}\n  config = {config}')
            failures += 1
            continue
        bad = (compare('mass_matrix', m_e, m_o, worst) + compare('forcing', f_e, f_o, worst)
               + compare('xdot', xd_e, xd_o, worst))
        if bad:
            failures += 1
            print(f'FAIL {label} state {k}: t = {t!r}\n  x = {fmt_vec(x)}\n  r = {fmt_vec(r)}\n'
                  f'  overrides = {overrides}\n  config = {config}')
            for name, idx, a, b, tol in bad:
                print(f'  {name}{list(idx)}: engine = {a!r}, oracle = {b!r}, '
                      f'|diff| = {abs(a - b):.3e} > tol = {tol:.3e}')
    print(f'{label}: {num_states - failures}/{num_states} states agree '
          f'(rel. tol {REL_TOL:g}, |u| up to {MAX_SPEED:g}); worst agreeing |diff|/scale: '
          + (', '.join(f'{key} {value:.1e}' for key, value in sorted(worst.items())) or 'none'))
    return failures


def check_wrong_length(binary, model, workdir, label):
    """The CLI must reject a state of the wrong length and name the expected one."""
    config = oracle_cli.write_config(workdir, f'{label}_length.yaml', model, {})
    problems = 0
    for length in (2 * model.n - 1, 2 * model.n + 1):
        message = oracle_cli.expect_length_rejection(binary, config, length, 2 * model.n,
                                                     model.num_slots)
        if message:
            print(f'FAIL {label} wrong-length state ({length} entries): {message}')
            problems += 1
    if model.num_slots:
        message = oracle_cli.expect_length_rejection(
            binary, config, 2 * model.n, model.num_slots, model.num_slots - 1)
        if message:
            print(f'FAIL {label} wrong-length --restoring ({model.num_slots - 1} entries): '
                  f'{message}')
            problems += 1
    if not problems:
        print(f'{label}: wrong-length states' + (' and restoring forces' if model.num_slots
                                                 else '') + ' rejected with the expected length')
    return problems


def cases_for(model_name, num_states):
    """(label, derived model, number of states) for one model."""
    if model_name == 'rotor':
        return [('rotor N=3', oracle_models.derive_rotor(3), num_states),
                ('rotor N=2', oracle_models.derive_rotor(2), num_states)]
    if model_name == 'double_pendulum':
        return [('double_pendulum', oracle_models.derive_double_pendulum(), num_states)]
    return [('spinning_top', oracle_models.derive_spinning_top(), num_states)]


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--binary', help='path of the hybridtest executable')
    parser.add_argument('--model', choices=['rotor', 'double_pendulum', 'spinning_top', 'all'],
                        default='all')
    parser.add_argument('--states', type=int, default=100, help='random states per case')
    parser.add_argument('--seed', type=int, default=20260522)
    parser.add_argument('--self-test', action='store_true',
                        help='check the SymPy derivations against hand results only')
    args = parser.parse_args(argv)
    if args.self_test:
        import oracle_selftest
        return oracle_selftest.run()
    if not args.binary:
        parser.error('--binary is required (or use --self-test)')
    if not (os.path.isfile(args.binary) and os.access(args.binary, os.X_OK)):
        print(f'error: --binary {args.binary!r} is not an executable file; build it with '
              f'`cmake --build build/release --target hybridtest`', file=sys.stderr)
        return 2
    names = (['rotor', 'double_pendulum', 'spinning_top'] if args.model == 'all'
             else [args.model])
    workdir = tempfile.mkdtemp(prefix='kane_oracle_')
    failures = 0
    for offset, name in enumerate(names):
        for label, model, count in cases_for(name, args.states):
            rng = np.random.default_rng([args.seed, offset, model.n])
            failures += run_case(args.binary, model, rng, count, workdir, label)
            failures += check_wrong_length(args.binary, model, workdir, label)
    if failures:
        print(f'FAILED: {failures} failing checks; configs kept in {workdir}')
        return 1
    shutil.rmtree(workdir, ignore_errors=True)
    print('PASSED')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
