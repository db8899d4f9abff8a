#!/usr/bin/env python3
"""Generate LIGGGHTS-PUBLIC 3.8.0 (Debian liggghts 3.8.0+repack1-9+b2) reference
data: two spheres, pair_style gran model hertz tangential history
rolling_friction cdt|epsd|epsd2|epsd3, imposed motion.

Usage: python3 gen_liggghts.py [--liggghts liggghts] [--keep]

Motion (LIGGGHTS 3.8 has no python and `set ... omega` is illegal):
  * initial x, v, omega come from a data file (read_data, Velocities section
    "id vx vy vz wx wy wz"), so step 0 sees exactly these values;
  * fixed centres: `fix move rotate` about the atom's own centre (P = x0, so x
    stays exactly x0, v = 0, omega = (2 pi/period) * axis/|axis|, set in
    initial_integrate of every step >= 1);
  * general motion: `fix move linear vx vy vz` (x = x0 + v (t - t0), exact
    expression of fix move) with omega kept from the data file (nothing
    integrates omega; no nve/sphere);
  * reversal: a second `run` after `unfix`/`fix move rotate` with the opposite
    period; the second run has its own setup force call (step 0 semantics,
    see README) at the step where the first run ended.
No integrator besides fix move, so forces never feed back on the motion.
"""
import json, math, os, shutil, subprocess, sys

HERE = os.path.dirname(os.path.abspath(__file__))
EXE = "liggghts"
for i, a in enumerate(sys.argv):
    if a == "--liggghts":
        EXE = sys.argv[i + 1]
KEEP = "--keep" in sys.argv

U = [0.36, -0.48, 0.8]          # library normal 1 -> 2
E1 = [0.8, 0.6, 0.0]
E2 = [-0.48, 0.64, 0.6]
X1 = [0.1, -0.2, 0.3]
DT = 1.0e-3
DENSITY = 1.0
MAT = dict(youngsModulus=1.0e6, poissonsRatio=0.3, coefficientRestitution=0.5,
           coefficientFriction=0.5, coefficientRollingFriction=0.1,
           coefficientRollingViscousDamping=0.3, rollingStiffness=1.5)
MODELS = ["cdt", "epsd", "epsd2", "epsd3"]


def fmt(v): return repr(float(v))


def case_defs():
    C = []
    # name, R1, R2, delta, kind, params
    for mdl in MODELS:
        C.append((mdl + "_gear_roll", mdl, 1.0, 0.5, 0.01, "gear", dict(s=0.15, n=300)))
        C.append((mdl + "_roll_reverse", mdl, 1.0, 0.5, 0.01, "reverse", dict(s=0.15, n1=150, n2=150)))
        C.append((mdl + "_slide_r1_r3", mdl, 1.0, 3.0, 0.01, "slide", dict(w=0.05, n=250)))
        C.append((mdl + "_general", mdl, 1.0, 0.6, 0.01, "general",
                  dict(v1=[0.004, -0.003, 0.002], v2=[-0.002, 0.005, 0.0], w1=[0.3, -0.2, 0.5],
                       w2=[-0.4, 0.1, 0.2], n=300)))
    # `torsionTorque on`: the rolling models act on the whole relative spin (normal part kept).
    for mdl in MODELS:
        C.append((mdl + "_general_torsion", mdl, 1.0, 0.6, 0.01, "general",
                  dict(v1=[0.004, -0.003, 0.002], v2=[-0.002, 0.005, 0.0], w1=[0.3, -0.2, 0.5],
                       w2=[-0.4, 0.1, 0.2], n=300, torsion=True)))
    # Fixed centres, body 1 spinning mostly about the normal (twist) and a little about e1
    # (roll), body 2 at rest: without torsionTorque only the small rolling part is resisted.
    twist = [0.2 * U[d] + 0.05 * E1[d] for d in range(3)]
    for mdl in ("cdt", "epsd"):
        C.append((mdl + "_twist_torsion", mdl, 1.0, 0.5, 0.01, "general",
                  dict(v1=[0.0, 0.0, 0.0], v2=[0.0, 0.0, 0.0], w1=twist, w2=[0.0, 0.0, 0.0],
                       n=300, torsion=True)))
    return C


def pair_style(mdl, torsion):
    return "pair_style gran model hertz tangential history rolling_friction %s%s" % (
        mdl, " torsionTorque on" if torsion else "")


def header(mdl, torsion=False):
    lines = ["atom_style granular", "atom_modify map array sort 0 0", "boundary f f f", "newton off",
             "communicate single vel yes", "units si", "soft_particles yes", "read_data data.CASE",
             "neighbor 0.1 bin", "neigh_modify delay 0",
             "fix m1 all property/global youngsModulus peratomtype %s" % fmt(MAT["youngsModulus"]),
             "fix m2 all property/global poissonsRatio peratomtype %s" % fmt(MAT["poissonsRatio"]),
             "fix m3 all property/global coefficientRestitution peratomtypepair 1 %s" % fmt(MAT["coefficientRestitution"]),
             "fix m4 all property/global coefficientFriction peratomtypepair 1 %s" % fmt(MAT["coefficientFriction"]),
             "fix m5 all property/global coefficientRollingFriction peratomtypepair 1 %s" % fmt(MAT["coefficientRollingFriction"])]
    if mdl in ("epsd", "epsd3"):
        lines.append("fix m6 all property/global coefficientRollingViscousDamping peratomtypepair 1 %s" % fmt(MAT["coefficientRollingViscousDamping"]))
    if mdl == "epsd3":
        lines.append("fix m7 all property/global rollingStiffness scalar %s" % fmt(MAT["rollingStiffness"]))
    lines += [pair_style(mdl, torsion), "pair_coeff * *",
              "timestep %s" % fmt(DT), "group a1 id 1", "group a2 id 2"]
    return lines

def nloc(mdl):
    # pos_i(3) pos_j(3) vel_i(3) vel_j(3) id_i id_j periodic force(3) torque(3) history(3 or 6) delta
    return 25 if mdl == "cdt" else 28


def outputs(case, mdl):
    NLOC = nloc(mdl)
    cols = " ".join("c_pl[%d]" % k for k in range(1, NLOC + 1))
    return ["compute pl all pair/gran/local pos vel id force torque history delta",
            "dump d1 all custom 1 atoms_%s.dump id x y z vx vy vz omegax omegay omegaz radius mass fx fy fz tqx tqy tqz" % case,
            'dump_modify d1 sort id format "%d' + " %.17g" * 17 + '"',
            "dump d2 all local 1 pair_%s.dump %s" % (case, cols),
            'dump_modify d2 format "' + " ".join(["%.17g"] * NLOC) + '"',
            "thermo 1000"]


def build(case, mdl, R1, R2, delta, kind, p):
    x1 = X1
    x2 = [X1[d] + (R1 + R2 - delta) * U[d] for d in range(3)]
    z = [0.0, 0.0, 0.0]
    L = header(mdl, p.get("torsion", False)) + outputs(case, mdl)
    if kind in ("gear", "reverse"):
        # w1 = s e1, w2 = -(R1/R2) s e1: R1 w1 + R2 w2 = 0 (no slip with full radii)
        s = p["s"]
        w1 = [s * c for c in E1]; w2 = [-(R1 / R2) * s * c for c in E1]
        per1 = 2 * math.pi / s; per2 = -2 * math.pi / ((R1 / R2) * s)
        v1 = v2 = z
        L += ["fix mv1 a1 move rotate %s %s %s %s" % (" ".join(map(fmt, x1)), fmt(E1[0]), fmt(E1[1]) + " " + fmt(E1[2]), fmt(per1)),
              "fix mv2 a2 move rotate %s %s %s %s" % (" ".join(map(fmt, x2)), fmt(E1[0]), fmt(E1[1]) + " " + fmt(E1[2]), fmt(per2))]
        if kind == "gear":
            L += ["run %d" % p["n"]]
        else:
            L += ["run %d" % p["n1"], "unfix mv1", "unfix mv2",
                  "fix mv1 a1 move rotate %s %s %s %s" % (" ".join(map(fmt, x1)), fmt(E1[0]), fmt(E1[1]) + " " + fmt(E1[2]), fmt(-per1)),
                  "fix mv2 a2 move rotate %s %s %s %s" % (" ".join(map(fmt, x2)), fmt(E1[0]), fmt(E1[1]) + " " + fmt(E1[2]), fmt(-per2)),
                  "run %d" % p["n2"]]
    elif kind == "slide":
        w = p["w"]
        w1 = [w * c for c in E2]; w2 = list(w1)
        per = 2 * math.pi / w
        v1 = v2 = z
        ax = " ".join(map(fmt, E2))
        L += ["fix mv1 a1 move rotate %s %s %s" % (" ".join(map(fmt, x1)), ax, fmt(per)),
              "fix mv2 a2 move rotate %s %s %s" % (" ".join(map(fmt, x2)), ax, fmt(per)),
              "run %d" % p["n"]]
    else:
        v1, v2, w1, w2 = p["v1"], p["v2"], p["w1"], p["w2"]
        L += ["fix mv1 a1 move linear %s" % " ".join(map(fmt, v1)),
              "fix mv2 a2 move linear %s" % " ".join(map(fmt, v2)),
              "run %d" % p["n"]]
    data = ["LIGGGHTS data file for %s" % case, "", "2 atoms", "1 atom types",
            "-5 5 xlo xhi", "-5 5 ylo yhi", "-5 5 zlo zhi", "", "Atoms", "",
            "1 1 %s %s %s" % (fmt(2 * R1), fmt(DENSITY), " ".join(map(fmt, x1))),
            "2 1 %s %s %s" % (fmt(2 * R2), fmt(DENSITY), " ".join(map(fmt, x2))), "", "Velocities", "",
            "1 %s %s" % (" ".join(map(fmt, v1)), " ".join(map(fmt, w1))),
            "2 %s %s" % (" ".join(map(fmt, v2)), " ".join(map(fmt, w2))), ""]
    inp = "# rollslide reference case %s (generated by gen_liggghts.py)\n" % case + \
        "\n".join(L).replace("data.CASE", "data.%s" % case) + "\n"
    return inp, "\n".join(data), dict(p, w1=w1, w2=w2, v1=v1, v2=v2)


def frames(path):
    out = {}
    lines = open(path).read().splitlines()
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: TIMESTEP"):
            step = int(lines[i + 1]); i += 2
            n = int(lines[i + 1]); i += 2
            i += 4
            cols = lines[i].split()[2:]; i += 1
            rows = [lines[i + j].split() for j in range(n)]; i += n
            out.setdefault(step, []).append((cols, rows))   # a step can appear twice (run boundary)
        else:
            i += 1
    return out


COLS = ["case", "step", "call", "x1", "y1", "z1", "x2", "y2", "z2", "v1x", "v1y", "v1z", "v2x", "v2y", "v2z",
        "w1x", "w1y", "w1z", "w2x", "w2y", "w2z", "r1", "r2", "m1", "m2", "contact", "fn",
        "f1x", "f1y", "f1z", "t1x", "t1y", "t1z", "f2x", "f2y", "f2z", "t2x", "t2y", "t2z",
        "loc_fx", "loc_fy", "loc_fz", "loc_tx", "loc_ty", "loc_tz",
        "shear_x", "shear_y", "shear_z", "rtorque_x", "rtorque_y", "rtorque_z", "delta"]


def main():
    work = os.path.join(HERE, "work")
    shutil.rmtree(work, ignore_errors=True); os.makedirs(work)
    for d in ("inputs", "params"):
        os.makedirs(os.path.join(HERE, d), exist_ok=True)
    out = []
    for (case, mdl, R1, R2, delta, kind, p) in case_defs():
        inp, data, extra = build(case, mdl, R1, R2, delta, kind, p)
        for d in (work, os.path.join(HERE, "inputs")):
            open(os.path.join(d, "in." + case), "w").write(inp)
            open(os.path.join(d, "data." + case), "w").write(data)
        cmd = [EXE, "-in", "in." + case, "-log", "log." + case, "-echo", "none"]
        with open(os.path.join(work, "screen." + case), "w") as so:
            subprocess.run(cmd, cwd=work, check=True, stdout=so, stderr=subprocess.STDOUT)
        fa = frames(os.path.join(work, "atoms_%s.dump" % case))
        fp = frames(os.path.join(work, "pair_%s.dump" % case))
        m1 = m2 = None
        for step in sorted(fa):
            for call, (cols, rows) in enumerate(fa[step]):
                a = [dict(zip(cols, r)) for r in rows]
                assert a[0]["id"] == "1" and a[1]["id"] == "2"
                row = [case, str(step), str(call)]
                for keys in (("x", "y", "z"), ("vx", "vy", "vz"), ("omegax", "omegay", "omegaz")):
                    for b in (0, 1):
                        row += [a[b][k] for k in keys]
                row += [a[0]["radius"], a[1]["radius"], a[0]["mass"], a[1]["mass"]]
                m1, m2 = a[0]["mass"], a[1]["mass"]
                lp = fp[step][call][1] if step in fp and call < len(fp[step]) else []
                x1 = [float(a[0][k]) for k in "xyz"]; x2 = [float(a[1][k]) for k in "xyz"]
                dd = [x1[c] - x2[c] for c in range(3)]
                r = math.sqrt(sum(c * c for c in dd)); n = [c / r for c in dd]
                f1 = [float(a[0][k]) for k in ("fx", "fy", "fz")]
                if lp:
                    q = lp[0]
                    assert q[12] in ("1", "1.0") or float(q[12]) == 1.0, q[12]
                    row += ["1", repr(sum(f1[c] * n[c] for c in range(3)))]
                else:
                    row += ["0", "0"]
                for b in (0, 1):
                    row += [a[b][k] for k in ("fx", "fy", "fz", "tqx", "tqy", "tqz")]
                if lp:
                    q = lp[0]
                    if mdl == "cdt":
                        row += q[15:21] + q[21:24] + ["", "", ""] + [q[24]]
                    else:
                        row += q[15:21] + q[21:27] + [q[27]]
                else:
                    row += ["0"] * 13
                assert len(row) == len(COLS), (len(row), len(COLS))
                out.append(row)
        params = dict(case=case, code="LIGGGHTS-PUBLIC 3.8.0 (Debian liggghts 3.8.0+repack1-9+b2)",
                      rolling_friction=mdl, materials=MAT, R1=R1, R2=R2, delta0=delta, dt=DT, density=DENSITY,
                      mass1=float(m1), mass2=float(m2), units="si (soft_particles yes)",
                      pair_style=pair_style(mdl, p.get("torsion", False)),
                      torsion_torque=bool(p.get("torsion", False)),
                      atom_i="atom 1 (id 1) is i; n_liggghts = (x1 - x2)/|x1 - x2|", kind=kind, motion=extra,
                      library_normal_U=U, command="cd inputs && %s -in in.%s -log log.%s -echo none" % (EXE, case, case),
                      input_script="inputs/in.%s" % case, data_file="inputs/data.%s" % case)
        json.dump(params, open(os.path.join(HERE, "params", case + ".json"), "w"), indent=1)
    with open(os.path.join(HERE, "liggghts_reference.csv"), "w") as fh:
        fh.write(",".join(COLS) + "\n")
        for r in out:
            fh.write(",".join(r) + "\n")
    if not KEEP:
        shutil.rmtree(work, ignore_errors=True)
    print("rows:", len(out))


if __name__ == "__main__":
    main()
