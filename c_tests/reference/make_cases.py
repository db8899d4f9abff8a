#!/usr/bin/env python3
"""Generate cases.json (the case list read by yade_reference.py).

Plain python3, deterministic (random cases use random.Random(SEED)).
Run:  python3 c_tests/reference/make_cases.py   (writes cases.json beside this file)

Angular rates are chosen from rough estimates of the elastic limits so that each
loading segment reaches the rolling / twisting / sliding limit after ~30 steps
(elastic first, then plastic); reverse segments unload through the elastic range.
"""
import json
import math
import os
import random

SEED = 12345
DT = 1e-3

# unit normal (1 -> 2) and two tangent unit vectors, all exact-ish decimal
N = (0.48, 0.6, 0.64)
T1 = (0.8, 0.0, -0.6)
T2 = (-0.36, 0.8, -0.48)  # = N x T1

COH_MAT = dict(young=1e5, poisson=0.3, frictionAngle=0.5, alphaKr=0.5, alphaKtw=0.5,
               etaRoll=0.2, etaTwist=0.1)
MIND_MAT = dict(young=1e7, poisson=0.3, frictionAngle=0.5)
MIND_IP2 = dict(krot=2e4, ktwist=2e4, eta=0.1)


def sc(a, v):
    return [a * x for x in v]


def add(*vs):
    return [sum(c) for c in zip(*vs)]


def est(law, r1, r2, delta, mat, ip2):
    """Rough elastic limits: (slide displacement, rolling angle, twist angle)."""
    E, nu, phi = mat['young'], mat['poisson'], mat['frictionAngle']
    if law == 'cohfrict':
        kn = 2 * E * r1 * E * r2 / (E * r1 + E * r2)
        ks = nu * kn
        fn = kn * delta
        kr = r1 * r2 * ks * mat['alphaKr']
        ktw = r1 * r2 * ks * mat['alphaKtw']
        roll = min(mat['etaRoll'] * r1, mat['etaRoll'] * r2) * fn / kr
        twist = min(mat['etaTwist'] * r1, mat['etaTwist'] * r2) * fn / ktw
    else:
        G = E / (2 * (1 + nu))
        Es = E / (2 * (1 - nu * nu))
        R = r1 * r2 / (r1 + r2)
        kno = 4.0 / 3.0 * Es * math.sqrt(R)
        kso = 2 * math.sqrt(4 * R) * G / (2 - nu)
        fn = kno * delta ** 1.5
        ks = kso * math.sqrt(delta)
        roll = ip2['eta'] * (r1 + r2) / 2 * fn / ip2['krot']
        twist = 0.5 * fn * min(r1, r2) / ip2['ktwist']  # no limit in Mindlin; just a scale
    slide = math.tan(phi) * fn / ks
    return slide, roll, twist


def base_case(name, law, r1, r2, note, delta_rel=1e-3, mat=None, ip2=None, x1=(0.0, 0.0, 0.0)):
    delta = delta_rel * min(r1, r2)
    d = r1 + r2 - delta
    c = dict(name=name, law=law, note=note, r1=r1, r2=r2, dt=DT,
             x1=list(x1), x2=[x1[i] + d * N[i] for i in range(3)], segments=[])
    if law == 'cohfrict':
        c['material'] = dict(COH_MAT, **(mat or {}))
    else:
        c['material'] = dict(MIND_MAT, **(mat or {}))
        c['ip2'] = dict(MIND_IP2, **(ip2 or {}))
    c['_lim'] = est(law, r1, r2, delta, c['material'], c.get('ip2'))
    c['_delta'] = delta
    return c


def lrh(c, seg, n_load=70, n_rev=70, n_hold=15):
    """load / reverse / hold (unload) history from one segment template."""
    neg = {k: (sc(-1, v) if isinstance(v, list) else v) for k, v in seg.items()}
    c['segments'] += [dict(seg, steps=n_load), dict(neg, steps=n_rev), dict(steps=n_hold)]


def gear(name, law, r1, r2, **kw):
    c = base_case(name, law, r1, r2, 'gear-like rolling at fixed centres, load/reverse/hold', **kw)
    roll = c['_lim'][1]
    # relative rotation per step = roll/30; w2 - w1 = -(1 + r1/r2) w1
    w = roll / 30.0 / DT / (1 + r1 / r2)
    lrh(c, dict(w1=sc(w, T1), w2=sc(-r1 / r2 * w, T1)))
    return c


def slide(name, law, r1, r2, **kw):
    c = base_case(name, law, r1, r2, 'pure sliding (w1 = w2) at fixed centres, load/reverse/hold', **kw)
    s = c['_lim'][0]
    w = s / 30.0 / DT / (r1 + r2)
    lrh(c, dict(w1=sc(w, T2), w2=sc(w, T2)))
    return c


def twist(name, law, r1, r2, spin_ratio=1.0, **kw):
    c = base_case(name, law, r1, r2, 'pure twisting (w1 = a n, w2 = -b n), load/reverse/hold', **kw)
    t = c['_lim'][2]
    w = t / 30.0 / DT / (1 + spin_ratio)
    lrh(c, dict(w1=sc(w, N), w2=sc(-spin_ratio * w, N)))
    return c


def rigid(name, law, r1, r2, **kw):
    c = base_case(name, law, r1, r2,
                  'preload (gear+slide+twist, elastic) then rigid rotation of the pair about an axis '
                  'through the midpoint of the centres, W=(1,0,1)/sqrt2*5 (alpha=5e-3/step, spin part W.n != 0)', **kw)
    s, roll, tw = c['_lim']
    wr = 0.5 * roll / 30.0 / DT / (1 + r1 / r2)
    ws = 0.5 * s / 30.0 / DT / (r1 + r2)
    wt = 0.5 * tw / 30.0 / DT / 2
    w1 = add(sc(wr, T1), sc(ws, T2), sc(wt, N))
    w2 = add(sc(-r1 / r2 * wr, T1), sc(ws, T2), sc(-wt, N))
    W = sc(5.0 / math.sqrt(2.0), [1.0, 0.0, 1.0])
    c['segments'] = [dict(steps=30, w1=w1, w2=w2), dict(steps=180, rigid=W)]
    return c


def orbit(name, law, r1, r2, small, **kw):
    """the small sphere rolls without slip (YADE's definition: R1 w1 + R2 w2 = (R1+R2) Om on the
    tangent plane) over the fixed large one; forward then backward."""
    c = base_case(name, law, r1, r2, 'rolling without slip of the small sphere over the large fixed '
                  'one (orbit of the small centre about the large centre), forward/backward/hold', **kw)
    roll = c['_lim'][1]
    R = r1 + r2
    if small == 1:
        om = roll / 20.0 / DT / (R / r1)
        seg = dict(orbit1=sc(om, T1), w1=sc(om * R / r1, T1))
    else:
        om = roll / 20.0 / DT / (R / r2)
        seg = dict(orbit2=sc(om, T1), w2=sc(om * R / r2, T1))
    lrh(c, seg, 80, 80, 15)
    return c


def rnd_vec(rng, s):
    return [rng.gauss(0.0, s) for _ in range(3)]


def randomcase(name, law, r1, r2, nseg=5, nsteps=40, **kw):
    c = base_case(name, law, r1, r2, 'random general motion (seeded): common translation, relative '
                  'orbit (tumbling), radial approach/retreat, random spins; 5 segments x 40 steps', **kw)
    rng = random.Random(SEED + len(name) * 7 + int(r2 * 10))
    s, roll, tw = c['_lim']
    delta = c['_delta']
    for k in range(nseg):
        U = rnd_vec(rng, 0.05)
        # relative tumbling: tangential relative displacement ~ slide limit over the segment
        Om = rnd_vec(rng, 1.2 * s / nsteps / DT / (r1 + r2))
        # radial: alternate +-0.3 delta over the segment (keeps the overlap in (0.4, 1.6) delta)
        vr = (0.3 if k % 2 == 0 else -0.3) * delta / (nsteps * DT)
        wc = rnd_vec(rng, 0.05)  # common spin
        wrel = rnd_vec(rng, 1.2 * roll / nsteps / DT)
        w1 = add(wc, sc(0.5, wrel))
        w2 = add(wc, sc(-0.5, wrel))
        c['segments'].append(dict(steps=nsteps, v1=U, v2=U, orbit2=Om, radial=vr, w1=w1, w2=w2))
    return c


def contact_point(c):
    """the case with Ig2_Sphere_Sphere_ScGeom6D(avoidGranularRatcheting=False): YADE's shear
    increment from the contact points' relative velocity instead of its default incident velocity"""
    c['avoidGranularRatcheting'] = False
    c['note'] += '; avoidGranularRatcheting=False'
    return c


def cohesive(name, r1, r2, fragile, segments, normal_cohesion=200.0, shear_cohesion=30.0):
    """A CohFrict case with normal and shear cohesion (CohFrictMat isCohesive=True,
    Ip2 setCohesionOnNewContacts=True): normalAdhesion = normalCohesion min(R1,R2)^2 and
    shearAdhesion = shearCohesion min(R1,R2)^2 (Ip2_CohFrictMat_CohFrictMat_CohFrictPhys)."""
    c = base_case(name, 'cohfrict', r1, r2, '')
    c['cohesion'] = dict(normalCohesion=normal_cohesion, shearCohesion=shear_cohesion, fragile=fragile)
    c['segments'] = segments
    return c


def cohesive_cases():
    """CohFrict with cohesion: kn = 1e5, ks = 3e4 (R1 = R2 = 1), overlap 1e-3 (F_n = 100),
    normalAdhesion 200 and shearAdhesion 30 (min R = 1). The radial rate moves the overlap by
    1.5e-3 in 40 steps (F_n from 100 to -50, never beyond -normalAdhesion: no normal plasticity,
    no tensile break)."""
    dt = DT
    radial = 1.5e-3 / (40 * dt)
    w_slide = 0.03  # |2 w| dt ks = 1.8 of shear force per step
    w_gear = 0.02   # gear: k_r 2 w dt = 0.6 of rolling moment per step
    w_twist = 0.02

    def seg(steps, radial_rate=0.0, slide=0.0, gear=0.0, twist=0.0, ratio=1.0):
        # gear: w1 = gear T1, w2 = -ratio gear T1 (ratio R1/R2: no sliding from the gear)
        s = dict(steps=steps)
        w1 = add(sc(slide, T2), sc(gear, T1), sc(twist, N))
        w2 = add(sc(slide, T2), sc(-ratio * gear, T1), sc(-twist, N))
        if any(w1):
            s['w1'] = w1
        if any(w2):
            s['w2'] = w2
        if radial_rate:
            s['radial'] = radial_rate
        return s
    tension = cohesive(
        'coh_adh_tension_slide', 1.0, 1.0, False,
        [seg(40, radial, gear=w_gear, twist=w_twist),          # into tension, rolling and twisting on |F_n|
         seg(40, 0.0, slide=w_slide, gear=w_gear),              # slides at 30 + F_n tan(phi) in tension
         seg(40, -radial, slide=-w_slide, gear=-w_gear, twist=-w_twist),  # back to compression, reversed
         seg(15)])
    tension['note'] = ('not fragile: tension to F_n = -50 with rolling and twisting, sliding limit '
                       'shearAdhesion + F_n tan(phi) reached in tension, back to compression')
    # kn = 1.2e5 here; F_n from 120 to -36: the adhesive limit 30 + F_n tan(phi) stays above 10 (at
    # F_n < -30/tan(phi) it would be 0, and a fragile bond would break on the rounding of a zero
    # shear force)
    r = 1.0 / 1.5
    radial_f = 1.3e-3 / (40 * dt)
    fragile = cohesive(
        'coh_adh_fragile_break', 1.0, 1.5, True,
        [seg(40, radial_f, gear=w_gear, twist=w_twist, ratio=r),    # into tension (no sliding: bonded)
         seg(40, -radial_f, gear=-w_gear, twist=-w_twist, ratio=r),  # back to F_n = 120
         seg(70, 0.0, slide=w_slide, gear=w_gear, ratio=r),        # 30 + 54.6 exceeded: the bond breaks
         seg(70, 0.0, slide=-w_slide, gear=-w_gear, ratio=r),      # frictional only, reversed
         seg(15)])
    fragile['note'] = ('fragile: tension and back with rolling and twisting, then sliding past '
                       'shearAdhesion + F_n tan(phi) in compression: the bond breaks, friction only after')
    cases = [tension, fragile]
    for c in cases:
        del c['_lim'], c['_delta']
        c['nsteps'] = sum(s['steps'] for s in c['segments'])
    return cases


def main():
    cases = [
        gear('coh_gear_eq', 'cohfrict', 1.0, 1.0),
        gear('coh_gear_r1.5', 'cohfrict', 1.5, 1.0),
        gear('coh_gear_r10', 'cohfrict', 10.0, 1.0),
        gear('coh_gear_r1000', 'cohfrict', 1000.0, 1.0),
        slide('coh_slide_eq', 'cohfrict', 1.0, 1.0),
        slide('coh_slide_r10', 'cohfrict', 1.0, 10.0),
        twist('coh_twist_eq', 'cohfrict', 1.0, 1.0),
        twist('coh_twist_r1.5', 'cohfrict', 1.0, 1.5, spin_ratio=0.5),
        rigid('coh_rigid_rot', 'cohfrict', 1.0, 0.5),
        orbit('coh_orbit_small1', 'cohfrict', 1.0, 50.0, small=1, mat=dict(alphaKr=0.01, etaRoll=1.0)),
        randomcase('coh_random_eq', 'cohfrict', 1.0, 1.0),
        randomcase('coh_random_r10', 'cohfrict', 1.0, 10.0),
        gear('mind_gear_eq', 'mindlin', 1.0, 1.0),
        gear('mind_gear_r1.5', 'mindlin', 1.0, 1.5),
        slide('mind_slide_r10', 'mindlin', 10.0, 1.0),
        twist('mind_twist_eq', 'mindlin', 1.0, 1.0),
        rigid('mind_rigid_rot', 'mindlin', 1.0, 0.5),
        orbit('mind_orbit_r1000', 'mindlin', 1000.0, 1.0, small=2, ip2=dict(eta=0.001)),
        randomcase('mind_random_r1.5', 'mindlin', 1.0, 1.5),
        # avoidGranularRatcheting=False (appended: the cases above keep their rows)
        contact_point(gear('coh_gear_r10_cp', 'cohfrict', 10.0, 1.0, delta_rel=1e-2)),
        contact_point(slide('coh_slide_r10_cp', 'cohfrict', 1.0, 10.0, delta_rel=1e-2)),
        contact_point(randomcase('coh_random_r10_cp', 'cohfrict', 1.0, 10.0, delta_rel=1e-2)),
        contact_point(randomcase('mind_random_r1.5_cp', 'mindlin', 1.0, 1.5, delta_rel=1e-2)),
    ]
    for c in cases:
        del c['_lim'], c['_delta']
        c['nsteps'] = sum(s['steps'] for s in c['segments'])
    out = dict(
        description='rollslide YADE reference cases; read by yade_reference.py and mp_replay.py. '
                    'Body ids: 0 = body 1, 1 = body 2. Segments are applied in order; keys: steps, '
                    'v1, w1, v2, w2 (constant imposed vectors, default 0), orbit1/orbit2 (angular '
                    'velocity vector O: add to v1 (v2) the velocity O x d + s d/|d| of the end of '
                    'd = x1 - x2 (x2 - x1), i.e. orbit about the other centre, where the radial '
                    'correction s keeps |d| exact under x += v dt: (|d| + s dt)^2 + dt^2 |O x d|^2 = |d|^2), '
                    'radial (scalar: add radial*n to v2), rigid (W: rigid rotation of the pair about the '
                    'midpoint of the centres: v1 -= u/2, v2 += u/2 with u = W x d + s d/|d| as for orbit, '
                    'd = x2 - x1, and W is added to both angular velocities).',
        seed=SEED, cases=cases)
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'cases.json')
    with open(path, 'w') as f:
        json.dump(out, f, indent=1)
        f.write('\n')
    print('wrote', path, 'cases', len(cases), 'rows', sum(c['nsteps'] for c in cases))
    coh = cohesive_cases()
    out = dict(
        description='rollslide YADE reference cases with CohFrict cohesion; read by yade_reference.py '
                    '(same keys as cases.json, plus cohesion: normalCohesion, shearCohesion, fragile '
                    'of the CohFrictMat, isCohesive=True, Ip2 setCohesionOnNewContacts=True).',
        cases=coh)
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'cohesive_cases.json')
    with open(path, 'w') as f:
        json.dump(out, f, indent=1)
        f.write('\n')
    print('wrote', path, 'cases', len(coh), 'rows', sum(c['nsteps'] for c in coh))


if __name__ == '__main__':
    main()
