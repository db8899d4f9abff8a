#!/usr/bin/env python3
"""Writes the committed seed corpus of the fuzz targets (fuzz/corpus/<target>/seed-*): valid
inputs laid out as each target reads its bytes (little-endian f64/i32/u32 fields, see
fuzz_targets/common.rs), so the fuzzer starts from contacts that reach every law. Files named
seed-regression-* are inputs the fuzzer found failing, kept as they were (not made here)."""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def d(*xs):
    return struct.pack("<%dd" % len(xs), *xs)


def i32(*xs):
    return struct.pack("<%di" % len(xs), *xs)


def u32(*xs):
    return struct.pack("<%dI" % len(xs), *xs)


def b(*xs):
    return bytes(xs)


# spheres: position, velocity, angular velocity, radius
CASE6_1 = d(1, 2, 3, 0.3, -0.2, 0.1, 1, -2, 0.5, 1.0)
CASE6_2 = d(1, 2 + 0.6 * 1.49, 3 + 0.8 * 1.49, -0.1, 0.4, 0.2, 0.2, 0.3, -1, 0.5)
GEAR_1 = d(0, 0, 0, 0, 0, 0, 0, 0, 2, 0.7)
GEAR_2 = d(2.99, 0, 0, 0, 0, 0, 0, 0, -2 * 0.7 / 2.3, 2.3)
BALL = d(0.3, 0.2, 0.69, 1.7, -0.4, 0, 0.4 / 0.7, 1.7 / 0.7, 0, 0.7)
WALL = d(0, 0, 0, 0, 0, 2, 0.1, 0, 0, 0, 0, 0.2)  # point, normal, velocity, angular velocity
OPTS_DEFAULT = i32(0, 0) + u32(63)
OPTS_RADII = i32(1, 1) + u32(63)
OPTS_SOME = i32(0, 0) + u32(4 | 8)

# rsl_contact_input: 18 doubles (the last, shear_adhesion, since 0.2.0) then flags, reserved
INPUT = d(10.0, 1e-3, 1e4, 0.05, 1.0, 2.0, 0.1, 0.2, 900, 0.4, 9, 80, 0.2, 0.2, 40, 0.01, 0.03, 3.0) + u32(0, 0)
INPUT_OVR = INPUT[:-8] + u32(1 | 2 | 8 | 16 | 32 | 64 | 128 | 256 | 512, 0)
# a fragile bond (shear adhesion 3, fragile) under tension, no other override
INPUT_BOND = d(-2.0, 1e-3, 1e4, 0.05, 1.0, 2.0, 0.1, 0.2, 900, 0.4, 9, 80, 0.2, 0.2, 40, 0.01, 0.03, 3.0) + u32(1024 | 2048, 0)

# model ops (see model_from in common.rs): preset byte, op count, then per op a selector byte
# and its fields; param(): a selector byte (0..4 fixed values, 5..7 then 8 raw bytes)
def param(x):
    return b(5) + d(x)


SLIDING = b(0) + b(1) + param(1e3) + param(0.5) + param(0.4)
TWIST_SDS = b(1) + b(1) + param(50.0) + param(0.05) + param(0.05)
TWIST_MARSHALL = b(1) + b(2) + param(0) + param(0) + param(0)
def rolling(law, form=0, srule=0, drule=0, dmode=0, k=1e2, c=0.1, mu=0.1, thr=0.0, fac=1.0):
    return b(2) + b(law, form, srule, drule, dmode) + param(k) + param(c) + param(mu) + param(thr) + param(fac)
ENERGY = b(5) + b(1)
TRANSPORT = lambda s, r: b(3) + b(s, r)


def model(preset, *ops):
    return b(preset, len(ops)) + b"".join(ops)


MODELS = {
    "objective": model(0, SLIDING, rolling(3), TWIST_SDS, ENERGY),
    "lammps": model(1, SLIDING, rolling(3), TWIST_MARSHALL, ENERGY),
    "yade": model(2, SLIDING, rolling(3, form=1, k=5.0, mu=0.05), TWIST_SDS),
    "liggghts": model(3, SLIDING, rolling(1, form=1, mu=0.05), ENERGY),
    "epsd_ratio": model(0, SLIDING, rolling(3, srule=1, drule=1, c=0.3), TRANSPORT(1, 2), ENERGY),
    "viscous": model(0, SLIDING, rolling(2, c=0.5, mu=0.2), TRANSPORT(2, 4), ENERGY),
}

SEEDS = {
    "decompose": {
        "case6": CASE6_1 + CASE6_2 + OPTS_DEFAULT + b(0),
        "gear_radii": GEAR_1 + GEAR_2 + OPTS_RADII + b(1),
        "case6_parts": CASE6_1 + CASE6_2 + OPTS_SOME + b(1),
    },
    "decompose_wall": {
        "ball": BALL + WALL + OPTS_DEFAULT + b(0),
        "ball_radii": BALL + WALL + OPTS_RADII + b(1),
    },
    "compose": {
        "case6": b(1) + OPTS_DEFAULT + CASE6_1 + CASE6_2,
        "gear_radii": b(3) + OPTS_RADII + GEAR_1 + GEAR_2,
    },
    "contact_step": {},
    "contact_step_wall": {},
    "model_setters": {},
}
for name, m in MODELS.items():
    SEEDS["model_setters"][name] = m
    for state in (b(0), b(1) + d(1e-3, -2e-3, 0, 2e-3, 1e-3, -1e-3, 0.01, 0, 0, 0, 0, 0.6, 0.8) + u32(0, 0)):
        tag = name + ("_state" if state != b(0) else "")
        steps = b(3)
        SEEDS["contact_step"][tag] = m + state + steps + (CASE6_1 + CASE6_2 + INPUT_OVR) * 3
        SEEDS["contact_step_wall"][tag] = m + state + steps + (BALL + WALL + INPUT) * 3
    SEEDS["contact_step"][name + "_bond"] = m + b(0) + b(3) + (CASE6_1 + CASE6_2 + INPUT_BOND) * 3

for target, seeds in SEEDS.items():
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    for name, data in seeds.items():
        with open(os.path.join(folder, "seed-" + name), "wb") as f:
            f.write(data)
print("wrote", sum(len(s) for s in SEEDS.values()), "seeds")
