# YADE script: per-step contact kinematics and loads of two imposed-motion spheres.
#
#   yade -n -x c_tests/reference/yade_reference.py OUT.csv [CASES.json]
#
# Reads CASES.json (default cases.json beside this file), runs every case in a fresh scene and
# writes one CSV (columns documented in README.md). Cases with a `cohesion` key (those of
# cohesive_cases.json) get cohesive CohFrict materials; a CSV with any of them has the
# cohesion columns COH_COLUMNS appended. Runs headless; needs no display.
# Written for Debian's yade 2023.02a (double precision).
import json
import math
import os
import sys

from yade import *  # noqa: F401,F403  (O, Vector3, sphere, engines...)
import yade

# yade -x sets __file__ to /usr/bin/yade; the script path is sys.argv[0]
HERE = os.path.dirname(os.path.abspath(sys.argv[0]))

VEC_IN = ['x1', 'x2', 'v1', 'v2', 'w1', 'w2']
PARAMS = ['param_kn', 'param_ks', 'param_kr', 'param_ktw', 'param_tanphi', 'param_maxroll', 'param_maxtwist',
          'param_ratchet']
VEC_OUT = ['n']
COLUMNS = (['case', 'step', 'law', 'dt', 'r1', 'r2']
           + [v + '_' + c for v in VEC_IN for c in 'xyz']
           + PARAMS
           + ['n_x', 'n_y', 'n_z', 'pen', 'cp_x', 'cp_y', 'cp_z']
           + ['relangvel_' + c for c in 'xyz']
           + ['incvel_' + c for c in 'xyz']
           + ['shearinc_' + c for c in 'xyz']
           + ['kn', 'ks']
           + [v + '_' + c for v in ['fn', 'fs', 'mb', 'mt', 'f1', 'f2', 't1', 't2'] for c in 'xyz'])
# cohesive cases only: the adhesions CohFrictPhys got at creation (param_*) and after the step
COH_COLUMNS = ['param_fragile', 'param_nadh', 'param_sadh', 'unp', 'nadh', 'sadh', 'coh_broken']


def v3(v):
    """copy a YADE Vector3 (aliases C++ storage) into a tuple of Python floats"""
    return (float(v[0]), float(v[1]), float(v[2]))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def tumble(O, dt, d):
    """velocity of the end of d (relative to its start) for a rotation O of d that keeps |d| exact
    under the explicit update d += dt*v: tangent part O x d plus a radial correction s d/|d| with
    (|d| + s dt)^2 + dt^2 |O x d|^2 = |d|^2. The tangent part is exactly O x d, so the relative
    motion is objective at the time the law evaluates it (a chord velocity would not be)."""
    u = cross(O, d)
    L = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
    uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2]
    s = (math.sqrt(L * L - dt * dt * uu) - L) / dt
    return tuple(u[i] + s * d[i] / L for i in range(3))


def ratchet(case):
    """the case's avoidGranularRatcheting flag (default True, as YADE's)"""
    return bool(case.get('avoidGranularRatcheting', True))


def setup(case):
    O.reset()
    law = case['law']
    m = case['material']
    coh = case.get('cohesion')
    if law == 'cohfrict' and coh:
        # cohesive: normalAdhesion = normalCohesion min(R)^2, shearAdhesion likewise, set when
        # the interaction is created; fragile bonds break for good when the shear limit is exceeded
        mat = CohFrictMat(young=m['young'], poisson=m['poisson'], frictionAngle=m['frictionAngle'],
                          alphaKr=m['alphaKr'], alphaKtw=m['alphaKtw'], etaRoll=m['etaRoll'],
                          etaTwist=m['etaTwist'], momentRotationLaw=True, isCohesive=True,
                          normalCohesion=coh['normalCohesion'], shearCohesion=coh['shearCohesion'],
                          fragile=coh['fragile'])
        ip2 = Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionOnNewContacts=True)
        law2 = Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True, always_use_moment_law=True)
    elif law == 'cohfrict':
        mat = CohFrictMat(young=m['young'], poisson=m['poisson'], frictionAngle=m['frictionAngle'],
                          alphaKr=m['alphaKr'], alphaKtw=m['alphaKtw'], etaRoll=m['etaRoll'],
                          etaTwist=m['etaTwist'], momentRotationLaw=True, isCohesive=False)
        ip2 = Ip2_CohFrictMat_CohFrictMat_CohFrictPhys()
        law2 = Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True, always_use_moment_law=True)
    elif law == 'mindlin':
        mat = FrictMat(young=m['young'], poisson=m['poisson'], frictionAngle=m['frictionAngle'])
        p = case['ip2']
        ip2 = Ip2_FrictMat_FrictMat_MindlinPhys(krot=p['krot'], ktwist=p['ktwist'], eta=p['eta'])
        law2 = Law2_ScGeom_MindlinPhys_Mindlin(includeMoment=True)
    else:
        raise ValueError(law)
    mid = O.materials.append(mat)
    r1, r2 = case['r1'], case['r2']
    O.bodies.append(sphere(tuple(case['x1']), r1, material=mid))
    O.bodies.append(sphere(tuple(case['x2']), r2, material=mid))
    for b in O.bodies:
        b.state.blockedDOFs = 'xyzXYZ'
        b.state.vel = Vector3(0, 0, 0)
        b.state.angVel = Vector3(0, 0, 0)
    rmin = min(r1, r2)
    O.engines = [
        ForceResetter(),
        # verletDist: bounding boxes enlarged by half the smaller radius, so the pair is always
        # in the collider's list; the interaction is created at step 0 (spheres overlap).
        InsertionSortCollider([Bo1_Sphere_Aabb()], verletDist=0.5 * rmin),
        # avoidGranularRatcheting: YADE's default True unless the case says False
        InteractionLoop([Ig2_Sphere_Sphere_ScGeom6D(avoidGranularRatcheting=ratchet(case))], [ip2], [law2]),
        NewtonIntegrator(damping=0, gravity=(0, 0, 0)),
    ]
    O.dt = case['dt']


def velocities(seg, x1, x2, dt):
    z = (0.0, 0.0, 0.0)
    v1 = list(seg.get('v1', z))
    v2 = list(seg.get('v2', z))
    w1 = list(seg.get('w1', z))
    w2 = list(seg.get('w2', z))
    if 'orbit1' in seg:  # body 1 orbits about the centre of body 2
        c = tumble(seg['orbit1'], dt, tuple(x1[i] - x2[i] for i in range(3)))
        v1 = [v1[i] + c[i] for i in range(3)]
    if 'orbit2' in seg:  # body 2 orbits about the centre of body 1
        c = tumble(seg['orbit2'], dt, tuple(x2[i] - x1[i] for i in range(3)))
        v2 = [v2[i] + c[i] for i in range(3)]
    if 'radial' in seg:
        d = tuple(x2[i] - x1[i] for i in range(3))
        L = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        v2 = [v2[i] + seg['radial'] * d[i] / L for i in range(3)]
    if 'rigid' in seg:  # rigid rotation W of the pair about the midpoint of the centres
        W = seg['rigid']
        c = tumble(W, dt, tuple(x2[i] - x1[i] for i in range(3)))
        v1 = [v1[i] - 0.5 * c[i] for i in range(3)]
        v2 = [v2[i] + 0.5 * c[i] for i in range(3)]
        w1 = [w1[i] + W[i] for i in range(3)]
        w2 = [w2[i] + W[i] for i in range(3)]
    return v1, v2, w1, w2


def run_case(case, out, cohesive_columns):
    setup(case)
    initial = None
    law = case['law']
    dt = case['dt']
    b1, b2 = O.bodies[0], O.bodies[1]
    step = 0
    for seg in case['segments']:
        for _ in range(seg['steps']):
            x1 = v3(b1.state.pos)
            x2 = v3(b2.state.pos)
            v1, v2, w1, w2 = velocities(seg, x1, x2, dt)
            b1.state.vel = Vector3(*v1)
            b2.state.vel = Vector3(*v2)
            b1.state.angVel = Vector3(*w1)
            b2.state.angVel = Vector3(*w2)
            # inputs exactly as the law will see them: InteractionLoop runs before NewtonIntegrator
            inp = [v3(b1.state.pos), v3(b2.state.pos), v3(b1.state.vel), v3(b2.state.vel),
                   v3(b1.state.angVel), v3(b2.state.angVel)]
            r1 = float(b1.shape.radius)
            r2 = float(b2.shape.radius)
            O.step()
            i = O.interactions[0, 1]
            if not i.isReal:
                raise RuntimeError('case %s step %d: contact lost' % (case['name'], step))
            g, p = i.geom, i.phys
            if law == 'cohfrict':
                params = [p.kn, p.ks, p.kr, p.ktw, p.tangensOfFrictionAngle, p.maxRollPl, p.maxTwistPl]
                mb, mt = v3(p.moment_bending), v3(p.moment_twist)
            else:
                params = [p.kno, p.kso, p.kr, p.ktw, p.tangensOfFrictionAngle, p.maxBendPl, -1.0]
                mb, mt = v3(p.momentBend), v3(p.momentTwist)
            row = [case['name'], str(step), law, repr(float(dt)), repr(r1), repr(r2)]
            for v in inp:
                row += [repr(c) for c in v]
            params.append(1.0 if ratchet(case) else 0.0)
            row += [repr(float(c)) for c in params]
            row += [repr(c) for c in v3(g.normal)] + [repr(float(g.penetrationDepth))]
            row += [repr(c) for c in v3(g.contactPoint)]
            # velocities are not changed by NewtonIntegrator (all DOFs blocked), so these methods,
            # called after the step, see the same states as the law did (the ratcheting-free
            # incident velocity uses no positions). The column is that default incident velocity in
            # every case; with avoidGranularRatcheting=False the law's shearInc comes from the
            # contact points instead (see param_ratchet).
            row += [repr(c) for c in v3(g.relAngVel(i))]
            row += [repr(c) for c in v3(g.incidentVel(i, True))]
            row += [repr(c) for c in v3(g.shearInc)]
            row += [repr(float(p.kn)), repr(float(p.ks))]
            for v in (v3(p.normalForce), v3(p.shearForce), mb, mt,
                      v3(O.forces.f(0)), v3(O.forces.f(1)), v3(O.forces.t(0)), v3(O.forces.t(1))):
                row += [repr(c) for c in v]
            if cohesive_columns:
                if initial is None:
                    # the adhesions the Ip2 gave the new interaction (step 0 does not break it)
                    assert not p.cohesionBroken, case['name']
                    initial = (float(p.normalAdhesion), float(p.shearAdhesion))
                row += [repr(1.0 if p.fragile else 0.0), repr(initial[0]), repr(initial[1]),
                        repr(float(p.unp)), repr(float(p.normalAdhesion)), repr(float(p.shearAdhesion)),
                        repr(1.0 if p.cohesionBroken else 0.0)]
            assert len(row) == len(COLUMNS) + (len(COH_COLUMNS) if cohesive_columns else 0)
            out.write(','.join(row) + '\n')
            step += 1


def main():
    args = sys.argv[1:]
    if len(args) not in (1, 2):
        raise SystemExit('usage: yade -n -x yade_reference.py OUT.csv [CASES.json]')
    outpath = args[0]
    casespath = args[1] if len(args) == 2 else os.path.join(HERE, 'cases.json')
    with open(casespath) as f:
        cases = json.load(f)['cases']
    cohesive_columns = any('cohesion' in c for c in cases)
    with open(outpath, 'w') as out:
        out.write(','.join(COLUMNS + (COH_COLUMNS if cohesive_columns else [])) + '\n')
        for case in cases:
            run_case(case, out, cohesive_columns)
    print('yade_reference: wrote %s (%d cases, yade %s)' % (outpath, len(cases), yade.config.version))


main()
