#!/usr/bin/env python3
"""Check what the library assumes of YADE 2023.02a (its normal, relative angular velocity,
incident velocity and moment conventions, listed with each check below) against yade_double.csv.

    python3 c_tests/reference/verify_peers.py [yade_double.csv]

Plain python3, double precision. Each check prints the largest deviation found, relative to the
magnitude of the quantity (scale = largest |value| of the compared vector within the case);
'exact' means bit-identical when YADE's own order of operations is reproduced.
Exit status 1 if a check fails its tolerance.
"""
import csv
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def V(r, p):
    return [float(r[p + '_' + c]) for c in 'xyz']


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def addv(a, b):
    return [a[i] + b[i] for i in range(3)]


def mul(s, a):
    return [s * x for x in a]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def norm(a):
    return math.sqrt(dot(a, a))


class Check:
    def __init__(self, name, tol):
        self.name, self.tol, self.worst, self.where, self.exact = name, tol, 0.0, '', True

    def add(self, got, ref, scale, where):
        for g, e in zip(got, ref):
            if g != e:
                self.exact = False
            d = abs(g - e) / scale if scale > 0 else abs(g - e)
            if d > self.worst:
                self.worst, self.where = d, where

    def report(self):
        ok = self.worst <= self.tol
        print('%-4s %-68s max rel dev %.3g%s%s' % ('ok' if ok else 'FAIL', self.name, self.worst,
                                                    ' (exact)' if self.exact else '',
                                                    '' if not self.where else '  [' + self.where + ']'))
        return ok


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, 'yade_double.csv')
    rows = list(csv.DictReader(open(path)))
    cases = {c['name']: c for c in json.load(open(os.path.join(HERE, 'cases.json')))['cases']}
    by = {}
    for r in rows:
        by.setdefault(r['case'], []).append(r)

    C = dict(
        geom=Check('n=(x2-x1)/|x2-x1|, pen=R1+R2-|d|, cp=x1+(R1-pen/2)n from pre-step positions', 0.0),
        relang=Check('relAngVel = w2 - w1', 0.0),
        incvel=Check('incidentVel = alpha(v2-v1) - (R1 w1 + R2 w2) x n', 1e-15),
        shinc=Check('shearInc = (incidentVel)_t dt', 1e-15),
        shinc_cp=Check('avoidGranularRatcheting=False: shearInc = (v2 + w2 x (cp-x2) - v1 - w1 x (cp-x1))_t dt', 1e-15),
        force=Check('f2 = normalForce + shearForce, f1 = -f2 (loads act on body 2)', 1e-15),
        torque=Check('t1 = -(mb+mt) + (cp-x1) x f1, t2 = (mb+mt) + (cp-x2) x f2', 1e-14),
        advance=Check('blocked DOFs: x(k+1) = x(k) + v(k) dt (positions advance)', 0.0),
        cparams=Check('CohFrict kn, ks, kr=R1R2 ks aKr, ktw=R1R2 ks aKtw, maxRollPl, maxTwistPl', 1e-15),
        mparams=Check('Mindlin kr=krot, ktw=ktwist, maxBendPl = eta (R1+R2)/2', 1e-15),
        rlim=Check('|M_b| <= maxRoll |F_n| (radial scaling; = at the limit)', 1e-14),
        tlim=Check('CohFrict |M_t| <= maxTwistPl |F_n|', 1e-14),
        slim=Check('|F_s| <= tan(phi) |F_n|', 1e-14),
        hold=Check('no rotational damping: loads constant in the hold segment (w=0, v=0)', 1e-15),
        first=Check('first step: M_b = -kr dt (w2-w1)_t, M_t = -ktw dt ((w2-w1).n) n, F_s = -ks shearInc', 1e-15),
    )
    twist_unbounded = {}
    slide_vs_ours = {}
    for name, rs in by.items():
        case = cases[name]
        law = case['law']
        scl = {}
        for p in ('x1', 'x2', 'n', 'cp', 'relangvel', 'incvel', 'shearinc', 'fn', 'fs', 'mb', 'mt', 'f1', 't1', 'v1', 'v2'):
            scl[p] = max(max(abs(x) for x in V(r, p)) for r in rs) or 1.0
        for k, r in enumerate(rs):
            where = '%s step %s' % (name, r['step'])
            r1, r2, dt = float(r['r1']), float(r['r2']), float(r['dt'])
            x1, x2, v1, v2, w1, w2 = (V(r, p) for p in ('x1', 'x2', 'v1', 'v2', 'w1', 'w2'))
            # geometry, reproducing Ig2_Sphere_Sphere_ScGeom's order of operations
            d = sub(x2, x1)
            # Eigen (as built in Debian's yade) sums the squares as x^2 + (y^2 + z^2)
            L = math.sqrt(d[0] * d[0] + (d[1] * d[1] + d[2] * d[2]))
            n = [d[0] / L, d[1] / L, d[2] / L]
            pen = r1 + r2 - L
            cp = addv(x1, mul(r1 - 0.5 * pen, n))
            C['geom'].add(n + [pen] + cp, V(r, 'n') + [float(r['pen'])] + V(r, 'cp'), 1.0, where)
            C['relang'].add(sub(w2, w1), V(r, 'relangvel'), 1.0, where)
            alpha = (r1 + r2) / (r1 + r2 - pen)
            iv = sub(addv(mul(alpha, sub(v2, v1)), cross(w2, mul(-r2, n))), cross(w1, mul(r1, n)))
            C['incvel'].add(iv, V(r, 'incvel'), scl['incvel'], where)
            if case.get('avoidGranularRatcheting', True):
                ivr = V(r, 'incvel')
                si = mul(dt, sub(ivr, mul(dot(n, ivr), n)))
                C['shinc'].add(si, V(r, 'shearinc'), scl['incvel'] * dt, where)
            else:
                # avoidGranularRatcheting=False: the contact points' relative velocity
                cpv = sub(addv(v2, cross(w2, sub(cp, x2))), addv(v1, cross(w1, sub(cp, x1))))
                si = mul(dt, sub(cpv, mul(dot(n, cpv), n)))
                C['shinc_cp'].add(si, V(r, 'shearinc'), scl['incvel'] * dt, where)
            fn, fs, mb, mt = V(r, 'fn'), V(r, 'fs'), V(r, 'mb'), V(r, 'mt')
            f1, f2, t1, t2 = V(r, 'f1'), V(r, 'f2'), V(r, 't1'), V(r, 't2')
            fsc = max(scl['fn'], scl['fs'])
            C['force'].add(addv(fn, fs) + mul(-1, addv(fn, fs)), f2 + f1, fsc, where)
            M = addv(mb, mt)
            ex1 = addv(mul(-1, M), cross(sub(cp, x1), f1))
            ex2 = addv(M, cross(sub(cp, x2), f2))
            C['torque'].add(ex1 + ex2, t1 + t2, max(scl['t1'], scl['mb'], scl['mt']), where)
            if k + 1 < len(rs):
                nx = rs[k + 1]
                C['advance'].add(addv(x1, mul(dt, v1)) + addv(x2, mul(dt, v2)), V(nx, 'x1') + V(nx, 'x2'), 1.0, where)
            m = case['material']
            if law == 'cohfrict':
                E, nu = m['young'], m['poisson']
                kn = 2.0 * E * r1 * E * r2 / (E * r1 + E * r2)
                ks = 2.0 * E * r1 * nu * E * r2 * nu / (E * r1 * nu + E * r2 * nu)
                aKr = 2.0 * m['alphaKr'] * m['alphaKr'] / (m['alphaKr'] + m['alphaKr'])
                aKtw = 2.0 * m['alphaKtw'] * m['alphaKtw'] / (m['alphaKtw'] + m['alphaKtw'])
                exp = [kn, ks, r1 * r2 * ks * aKr, r1 * r2 * ks * aKtw, math.tan(m['frictionAngle']),
                       min(m['etaRoll'] * r1, m['etaRoll'] * r2), min(m['etaTwist'] * r1, m['etaTwist'] * r2)]
                got = [float(r[c]) for c in ('param_kn', 'param_ks', 'param_kr', 'param_ktw', 'param_tanphi',
                                             'param_maxroll', 'param_maxtwist')]
                for g, e in zip(got, exp):
                    C['cparams'].add([g], [e], abs(e), where)
                tmax = float(r['param_maxtwist']) * norm(fn)
                if norm(mt) > tmax:
                    C['tlim'].add([norm(mt)], [tmax], tmax, where)
            else:
                p = case['ip2']
                exp = [p['krot'], p['ktwist'], p['eta'] * (r1 + r2) / 2.0]
                got = [float(r['param_kr']), float(r['param_ktw']), float(r['param_maxroll'])]
                for g, e in zip(got, exp):
                    C['mparams'].add([g], [e], abs(e), where)
                twist_unbounded[name] = max(twist_unbounded.get(name, 0.0), norm(mt) / (norm(fn) * min(r1, r2)))
            rmax = float(r['param_maxroll']) * norm(fn)
            if norm(mb) > rmax:
                C['rlim'].add([norm(mb)], [rmax], rmax, where)
            smax = float(r['param_tanphi']) * norm(fn)
            if norm(fs) > smax:
                C['slim'].add([norm(fs)], [smax], smax, where)
            # hold segment: last segment of load/reverse/hold cases has no motion
            segs = case['segments']
            if len(segs[-1]) == 1 and k > len(rs) - segs[-1]['steps']:
                pr = rs[k - 1]
                C['hold'].add(fs + mb + mt, V(pr, 'fs') + V(pr, 'mb') + V(pr, 'mt'), max(scl['fs'], scl['mb'], scl['mt'], 1e-300), where)
            if k == 0:
                rw = sub(w2, w1)
                rwn = dot(n, rw)
                exp_mb = mul(-float(r['param_kr']), mul(dt, sub(rw, mul(rwn, n))))
                exp_mt = mul(-float(r['param_ktw']), mul(dt, mul(rwn, n)))
                ks_now = float(r['ks'])
                C['first'].add(exp_mb + exp_mt + mul(-ks_now, V(r, 'shearinc')), mb + mt + fs,
                               max(scl['mb'], scl['mt'], scl['fs'], 1e-300), where)
            # our sliding velocity (midplane branches) vs -incidentVel_t
            l1, l2 = r1 - pen / 2, r2 - pen / 2
            dv = sub(v2, v1)
            vs = addv(mul(-1, sub(dv, mul(dot(dv, n), n))), cross(addv(mul(l1, w1), mul(l2, w2)), n))
            ivt = sub(ivr, mul(dot(ivr, n), n))
            dev = norm(addv(vs, ivt))
            ref = norm(dv) + r1 * norm(w1) + r2 * norm(w2)
            if ref > 0:
                slide_vs_ours[name] = max(slide_vs_ours.get(name, (0, 0))[0], dev / ref), pen / min(r1, r2)
    ok = all([c.report() for c in C.values()])
    print('Mindlin twisting moment without limit: max |M_t|/(|F_n| min R) per case:',
          ', '.join('%s %.3g' % kv for kv in sorted(twist_unbounded.items())))
    print('our v_s (midplane arms) vs -incidentVel_t: max |v_s + incvel_t|/(|v2-v1| + R1|w1| + R2|w2|) per case '
          '(delta/min R in brackets):')
    for k, (dv, dr) in sorted(slide_vs_ours.items()):
        print('   %-18s %.3g  [%.1e]' % (k, dv, dr))
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
