#!/usr/bin/env python3
"""Independent re-implementation of the LAMMPS 2021 pair granular tangential,
rolling (sds) and twisting (sds / marshall) laws as described in
shared/spec/peers.md, replayed on the positions/velocities of
lammps_reference.csv; prints the worst relative mismatch per case.

Options (to test the alternative readings of the code):
  --frame gt|lt|never   history re-projection when |xi.n| k >(gt, peers.md) / <(lt) 1e-10 mu Fncrit
  --setup-update        update the history at step 0 as well (default: no update at step 0)
  --twist-sign-trial    twisting clip keeps the sign of the trial moment (default: -sign(Omega))
  --fncrit-elastic      friction limits use the elastic normal force only (default: |F_n| with damping)
  --setup-no-clip-store the twisting clip at step 0 does not write the history (default: it does)
"""
import csv
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
FRAME = "gt"
for i, a in enumerate(sys.argv):
    if a == "--frame":
        FRAME = sys.argv[i + 1]
SETUP_UPDATE = "--setup-update" in sys.argv
SETUP_NO_CLIP_STORE = "--setup-no-clip-store" in sys.argv
TWIST_SIGN_TRIAL = "--twist-sign-trial" in sys.argv
FNCRIT_ELASTIC = "--fncrit-elastic" in sys.argv
EPS = 1e-10


def sub(a, b): return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
def add(a, b): return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
def mul(s, a): return [s * a[0], s * a[1], s * a[2]]
def dot(a, b): return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
def cross(a, b): return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
def norm(a): return math.sqrt(dot(a, a))


def reproject(h, n, k, crit):
    rs = dot(h, n)
    if FRAME == "never":
        return h
    do = abs(rs) * k > EPS * crit if FRAME == "gt" else abs(rs) * k < EPS * crit
    if not do:
        return h
    mag = norm(h)
    h = sub(h, mul(rs, n))
    p = norm(h)
    return mul(mag / p if p > 0 else 0.0, h)


def spring(h, v, k, g, crit, update, n, dt):
    if update:
        h = reproject(h, n, k, crit)
        h = add(h, mul(dt, v))
    f = sub(mul(-k, h), mul(g, v))
    fm = norm(f)
    if fm > crit:
        if norm(h) != 0.0:
            h = mul(-1.0 / k, add(mul(crit / fm, f), mul(g, v)))
            f = mul(crit / fm, f)
        else:
            f = [0.0, 0.0, 0.0]
    return h, f


def run_case(rows, P):
    law = P["law"]
    dt = P["dt"]
    hs = [0.0] * 3
    hr = [0.0] * 3
    ht = 0.0
    worst = 0.0
    worst_at = None
    for r in rows:
        step = int(r["step"])
        g = lambda *k: [float(r[x]) for x in k]
        x1, x2 = g("x1", "y1", "z1"), g("x2", "y2", "z2")
        v1, v2 = g("v1x", "v1y", "v1z"), g("v2x", "v2y", "v2z")
        w1, w2 = g("w1x", "w1y", "w1z"), g("w2x", "w2y", "w2z")
        Ri, Rj = float(r["r1"]), float(r["r2"])
        mi, mj = float(r["m1"]), float(r["m2"])
        d = sub(x1, x2)
        rr = norm(d)
        if rr >= Ri + Rj:
            hs, hr, ht = [0.0] * 3, [0.0] * 3, 0.0
            continue
        n = mul(1.0 / rr, d)
        delta = Ri + Rj - rr
        Reff = Ri * Rj / (Ri + Rj)
        vr = sub(v1, v2)
        vnn = dot(vr, n)
        vt = sub(vr, mul(vnn, n))
        meff = mi * mj / (mi + mj)
        a = math.sqrt(delta * Reff)
        if law["normal"] == "hooke":
            Fne = law["kn"] * delta
        else:
            Estar = law["E"] / (2 * (1 - law["poisson"] ** 2))
            Fne = 4.0 / 3.0 * Estar * delta * a
        damp = 1.0 if law["damping"] == "velocity" else a * meff
        pref = law["eta_n"] * damp
        Fn = Fne - pref * vnn
        Fncrit = abs(Fne) if FNCRIT_ELASTIC else abs(Fn)
        wr = add(mul(Ri, w1), mul(Rj, w2))
        vtr = add(vt, cross(n, wr))
        kt = law["kt"]
        gt = law["xgammat"] * pref
        update = step > 0 or SETUP_UPDATE
        hs, fs = spring(hs, vtr, kt, gt, law["mu_s"] * Fncrit, update, n, dt)
        relrot = sub(w1, w2)
        vrl = mul(Reff, cross(relrot, n))
        hr, fr = spring(hr, vrl, law["kr"], law["gr"], law["mu_r"] * Fncrit, update, n, dt)
        om = dot(relrot, n)
        if law["twist"] == "marshall":
            ktw, gtw, mutw = 0.5 * kt * a * a, 0.5 * gt * a * a, 2.0 / 3.0 * a * law["mu_s"]
        else:
            ktw, gtw, mutw = law["ktw"], law["gtw"], law["mu_tw"]
        if update:
            ht += om * dt
        M = -ktw * ht - gtw * om
        sgn = (om > 0) - (om < 0)
        if TWIST_SIGN_TRIAL:
            sgn = -((M > 0) - (M < 0))
        Mc = mutw * Fncrit
        if abs(M) > Mc:
            if update or not SETUP_NO_CLIP_STORE:
                ht = (Mc * sgn - gtw * om) / ktw
            M = -Mc * sgn
        f1 = add(mul(Fn, n), fs)
        ncf = cross(n, fs)
        t1 = add(add(mul(-(Ri - 0.5 * delta), ncf), mul(M, n)), mul(Reff, cross(n, fr)))
        t2 = sub(sub(mul(-(Rj - 0.5 * delta), ncf), mul(M, n)), mul(Reff, cross(n, fr)))
        got = g("f1x", "f1y", "f1z") + g("t1x", "t1y", "t1z") + g("f2x", "f2y", "f2z") + g("t2x", "t2y", "t2z")
        want = f1 + t1 + mul(-1, f1) + t2
        scale = max(1e-300, max(abs(x) for x in got + want), Fncrit)
        err = max(abs(p - q) for p, q in zip(got, want)) / scale
        if err > worst:
            worst, worst_at = err, step
    return worst, worst_at


def main():
    path = os.path.join(HERE, "lammps_reference.csv")
    by = {}
    with open(path) as fh:
        for r in csv.DictReader(fh):
            by.setdefault(r["case"], []).append(r)
    bad = 0
    for case, rows in by.items():
        P = json.load(open(os.path.join(HERE, "params", case + ".json")))
        w, at = run_case(rows, P)
        flag = "OK " if w < 1e-9 else "BAD"
        bad += w >= 1e-9
        print("%s %-28s worst rel err %.3e at step %s" % (flag, case, w, at))
    return bad


if __name__ == "__main__":
    sys.exit(1 if main() else 0)
