#!/usr/bin/env python3
"""High-precision (150 digits) replay of YADE 2023.02a's per-step contact algorithm.

    python3 c_tests/reference/mp_replay.py [yade_double.csv] [yade_mp150.csv]

Stand-in for the unavailable yade-mpfr150: takes the inputs the law saw in every step (positions,
velocities, angular velocities, radii, dt: the exact double values recorded in yade_double.csv)
and the material parameters of cases.json (exact doubles), and replays in mpmath at 150 digits:

  Ig2_Sphere_Sphere_ScGeom(6D) + ScGeom::precompute
      d = x2 - x1, n = d/|d|, pen = R1 + R2 - |d|, cp = x1 + (R1 - pen/2) n
      (not the first step) orth = n_old x n,  twist = dt/2 (n_old.(w1 + w2)) n_old
      incidentVel = alpha (v2 - v1) + w2 x (-R2 n) - w1 x (R1 n),  alpha = (R1+R2)/(R1+R2-pen)
      shearInc = (incidentVel - (n.incidentVel) n) dt
      (avoidGranularRatcheting=False: incidentVel replaced in shearInc by the contact points'
       relative velocity v2 + w2 x (cp - x2) - v1 - w1 x (cp - x1); the incidentVel column keeps
       the default form)
  ScGeom::rotate(u):  u -= u x orth;  u -= u x twist          (first-order transport)
  Law2_ScGeom6D_CohFrictPhys_CohesionMoment (useIncrementalForm, always_use_moment_law, no cohesion)
      F_n = kn pen, normalForce = F_n n
      F_s = rotate(F_s) - ks shearInc;   |F_s| > max(0, F_n tan phi)  ->  radial scaling
      M_b = rotate(M_b) - kr dt (w2-w1)_t;  M_t = rotate(M_t) - ktw dt ((w2-w1).n) n
      |M_b| > maxRollPl |normalForce|  -> radial scaling;  same for M_t with maxTwistPl
      kn = 2 E1 R1 E2 R2/(E1 R1 + E2 R2), ks = same with E nu, kr = R1 R2 ks aKr, ktw = R1 R2 ks aKtw
      (aKr, aKtw harmonic means), maxRollPl = min(etaRoll_i R_i), maxTwistPl = min(etaTwist_i R_i)
  Law2_ScGeom_MindlinPhys_Mindlin (includeMoment, no damping, no adhesion)
      F_n = kno pen^1.5, kn = 3/2 kno pen^0.5, ks = kso pen^0.5
      F_s = rotate(F_s) - ks shearInc; |F_s| > |normalForce| tan phi -> radial scaling
      M_b, M_t as above with kr = krot, ktw = ktwist; |M_b| > eta (R1+R2)/2 |normalForce| -> scaling
      (no twisting limit); kno = 4/3 E* sqrt(R*), kso = 8 sqrt(R*) G*, G* = 1/((2-v1)/G1 + (2-v2)/G2)
  loads: f2 = normalForce + F_s, f1 = -f2, t1 = -(M_b + M_t) + (cp - x1) x f1,
         t2 = (M_b + M_t) + (cp - x2) x f2

Writes the same columns as yade_double.csv (inputs copied verbatim; every computed value rounded
correctly to the nearest double and printed with repr) and prints, per column, the largest
deviation of double YADE from this replay (also written to mp_agreement.txt).
"""
import csv
import json
import os
import sys

try:
    import mpmath
    from mpmath import mp, mpf
except ImportError:  # pragma: no cover
    sys.exit('mp_replay.py needs mpmath: pip install mpmath')

mp.dps = 150
HERE = os.path.dirname(os.path.abspath(__file__))
ZERO = None


def F(x):
    """exact value of a double (the value YADE holds), not of its decimal string"""
    return mpf(float(x))


def vec(r, p):
    return [F(r[p + '_' + c]) for c in 'xyz']


def add(a, b):
    return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def mul(s, a):
    return [s * a[0], s * a[1], s * a[2]]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def norm(a):
    return mpmath.sqrt(dot(a, a))


def params(case, r1, r2):
    m = case['material']
    E, nu, phi = F(m['young']), F(m['poisson']), F(m['frictionAngle'])
    tanphi = mpmath.tan(phi)
    if case['law'] == 'cohfrict':
        Ea = Eb = E
        Va = Vb = nu
        kn = 2 * Ea * r1 * Eb * r2 / (Ea * r1 + Eb * r2)
        ks = 2 * Ea * r1 * Va * Eb * r2 * Vb / (Ea * r1 * Va + Eb * r2 * Vb)
        a, b = F(m['alphaKr']), F(m['alphaKr'])
        aKr = 2 * a * b / (a + b)
        a, b = F(m['alphaKtw']), F(m['alphaKtw'])
        aKtw = 2 * a * b / (a + b)
        kr = r1 * r2 * ks * aKr
        ktw = r1 * r2 * ks * aKtw
        maxroll = min(F(m['etaRoll']) * r1, F(m['etaRoll']) * r2)
        maxtwist = min(F(m['etaTwist']) * r1, F(m['etaTwist']) * r2)
        return dict(kn=kn, ks=ks, kr=kr, ktw=ktw, tanphi=tanphi, maxroll=maxroll, maxtwist=maxtwist)
    p = case['ip2']
    G = E / (2 * (1 + nu))
    Geff = 1 / ((2 - nu) / G + (2 - nu) / G)
    Es = E * E / ((1 - nu ** 2) * E + (1 - nu ** 2) * E)
    R = r1 * r2 / (r1 + r2)
    kno = mpf(4) / 3 * Es * mpmath.sqrt(R)
    kso = 8 * mpmath.sqrt(R) * Geff
    return dict(kn=kno, ks=kso, kr=F(p['krot']), ktw=F(p['ktwist']), tanphi=tanphi,
                maxroll=F(p['eta']) * (r1 + r2) / 2, maxtwist=mpf(-1))


def replay_case(case, rows):
    law = case['law']
    out = []
    fs = [mpf(0)] * 3
    mb = [mpf(0)] * 3
    mt = [mpf(0)] * 3
    n_old = None
    P = None
    for k, r in enumerate(rows):
        r1, r2, dt = F(r['r1']), F(r['r2']), F(r['dt'])
        if P is None:
            P = params(case, r1, r2)
        x1, x2, v1, v2, w1, w2 = (vec(r, p) for p in ('x1', 'x2', 'v1', 'v2', 'w1', 'w2'))
        # --- geometry (Ig2_Sphere_Sphere_ScGeom::go) ---
        d = sub(x2, x1)
        L = norm(d)
        n = mul(1 / L, d)
        pen = r1 + r2 - L
        cp = add(x1, mul(r1 - pen / 2, n))
        # --- ScGeom::precompute ---
        if n_old is None:
            orth = [mpf(0)] * 3
            twa = [mpf(0)] * 3
        else:
            orth = cross(n_old, n)
            twa = mul(dt / 2 * dot(n_old, add(w1, w2)), n_old)
        n_old = n
        alpha = (r1 + r2) / (r1 + r2 - pen)
        iv = sub(add(mul(alpha, sub(v2, v1)), cross(w2, mul(-r2, n))), cross(w1, mul(r1, n)))
        if case.get('avoidGranularRatcheting', True):
            used = iv
        else:
            # avoidGranularRatcheting=False: the material points' velocities at the contact point
            used = sub(add(v2, cross(w2, sub(cp, x2))), add(v1, cross(w1, sub(cp, x1))))
        sinc = mul(dt, sub(used, mul(dot(n, used), n)))

        def rotate(u):
            u = sub(u, cross(u, orth))
            return sub(u, cross(u, twa))

        rav = sub(w2, w1)
        ravn = dot(n, rav)
        rbend = mul(dt, sub(rav, mul(ravn, n)))
        rtw = mul(dt, mul(ravn, n))
        if law == 'cohfrict':
            Fn = P['kn'] * pen
            kn_now, ks_now = P['kn'], P['ks']
            fnv = mul(Fn, n)
            fs = sub(rotate(fs), mul(ks_now, sinc))
            maxFs = max(mpf(0), Fn * P['tanphi'])
            Fs = norm(fs)
            if Fs > maxFs:
                fs = mul(maxFs / Fs, fs)
                if Fn < 0:
                    fnv = [mpf(0)] * 3
        else:
            Fn = P['kn'] * pen ** mpf(1.5)
            kn_now = mpf(3) / 2 * P['kn'] * mpmath.sqrt(pen)
            ks_now = P['ks'] * mpmath.sqrt(pen)
            fnv = mul(Fn, n)
            fs = sub(rotate(fs), mul(ks_now, sinc))
            maxFs = norm(fnv) * P['tanphi']
            if dot(fs, fs) > maxFs * maxFs:
                fs = mul(maxFs / norm(fs), fs)
        mb = sub(rotate(mb), mul(P['kr'], rbend))
        mt = sub(rotate(mt), mul(P['ktw'], rtw))
        fnorm = norm(fnv)
        if law == 'cohfrict':
            if P['maxroll'] >= 0:
                lim = P['maxroll'] * fnorm
                s = norm(mb)
                if s > lim:
                    mb = mul(lim / s, mb)
            if P['maxtwist'] >= 0:
                lim = P['maxtwist'] * fnorm
                s = norm(mt)
                if s > lim:
                    mt = mul(lim / s, mt)
        else:
            lim = P['maxroll'] * fnorm
            s = norm(mb)
            if lim > 0 and s > lim:
                mb = mul(lim / s, mb)
        f2 = add(fnv, fs)
        f1 = mul(-1, f2)
        M = add(mb, mt)
        t1 = add(mul(-1, M), cross(sub(cp, x1), f1))
        t2 = add(M, cross(sub(cp, x2), f2))
        vals = dict(n=n, cp=cp, relangvel=rav, incvel=iv, shearinc=sinc, fn=fnv, fs=fs, mb=mb, mt=mt,
                    f1=f1, f2=f2, t1=t1, t2=t2)
        res = {}
        for key, v in vals.items():
            for c, x in zip('xyz', v):
                res[key + '_' + c] = x
        res['pen'] = pen
        res['kn'] = kn_now
        res['ks'] = ks_now
        for key in ('kn', 'ks', 'kr', 'ktw', 'tanphi', 'maxroll', 'maxtwist'):
            res['param_' + key] = P[key]
        res['param_ratchet'] = mpf(1 if case.get('avoidGranularRatcheting', True) else 0)
        out.append(res)
    return out


def row_scales(r, c):
    """natural magnitude of each output quantity in one row (for relative errors of components
    whose exact value may be zero)"""
    x1, x2, v1, v2, w1, w2 = (vec(r, p) for p in ('x1', 'x2', 'v1', 'v2', 'w1', 'w2'))
    r1, r2, dt = F(r['r1']), F(r['r2']), F(r['dt'])
    fn = norm([c['fn_x'], c['fn_y'], c['fn_z']])
    mtn = norm([c['mt_x'], c['mt_y'], c['mt_z']])
    roll = c['param_maxroll'] * fn
    twist = c['param_maxtwist'] * fn if c['param_maxtwist'] > 0 else max(mtn, roll)
    slip = c['param_tanphi'] * fn
    kin = norm(sub(v2, v1)) + r1 * norm(w1) + r2 * norm(w2)
    s = dict(n=1, pen=abs(c['pen']), cp=max(norm(x1), norm(x2), r1 + r2), relangvel=norm(w1) + norm(w2),
             incvel=kin, shearinc=kin * dt, kn=c['kn'], ks=c['ks'], fn=fn, fs=slip, mb=roll, mt=twist,
             f1=fn + slip, f2=fn + slip)
    s['t1'] = s['t2'] = max(r1, r2) * slip + roll + twist
    for k in ('kn', 'ks', 'kr', 'ktw', 'tanphi', 'maxroll', 'maxtwist', 'ratchet'):
        s['param_' + k] = abs(c['param_' + k])
    return {k: float(v) for k, v in s.items()}


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, 'yade_double.csv')
    dst = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, 'yade_mp150.csv')
    with open(src, newline='') as f:
        rd = csv.reader(f)
        header = next(rd)
        raw = [row for row in rd if row]
    rows = [dict(zip(header, row)) for row in raw]
    cases = {c['name']: c for c in json.load(open(os.path.join(HERE, 'cases.json')))['cases']}
    groups = {}
    order = []
    for r in rows:
        if r['case'] not in groups:
            order.append(r['case'])
        groups.setdefault(r['case'], []).append(r)
    computed = []
    for name in order:
        computed += replay_case(cases[name], groups[name])
    worst = {}
    with open(dst, 'w', newline='') as f:
        f.write(','.join(header) + '\n')
        for r, c in zip(rows, computed):
            sc = row_scales(r, c)
            line = []
            for h in header:
                if h in c:
                    line.append(repr(float(c[h])))
                    err = float(abs(F(r[h]) - c[h]))
                    s = sc[h.split('_')[0] if not h.startswith('param_') else h]
                    e = err / s if s > 0 else err
                    if e > worst.get(h, (-1.0,))[0]:
                        worst[h] = (e, r['case'], r['step'])
                else:
                    line.append(r[h])
            f.write(','.join(line) + '\n')
    lines = ['double YADE 2023.02a vs 150-digit replay: per column, max over all %d rows of' % len(rows),
             '|yade - mp| / scale, scale = the natural magnitude of the quantity in that row (see',
             'row_scales in mp_replay.py: e.g. the slip limit tan(phi)|F_n| for shear force components,',
             'the rolling limit for M_b, |v2-v1| + R1|w1| + R2|w2| for incidentVel); worst case and step in brackets']
    for h in header:
        if h in worst:
            e, cname, step = worst[h]
            lines.append('  %-16s %.3g   [%s step %s]' % (h, e, cname, step))
    text = '\n'.join(lines) + '\n'
    print(text, end='')
    with open(os.path.join(os.path.dirname(os.path.abspath(dst)), 'mp_agreement.txt'), 'w') as f:
        f.write(text)
    print('mp_replay: wrote', dst)


if __name__ == '__main__':
    main()
