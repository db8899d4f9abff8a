#!/usr/bin/env python3
"""Independent re-implementation of the LAMMPS 2021 pair granular tangential,
rolling (sds) and twisting (sds / marshall) laws as LAMMPS 20220106's
pair_granular.cpp computes them (docs/laws.md, LAMMPS_2021 preset), with the normal models hooke, hertz/material, jkr and dmt,
replayed on the positions/velocities of lammps_reference.csv; prints the worst
relative mismatch per case. For jkr and dmt it also compares its own normal force
and friction-limit force with the CSV's `fn_signed` and `fn` (written by
gen_lammps.py from LAMMPS' formulas), and counts the rows where each law is at its
limit, and those of them under tension.

Options (to test the alternative readings of the code):
  --frame gt|lt|never   history re-projection when |xi.n| k >(gt, peers.md) / <(lt) 1e-10 mu Fncrit
  --setup-update        update the history at step 0 as well (default: no update at step 0)
  --twist-sign-trial    twisting clip keeps the sign of the trial moment (default: -sign(Omega))
  --fncrit-elastic      friction limits use the elastic normal force only (default: |F_n| with damping)
  --setup-no-clip-store the twisting clip at step 0 does not write the history (default: it does)
  --fncrit-total        jkr/dmt limits use |F_n| with damping, as the other normal models
  --dmt-pulloff         dmt limits use |F_ne + 2 F_pulloff|, F_pulloff = 4 pi cohesion Reff
                        (the source's formula; default |F_ne|, what this build computes)
  --jkr-overlap-contact a jkr contact ends when the overlap reaches 0 (default: LAMMPS keeps
                        a touching pair until the overlap falls below its pull-off overlap)
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
FNCRIT_TOTAL = "--fncrit-total" in sys.argv
DMT_PULLOFF = "--dmt-pulloff" in sys.argv
JKR_OVERLAP_CONTACT = "--jkr-overlap-contact" in sys.argv
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


def estar(law):
    """Effective modulus of one material, E* = E / (2 (1 - nu^2))."""
    return law["E"] / (2 * (1 - law["poisson"] ** 2))


def jkr_overlap(a, R, Es, w):
    """JKR overlap at contact radius a, work of adhesion w: a^2/R - sqrt(2 pi w a / E*)."""
    return a * a / R - math.sqrt(2 * math.pi * w * a / Es)


def jkr_contact_radius(delta, R, Es, w):
    """The contact radius on the stable branch (a above the minimum of jkr_overlap), by
    bisection to the last bit."""
    lo = (math.pi * w * R * R / (8 * Es)) ** (1.0 / 3.0)   # d overlap / da = 0 there
    hi = 2 * lo
    while jkr_overlap(hi, R, Es, w) < delta:
        hi *= 2
    while True:
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            return hi
        if jkr_overlap(mid, R, Es, w) < delta:
            lo = mid
        else:
            hi = mid


def cohesive_normal(law, delta, R):
    """(elastic normal force, contact radius, Fncrit from the elastic force) of jkr / dmt.
    LAMMPS' `cohesion` is half the work of adhesion w: its JKR force is
    4 E* a^3/(3R) - sqrt(8 pi w E* a^3) with w = 2 cohesion, its pull-off force
    3 pi cohesion R; DMT: 4/3 E* sqrt(R) delta^1.5 - 4 pi cohesion R."""
    Es = estar(law)
    coh = law["cohesion"]
    if law["normal"] == "jkr":
        a = jkr_contact_radius(delta, R, Es, 2 * coh)
        Fne = 4 * Es * a ** 3 / (3 * R) - math.sqrt(16 * math.pi * coh * Es * a ** 3)
        crit = abs(Fne + 6 * math.pi * coh * R)
    else:
        a = math.sqrt(delta * R)
        Fne = 4.0 / 3.0 * Es * delta * a - 4 * math.pi * coh * R
        crit = abs(Fne + 8 * math.pi * coh * R) if DMT_PULLOFF else abs(Fne)
    return Fne, a, crit


def jkr_pulloff_overlap(law, R):
    """Overlap at which a touching JKR pair separates in LAMMPS: jkr_overlap at the
    contact radius a0, a0^3 = 9 pi w R^2 / (8 E*)."""
    Es, w = estar(law), 2 * law["cohesion"]
    a0 = (9 * math.pi * w * R * R / (8 * Es)) ** (1.0 / 3.0)
    return jkr_overlap(a0, R, Es, w)


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
    cohesive = law["normal"] in ("jkr", "dmt")
    touching = False
    fn_err = 0.0          # own F_n and Fncrit against the CSV's, relative to the case's scale
    case_scale = max(abs(float(r[k])) for r in rows for k in ("fn", "f1x", "f1y", "f1z"))
    slips = [0, 0, 0]     # rows at the sliding, rolling, twisting limit
    tensile_slips = [0, 0, 0]
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
        delta = Ri + Rj - rr
        Reff = Ri * Rj / (Ri + Rj)
        if law["normal"] == "jkr" and touching and not JKR_OVERLAP_CONTACT:
            touching = delta > jkr_pulloff_overlap(law, Reff)
        else:
            touching = rr < Ri + Rj
        if not touching:
            hs, hr, ht = [0.0] * 3, [0.0] * 3, 0.0
            if cohesive:   # LAMMPS must apply nothing
                loads = g("f1x", "f1y", "f1z", "t1x", "t1y", "t1z", "f2x", "f2y", "f2z", "t2x", "t2y", "t2z")
                err = max(abs(x) for x in loads) / case_scale
                if err > worst:
                    worst, worst_at = err, step
            continue
        n = mul(1.0 / rr, d)
        vr = sub(v1, v2)
        vnn = dot(vr, n)
        vt = sub(vr, mul(vnn, n))
        meff = mi * mj / (mi + mj)
        if law["normal"] == "hooke":
            a = math.sqrt(delta * Reff)
            Fne = law["kn"] * delta
        elif cohesive:
            Fne, a, crit = cohesive_normal(law, delta, Reff)
        else:
            a = math.sqrt(delta * Reff)
            Estar = law["E"] / (2 * (1 - law["poisson"] ** 2))
            Fne = 4.0 / 3.0 * Estar * delta * a
        damp = 1.0 if law["damping"] == "velocity" else a * meff
        pref = law["eta_n"] * damp
        Fn = Fne - pref * vnn
        if FNCRIT_ELASTIC:
            Fncrit = abs(Fne)
        elif cohesive and not FNCRIT_TOTAL:
            Fncrit = crit
        else:
            Fncrit = abs(Fn)
        if cohesive:
            fn_err = max(fn_err, abs(Fn - float(r["fn_signed"])) / case_scale,
                         abs(Fncrit - float(r["fn"])) / case_scale)
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
        at_limit = [norm(fs) >= (1 - 1e-12) * law["mu_s"] * Fncrit,
                    norm(fr) >= (1 - 1e-12) * law["mu_r"] * Fncrit,
                    abs(M) > Mc]
        for k in range(3):
            slips[k] += at_limit[k]
            tensile_slips[k] += at_limit[k] and Fn < 0
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
    extra = ""
    if cohesive:
        extra = ("; own F_n, Fncrit vs CSV %.1e; at the limit (sliding, rolling, twisting) %s rows, "
                 "%s of them tensile" % (fn_err, slips, tensile_slips))
    return worst, worst_at, fn_err, extra


def main():
    path = os.path.join(HERE, "lammps_reference.csv")
    by = {}
    with open(path) as fh:
        for r in csv.DictReader(fh):
            by.setdefault(r["case"], []).append(r)
    bad = 0
    for case, rows in by.items():
        P = json.load(open(os.path.join(HERE, "params", case + ".json")))
        w, at, fn_err, extra = run_case(rows, P)
        ok = w < 1e-9 and fn_err < 1e-13
        flag = "OK " if ok else "BAD"
        bad += not ok
        print("%s %-28s worst rel err %.3e at step %s%s" % (flag, case, w, at, extra))
    return bad


if __name__ == "__main__":
    sys.exit(1 if main() else 0)
