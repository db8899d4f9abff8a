#!/usr/bin/env python3
"""Compare two reference CSVs written by yade_reference.py (or mp_replay.py).

    python3 compare_reference.py A.csv B.csv [--rtol 1e-9] [--afloor 1e-12]

Plain python3 (no numpy). Rows are matched by position; the columns case, step and law must be
equal. A numeric field passes when

    |a - b| <= rtol * max(|a|, |b|) + afloor * scale(case, column)

where scale(case, column) is the largest |value| within that case in A over the column's family:
positions (x1, x2, cp), velocities (v1, v2), angular velocities (w1, w2, relangvel), incvel,
shearinc (these two with the kinematic scale max(|v_k|, R_k |w_k|, |incvel|), times dt for
shearinc), n, pen, stiffnesses (kn, ks), forces (fn, fs, f1, f2), moments (mb, mt, t1, t2), and each
param_ column alone. So the absolute floor follows the magnitude of the physical quantity, and
components that are exactly zero in theory but carry rounding noise do not fail. Prints the worst column (largest error / tolerance) and exits 1 if
any field fails, 2 on a structural mismatch (header, row count, case/step/law)."""
import argparse
import csv
import math
import sys

KEYS = ('case', 'step', 'law')


FAMILIES = {'x1': 'pos', 'x2': 'pos', 'cp': 'pos', 'v1': 'vel', 'v2': 'vel', 'w1': 'angvel', 'w2': 'angvel',
            'relangvel': 'angvel', 'kn': 'stiff', 'ks': 'stiff', 'fn': 'force', 'fs': 'force', 'f1': 'force',
            'f2': 'force', 'mb': 'moment', 'mt': 'moment', 't1': 'moment', 't2': 'moment'}


def family(col):
    if col.startswith('param_'):
        return col
    base = col.rsplit('_', 1)[0] if col[-2:] in ('_x', '_y', '_z') else col
    return FAMILIES.get(base, base)


def load(path):
    with open(path, newline='') as f:
        r = csv.reader(f)
        header = next(r)
        rows = [row for row in r if row]
    return header, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('a')
    ap.add_argument('b')
    ap.add_argument('--rtol', type=float, default=1e-9)
    ap.add_argument('--afloor', type=float, default=1e-12)
    args = ap.parse_args()
    ha, ra = load(args.a)
    hb, rb = load(args.b)
    if ha != hb:
        print('header mismatch:', set(ha) ^ set(hb) or 'column order differs')
        return 2
    if len(ra) != len(rb):
        print('row count mismatch: %d vs %d' % (len(ra), len(rb)))
        return 2
    kidx = [ha.index(k) for k in KEYS if k in ha]
    nidx = [j for j, h in enumerate(ha) if h not in KEYS]
    # per (case, family) magnitude
    ci = ha.index('case')
    fam = {j: family(ha[j]) for j in nidx}
    famscale = {}
    for row in ra:
        for j in nidx:
            key = (row[ci], fam[j])
            v = abs(float(row[j]))
            if math.isfinite(v) and v > famscale.get(key, 0.0):
                famscale[key] = v
    # incident velocity and shear increment: kinematic scale max(|v_k|, R_k |w_k|, |incvel|)
    # (their exact value is zero in no-slip cases, where only rounding noise remains)
    kin = {}
    if all(c in ha for c in ('r1', 'r2', 'dt', 'v1_x', 'w1_x')):
        col = {h: j for j, h in enumerate(ha)}
        for row in ra:
            r1, r2, dt = float(row[col['r1']]), float(row[col['r2']]), float(row[col['dt']])
            k = max([abs(float(row[col[p + '_' + c]])) for p in ('v1', 'v2', 'incvel') for c in 'xyz']
                    + [r1 * abs(float(row[col['w1_' + c]])) for c in 'xyz']
                    + [r2 * abs(float(row[col['w2_' + c]])) for c in 'xyz'])
            if k > kin.get(row[ci], (0.0, dt))[0]:
                kin[row[ci]] = (k, dt)
    scale = {}
    for row in ra:
        for j in nidx:
            v = famscale.get((row[ci], fam[j]), 0.0)
            if fam[j] in ('incvel', 'shearinc') and row[ci] in kin:
                k, dt = kin[row[ci]]
                v = max(v, k if fam[j] == 'incvel' else k * dt)
            scale[(row[ci], j)] = v
    worst = {}  # column -> (ratio, abs err, row index, a, b)
    nfail = 0
    for i, (x, y) in enumerate(zip(ra, rb)):
        for j in kidx:
            if x[j] != y[j]:
                print('row %d: %s differs: %r vs %r' % (i + 1, ha[j], x[j], y[j]))
                return 2
        for j in nidx:
            a, b = float(x[j]), float(y[j])
            if a == b:
                continue
            err = abs(a - b)
            if not math.isfinite(err):
                ratio = math.inf
            else:
                tol = args.rtol * max(abs(a), abs(b)) + args.afloor * scale.get((x[ci], j), 0.0)
                ratio = err / tol if tol > 0 else math.inf
            if ratio > 1.0:
                nfail += 1
            if ratio > worst.get(j, (-1.0,))[0]:
                worst[j] = (ratio, err, i, a, b)
    if not worst:
        print('compare_reference: identical numeric fields (%d rows, %d numeric columns)' % (len(ra), len(nidx)))
        return 0
    j = max(worst, key=lambda k: worst[k][0])
    ratio, err, i, a, b = worst[j]
    print('compare_reference: %d rows, %d numeric columns, %d fields over tolerance (rtol=%g, afloor=%g)'
          % (len(ra), len(nidx), nfail, args.rtol, args.afloor))
    print('worst column: %s  (error/tolerance %.3g, |a-b| = %.3g at row %d, case %s step %s: %r vs %r)'
          % (ha[j], ratio, err, i + 1, ra[i][ci], ra[i][ha.index('step')], a, b))
    return 1 if nfail else 0


if __name__ == '__main__':
    sys.exit(main())
