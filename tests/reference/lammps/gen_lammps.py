#!/usr/bin/env python3
"""Generate LAMMPS (Debian lammps 20220106 = 29 Sep 2021 update 2) reference data
for two spheres in contact under imposed motion.

Usage: python3 gen_lammps.py [--lmp lmp] [--keep]

Writes, next to this script:
  inputs/in.<case>          the exact LAMMPS input scripts that were run
  inputs/motion_<case>.txt  the imposed motion table read by the inputs
  params/<case>.json        every parameter of the case
  lammps_reference.csv      one row per (case, step)

Motion is imposed by a Python function (LAMMPS PYTHON package, `fix python/invoke
... end_of_step`) that, at the end of step k, overwrites x, v and omega of both
atoms with row k+1 of the motion table.  No integrator fix is defined, so the
pair forces never feed back on the motion.  The motion table is built here:
positions advance as x_{k+1} = x_k + dt*v_{k+1} (IEEE double, same expression
as fix nve/noforce) except in the rigid-rotation phase, where
x_k = c + Rot(W (t_k - t_0)) (x_{k0} - c) exactly (Rodrigues formula) and
v = W x (x - c), omega1 = omega2 = W.
"""
import json
import math
import os
import random
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
LMP = "lmp"
for i, a in enumerate(sys.argv):
    if a == "--lmp":
        LMP = sys.argv[i + 1]
KEEP = "--keep" in sys.argv

# ---------------------------------------------------------------- vectors
def add(a, b): return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
def sub(a, b): return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
def mul(s, a): return [s * a[0], s * a[1], s * a[2]]
def dot(a, b): return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
def cross(a, b): return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
def norm(a): return math.sqrt(dot(a, a))
def unit(a): return mul(1.0 / norm(a), a)

def rodrigues(axis, ang, v):
    k = unit(axis)
    c, s = math.cos(ang), math.sin(ang)
    return add(add(mul(c, v), mul(s, cross(k, v))), mul((1 - c) * dot(k, v), k))

# library normal (1 -> 2) and a tangent basis, all exactly unit in decimal
U = [0.36, -0.48, 0.8]
E1 = [0.8, 0.6, 0.0]
E2 = cross(U, E1)          # (-0.48, 0.64, 0.6)
X1_0 = [0.1, -0.2, 0.3]
DT = 1.0e-3
DENSITY = 1.0

# ---------------------------------------------------------------- parameter sets
SETS = {
    "sds": dict(
        normal="hooke", kn=1.0e4, eta_n=50.0, damping="velocity",
        kt=8000.0, xgammat=0.5, mu_s=0.5,
        kr=4000.0, gr=40.0, mu_r=0.1,
        twist="sds", ktw=200.0, gtw=2.0, mu_tw=0.05,
        pair_coeff="hooke 10000.0 50.0 damping velocity tangential linear_history 8000.0 0.5 0.5 "
                   "rolling sds 4000.0 40.0 0.1 twisting sds 200.0 2.0 0.05"),
    "marshall": dict(
        normal="hertz/material", E=1.0e6, eta_n=1000.0, poisson=0.3, damping="viscoelastic (default)",
        kt=8000.0, xgammat=0.5, mu_s=0.5,
        kr=4000.0, gr=40.0, mu_r=0.1,
        twist="marshall",
        pair_coeff="hertz/material 1000000.0 1000.0 0.3 tangential linear_history 8000.0 0.5 0.5 "
                   "rolling sds 4000.0 40.0 0.1 twisting marshall"),
    # cohesive normal models: the friction limits use LAMMPS' Fncrit, not |Fntot| (see
    # lammps_normal below and README.md)
    "jkr": dict(
        normal="jkr", E=1.0e6, eta_n=50.0, poisson=0.3, cohesion=50.0, damping="velocity",
        kt=8000.0, xgammat=0.5, mu_s=0.5,
        kr=4000.0, gr=40.0, mu_r=0.1,
        twist="sds", ktw=200.0, gtw=2.0, mu_tw=0.05,
        fncrit="|Fne + 2 F_pulloff|, F_pulloff = 3 pi cohesion Reff (Fne: JKR elastic force, no damping)",
        pair_coeff="jkr 1000000.0 50.0 0.3 50.0 damping velocity tangential linear_history 8000.0 0.5 0.5 "
                   "rolling sds 4000.0 40.0 0.1 twisting sds 200.0 2.0 0.05"),
    "dmt": dict(
        normal="dmt", E=1.0e6, eta_n=1000.0, poisson=0.3, cohesion=50.0, damping="viscoelastic (default)",
        kt=8000.0, xgammat=0.5, mu_s=0.5,
        kr=4000.0, gr=40.0, mu_r=0.1,
        twist="sds", ktw=200.0, gtw=2.0, mu_tw=0.05,
        fncrit="|Fne| (Fne = (4/3) E* delta a - 4 pi cohesion Reff, no damping): the source's "
               "F_pulloff = 4 pi coh Reff reads a variable only the JKR branches assign; this "
               "build behaves as coh = 0 there",
        pair_coeff="dmt 1000000.0 1000.0 0.3 50.0 tangential linear_history 8000.0 0.5 0.5 "
                   "rolling sds 4000.0 40.0 0.1 twisting sds 200.0 2.0 0.05"),
}

def fn_estimate(P, R1, R2, delta):
    reff = R1 * R2 / (R1 + R2)
    if P["normal"] == "hooke":
        return P["kn"] * delta
    estar = P["E"] / (2 * (1 - P["poisson"] ** 2))
    return 4.0 / 3.0 * estar * math.sqrt(reff * delta) * delta

def twist_params(P, R1, R2, delta):
    if P["twist"] == "sds":
        return P["ktw"], P["mu_tw"]
    reff = R1 * R2 / (R1 + R2)
    a = math.sqrt(reff * delta)
    return 0.5 * P["kt"] * a * a, 2.0 / 3.0 * a * P["mu_s"]

# ---------------------------------------------------------------- LAMMPS' cohesive normal forces
# The values LAMMPS 29 Sep 2021 computes in PairGranular::compute() for `jkr` and `dmt`, with
# its operations in its order (IEEE double; Python evaluates a*b*c left to right as C does), so
# that Fntot is LAMMPS' bit for bit (asserted against compute pair/local below).
M_PI = 3.14159265358979323846
PI27SQ = 266.47931882941264802866    # 27 pi^2
THREEROOT3 = 5.19615242270663202362  # 3 sqrt(3)
SIXROOT6 = 14.69693845669906728801   # 6 sqrt(6)
INVROOT6 = 0.40824829046386307274    # 1/sqrt(6)

def c_max0(x):
    """C's MAX(0, x) macro: (0 > x ? 0 : x)."""
    return 0.0 if 0 > x else x

def normal_coeff0(P):
    """pair_coeff stores (4/3) E* for hertz/material, dmt, jkr; E* = 1/(2 (1 - nu^2)/E)."""
    nu, E = P["poisson"], P["E"]
    return (4.0 / 3.0) * (1 / ((1 - nu * nu) / E + (1 - nu * nu) / E))

def jkr_pulloff_distance(P, radsum, Reff):
    """compute(): a touching JKR pair stays in contact while rsq < dist_pulloff^2."""
    E = normal_coeff0(P) * 0.75
    coh = P["cohesion"]
    a = math.cbrt(9.0 * M_PI * coh * (Reff * Reff) / (4 * E))
    delta_pulloff = a * a / Reff - 2 * math.sqrt(M_PI * coh * a / E)
    return radsum - delta_pulloff

def lammps_normal(P, radi, radj, mi, mj, x1, x2, v1, v2):
    """(Fne, Fntot, Fncrit, a) of compute() for the pair (i, j) = (atom 1, atom 2) in contact."""
    delx, dely, delz = x1[0] - x2[0], x1[1] - x2[1], x1[2] - x2[2]
    rsq = delx * delx + dely * dely + delz * delz
    radsum = radi + radj
    Reff = radi * radj / radsum
    r = math.sqrt(rsq)
    rinv = 1.0 / r
    nx, ny, nz = delx * rinv, dely * rinv, delz * rinv
    vnnr = (v1[0] - v2[0]) * nx + (v1[1] - v2[1]) * ny + (v1[2] - v2[2]) * nz
    meff = mi * mj / (mi + mj)
    delta = radsum - r
    dR = delta * Reff
    coh = P["cohesion"]
    if P["normal"] == "jkr":
        E = normal_coeff0(P) * 0.75
        R2 = Reff * Reff
        dR2 = dR * dR
        t0 = coh * coh * R2 * R2 * E
        t1 = PI27SQ * t0
        t2 = 8 * dR * dR2 * E * E * E
        t3 = 4 * dR2 * E
        sqrt1 = c_max0(t0 * (t1 + 2 * t2))
        t4 = math.cbrt(t1 + t2 + THREEROOT3 * M_PI * math.sqrt(sqrt1))
        t5 = t3 / t4 + t4 / E
        sqrt2 = c_max0(2 * dR + t5)
        t6 = math.sqrt(sqrt2)
        sqrt3 = c_max0(4 * dR - t5 + SIXROOT6 * coh * M_PI * R2 / (E * t6))
        a = INVROOT6 * (t6 + math.sqrt(sqrt3))
        a2 = a * a
        knfac = normal_coeff0(P) * a
        Fne = knfac * a2 / Reff - (2 * M_PI) * a2 * math.sqrt(4 * coh * E / (M_PI * a))
        Fncrit = abs(Fne + 2 * (3 * M_PI * coh * Reff))
    else:  # dmt
        Fne = normal_coeff0(P) * delta
        a = math.sqrt(dR)
        Fne *= a
        Fne -= 4 * M_PI * coh * Reff
        # |Fne + 2 F_pulloff| with F_pulloff = 4 pi coh Reff, where this build's coh is 0
        Fncrit = abs(Fne + 2 * (4 * M_PI * 0.0 * Reff))
    damp = 1 if P["damping"] == "velocity" else a * meff
    Fdamp = -(P["eta_n"] * damp) * vnnr
    return Fne, Fne + Fdamp, Fncrit, a

def fncrit_at(P, R1, R2, delta):
    """LAMMPS' Fncrit at overlap delta and rest (scales the rates of the cohesive cases)."""
    x2 = mul(R1 + R2 - delta, U)
    return lammps_normal(P, R1, R2, 1.0, 1.0, [0.0] * 3, x2, [0.0] * 3, [0.0] * 3)[2]

# ---------------------------------------------------------------- motion tables
class Motion:
    """rows[k] = (x1, x2, v1, v2, w1, w2) seen by the pair at step k."""
    def __init__(self, R1, R2, delta0):
        self.R1, self.R2 = R1, R2
        x1 = list(X1_0)
        x2 = add(x1, mul(R1 + R2 - delta0, U))
        self.rows = [(x1, x2, [0.0] * 3, [0.0] * 3, [0.0] * 3, [0.0] * 3)]

    def set0(self, v1, v2, w1, w2):
        x1, x2 = self.rows[0][0], self.rows[0][1]
        self.rows[0] = (x1, x2, list(v1), list(v2), list(w1), list(w2))

    def step(self, v1, v2, w1, w2):
        x1, x2 = self.rows[-1][0], self.rows[-1][1]
        nx1 = [x1[d] + DT * v1[d] for d in range(3)]
        nx2 = [x2[d] + DT * v2[d] for d in range(3)]
        self.rows.append((nx1, nx2, list(v1), list(v2), list(w1), list(w2)))

    def steps(self, n, v1, v2, w1, w2):
        for _ in range(n):
            self.step(v1, v2, w1, w2)

    def rigid(self, n, W):
        k0 = len(self.rows) - 1
        x1, x2 = self.rows[k0][0], self.rows[k0][1]
        c = mul(0.5, add(x1, x2))
        d1, d2 = sub(x1, c), sub(x2, c)
        wm = norm(W)
        for k in range(1, n + 1):
            ang = wm * DT * k
            y1 = add(c, rodrigues(W, ang, d1))
            y2 = add(c, rodrigues(W, ang, d2))
            self.rows.append((y1, y2, cross(W, sub(y1, c)), cross(W, sub(y2, c)), list(W), list(W)))

    def write(self, path):
        with open(path, "w") as f:
            f.write("# step x1 y1 z1 x2 y2 z2 v1x v1y v1z v2x v2y v2z w1x w1y w1z w2x w2y w2z\n")
            for k, r in enumerate(self.rows):
                vals = [repr(float(c)) for vec in r for c in vec]
                f.write("%d %s\n" % (k, " ".join(vals)))


def case_gear(P, R1, R2, delta, nsteps, t_el=100):
    """gear-like rolling at fixed centres: R1 w1 + R2 w2 = 0 -> no sliding."""
    reff = R1 * R2 / (R1 + R2)
    fn = fn_estimate(P, R1, R2, delta)
    xi_lim = P["mu_r"] * fn / P["kr"]
    vrl = xi_lim / (t_el * DT)            # reach the limit after ~t_el steps
    # |relrot| = vrl/reff; relrot = w1 - w2 = s e1 (1 + R1/R2)
    s = vrl / reff / (1.0 + R1 / R2)
    w1 = mul(s, E1)
    w2 = mul(-(R1 / R2) * s, E1)
    m = Motion(R1, R2, delta)
    m.set0([0.0] * 3, [0.0] * 3, w1, w2)
    m.steps(nsteps, [0.0] * 3, [0.0] * 3, w1, w2)
    return m, dict(s=s, w1=w1, w2=w2)


def case_reverse(P, R1, R2, delta, t_el=80):
    """load (roll +) 150 steps, reverse (roll -) 150 steps, then normal unloading
    while rolling stops: atom 2 moves away along U until contact is lost."""
    reff = R1 * R2 / (R1 + R2)
    fn = fn_estimate(P, R1, R2, delta)
    vrl = P["mu_r"] * fn / P["kr"] / (t_el * DT)
    s = vrl / reff / (1.0 + R1 / R2)
    w1 = mul(s, E1); w2 = mul(-(R1 / R2) * s, E1)
    z = [0.0] * 3
    m = Motion(R1, R2, delta)
    m.set0(z, z, w1, w2)
    m.steps(150, z, z, w1, w2)
    m.steps(150, z, z, mul(-1, w1), mul(-1, w2))
    vsep = (delta * 1.1) / (110 * DT)      # separate over ~110 steps
    m.steps(120, z, mul(vsep, U), mul(0.3, w1), mul(0.3, w2))
    return m, dict(s=s, vsep=vsep)


def case_slide(P, R1, R2, delta, t_el=60):
    """pure sliding at fixed centres: w1 = w2 = w e2 (relrot = 0)."""
    fn = fn_estimate(P, R1, R2, delta)
    xi_lim = P["mu_s"] * fn / P["kt"]
    vt = xi_lim / (t_el * DT)
    w = vt / (R1 + R2)
    z = [0.0] * 3
    m = Motion(R1, R2, delta)
    m.set0(z, z, mul(w, E2), mul(w, E2))
    m.steps(200, z, z, mul(w, E2), mul(w, E2))
    m.steps(100, z, z, mul(-w, E2), mul(-w, E2))
    return m, dict(w=w)


def case_twist(P, R1, R2, delta, t_el=80):
    """pure twisting: w1 = +O/2 U, w2 = -O/2 U, elastic -> plastic -> reverse."""
    fn = fn_estimate(P, R1, R2, delta)
    ktw, mutw = twist_params(P, R1, R2, delta)
    th = mutw * fn / ktw
    om = th / (t_el * DT)
    z = [0.0] * 3
    m = Motion(R1, R2, delta)
    m.set0(z, z, mul(0.5 * om, U), mul(-0.5 * om, U))
    m.steps(180, z, z, mul(0.5 * om, U), mul(-0.5 * om, U))
    m.steps(120, z, z, mul(-0.5 * om, U), mul(0.5 * om, U))
    return m, dict(omega_twist=om)


def case_twist_unload(P, R1, R2, delta, t_el=60):
    """twist into the plastic range, then stop twisting (Omega = 0) while the
    normal force is reduced (atom 2 moves away along U), then twist back slowly
    while still unloading: tests the sign used by the twisting clip."""
    fn = fn_estimate(P, R1, R2, delta)
    ktw, mutw = twist_params(P, R1, R2, delta)
    om = mutw * fn / ktw / (t_el * DT)
    z = [0.0] * 3
    m = Motion(R1, R2, delta)
    m.set0(z, z, mul(0.5 * om, U), mul(-0.5 * om, U))
    m.steps(100, z, z, mul(0.5 * om, U), mul(-0.5 * om, U))
    vsep = 0.5 * delta / (100 * DT)
    m.steps(50, z, mul(vsep, U), z, z)
    m.steps(50, z, mul(vsep, U), mul(-0.02 * om, U), mul(0.02 * om, U))
    return m, dict(omega_twist=om, vsep=vsep)


def case_rigid(P, R1, R2, delta, npre=100, nrot=300):
    """preload sliding, rolling and twisting springs (elastic, fixed centres),
    then rotate the overlapping pair rigidly by 90 deg about W ~ (1,0,1)."""
    reff = R1 * R2 / (R1 + R2)
    fn = fn_estimate(P, R1, R2, delta)
    ktw, mutw = twist_params(P, R1, R2, delta)
    # target ~50% of each limit after npre steps
    vrl = 0.5 * P["mu_r"] * fn / P["kr"] / (npre * DT)
    vt = 0.5 * P["mu_s"] * fn / P["kt"] / (npre * DT)
    om = 0.5 * mutw * fn / ktw / (npre * DT)
    # relrot = w1 - w2 = (vrl/reff) e1 + om U ; R1 w1 + R2 w2 (tangent) gives sliding along e1 x ...
    rr = add(mul(vrl / reff, E1), mul(om, U))
    # choose w2 such that R1 w1 + R2 w2 = (vt/(R1+R2))*(R1+R2) e2 ... solve: w1 = w2 + rr
    # R1 (w2 + rr) + R2 w2 = S  -> w2 = (S - R1 rr)/(R1 + R2)
    S = mul(vt, E2)
    w2 = mul(1.0 / (R1 + R2), sub(S, mul(R1, rr)))
    w1 = add(w2, rr)
    z = [0.0] * 3
    m = Motion(R1, R2, delta)
    m.set0(z, z, w1, w2)
    m.steps(npre, z, z, w1, w2)
    Wdir = unit([1.0, 0.0, 1.0])
    Wmag = (math.pi / 2) / (nrot * DT)
    m.rigid(nrot, mul(Wmag, Wdir))
    return m, dict(w1_pre=w1, w2_pre=w2, W=mul(Wmag, Wdir))


def case_random(P, R1, R2, delta, seed, nseg=20, seglen=20):
    """general motion: piecewise-constant random v and omega on 20-step segments;
    the normal relative velocity is steered to keep the overlap in a band."""
    rng = random.Random(seed)
    fn = fn_estimate(P, R1, R2, delta)
    reff = R1 * R2 / (R1 + R2)
    vt = 0.6 * P["mu_s"] * fn / P["kt"] / (15 * DT)     # sliding rate scale
    wr = 0.6 * P["mu_r"] * fn / P["kr"] / (15 * DT) / reff
    m = Motion(R1, R2, delta)
    def rv(scale):
        return [scale * (2 * rng.random() - 1) for _ in range(3)]
    first = True
    for seg in range(nseg):
        x1, x2 = m.rows[-1][0], m.rows[-1][1]
        d = sub(x2, x1)
        r = norm(d)
        u = mul(1.0 / r, d)
        dcur = R1 + R2 - r
        dtarget = delta * (0.5 + rng.random())
        vn = (dcur - dtarget) / (seglen * DT)   # relative normal speed (2 away from 1)
        v1 = rv(vt)
        v2 = add(v1, rv(vt))
        v2 = add(v2, mul(vn - dot(sub(v2, v1), u), u))
        w1 = rv(wr)
        w2 = rv(wr)
        if first:
            m.set0(v1, v2, w1, w2)
            first = False
        m.steps(seglen, v1, v2, w1, w2)
    return m, dict(seed=seed, nseg=nseg, seglen=seglen)


def case_setup_clip(P, R1, R2, delta):
    """large rates from step 0 so that the dashpot alone exceeds every limit at
    setup (history still zero): shows what the setup call does."""
    reff = R1 * R2 / (R1 + R2)
    fn = fn_estimate(P, R1, R2, delta)
    ktw, mutw = twist_params(P, R1, R2, delta)
    # make |gamma * rate| = 3 x limit for each law
    damp_t = P["xgammat"] * P["eta_n"]
    vt = 3 * P["mu_s"] * fn / damp_t
    vrl = 3 * P["mu_r"] * fn / P["gr"]
    om = 3 * mutw * fn / P["gtw"]
    rr = add(mul(vrl / reff, E1), mul(om, U))
    S = mul(vt, E2)
    w2 = mul(1.0 / (R1 + R2), sub(S, mul(R1, rr)))
    w1 = add(w2, rr)
    z = [0.0] * 3
    m = Motion(R1, R2, delta)
    m.set0(z, z, w1, w2)
    # then 1/10 of the rates (same directions): if the setup call stored a clipped
    # history, step 1 starts from it; otherwise from zero
    m.steps(10, z, z, mul(0.1, w1), mul(0.1, w2))
    return m, dict(w1_step0=w1, w2_step0=w2, w1_later=mul(0.1, w1), w2_later=mul(0.1, w2))


def case_cohesive_random(P, R1, R2, dmin, dmax, dout, seed, nseg=20, seglen=20):
    """general motion of a cohesive pair: piecewise-constant random v and omega on 20-step
    segments whose rates reach the sliding, rolling and twisting limits in ~15 steps (the
    twisting rate along the current normal); the overlap is steered to a random target in
    [dmin, dmax] (tensile range, for JKR negative overlap), then the pair is pulled apart
    beyond the end of contact (overlap dout), pushed back into contact and moved on."""
    rng = random.Random(seed)
    fc = 0.5 * (fncrit_at(P, R1, R2, dmin) + fncrit_at(P, R1, R2, dmax))
    reff = R1 * R2 / (R1 + R2)
    vt = 0.6 * P["mu_s"] * fc / P["kt"] / (15 * DT)
    wr = 0.6 * P["mu_r"] * fc / P["kr"] / (15 * DT) / reff
    om = 0.6 * P["mu_tw"] * fc / P["ktw"] / (15 * DT)
    m = Motion(R1, R2, dmax)
    def rv(scale):
        return [scale * (2 * rng.random() - 1) for _ in range(3)]
    targets = [dmin + (dmax - dmin) * rng.random() for _ in range(nseg)]
    targets += [dout, 0.5 * dmax, dmin + (dmax - dmin) * rng.random()]
    for seg, dtarget in enumerate(targets):
        x1, x2 = m.rows[-1][0], m.rows[-1][1]
        d = sub(x2, x1)
        r = norm(d)
        u = mul(1.0 / r, d)
        vn = ((R1 + R2 - r) - dtarget) / (seglen * DT)   # relative normal speed (2 away from 1)
        v1 = rv(vt)
        v2 = add(v1, rv(vt))
        v2 = add(v2, mul(vn - dot(sub(v2, v1), u), u))
        w1 = rv(wr)
        w2 = sub(w1, add(rv(wr), mul(om * (2 * rng.random() - 1), u)))
        if seg == 0:
            m.set0(v1, v2, w1, w2)
        m.steps(seglen, v1, v2, w1, w2)
    return m, dict(seed=seed, nseg=nseg, seglen=seglen, overlap_targets=targets)


def case_pull_off(P, R1, R2, delta, dend, npre=60, nsep=240):
    """sliding, rolling and twisting at constant rates that reach each limit after ~npre/2
    steps at rest overlap delta; after npre steps atom 2 moves away along U at constant speed
    (same rates) through the tensile range until the overlap is dend, past the end of contact."""
    reff = R1 * R2 / (R1 + R2)
    fc = fncrit_at(P, R1, R2, delta)
    t_el = 0.5 * npre * DT
    vrl = P["mu_r"] * fc / P["kr"] / t_el
    vt = P["mu_s"] * fc / P["kt"] / t_el
    om = P["mu_tw"] * fc / P["ktw"] / t_el
    rr = add(mul(vrl / reff, E1), mul(om, U))
    S = mul(vt, E2)
    w2 = mul(1.0 / (R1 + R2), sub(S, mul(R1, rr)))
    w1 = add(w2, rr)
    z = [0.0] * 3
    m = Motion(R1, R2, delta)
    m.set0(z, z, w1, w2)
    m.steps(npre, z, z, w1, w2)
    vsep = (delta - dend) / (nsep * DT)
    m.steps(nsep, z, mul(vsep, U), w1, w2)
    return m, dict(w1=w1, w2=w2, vsep=vsep, npre=npre, nsep=nsep, overlap_end=dend)


def build_cases():
    C = []
    S, M = SETS["sds"], SETS["marshall"]
    C.append(("sds_gear_roll", "sds", 1.0, 0.5, 0.01) + case_gear(S, 1.0, 0.5, 0.01, 300))
    C.append(("sds_roll_reverse_unload", "sds", 1.0, 0.5, 0.01) + case_reverse(S, 1.0, 0.5, 0.01))
    C.append(("sds_slide_r1_r3", "sds", 1.0, 3.0, 0.01) + case_slide(S, 1.0, 3.0, 0.01))
    C.append(("sds_twist", "sds", 1.0, 0.5, 0.01) + case_twist(S, 1.0, 0.5, 0.01))
    C.append(("sds_twist_unload", "sds", 1.0, 0.5, 0.01) + case_twist_unload(S, 1.0, 0.5, 0.01))
    C.append(("sds_rigid_rotation", "sds", 1.0, 0.5, 0.01) + case_rigid(S, 1.0, 0.5, 0.01))
    C.append(("sds_random", "sds", 1.0, 0.6, 0.01) + case_random(S, 1.0, 0.6, 0.01, seed=12345))
    C.append(("sds_equal_radii", "sds", 0.8, 0.8, 0.01) + case_random(S, 0.8, 0.8, 0.01, seed=777, nseg=15))
    C.append(("sds_setup_clip", "sds", 1.0, 0.5, 0.01) + case_setup_clip(S, 1.0, 0.5, 0.01))
    C.append(("marshall_gear_roll", "marshall", 1.0, 0.5, 0.01) + case_gear(M, 1.0, 0.5, 0.01, 250))
    C.append(("marshall_twist", "marshall", 1.0, 0.5, 0.01) + case_twist(M, 1.0, 0.5, 0.01))
    C.append(("marshall_rigid_rotation", "marshall", 1.0, 0.5, 0.01) + case_rigid(M, 1.0, 0.5, 0.01))
    C.append(("marshall_random", "marshall", 1.0, 0.6, 0.01) + case_random(M, 1.0, 0.6, 0.01, seed=4242))
    J, D = SETS["jkr"], SETS["dmt"]
    # JKR: contact ends at overlap delta_pulloff = -0.00172 (R1 = 1, R2 = 0.5), -0.00179
    # (R1 = 1, R2 = 0.6); the elastic force is tensile below overlap 0.0043 (0.0045)
    C.append(("jkr_pull_off", "jkr", 1.0, 0.5, 0.01) + case_pull_off(J, 1.0, 0.5, 0.01, -0.003))
    C.append(("jkr_random", "jkr", 1.0, 0.6, 0.01)
             + case_cohesive_random(J, 1.0, 0.6, -0.0012, 0.012, -0.004, seed=2718))
    # DMT: the elastic force is tensile below overlap 0.0063 (0.0065); contact ends at 0
    C.append(("dmt_pull_off", "dmt", 1.0, 0.5, 0.01) + case_pull_off(D, 1.0, 0.5, 0.01, -0.002))
    C.append(("dmt_random", "dmt", 1.0, 0.6, 0.01)
             + case_cohesive_random(D, 1.0, 0.6, 0.0008, 0.012, -0.002, seed=3141))
    return C

# ---------------------------------------------------------------- LAMMPS input
def lammps_input(case, P, R1, R2, m):
    r0 = m.rows[0]
    f = lambda v: " ".join(repr(float(c)) for c in v)
    nsteps = len(m.rows) - 1
    return f"""# rollslide reference case {case} (generated by gen_lammps.py)
units           lj
atom_style      sphere
atom_modify     map array sort 0 0.0
dimension       3
boundary        f f f
newton          off
comm_modify     vel yes
region          box block -20 20 -20 20 -20 20
create_box      1 box
create_atoms    1 single {f(r0[0])} units box
create_atoms    1 single {f(r0[1])} units box
group           a1 id 1
group           a2 id 2
set             atom 1 diameter {repr(2 * R1)}
set             atom 2 diameter {repr(2 * R2)}
set             atom * density {repr(DENSITY)}
velocity        a1 set {f(r0[2])} units box
velocity        a2 set {f(r0[3])} units box
set             atom 1 omega {f(r0[4])}
set             atom 2 omega {f(r0[5])}
pair_style      granular
pair_coeff      * * {P['pair_coeff']}
timestep        {repr(DT)}
neighbor        0.5 bin
neigh_modify    every 1 delay 0 check yes
# no integrator: fix python/move sets x, v, omega of step k from row k of
# motion_{case}.txt in initial_integrate (see tablemove.py)
fix             mv all python/move move_{case}.Table
compute         pl all pair/local dist force fx fy fz p1 p2 p3 p4 p5 p6 p7 p8 p9 p10 p11 p12
dump            da all custom 1 atoms_{case}.dump id radius mass x y z vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz
dump_modify     da format float %.17g sort id
dump            dp all local 1 pair_{case}.dump c_pl[*]
dump_modify     dp format float %.17g
thermo          1000
run             {nsteps}
"""

def clean_env():
    """LAMMPS embeds the system libpython; keep a pyenv/venv python out of its way."""
    env = dict(os.environ)
    for k in list(env):
        if k.startswith("PYENV") or k in ("PYTHONHOME", "PYTHONPATH", "VIRTUAL_ENV"):
            del env[k]
    env["PYTHONPATH"] = "."
    env["PATH"] = ":".join(p for p in env.get("PATH", "").split(":")
                           if ".pyenv" not in p and "virtualenv" not in p) or "/usr/bin:/bin"
    return env

# ---------------------------------------------------------------- parse
def read_dump_frames(path):
    frames = {}
    with open(path) as fh:
        lines = fh.read().splitlines()
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: TIMESTEP"):
            step = int(lines[i + 1]); i += 2
            assert lines[i].startswith("ITEM: NUMBER OF"); n = int(lines[i + 1]); i += 2
            assert lines[i].startswith("ITEM: BOX"); i += 4
            assert lines[i].startswith("ITEM: ATOMS") or lines[i].startswith("ITEM: ENTRIES")
            cols = lines[i].split()[2:]; i += 1
            rows = [lines[i + j].split() for j in range(n)]; i += n
            frames[step] = (cols, rows)
        else:
            i += 1
    return frames

COLS = (["case", "step"] + ["x1", "y1", "z1", "x2", "y2", "z2",
         "v1x", "v1y", "v1z", "v2x", "v2y", "v2z",
         "w1x", "w1y", "w1z", "w2x", "w2y", "w2z", "r1", "r2", "m1", "m2", "contact", "fn",
         "f1x", "f1y", "f1z", "t1x", "t1y", "t1z", "f2x", "f2y", "f2z", "t2x", "t2y", "t2z",
         "fn_signed", "fs_x", "fs_y", "fs_z", "fr_x", "fr_y", "fr_z", "mtw_single",
         "dij_x", "dij_y", "dij_z", "mtw"])


def cohesive_columns(P, a, pr, was_touching, forces, case, step):
    """Columns contact..mtw of a `jkr` or `dmt` row. compute pair/local cannot give them:
    its single() tests JKR contact with radsum + delta_pulloff (compute() uses radsum -
    delta_pulloff) and returns zeros below overlap |delta_pulloff|, and it lists a JKR pair
    within the cutoff after contact ends. So `contact` is compute()'s touch rule, `fn`
    (Fncrit) and `fn_signed` (Fntot) are compute()'s values from the state the pair saw
    (lammps_normal), checked against pair/local where single() is valid (bit for bit) and
    against the dumped per-atom force everywhere; fs, fr, mtw_single are pair/local's where
    single() is valid, empty where it is not, and `dij` is x1 - x2."""
    g = lambda b, ks: [float(a[b][k]) for k in ks]
    x1, x2 = g(0, "xyz"), g(1, "xyz")
    radi, radj = float(a[0]["radius"]), float(a[1]["radius"])
    delx, dely, delz = x1[0] - x2[0], x1[1] - x2[1], x1[2] - x2[2]
    rsq = delx * delx + dely * dely + delz * delz
    radsum = radi + radj
    Reff = radi * radj / radsum
    if P["normal"] == "jkr" and was_touching:
        dist = jkr_pulloff_distance(P, radsum, Reff)
        touching = rsq < dist * dist
    else:
        touching = rsq < radsum * radsum
    p = pr[0] if len(pr) == 1 else None
    dumped = [a[b][k] for b in (0, 1) for k in ("fx", "fy", "fz", "tqx", "tqy", "tqz")]
    if not touching:
        assert all(f == 0.0 for f in forces), (case, step, "force without contact")
        if p is not None:
            assert all(float(c) == 0.0 for c in p[1:]), (case, step)
        return ["0", "0"] + dumped + ["0"] * 11 + ["0"]
    assert any(f != 0.0 for f in forces), (case, step, "contact without force")
    Fne, Fntot, Fncrit, _ = lammps_normal(P, radi, radj, float(a[0]["mass"]), float(a[1]["mass"]),
                                          x1, x2, g(0, ("vx", "vy", "vz")), g(1, ("vx", "vy", "vz")))
    r = math.sqrt(rsq)
    n = [delx / r, dely / r, delz / r]
    f1 = forces[0:3]
    assert abs(dot(f1, n) - Fntot) <= 1e-12 * max(map(abs, f1)), (case, step, dot(f1, n), Fntot)
    if P["normal"] == "jkr":
        E = normal_coeff0(P) * 0.75
        coh = P["cohesion"]
        a0 = math.cbrt(9.0 * M_PI * coh * (Reff * Reff) / (4 * E))
        single_dist = radsum + (a0 * a0 / Reff - 2 * math.sqrt(M_PI * coh * a0 / E))
        single_valid = rsq <= single_dist * single_dist
    else:
        single_valid = True
    assert p is not None, (case, step, "pair/local does not list a touching pair")
    if single_valid:
        # pair/local force = sqrt(rsq) * fforce, fforce = Fntot * (1/r)
        assert float(p[1]) == math.sqrt(rsq) * (Fntot * (1.0 / r)), (case, step, p[1], Fntot)
        assert [float(c) for c in p[14:17]] == [delx, dely, delz]
        single_cols = [p[5], p[6], p[7], p[9], p[10], p[11], p[13]]
    else:
        assert all(float(c) == 0.0 for c in p[1:]), (case, step)
        single_cols = [""] * 7
    # twisting moment on i, as for the other sets
    mtw = dot(forces[3:6], [delx, dely, delz]) / math.sqrt(delx * delx + dely * dely + delz * delz)
    return (["1", repr(Fncrit)] + dumped + [repr(Fntot)] + single_cols
            + [repr(delx), repr(dely), repr(delz), repr(mtw)])


def main():
    work = os.path.join(HERE, "work")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    os.makedirs(os.path.join(HERE, "inputs"), exist_ok=True)
    os.makedirs(os.path.join(HERE, "params"), exist_ok=True)
    out = []
    for (case, setname, R1, R2, delta, m, extra) in build_cases():
        P = SETS[setname]
        inp = lammps_input(case, P, R1, R2, m)
        for d in (work, os.path.join(HERE, "inputs")):
            with open(os.path.join(d, "in." + case), "w") as fh:
                fh.write(inp)
            m.write(os.path.join(d, "motion_%s.txt" % case))
            with open(os.path.join(d, "move_%s.py" % case), "w") as fh:
                fh.write("from tablemove import make\nTable = make('motion_%s.txt')\n" % case)
        shutil.copy(os.path.join(HERE, "tablemove.py"), work)
        cmd = [LMP, "-in", "in." + case, "-log", "log." + case, "-screen", "none", "-nocite"]
        subprocess.run(cmd, cwd=work, check=True, env=clean_env())
        fa = read_dump_frames(os.path.join(work, "atoms_%s.dump" % case))
        fp = read_dump_frames(os.path.join(work, "pair_%s.dump" % case))
        m1 = m2 = None
        cohesive = P["normal"] in ("jkr", "dmt")
        touching = False   # compute()'s touch flag of the pair (JKR: kept past overlap 0)
        for step in sorted(fa):
            cols, rows = fa[step]
            assert [r[0] for r in rows] == ["1", "2"]
            a = [dict(zip(cols, r)) for r in rows]
            row = [case, str(step)]
            for keys in (("x", "y", "z"), ("vx", "vy", "vz"), ("omegax", "omegay", "omegaz")):
                for b in (0, 1):
                    row += [a[b][k] for k in keys]
            row += [a[0]["radius"], a[1]["radius"], a[0]["mass"], a[1]["mass"]]
            m1, m2 = a[0]["mass"], a[1]["mass"]
            pc, pr = fp.get(step, ([], []))
            forces = [float(a[b][k]) for b in (0, 1) for k in ("fx", "fy", "fz", "tqx", "tqy", "tqz")]
            if cohesive:
                row += cohesive_columns(P, a, pr, touching, forces, case, step)
                touching = row[COLS.index("contact")] == "1"
                assert len(row) == len(COLS)
                out.append(row)
                continue
            if len(pr) == 1:
                p = pr[0]
                # c_pl: dist force fx fy fz p1..p12
                fns = p[1]
                row += ["1", repr(abs(float(fns)))]
            else:
                assert len(pr) == 0
                p = None
                row += ["0", "0"]
            for b in (0, 1):
                row += [a[b][k] for k in ("fx", "fy", "fz", "tqx", "tqy", "tqz")]
            if p is not None:
                row += [p[1], p[5], p[6], p[7], p[9], p[10], p[11], p[13], p[14], p[15], p[16]]
            else:
                row += ["0"] * 11
            # twisting moment on i, M = t1 . n_lammps (rolling and sliding torques are normal to n)
            if p is not None:
                d = [float(row[2 + c]) - float(row[5 + c]) for c in range(3)]
                rr = math.sqrt(dot(d, d))
                t1 = [float(a[0][k]) for k in ("tqx", "tqy", "tqz")]
                row += [repr(dot(t1, d) / rr)]
            else:
                row += ["0"]
            assert len(row) == len(COLS)
            out.append(row)
        # sanity: the state the pair saw equals the motion table exactly
        for step in sorted(fa):
            cols, rows = fa[step]
            a = [dict(zip(cols, r)) for r in rows]
            tab = m.rows[step]
            got = [float(a[b][k]) for k in ("x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz") for b in (0, 1)]
            want = [tab[j][d] for j in (0, 1, 2, 3, 4, 5) for d in range(3)]
            got = [float(a[b][k]) for kk in (("x", "y", "z"), ("vx", "vy", "vz"), ("omegax", "omegay", "omegaz")) for b in (0, 1) for k in kk]
            assert got == want, (case, step)
        params = dict(case=case, code="LAMMPS 29 Sep 2021 update 2 (Debian lammps 20220106.git7586adbb6a+ds1-2+b2)",
                      parameter_set=setname, law=P, R1=R1, R2=R2, delta0=delta, dt=DT, density=DENSITY,
                      mass1=float(m1), mass2=float(m2), units="lj (dimensionless)",
                      pair_style="pair_style granular",
                      pair_coeff="pair_coeff * * " + P["pair_coeff"],
                      atom_i="atom 1 (id 1) is i; n_lammps = (x1 - x2)/|x1 - x2|",
                      nsteps=len(m.rows) - 1, motion=extra,
                      library_normal_U=U, tangent_e1=E1, tangent_e2=E2,
                      command="cd inputs && PYTHONPATH=.:.. %s -in in.%s -log log.%s -screen none -nocite" % (LMP, case, case),
                      input_script="inputs/in.%s" % case, motion_table="inputs/motion_%s.txt" % case)
        with open(os.path.join(HERE, "params", case + ".json"), "w") as fh:
            json.dump(params, fh, indent=1)
    with open(os.path.join(HERE, "lammps_reference.csv"), "w") as fh:
        fh.write(",".join(COLS) + "\n")
        for r in out:
            fh.write(",".join(r) + "\n")
    if not KEEP:
        shutil.rmtree(work, ignore_errors=True)
    print("rows:", len(out))


if __name__ == "__main__":
    main()
