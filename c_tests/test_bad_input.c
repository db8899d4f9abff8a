/* Bad input through every C entry point (issue #7). For each call that must fail:
 *   - the status is the documented one (each kind of bad input has its own code),
 *   - rsl_last_error_message() is non-empty and contains a needle naming the field or argument,
 *   - every output is byte-for-byte untouched (pre-filled with 0xA5 and compared with memcmp),
 *   - every per-contact state is byte-for-byte untouched (compared with a copy),
 *   - a model refused by a setter behaves exactly as before (same loads, bit for bit).
 * Non-finite values are poked systematically into every double of every input struct (NaN, +inf,
 * -inf), from field tables built with offsetof, so a field added to a struct and left out of the
 * table is caught by the size checks at the top of each table.
 *
 * Not tested on purpose: a real use-after-free of a model (rsl_model_free then a call). That is
 * undefined behaviour in C; the library's magic-number check catches it only while the freed
 * block has not been reused, and AddressSanitizer rightly reports the read. The "not a live
 * model" case is tested with a zeroed buffer and with a buffer of 0xA5 bytes instead. */
#include "rollslide.h" /* first: the header must compile on its own */

#include <float.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "rsl_test.h"

#define PATTERN 0xA5

typedef struct {
    const char *name;   /* for failure messages */
    size_t offset;      /* of the double in its struct */
    const char *needle; /* must appear in rsl_last_error_message() */
} field;

#define F3(type, member, needle)                                       \
    {#member ".x", offsetof(type, member) + 0 * sizeof(double), needle}, \
        {#member ".y", offsetof(type, member) + 1 * sizeof(double), needle}, \
        {#member ".z", offsetof(type, member) + 2 * sizeof(double), needle}
#define F1(type, member, needle) {#member, offsetof(type, member), needle}
#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

static const double NONFINITE[3] = {NAN, INFINITY, -INFINITY};
static const char *const NONFINITE_NAME[3] = {"NaN", "+inf", "-inf"};

/* ---- checking helpers ------------------------------------------------------------------- */

static int all_pattern(const void *p, size_t n) {
    const unsigned char *b = (const unsigned char *)p;
    for (size_t i = 0; i < n; i++)
        if (b[i] != PATTERN) return 0;
    return 1;
}

/* Checks a failing call: status, message needle, untouched output (0xA5), untouched state. */
static void check_failure(int32_t status, int32_t expected, const char *needle, const void *out,
                          size_t out_size, const void *state, const void *state_copy,
                          size_t state_size, const char *what, const char *file, int line) {
    const char *msg = rsl_last_error_message();
    if (status != expected) {
        fprintf(stderr, "%s:%d: %s: status %d (%s: %s), expected %d (%s)\n", file, line, what,
                (int)status, rsl_status_str(status), msg, (int)expected,
                rsl_status_str(expected));
        rsl_test_failures++;
        return;
    }
    if (msg == NULL || msg[0] == '\0' || (needle != NULL && strstr(msg, needle) == NULL)) {
        fprintf(stderr, "%s:%d: %s: message \"%s\" lacks \"%s\"\n", file, line, what,
                msg ? msg : "(null)", needle ? needle : "");
        rsl_test_failures++;
    }
    if (out != NULL && !all_pattern(out, out_size)) {
        fprintf(stderr, "%s:%d: %s: output written on failure\n", file, line, what);
        rsl_test_failures++;
    }
    if (state != NULL && memcmp(state, state_copy, state_size) != 0) {
        fprintf(stderr, "%s:%d: %s: state written on failure\n", file, line, what);
        rsl_test_failures++;
    }
}

#define FAIL_OUT(call, expected, needle, outp, what)                                              \
    do {                                                                                        \
        memset((outp), PATTERN, sizeof *(outp));                                                \
        check_failure((call), (expected), (needle), (outp), sizeof *(outp), NULL, NULL, 0, (what), \
                      __FILE__, __LINE__);                                                      \
    } while (0)

/* A fresh rsl_decomposition, rsl_contact_loads... pre-filled with the pattern. */
static void poke(void *base, size_t offset, double value) {
    memcpy((unsigned char *)base + offset, &value, sizeof value);
}

/* ---- fixtures --------------------------------------------------------------------------- */

static rsl_sphere sphere(double x, double y, double z, double r) {
    rsl_sphere s;
    memset(&s, 0, sizeof s);
    s.position = rsl_test_vec(x, y, z);
    s.velocity = rsl_test_vec(0.3, -0.2, 0.1);
    s.angular_velocity = rsl_test_vec(1.0, -2.0, 0.5);
    s.radius = r;
    return s;
}

/* kinematics.md case 6: R1 = 1, R2 = 0.5, delta = 0.01, n = (0, 0.6, 0.8). */
static void pair(rsl_sphere *a, rsl_sphere *b) {
    *a = sphere(1, 2, 3, 1.0);
    *b = sphere(1, 2 + 0.6 * 1.49, 3 + 0.8 * 1.49, 0.5);
    b->velocity = rsl_test_vec(-0.1, 0.4, 0.2);
    b->angular_velocity = rsl_test_vec(0.2, 0.3, -1.0);
}

static rsl_wall floor_wall(void) {
    rsl_wall w;
    memset(&w, 0, sizeof w);
    w.normal = rsl_test_vec(0, 0, 1);
    w.velocity = rsl_test_vec(0.1, 0, 0);
    w.angular_velocity = rsl_test_vec(0, 0, 0.2);
    return w;
}

static rsl_sphere on_floor(void) { return sphere(0.3, 0.2, 0.69, 0.7); }

static rsl_model *full_model(void) {
    rsl_model *m = NULL;
    CHECK_STATUS(rsl_model_new(RSL_PRESET_OBJECTIVE, &m), RSL_OK);
    CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e3, 0.5, 0.4), RSL_OK);
    rsl_rolling_params p;
    CHECK_STATUS(rsl_model_get_rolling(m, &p), RSL_OK);
    p.law = RSL_ROLLING_EPSD;
    p.stiffness = 1e2;
    p.damping = 0.1;
    p.friction = 0.1;
    CHECK_STATUS(rsl_model_set_rolling(m, &p), RSL_OK);
    CHECK_STATUS(rsl_model_set_twisting(m, RSL_TWISTING_SDS, 50.0, 0.05, 0.05), RSL_OK);
    CHECK_STATUS(rsl_model_set_energy_tracking(m, 1), RSL_OK);
    return m;
}

/* Every per-contact override flag (not SETUP), so every double of the input is read. */
#define ALL_OVERRIDES                                                                         \
    (RSL_INPUT_SLIDING_STIFFNESS | RSL_INPUT_SLIDING_DAMPING | RSL_INPUT_LIMIT_FORCE |        \
     RSL_INPUT_ROLLING_STIFFNESS | RSL_INPUT_ROLLING_DAMPING | RSL_INPUT_ROLLING_FRICTION |   \
     RSL_INPUT_TWISTING_STIFFNESS | RSL_INPUT_TWISTING_DAMPING | RSL_INPUT_TWISTING_FRICTION |  \
     RSL_INPUT_SHEAR_ADHESION)

static rsl_contact_input full_input(void) {
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = 10.0;
    in.dt = 1e-3;
    in.normal_stiffness = 1e4;
    in.contact_radius = 0.05;
    in.mass1 = 1.0;
    in.mass2 = 2.0;
    in.inertia1 = 0.1;
    in.inertia2 = 0.2;
    in.sliding_stiffness = 900.0;
    in.sliding_damping = 0.4;
    in.limit_force = 9.0;
    in.rolling_stiffness = 80.0;
    in.rolling_damping = 0.2;
    in.rolling_friction = 0.2;
    in.twisting_stiffness = 40.0;
    in.twisting_damping = 0.01;
    in.twisting_friction = 0.03;
    in.shear_adhesion = 2.0;
    in.flags = ALL_OVERRIDES;
    return in;
}

/* A state with history in every field (a few steps of the model, plus a YADE-only part). */
static rsl_contact_state loaded_state(const rsl_model *m) {
    rsl_sphere a, b;
    pair(&a, &b);
    rsl_contact_input in = full_input();
    rsl_contact_state st;
    rsl_contact_loads out;
    memset(&st, 0, sizeof st);
    for (int i = 0; i < 3; i++) CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &out), RSL_OK);
    CHECK(st.sliding_spring.x != 0.0 && st.rolling_spring.x != 0.0 && st.twisting_angle != 0.0);
    return st;
}

/* ---- field tables ----------------------------------------------------------------------- */

static const field SPHERE1[] = {
    F3(rsl_sphere, position, "position of body 1"),
    F3(rsl_sphere, velocity, "velocity of body 1"),
    F3(rsl_sphere, angular_velocity, "angular velocity of body 1"),
    F1(rsl_sphere, radius, "radius of body 1"),
};
static const field SPHERE2[] = {
    F3(rsl_sphere, position, "position of body 2"),
    F3(rsl_sphere, velocity, "velocity of body 2"),
    F3(rsl_sphere, angular_velocity, "angular velocity of body 2"),
    F1(rsl_sphere, radius, "radius of body 2"),
};
static const field WALL_SPHERE[] = {
    F3(rsl_sphere, position, "position of the sphere"),
    F3(rsl_sphere, velocity, "velocity of body 1"),
    F3(rsl_sphere, angular_velocity, "angular velocity of body 1"),
    F1(rsl_sphere, radius, "radius of the sphere"),
};
static const field WALL[] = {
    F3(rsl_wall, point, "wall point"),
    F3(rsl_wall, normal, "wall normal"),
    F3(rsl_wall, velocity, "wall velocity"),
    F3(rsl_wall, angular_velocity, "wall angular velocity"),
};
static const field DECOMPOSITION[] = {
    F3(rsl_decomposition, normal, "decomposition.normal"),
    F1(rsl_decomposition, distance, "decomposition.distance"),
    F1(rsl_decomposition, overlap, "decomposition.overlap"),
    F1(rsl_decomposition, branch1, "decomposition.branch1"),
    F1(rsl_decomposition, branch2, "decomposition.branch2"),
    F1(rsl_decomposition, rolling_radius, "decomposition.rolling_radius"),
    F3(rsl_decomposition, contact_point, "decomposition.contact_point"),
    F1(rsl_decomposition, normal_rate, "decomposition.normal_rate"),
    F3(rsl_decomposition, sliding_velocity, "decomposition.sliding_velocity"),
    F3(rsl_decomposition, rolling_velocity, "decomposition.rolling_velocity"),
    F1(rsl_decomposition, twisting_rate, "decomposition.twisting_rate"),
    F3(rsl_decomposition, contact_velocity, "decomposition.contact_velocity"),
    F3(rsl_decomposition, tumbling, "decomposition.tumbling"),
    F1(rsl_decomposition, frame_spin, "decomposition.frame_spin"),
    F3(rsl_decomposition, objective_velocity1, "decomposition.objective_velocity1"),
    F3(rsl_decomposition, objective_velocity2, "decomposition.objective_velocity2"),
};
static const field INPUT[] = {
    F1(rsl_contact_input, normal_force, "normal force"),
    F1(rsl_contact_input, dt, "dt"),
    F1(rsl_contact_input, normal_stiffness, "normal_stiffness"),
    F1(rsl_contact_input, contact_radius, "contact_radius"),
    F1(rsl_contact_input, mass1, "mass1"),
    F1(rsl_contact_input, mass2, "mass2"),
    F1(rsl_contact_input, inertia1, "inertia1"),
    F1(rsl_contact_input, inertia2, "inertia2"),
    F1(rsl_contact_input, sliding_stiffness, "sliding_stiffness"),
    F1(rsl_contact_input, sliding_damping, "sliding_damping"),
    F1(rsl_contact_input, limit_force, "limit_force"),
    F1(rsl_contact_input, rolling_stiffness, "rolling_stiffness"),
    F1(rsl_contact_input, rolling_damping, "rolling_damping"),
    F1(rsl_contact_input, rolling_friction, "rolling_friction"),
    F1(rsl_contact_input, twisting_stiffness, "twisting_stiffness"),
    F1(rsl_contact_input, twisting_damping, "twisting_damping"),
    F1(rsl_contact_input, twisting_friction, "twisting_friction"),
    F1(rsl_contact_input, shear_adhesion, "shear_adhesion"),
};
static const field STATE[] = {
    F3(rsl_contact_state, sliding_spring, "state: sliding spring"),
    F3(rsl_contact_state, rolling_spring, "state: rolling spring"),
    F1(rsl_contact_state, twisting_angle, "state: twisting angle"),
    F3(rsl_contact_state, model_memory, "state: model memory"),
    F3(rsl_contact_state, previous_normal, "state: previous normal"),
};
static const field ROLLING[] = {
    F1(rsl_rolling_params, stiffness, "rolling stiffness"),
    F1(rsl_rolling_params, damping, "rolling damping"),
    F1(rsl_rolling_params, friction, "rolling friction"),
    F1(rsl_rolling_params, rate_threshold, "rate_threshold"),
    F1(rsl_rolling_params, stiffness_factor, "stiffness_factor"),
};

/* Every double of each struct is in its table (the structs hold doubles, then at most 8 bytes of
 * integer flags/padding, or 24 bytes of int32 codes before them for rsl_rolling_params). */
static void check_tables_cover_the_structs(void) {
    CHECK(COUNT(SPHERE1) * sizeof(double) == sizeof(rsl_sphere));
    CHECK(COUNT(WALL) * sizeof(double) == sizeof(rsl_wall));
    CHECK(COUNT(DECOMPOSITION) * sizeof(double) == sizeof(rsl_decomposition));
    CHECK(COUNT(INPUT) * sizeof(double) + 8 == sizeof(rsl_contact_input));
    CHECK(COUNT(STATE) * sizeof(double) + 8 == sizeof(rsl_contact_state));
    CHECK(COUNT(ROLLING) * sizeof(double) + 6 * sizeof(int32_t) == sizeof(rsl_rolling_params));
}

static void label(char *buf, size_t n, const char *fn, const char *arg, const field *f, int v) {
    snprintf(buf, n, "%s: %s.%s = %s", fn, arg, f->name, NONFINITE_NAME[v]);
}

/* ---- decomposition entry points --------------------------------------------------------- */

void test_bad_input_nonfinite_every_field_of_decompose(void) {
    check_tables_cover_the_structs();
    rsl_sphere a, b;
    pair(&a, &b);
    rsl_decomposition out;
    rsl_legacy_rolling legacy;
    char what[160];
    CHECK_STATUS(rsl_decompose(&a, &b, NULL, &out), RSL_OK);
    for (int v = 0; v < 3; v++) {
        for (size_t i = 0; i < COUNT(SPHERE1); i++) {
            rsl_sphere bad = a;
            poke(&bad, SPHERE1[i].offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_decompose", "body1", &SPHERE1[i], v);
            FAIL_OUT(rsl_decompose(&bad, &b, NULL, &out), RSL_ERR_NON_FINITE, SPHERE1[i].needle,
                     &out, what);
            label(what, sizeof what, "rsl_decompose_legacy", "body1", &SPHERE1[i], v);
            FAIL_OUT(rsl_decompose_legacy(&bad, &b, NULL, &legacy), RSL_ERR_NON_FINITE,
                     SPHERE1[i].needle, &legacy, what);
            bad = b;
            poke(&bad, SPHERE2[i].offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_decompose", "body2", &SPHERE2[i], v);
            FAIL_OUT(rsl_decompose(&a, &bad, NULL, &out), RSL_ERR_NON_FINITE, SPHERE2[i].needle,
                     &out, what);
            label(what, sizeof what, "rsl_decompose_legacy", "body2", &SPHERE2[i], v);
            FAIL_OUT(rsl_decompose_legacy(&a, &bad, NULL, &legacy), RSL_ERR_NON_FINITE,
                     SPHERE2[i].needle, &legacy, what);
        }
    }
}

void test_bad_input_nonfinite_every_field_of_decompose_wall(void) {
    rsl_sphere s = on_floor();
    rsl_wall w = floor_wall();
    rsl_decomposition out;
    char what[160];
    CHECK_STATUS(rsl_decompose_wall(&s, &w, NULL, &out), RSL_OK);
    for (int v = 0; v < 3; v++) {
        for (size_t i = 0; i < COUNT(WALL_SPHERE); i++) {
            rsl_sphere bad = s;
            poke(&bad, WALL_SPHERE[i].offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_decompose_wall", "sphere", &WALL_SPHERE[i], v);
            FAIL_OUT(rsl_decompose_wall(&bad, &w, NULL, &out), RSL_ERR_NON_FINITE,
                     WALL_SPHERE[i].needle, &out, what);
        }
        for (size_t i = 0; i < COUNT(WALL); i++) {
            rsl_wall bad = w;
            poke(&bad, WALL[i].offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_decompose_wall", "wall", &WALL[i], v);
            FAIL_OUT(rsl_decompose_wall(&s, &bad, NULL, &out), RSL_ERR_NON_FINITE, WALL[i].needle,
                     &out, what);
        }
    }
}

void test_bad_input_nonfinite_every_field_of_compose(void) {
    rsl_sphere a, b, s = on_floor();
    pair(&a, &b);
    rsl_wall w = floor_wall();
    rsl_decomposition dp, dw;
    CHECK_STATUS(rsl_decompose(&a, &b, NULL, &dp), RSL_OK);
    CHECK_STATUS(rsl_decompose_wall(&s, &w, NULL, &dw), RSL_OK);
    rsl_pair_velocities pv;
    rsl_wall_velocities wv;
    char what[160];
    for (int v = 0; v < 3; v++) {
        for (size_t i = 0; i < COUNT(DECOMPOSITION); i++) {
            const field *f = &DECOMPOSITION[i];
            rsl_decomposition bad = dp;
            poke(&bad, f->offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_compose", "decomposition", f, v);
            FAIL_OUT(rsl_compose(&bad, NULL, &pv), RSL_ERR_NON_FINITE, f->needle, &pv, what);
            bad = dw;
            poke(&bad, f->offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_compose_wall", "decomposition", f, v);
            int wall_infinite = (f->offset == offsetof(rsl_decomposition, distance) ||
                                 f->offset == offsetof(rsl_decomposition, branch2));
            if (wall_infinite && v == 1) {
                /* A wall's distance and branch2 are +inf by definition: accepted. */
                CHECK_STATUS(rsl_compose_wall(&bad, NULL, &wv), RSL_OK);
            } else {
                FAIL_OUT(rsl_compose_wall(&bad, NULL, &wv), RSL_ERR_NON_FINITE, f->needle, &wv,
                         what);
            }
        }
    }
}

void test_bad_input_geometry_and_options(void) {
    rsl_sphere a, b, bad;
    pair(&a, &b);
    rsl_decomposition out;
    rsl_legacy_rolling legacy;
    rsl_pair_velocities pv;
    rsl_wall_velocities wv;
    /* radius <= 0 on either body (0, -0, negative), and the smallest positive radius is fine */
    const double radii[3] = {0.0, -0.0, -1.0};
    for (int i = 0; i < 3; i++) {
        bad = a;
        bad.radius = radii[i];
        FAIL_OUT(rsl_decompose(&bad, &b, NULL, &out), RSL_ERR_INVALID_RADIUS, "radius of body 1",
                 &out, "radius1 <= 0");
        FAIL_OUT(rsl_decompose_legacy(&bad, &b, NULL, &legacy), RSL_ERR_INVALID_RADIUS,
                 "radius of body 1", &legacy, "legacy radius1 <= 0");
        bad = b;
        bad.radius = radii[i];
        FAIL_OUT(rsl_decompose(&a, &bad, NULL, &out), RSL_ERR_INVALID_RADIUS, "radius of body 2",
                 &out, "radius2 <= 0");
    }
    /* coincident centres: equal, and closer than eps (R1 + R2) */
    bad = b;
    bad.position = a.position;
    FAIL_OUT(rsl_decompose(&a, &bad, NULL, &out), RSL_ERR_COINCIDENT_CENTRES, "coincident", &out,
             "coincident");
    FAIL_OUT(rsl_decompose_legacy(&a, &bad, NULL, &legacy), RSL_ERR_COINCIDENT_CENTRES,
             "coincident", &legacy, "legacy coincident");
    {
        /* distinct centres closer than eps (R1 + R2) */
        rsl_sphere c1 = sphere(0, 0, 0, 1.0), c2 = sphere(1e-300, 0, 0, 0.5);
        FAIL_OUT(rsl_decompose(&c1, &c2, NULL, &out), RSL_ERR_COINCIDENT_CENTRES, "coincident",
                 &out, "nearly coincident");
    }
    {
        /* Found by fuzzing: centres 1e-160 apart (tinier radii) passed the coincidence test,
         * but |r2 - r1|^2 underflows into subnormals and the normal came out 1.3 long. */
        rsl_sphere c1 = sphere(0, 0, 0, 7.3e-304), c2 = sphere(1.08e-160, 5.3e-315, 0, 5.4e-312);
        FAIL_OUT(rsl_decompose(&c1, &c2, NULL, &out), RSL_ERR_INVALID_ARGUMENT, "unit normal",
                 &out, "subnormal distance");
        /* just above the limit: accepted, with a unit normal */
        c1.radius = c2.radius = 1e-153;
        c2.position = rsl_test_vec(1.5e-153, 1e-154, 0);
        CHECK_STATUS(rsl_decompose(&c1, &c2, NULL, &out), RSL_OK);
        CHECK_CLOSE(out.normal.x * out.normal.x + out.normal.y * out.normal.y, 1.0, 4e-16, 0.0);
    }
    /* overlap too deep: d = 0.05, R1 = 1, R2 = 0.5 -> l2 = R2 - delta/2 < 0 */
    bad = b;
    bad.position = rsl_test_vec(1, 2, 3.05);
    FAIL_OUT(rsl_decompose(&a, &bad, NULL, &out), RSL_ERR_NONPOSITIVE_BRANCH, "l2", &out,
             "l2 <= 0");
    /* exactly l2 = 0: d = R1 - R2 = 0.5 */
    bad.position = rsl_test_vec(1, 2, 3.5);
    FAIL_OUT(rsl_decompose(&a, &bad, NULL, &out), RSL_ERR_NONPOSITIVE_BRANCH, "l2", &out,
             "l2 == 0");
    /* body 1 the small one: l1 <= 0 */
    bad = b;
    bad.position = rsl_test_vec(1, 2, 3.05);
    FAIL_OUT(rsl_decompose(&bad, &a, NULL, &out), RSL_ERR_NONPOSITIVE_BRANCH, "l1", &out,
             "l1 <= 0");
    /* finite input whose results overflow */
    {
        rsl_sphere fast1 = a, fast2 = b;
        fast1.velocity = rsl_test_vec(1e308, 1e308, 1e308);
        fast2.velocity = rsl_test_vec(-1e308, -1e308, -1e308);
        FAIL_OUT(rsl_decompose(&fast1, &fast2, NULL, &out), RSL_ERR_NON_FINITE, "overflow", &out,
                 "result overflow");
    }
    bad = b;
    bad.position = rsl_test_vec(1.5e308, 0, 0);
    bad.radius = 1e308;
    a.radius = 1e308;
    FAIL_OUT(rsl_decompose(&a, &bad, NULL, &out), RSL_ERR_NON_FINITE, "overflow", &out,
             "distance overflow");
    pair(&a, &b);
    {
        /* Found by fuzzing: the legacy Iwashita-Oda measure R1 w1 - R2 w2 overflowed where the
         * decomposition did not, and came back RSL_OK with +inf. */
        rsl_sphere big1 = sphere(0, 0, 0, 1.0), big2 = sphere(0, 0, 1, 1.0);
        big1.angular_velocity = rsl_test_vec(1e308, 0, 0); /* l w = 0.5e308: fine */
        big2.angular_velocity = rsl_test_vec(-1e308, 0, 0); /* R1 w1 - R2 w2 = inf */
        FAIL_OUT(rsl_decompose_legacy(&big1, &big2, NULL, &legacy), RSL_ERR_NON_FINITE, "overflow",
                 &legacy, "legacy overflow");
    }
    /* invalid option codes */
    rsl_decompose_options o = rsl_decompose_options_default();
    const int32_t bad_codes[4] = {-1, 2, 7, INT32_MIN};
    for (int i = 0; i < 4; i++) {
        o = rsl_decompose_options_default();
        o.branch_rule = bad_codes[i];
        FAIL_OUT(rsl_decompose(&a, &b, &o, &out), RSL_ERR_INVALID_ARGUMENT, "branch_rule", &out,
                 "branch_rule");
        FAIL_OUT(rsl_decompose_legacy(&a, &b, &o, &legacy), RSL_ERR_INVALID_ARGUMENT,
                 "branch_rule", &legacy, "legacy branch_rule");
        o = rsl_decompose_options_default();
        o.rolling_radius_rule = bad_codes[i];
        FAIL_OUT(rsl_decompose(&a, &b, &o, &out), RSL_ERR_INVALID_ARGUMENT,
                 "rolling_radius_rule", &out, "rolling_radius_rule");
    }
    o = rsl_decompose_options_default();
    o.parts = RSL_PART_ALL + 1;
    FAIL_OUT(rsl_decompose(&a, &b, &o, &out), RSL_ERR_INVALID_ARGUMENT, "parts", &out, "parts");
    o.parts = 0x80000000u;
    FAIL_OUT(rsl_decompose(&a, &b, &o, &out), RSL_ERR_INVALID_ARGUMENT, "parts", &out, "parts");
    /* the same option checks on the inverse maps */
    rsl_decomposition d;
    CHECK_STATUS(rsl_decompose(&a, &b, NULL, &d), RSL_OK);
    o = rsl_decompose_options_default();
    o.branch_rule = 3;
    FAIL_OUT(rsl_compose(&d, &o, &pv), RSL_ERR_INVALID_ARGUMENT, "branch_rule", &pv,
             "compose branch_rule");
    FAIL_OUT(rsl_compose_wall(&d, &o, &wv), RSL_ERR_INVALID_ARGUMENT, "branch_rule", &wv,
             "compose_wall branch_rule");
    /* a decomposition that cannot be inverted: non-unit normal, branches <= 0 */
    rsl_decomposition bd = d;
    bd.normal.y *= 1.5;
    FAIL_OUT(rsl_compose(&bd, NULL, &pv), RSL_ERR_INVALID_ARGUMENT, "unit", &pv, "non-unit n");
    bd = d;
    bd.rolling_radius = 0.0;
    FAIL_OUT(rsl_compose(&bd, NULL, &pv), RSL_ERR_NONPOSITIVE_BRANCH, "R_r", &pv, "R_r = 0");
    bd = d;
    bd.branch2 = -0.1;
    FAIL_OUT(rsl_compose(&bd, NULL, &pv), RSL_ERR_NONPOSITIVE_BRANCH, "l2", &pv, "l2 < 0");
    /* finite but extreme: tiny rolling radius blows (w1 - w2)_t up */
    bd = d;
    bd.rolling_radius = 1e-320;
    bd.rolling_velocity = rsl_test_vec(1e300, 1e300, 0);
    FAIL_OUT(rsl_compose(&bd, NULL, &pv), RSL_ERR_NON_FINITE, "overflow", &pv,
             "compose overflow");
}

void test_bad_input_wall_geometry(void) {
    rsl_sphere s = on_floor(), bad;
    rsl_wall w = floor_wall(), bw;
    rsl_decomposition out;
    bw = w;
    bw.normal = rsl_test_vec(0, 0, 0);
    FAIL_OUT(rsl_decompose_wall(&s, &bw, NULL, &out), RSL_ERR_INVALID_ARGUMENT, "wall normal",
             &out, "zero wall normal");
    /* Any finite non-zero length is accepted (the header: "any non-zero length"), also where
     * the squared length under- or overflows: the same decomposition as the unit normal (its
     * components divide exactly here), or within 4 eps for a direction that does not. */
    rsl_decomposition unit_out, tilted_out;
    CHECK_STATUS(rsl_decompose_wall(&s, &w, NULL, &unit_out), RSL_OK);
    bw.normal = rsl_test_vec(0, 0, 1e-320); /* subnormal: its norm underflows to 0 */
    CHECK_STATUS(rsl_decompose_wall(&s, &bw, NULL, &out), RSL_OK);
    CHECK(memcmp(&out, &unit_out, sizeof out) == 0);
    bw.normal = rsl_test_vec(0, 0, 1e300); /* its square overflows */
    CHECK_STATUS(rsl_decompose_wall(&s, &bw, NULL, &out), RSL_OK);
    CHECK(memcmp(&out, &unit_out, sizeof out) == 0);
    bw.normal = rsl_test_vec(0, 1, 1);
    CHECK_STATUS(rsl_decompose_wall(&s, &bw, NULL, &tilted_out), RSL_OK);
    bw.normal = rsl_test_vec(0, 1e308, 1e308); /* its norm itself overflows */
    CHECK_STATUS(rsl_decompose_wall(&s, &bw, NULL, &out), RSL_OK);
    CHECK(memcmp(&out, &tilted_out, sizeof out) == 0);
    bw.normal = rsl_test_vec(5e-315, 1e-160, 1e-160); /* its square underflows */
    CHECK_STATUS(rsl_decompose_wall(&s, &bw, NULL, &out), RSL_OK);
    CHECK_VEC(out.normal, tilted_out.normal.x, tilted_out.normal.y, tilted_out.normal.z,
              4 * DBL_EPSILON);
    bad = s;
    bad.radius = 0.0;
    FAIL_OUT(rsl_decompose_wall(&bad, &w, NULL, &out), RSL_ERR_INVALID_RADIUS, "radius", &out,
             "wall radius 0");
    bad.radius = -2.0;
    FAIL_OUT(rsl_decompose_wall(&bad, &w, NULL, &out), RSL_ERR_INVALID_RADIUS, "radius", &out,
             "wall radius < 0");
    /* centre more than one radius behind the wall: l1 = R - delta/2 <= 0 */
    bad = s;
    bad.position.z = -0.71;
    FAIL_OUT(rsl_decompose_wall(&bad, &w, NULL, &out), RSL_ERR_NONPOSITIVE_BRANCH, "l1", &out,
             "behind the wall");
    bad.position.z = -0.7; /* exactly l1 = 0 */
    FAIL_OUT(rsl_decompose_wall(&bad, &w, NULL, &out), RSL_ERR_NONPOSITIVE_BRANCH, "l1", &out,
             "l1 == 0 at the wall");
    rsl_decompose_options o = rsl_decompose_options_default();
    o.rolling_radius_rule = 5;
    FAIL_OUT(rsl_decompose_wall(&s, &w, &o, &out), RSL_ERR_INVALID_ARGUMENT, "rolling_radius_rule",
             &out, "wall options");
}

/* ---- NULL and misaligned pointers, every argument of every entry point ---------------- */

/* Storage for misaligned pointers: 1 byte past an aligned buffer, with room for any struct. */
static _Alignas(16) unsigned char raw[1024];
#define MIS(type) ((type *)(void *)(raw + 1))

void test_bad_input_null_and_misaligned_pointers(void) {
    rsl_sphere a, b, s = on_floor();
    pair(&a, &b);
    rsl_wall w = floor_wall();
    rsl_decompose_options o = rsl_decompose_options_default();
    rsl_decomposition out, d;
    rsl_legacy_rolling legacy;
    rsl_pair_velocities pv;
    rsl_wall_velocities wv;
    CHECK_STATUS(rsl_decompose(&a, &b, NULL, &d), RSL_OK);
    memset(raw, 0, sizeof raw);
    memcpy(raw + 1, &a, sizeof a); /* valid bytes behind the misaligned pointer */

    FAIL_OUT(rsl_decompose(NULL, &b, &o, &out), RSL_ERR_NULL_POINTER, "body1", &out, "decompose body1");
    FAIL_OUT(rsl_decompose(&a, NULL, &o, &out), RSL_ERR_NULL_POINTER, "body2", &out, "decompose body2");
    CHECK_STATUS(rsl_decompose(&a, &b, NULL, NULL), RSL_ERR_NULL_POINTER);
    CHECK(strstr(rsl_last_error_message(), "null pointer: out") != NULL);
    FAIL_OUT(rsl_decompose(MIS(rsl_sphere), &b, &o, &out), RSL_ERR_MISALIGNED, "body1", &out, "mis body1");
    FAIL_OUT(rsl_decompose(&a, MIS(rsl_sphere), &o, &out), RSL_ERR_MISALIGNED, "body2", &out, "mis body2");
    FAIL_OUT(rsl_decompose(&a, &b, MIS(rsl_decompose_options), &out), RSL_ERR_MISALIGNED, "options", &out, "mis options");
    CHECK_STATUS(rsl_decompose(&a, &b, &o, MIS(rsl_decomposition)), RSL_ERR_MISALIGNED);
    CHECK(strstr(rsl_last_error_message(), "misaligned pointer: out") != NULL);

    FAIL_OUT(rsl_decompose_legacy(NULL, &b, &o, &legacy), RSL_ERR_NULL_POINTER, "body1", &legacy, "legacy body1");
    FAIL_OUT(rsl_decompose_legacy(&a, NULL, &o, &legacy), RSL_ERR_NULL_POINTER, "body2", &legacy, "legacy body2");
    CHECK_STATUS(rsl_decompose_legacy(&a, &b, &o, NULL), RSL_ERR_NULL_POINTER);
    FAIL_OUT(rsl_decompose_legacy(MIS(rsl_sphere), &b, &o, &legacy), RSL_ERR_MISALIGNED, "body1", &legacy, "legacy mis");
    FAIL_OUT(rsl_decompose_legacy(&a, &b, MIS(rsl_decompose_options), &legacy), RSL_ERR_MISALIGNED, "options", &legacy, "legacy mis options");
    CHECK_STATUS(rsl_decompose_legacy(&a, &b, &o, MIS(rsl_legacy_rolling)), RSL_ERR_MISALIGNED);

    FAIL_OUT(rsl_decompose_wall(NULL, &w, &o, &out), RSL_ERR_NULL_POINTER, "sphere", &out, "wall sphere");
    FAIL_OUT(rsl_decompose_wall(&s, NULL, &o, &out), RSL_ERR_NULL_POINTER, "wall", &out, "wall wall");
    CHECK_STATUS(rsl_decompose_wall(&s, &w, &o, NULL), RSL_ERR_NULL_POINTER);
    FAIL_OUT(rsl_decompose_wall(MIS(rsl_sphere), &w, &o, &out), RSL_ERR_MISALIGNED, "sphere", &out, "wall mis sphere");
    FAIL_OUT(rsl_decompose_wall(&s, MIS(rsl_wall), &o, &out), RSL_ERR_MISALIGNED, "wall", &out, "wall mis wall");
    FAIL_OUT(rsl_decompose_wall(&s, &w, MIS(rsl_decompose_options), &out), RSL_ERR_MISALIGNED, "options", &out, "wall mis options");
    CHECK_STATUS(rsl_decompose_wall(&s, &w, &o, MIS(rsl_decomposition)), RSL_ERR_MISALIGNED);

    FAIL_OUT(rsl_compose(NULL, &o, &pv), RSL_ERR_NULL_POINTER, "decomposition", &pv, "compose d");
    CHECK_STATUS(rsl_compose(&d, &o, NULL), RSL_ERR_NULL_POINTER);
    FAIL_OUT(rsl_compose(MIS(rsl_decomposition), &o, &pv), RSL_ERR_MISALIGNED, "decomposition", &pv, "compose mis d");
    FAIL_OUT(rsl_compose(&d, MIS(rsl_decompose_options), &pv), RSL_ERR_MISALIGNED, "options", &pv, "compose mis o");
    CHECK_STATUS(rsl_compose(&d, &o, MIS(rsl_pair_velocities)), RSL_ERR_MISALIGNED);
    FAIL_OUT(rsl_compose_wall(NULL, &o, &wv), RSL_ERR_NULL_POINTER, "decomposition", &wv, "compose_wall d");
    CHECK_STATUS(rsl_compose_wall(&d, &o, NULL), RSL_ERR_NULL_POINTER);
    FAIL_OUT(rsl_compose_wall(MIS(rsl_decomposition), &o, &wv), RSL_ERR_MISALIGNED, "decomposition", &wv, "compose_wall mis d");
    FAIL_OUT(rsl_compose_wall(&d, MIS(rsl_decompose_options), &wv), RSL_ERR_MISALIGNED, "options", &wv, "compose_wall mis o");
    CHECK_STATUS(rsl_compose_wall(&d, &o, MIS(rsl_wall_velocities)), RSL_ERR_MISALIGNED);

    CHECK_STATUS(rsl_contact_state_init(NULL), RSL_ERR_NULL_POINTER);
    CHECK(strstr(rsl_last_error_message(), "state") != NULL);
    CHECK_STATUS(rsl_contact_state_init(MIS(rsl_contact_state)), RSL_ERR_MISALIGNED);

    double dt = 0.0;
    FAIL_OUT(rsl_rotational_critical_time_step(1, 1, 1, 0, NULL), RSL_ERR_NULL_POINTER, "out", &dt, "rot NULL");
    CHECK_STATUS(rsl_rotational_critical_time_step(1, 1, 1, 0, MIS(double)), RSL_ERR_MISALIGNED);
    CHECK_STATUS(rsl_coupled_critical_time_step(1, 1, 1, 1, 1, 1, 1, 1, NULL), RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_coupled_critical_time_step(1, 1, 1, 1, 1, 1, 1, 1, MIS(double)), RSL_ERR_MISALIGNED);

    rsl_model *m = NULL;
    CHECK_STATUS(rsl_model_new(RSL_PRESET_OBJECTIVE, NULL), RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_model_new(RSL_PRESET_OBJECTIVE, MIS(rsl_model *)), RSL_ERR_MISALIGNED);
    /* raw + 1 still holds the bytes copied above: nothing was written there */
    CHECK(memcmp(raw + 1, &a, sizeof a) == 0);
    CHECK_STATUS(rsl_model_new(RSL_PRESET_OBJECTIVE, &m), RSL_OK);
    rsl_rolling_params p;
    CHECK_STATUS(rsl_model_get_rolling(m, &p), RSL_OK);
    CHECK_STATUS(rsl_model_get_rolling(NULL, &p), RSL_ERR_NULL_POINTER);
    CHECK(strstr(rsl_last_error_message(), "model") != NULL);
    CHECK_STATUS(rsl_model_get_rolling(m, NULL), RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_model_get_rolling(m, MIS(rsl_rolling_params)), RSL_ERR_MISALIGNED);
    CHECK_STATUS(rsl_model_get_rolling(MIS(rsl_model), &p), RSL_ERR_MISALIGNED);
    CHECK_STATUS(rsl_model_set_rolling(NULL, &p), RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_model_set_rolling(m, NULL), RSL_ERR_NULL_POINTER);
    CHECK(strstr(rsl_last_error_message(), "params") != NULL);
    CHECK_STATUS(rsl_model_set_rolling(m, MIS(rsl_rolling_params)), RSL_ERR_MISALIGNED);
    CHECK_STATUS(rsl_model_set_rolling(MIS(rsl_model), &p), RSL_ERR_MISALIGNED);
    CHECK_STATUS(rsl_model_set_geometry(NULL, 0, 0), RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_model_set_geometry(MIS(rsl_model), 0, 0), RSL_ERR_MISALIGNED);
    CHECK_STATUS(rsl_model_set_sliding(NULL, RSL_SLIDING_LINEAR, 1, 0, 0.5), RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_model_set_sliding(MIS(rsl_model), RSL_SLIDING_LINEAR, 1, 0, 0.5), RSL_ERR_MISALIGNED);
    CHECK_STATUS(rsl_model_set_twisting(NULL, RSL_TWISTING_SDS, 1, 0, 0.5), RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_model_set_twisting(MIS(rsl_model), RSL_TWISTING_SDS, 1, 0, 0.5), RSL_ERR_MISALIGNED);
    CHECK_STATUS(rsl_model_set_transport(NULL, 0, 0), RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_model_set_transport(MIS(rsl_model), 0, 0), RSL_ERR_MISALIGNED);
    CHECK_STATUS(rsl_model_set_energy_tracking(NULL, 1), RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_model_set_energy_tracking(MIS(rsl_model), 1), RSL_ERR_MISALIGNED);
    rsl_model_free(MIS(rsl_model)); /* ignored, like NULL */
    rsl_model_free(NULL);
    rsl_model_free(m);
}

/* ---- the contact step ------------------------------------------------------------------ */

/* Checks one failing step: status, needle, 0xA5 output, untouched state. */
#define FAIL_STEP(call, expected, needle, what)                                               \
    do {                                                                                      \
        memset(&out, PATTERN, sizeof out);                                                    \
        kept = st;                                                                            \
        check_failure((call), (expected), (needle), &out, sizeof out, &st, &kept, sizeof st, \
                      (what), __FILE__, __LINE__);                                            \
    } while (0)

void test_bad_input_contact_step_every_field_and_pointer(void) {
    rsl_model *m = full_model();
    rsl_sphere a, b;
    pair(&a, &b);
    rsl_contact_input in = full_input();
    rsl_contact_state st = loaded_state(m), kept;
    rsl_contact_loads out;
    char what[160];
    /* every double of both spheres, the input and the state */
    for (int v = 0; v < 3; v++) {
        for (size_t i = 0; i < COUNT(SPHERE1); i++) {
            rsl_sphere bad = a;
            poke(&bad, SPHERE1[i].offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_contact_step", "body1", &SPHERE1[i], v);
            FAIL_STEP(rsl_contact_step(m, &bad, &b, &in, &st, &out), RSL_ERR_NON_FINITE,
                      SPHERE1[i].needle, what);
            bad = b;
            poke(&bad, SPHERE2[i].offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_contact_step", "body2", &SPHERE2[i], v);
            FAIL_STEP(rsl_contact_step(m, &a, &bad, &in, &st, &out), RSL_ERR_NON_FINITE,
                      SPHERE2[i].needle, what);
        }
        for (size_t i = 0; i < COUNT(INPUT); i++) {
            const field *f = &INPUT[i];
            rsl_contact_input bad = in;
            poke(&bad, f->offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_contact_step", "input", f, v);
            int is_dt = f->offset == offsetof(rsl_contact_input, dt);
            int is_limit = f->offset == offsetof(rsl_contact_input, rolling_friction) ||
                           f->offset == offsetof(rsl_contact_input, twisting_friction) ||
                           f->offset == offsetof(rsl_contact_input, limit_force) ||
                           f->offset == offsetof(rsl_contact_input, shear_adhesion) ||
                           f->offset == offsetof(rsl_contact_input, mass2) ||
                           f->offset == offsetof(rsl_contact_input, inertia2);
            if (is_limit && v == 1) {
                /* +inf friction, limit force or shear adhesion is documented as "no limit", +inf
                 * mass2/inertia2 as a fixed body 2: accepted */
                rsl_contact_state copy = st;
                CHECK_STATUS(rsl_contact_step(m, &a, &b, &bad, &copy, &out), RSL_OK);
                continue;
            }
            FAIL_STEP(rsl_contact_step(m, &a, &b, &bad, &st, &out),
                      is_dt ? RSL_ERR_INVALID_TIME_STEP : RSL_ERR_NON_FINITE, f->needle, what);
            /* Without its flag an override field is not read: NaN there is ignored. */
            if (i >= 8 && v == 0) {
                rsl_contact_input unflagged = bad;
                unflagged.flags = 0;
                rsl_contact_state copy = st;
                CHECK_STATUS(rsl_contact_step(m, &a, &b, &unflagged, &copy, &out), RSL_OK);
            }
        }
        for (size_t i = 0; i < COUNT(STATE); i++) {
            rsl_contact_state bad = st;
            poke(&bad, STATE[i].offset, NONFINITE[v]);
            rsl_contact_state bad_copy = bad;
            label(what, sizeof what, "rsl_contact_step", "state", &STATE[i], v);
            memset(&out, PATTERN, sizeof out);
            check_failure(rsl_contact_step(m, &a, &b, &in, &bad, &out), RSL_ERR_NON_FINITE,
                          STATE[i].needle, &out, sizeof out, &bad, &bad_copy, sizeof bad, what,
                          __FILE__, __LINE__);
        }
    }
    /* domain errors of the input */
    rsl_contact_input bad = in;
    const double dts[3] = {0.0, -0.0, -1e-3};
    for (int i = 0; i < 3; i++) {
        bad = in;
        bad.dt = dts[i];
        FAIL_STEP(rsl_contact_step(m, &a, &b, &bad, &st, &out), RSL_ERR_INVALID_TIME_STEP, "dt",
                  "dt <= 0");
    }
    bad = in;
    bad.normal_force = NAN;
    FAIL_STEP(rsl_contact_step(m, &a, &b, &bad, &st, &out), RSL_ERR_NON_FINITE, "normal force",
              "f_n NaN");
    const size_t nonneg[] = {offsetof(rsl_contact_input, normal_stiffness),
                             offsetof(rsl_contact_input, contact_radius),
                             offsetof(rsl_contact_input, mass1),
                             offsetof(rsl_contact_input, mass2),
                             offsetof(rsl_contact_input, inertia1),
                             offsetof(rsl_contact_input, inertia2),
                             offsetof(rsl_contact_input, sliding_stiffness),
                             offsetof(rsl_contact_input, sliding_damping),
                             offsetof(rsl_contact_input, limit_force),
                             offsetof(rsl_contact_input, rolling_stiffness),
                             offsetof(rsl_contact_input, rolling_damping),
                             offsetof(rsl_contact_input, rolling_friction),
                             offsetof(rsl_contact_input, twisting_stiffness),
                             offsetof(rsl_contact_input, twisting_damping),
                             offsetof(rsl_contact_input, twisting_friction),
                             offsetof(rsl_contact_input, shear_adhesion)};
    for (size_t i = 0; i < COUNT(nonneg); i++) {
        bad = in;
        poke(&bad, nonneg[i], -1.0);
        snprintf(what, sizeof what, "negative input field at offset %zu", nonneg[i]);
        FAIL_STEP(rsl_contact_step(m, &a, &b, &bad, &st, &out), RSL_ERR_INVALID_ARGUMENT,
                  ">= 0", what);
    }
    bad = in;
    bad.flags = RSL_INPUT_FRAGILE_BOND; /* a fragile bond without its shear adhesion */
    FAIL_STEP(rsl_contact_step(m, &a, &b, &bad, &st, &out), RSL_ERR_INVALID_ARGUMENT,
              "shear_adhesion", "fragile without adhesion");
    bad.flags = 1u << 12;
    FAIL_STEP(rsl_contact_step(m, &a, &b, &bad, &st, &out), RSL_ERR_INVALID_ARGUMENT, "flags",
              "unknown flag");
    bad.flags = 0xFFFFFFFFu;
    FAIL_STEP(rsl_contact_step(m, &a, &b, &bad, &st, &out), RSL_ERR_INVALID_ARGUMENT, "flags",
              "all flags");
    /* geometry errors through the step */
    rsl_sphere bs = b;
    bs.radius = 0.0;
    FAIL_STEP(rsl_contact_step(m, &a, &bs, &in, &st, &out), RSL_ERR_INVALID_RADIUS, "radius",
              "step radius");
    bs = b;
    bs.position = a.position;
    FAIL_STEP(rsl_contact_step(m, &a, &bs, &in, &st, &out), RSL_ERR_COINCIDENT_CENTRES,
              "coincident", "step coincident");
    bs.position = rsl_test_vec(1, 2, 3.05);
    FAIL_STEP(rsl_contact_step(m, &a, &bs, &in, &st, &out), RSL_ERR_NONPOSITIVE_BRANCH, "l2",
              "step branch");
    /* finite input, overflowing result: huge stiffness times a huge spring */
    bad = in;
    bad.sliding_stiffness = 1e308;
    rsl_contact_state big = st;
    big.sliding_spring = rsl_test_vec(1e300, 0, 0);
    bad.flags = RSL_INPUT_SLIDING_STIFFNESS;
    bad.normal_force = 1e308;
    rsl_contact_state big_copy = big;
    memset(&out, PATTERN, sizeof out);
    check_failure(rsl_contact_step(m, &a, &b, &bad, &big, &out), RSL_ERR_NON_FINITE, "overflow",
                  &out, sizeof out, &big, &big_copy, sizeof big, "step overflow", __FILE__,
                  __LINE__);
    /* NULL and misaligned, each pointer argument */
    FAIL_STEP(rsl_contact_step(NULL, &a, &b, &in, &st, &out), RSL_ERR_NULL_POINTER, "model", "NULL model");
    FAIL_STEP(rsl_contact_step(m, NULL, &b, &in, &st, &out), RSL_ERR_NULL_POINTER, "body1", "NULL body1");
    FAIL_STEP(rsl_contact_step(m, &a, NULL, &in, &st, &out), RSL_ERR_NULL_POINTER, "body2", "NULL body2");
    FAIL_STEP(rsl_contact_step(m, &a, &b, NULL, &st, &out), RSL_ERR_NULL_POINTER, "null pointer: contact", "NULL contact");
    memset(&out, PATTERN, sizeof out);
    check_failure(rsl_contact_step(m, &a, &b, &in, NULL, &out), RSL_ERR_NULL_POINTER, "state",
                  &out, sizeof out, NULL, NULL, 0, "NULL state", __FILE__, __LINE__);
    kept = st;
    CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, NULL), RSL_ERR_NULL_POINTER);
    CHECK(strstr(rsl_last_error_message(), "out") != NULL);
    CHECK(memcmp(&st, &kept, sizeof st) == 0);
    memset(raw, 0, sizeof raw);
    FAIL_STEP(rsl_contact_step(MIS(rsl_model), &a, &b, &in, &st, &out), RSL_ERR_MISALIGNED, "model", "mis model");
    FAIL_STEP(rsl_contact_step(m, MIS(rsl_sphere), &b, &in, &st, &out), RSL_ERR_MISALIGNED, "body1", "mis body1");
    FAIL_STEP(rsl_contact_step(m, &a, MIS(rsl_sphere), &in, &st, &out), RSL_ERR_MISALIGNED, "body2", "mis body2");
    FAIL_STEP(rsl_contact_step(m, &a, &b, MIS(rsl_contact_input), &st, &out), RSL_ERR_MISALIGNED, "misaligned pointer: contact", "mis contact");
    memset(&out, PATTERN, sizeof out);
    check_failure(rsl_contact_step(m, &a, &b, &in, MIS(rsl_contact_state), &out),
                  RSL_ERR_MISALIGNED, "state", &out, sizeof out, NULL, NULL, 0, "mis state",
                  __FILE__, __LINE__);
    kept = st;
    CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, MIS(rsl_contact_loads)), RSL_ERR_MISALIGNED);
    CHECK(memcmp(&st, &kept, sizeof st) == 0);
    /* handles that are not live models: zero bytes, pattern bytes */
    static _Alignas(16) unsigned char fake[4096];
    memset(fake, 0, sizeof fake);
    FAIL_STEP(rsl_contact_step((const rsl_model *)(const void *)fake, &a, &b, &in, &st, &out),
              RSL_ERR_INVALID_HANDLE, "handle", "zeroed handle");
    memset(fake, PATTERN, sizeof fake);
    FAIL_STEP(rsl_contact_step((const rsl_model *)(const void *)fake, &a, &b, &in, &st, &out),
              RSL_ERR_INVALID_HANDLE, "handle", "0xA5 handle");
    /* a model needing an input the host did not give (EPSD-derived stiffness needs k_n) */
    rsl_rolling_params p;
    CHECK_STATUS(rsl_model_get_rolling(m, &p), RSL_OK);
    p.stiffness_rule = RSL_STIFFNESS_EPSD;
    CHECK_STATUS(rsl_model_set_rolling(m, &p), RSL_OK);
    bad = in;
    bad.normal_stiffness = 0.0;
    bad.flags = 0;
    FAIL_STEP(rsl_contact_step(m, &a, &b, &bad, &st, &out), RSL_ERR_INVALID_ARGUMENT,
              "normal_stiffness", "missing k_n");
    p.stiffness_rule = RSL_STIFFNESS_GIVEN;
    p.damping_rule = RSL_DAMPING_RATIO;
    CHECK_STATUS(rsl_model_set_rolling(m, &p), RSL_OK);
    bad = in;
    bad.mass2 = 0.0;
    FAIL_STEP(rsl_contact_step(m, &a, &b, &bad, &st, &out), RSL_ERR_INVALID_ARGUMENT, "mass2",
              "missing mass2");
    rsl_model_free(m);
}

void test_bad_input_contact_step_wall_every_field_and_pointer(void) {
    rsl_model *m = full_model();
    rsl_sphere s = on_floor();
    rsl_wall w = floor_wall();
    rsl_contact_input in = full_input();
    rsl_contact_state st, kept;
    rsl_contact_loads out;
    char what[160];
    memset(&st, 0, sizeof st);
    for (int i = 0; i < 3; i++) CHECK_STATUS(rsl_contact_step_wall(m, &s, &w, &in, &st, &out), RSL_OK);
    CHECK(st.sliding_spring.x != 0.0);
    for (int v = 0; v < 3; v++) {
        for (size_t i = 0; i < COUNT(WALL_SPHERE); i++) {
            rsl_sphere bad = s;
            poke(&bad, WALL_SPHERE[i].offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_contact_step_wall", "sphere", &WALL_SPHERE[i], v);
            FAIL_STEP(rsl_contact_step_wall(m, &bad, &w, &in, &st, &out), RSL_ERR_NON_FINITE,
                      WALL_SPHERE[i].needle, what);
        }
        for (size_t i = 0; i < COUNT(WALL); i++) {
            rsl_wall bad = w;
            poke(&bad, WALL[i].offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_contact_step_wall", "wall", &WALL[i], v);
            FAIL_STEP(rsl_contact_step_wall(m, &s, &bad, &in, &st, &out), RSL_ERR_NON_FINITE,
                      WALL[i].needle, what);
        }
        for (size_t i = 0; i < COUNT(INPUT); i++) {
            const field *f = &INPUT[i];
            int is_dt = f->offset == offsetof(rsl_contact_input, dt);
            int is_limit = f->offset == offsetof(rsl_contact_input, rolling_friction) ||
                           f->offset == offsetof(rsl_contact_input, twisting_friction) ||
                           f->offset == offsetof(rsl_contact_input, limit_force) ||
                           f->offset == offsetof(rsl_contact_input, shear_adhesion) ||
                           f->offset == offsetof(rsl_contact_input, mass2) ||
                           f->offset == offsetof(rsl_contact_input, inertia2);
            if (is_limit && v == 1) continue; /* +inf: no limit / fixed body (tested with the pair) */
            rsl_contact_input bad = in;
            poke(&bad, f->offset, NONFINITE[v]);
            label(what, sizeof what, "rsl_contact_step_wall", "input", f, v);
            FAIL_STEP(rsl_contact_step_wall(m, &s, &w, &bad, &st, &out),
                      is_dt ? RSL_ERR_INVALID_TIME_STEP : RSL_ERR_NON_FINITE, f->needle, what);
        }
        for (size_t i = 0; i < COUNT(STATE); i++) {
            rsl_contact_state bad = st;
            poke(&bad, STATE[i].offset, NONFINITE[v]);
            rsl_contact_state bad_copy = bad;
            label(what, sizeof what, "rsl_contact_step_wall", "state", &STATE[i], v);
            memset(&out, PATTERN, sizeof out);
            check_failure(rsl_contact_step_wall(m, &s, &w, &in, &bad, &out), RSL_ERR_NON_FINITE,
                          STATE[i].needle, &out, sizeof out, &bad, &bad_copy, sizeof bad, what,
                          __FILE__, __LINE__);
        }
    }
    rsl_contact_input bad = in;
    bad.dt = 0.0;
    FAIL_STEP(rsl_contact_step_wall(m, &s, &w, &bad, &st, &out), RSL_ERR_INVALID_TIME_STEP, "dt", "wall dt");
    bad = in;
    bad.normal_force = -INFINITY;
    FAIL_STEP(rsl_contact_step_wall(m, &s, &w, &bad, &st, &out), RSL_ERR_NON_FINITE, "normal force", "wall f_n");
    bad = in;
    bad.flags = 1u << 31;
    FAIL_STEP(rsl_contact_step_wall(m, &s, &w, &bad, &st, &out), RSL_ERR_INVALID_ARGUMENT, "flags", "wall flags");
    rsl_sphere bs = s;
    bs.radius = -0.7;
    FAIL_STEP(rsl_contact_step_wall(m, &bs, &w, &in, &st, &out), RSL_ERR_INVALID_RADIUS, "radius", "wall radius");
    bs = s;
    bs.position.z = -1.0;
    FAIL_STEP(rsl_contact_step_wall(m, &bs, &w, &in, &st, &out), RSL_ERR_NONPOSITIVE_BRANCH, "l1", "wall branch");
    rsl_wall bw = w;
    bw.normal = rsl_test_vec(0, 0, 0);
    FAIL_STEP(rsl_contact_step_wall(m, &s, &bw, &in, &st, &out), RSL_ERR_INVALID_ARGUMENT, "wall normal", "wall zero normal");
    FAIL_STEP(rsl_contact_step_wall(NULL, &s, &w, &in, &st, &out), RSL_ERR_NULL_POINTER, "model", "wall NULL model");
    FAIL_STEP(rsl_contact_step_wall(m, NULL, &w, &in, &st, &out), RSL_ERR_NULL_POINTER, "sphere", "wall NULL sphere");
    FAIL_STEP(rsl_contact_step_wall(m, &s, NULL, &in, &st, &out), RSL_ERR_NULL_POINTER, "wall", "wall NULL wall");
    FAIL_STEP(rsl_contact_step_wall(m, &s, &w, NULL, &st, &out), RSL_ERR_NULL_POINTER, "null pointer: contact", "wall NULL contact");
    memset(&out, PATTERN, sizeof out);
    check_failure(rsl_contact_step_wall(m, &s, &w, &in, NULL, &out), RSL_ERR_NULL_POINTER, "state",
                  &out, sizeof out, NULL, NULL, 0, "wall NULL state", __FILE__, __LINE__);
    kept = st;
    CHECK_STATUS(rsl_contact_step_wall(m, &s, &w, &in, &st, NULL), RSL_ERR_NULL_POINTER);
    CHECK(memcmp(&st, &kept, sizeof st) == 0);
    memset(raw, 0, sizeof raw);
    FAIL_STEP(rsl_contact_step_wall(MIS(rsl_model), &s, &w, &in, &st, &out), RSL_ERR_MISALIGNED, "model", "wall mis model");
    FAIL_STEP(rsl_contact_step_wall(m, MIS(rsl_sphere), &w, &in, &st, &out), RSL_ERR_MISALIGNED, "sphere", "wall mis sphere");
    FAIL_STEP(rsl_contact_step_wall(m, &s, MIS(rsl_wall), &in, &st, &out), RSL_ERR_MISALIGNED, "wall", "wall mis wall");
    FAIL_STEP(rsl_contact_step_wall(m, &s, &w, MIS(rsl_contact_input), &st, &out), RSL_ERR_MISALIGNED, "misaligned pointer: contact", "wall mis contact");
    CHECK_STATUS(rsl_contact_step_wall(m, &s, &w, &in, MIS(rsl_contact_state), &out), RSL_ERR_MISALIGNED);
    CHECK_STATUS(rsl_contact_step_wall(m, &s, &w, &in, &st, MIS(rsl_contact_loads)), RSL_ERR_MISALIGNED);
    CHECK(memcmp(&st, &kept, sizeof st) == 0);
    static _Alignas(16) unsigned char fake[4096];
    memset(fake, 0, sizeof fake);
    FAIL_STEP(rsl_contact_step_wall((const rsl_model *)(const void *)fake, &s, &w, &in, &st, &out),
              RSL_ERR_INVALID_HANDLE, "handle", "wall zeroed handle");
    rsl_model_free(m);
}

/* ---- the accumulating steps ----------------------------------------------------------- */

/* Accumulators before a step: distinct non-zero values, so that each add shows. */
static void fill_accumulators(rsl_vec3 acc[4]) {
    acc[0] = rsl_test_vec(1.5, -2.25, 3.125);
    acc[1] = rsl_test_vec(-0.75, 0.5, 7.0);
    acc[2] = rsl_test_vec(11.0, 0.0625, -4.5);
    acc[3] = rsl_test_vec(0.375, -9.0, 2.0);
}

static rsl_vec3 added(rsl_vec3 a, rsl_vec3 v, double sign) {
    return sign > 0 ? rsl_test_vec(a.x + v.x, a.y + v.y, a.z + v.z)
                    : rsl_test_vec(a.x - v.x, a.y - v.y, a.z - v.z);
}

/* rsl_contact_step_accumulate (wall: rsl_contact_step_wall_accumulate) against
 * rsl_contact_step (_wall) on the same arguments: same status, same message, same state bytes;
 * the accumulators hold exactly the returned loads added on success, and are untouched on
 * failure. `w` NULL: the pair step with `b`. Returns the status. */
static int32_t mirror(const rsl_model *m, const rsl_sphere *a, const rsl_sphere *b,
                      const rsl_wall *w, const rsl_contact_input *in, const rsl_contact_state *st,
                      const char *what) {
    rsl_contact_state s1 = *st, s2 = *st;
    rsl_contact_loads out;
    memset(&out, 0, sizeof out);
    int32_t status = w ? rsl_contact_step_wall(m, a, w, in, &s1, &out)
                       : rsl_contact_step(m, a, b, in, &s1, &out);
    char message[512];
    snprintf(message, sizeof message, "%s", rsl_last_error_message());
    rsl_vec3 acc[4], expected[4];
    fill_accumulators(acc);
    fill_accumulators(expected);
    int32_t acc_status = w ? rsl_contact_step_wall_accumulate(m, a, w, in, &s2, &acc[0], &acc[1])
                           : rsl_contact_step_accumulate(m, a, b, in, &s2, &acc[0], &acc[1],
                                                         &acc[2], &acc[3]);
    if (status == RSL_OK) {
        expected[0] = added(expected[0], out.force1, 1);
        expected[1] = added(expected[1], out.torque1, 1);
        if (!w) {
            expected[2] = added(expected[2], out.force1, -1);
            expected[3] = added(expected[3], out.torque2, 1);
        }
    }
    int ok = acc_status == status && memcmp(&s1, &s2, sizeof s1) == 0 &&
             memcmp(acc, expected, sizeof acc) == 0 &&
             (status == RSL_OK || strcmp(message, rsl_last_error_message()) == 0);
    if (!ok) {
        fprintf(stderr, "%s: accumulate differs: status %d vs %d, message \"%s\" vs \"%s\"\n",
                what, (int)acc_status, (int)status, rsl_last_error_message(), message);
        rsl_test_failures++;
    }
    return status;
}

/* Every bad input of the two tests above, through the accumulating entry points: they refuse
 * what rsl_contact_step refuses, with the same status and message, and write nothing; on
 * success they add exactly rsl_contact_step's loads. Then their own pointer arguments. */
void test_bad_input_contact_step_accumulate_mirrors_contact_step(void) {
    rsl_model *m = full_model();
    rsl_sphere a, b, s = on_floor();
    pair(&a, &b);
    rsl_wall w = floor_wall();
    rsl_contact_input in = full_input();
    rsl_contact_state st = loaded_state(m), fresh;
    memset(&fresh, 0, sizeof fresh);
    char what[160];
    int refused = 0, accepted = 0;
    /* both paths: every override flag (the checked step), none (the fast path) */
    for (int plain = 0; plain < 2; plain++) {
        rsl_contact_input base = in;
        if (plain) base.flags = 0;
        accepted += mirror(m, &a, &b, NULL, &base, &st, "pair, good input") == RSL_OK;
        accepted += mirror(m, &s, NULL, &w, &base, &fresh, "wall, good input") == RSL_OK;
        for (int v = 0; v < 3; v++) {
            for (size_t i = 0; i < COUNT(SPHERE1); i++) {
                rsl_sphere bad = a;
                poke(&bad, SPHERE1[i].offset, NONFINITE[v]);
                label(what, sizeof what, "accumulate", "body1", &SPHERE1[i], v);
                refused += mirror(m, &bad, &b, NULL, &base, &st, what) != RSL_OK;
                bad = b;
                poke(&bad, SPHERE2[i].offset, NONFINITE[v]);
                label(what, sizeof what, "accumulate", "body2", &SPHERE2[i], v);
                refused += mirror(m, &a, &bad, NULL, &base, &st, what) != RSL_OK;
                bad = s;
                poke(&bad, WALL_SPHERE[i].offset, NONFINITE[v]);
                label(what, sizeof what, "wall accumulate", "sphere", &WALL_SPHERE[i], v);
                refused += mirror(m, &bad, NULL, &w, &base, &fresh, what) != RSL_OK;
            }
            for (size_t i = 0; i < COUNT(WALL); i++) {
                rsl_wall bad = w;
                poke(&bad, WALL[i].offset, NONFINITE[v]);
                label(what, sizeof what, "wall accumulate", "wall", &WALL[i], v);
                refused += mirror(m, &s, NULL, &bad, &base, &fresh, what) != RSL_OK;
            }
            for (size_t i = 0; i < COUNT(INPUT); i++) {
                rsl_contact_input bad = base;
                poke(&bad, INPUT[i].offset, NONFINITE[v]);
                label(what, sizeof what, "accumulate", "input", &INPUT[i], v);
                refused += mirror(m, &a, &b, NULL, &bad, &st, what) != RSL_OK;
                refused += mirror(m, &s, NULL, &w, &bad, &fresh, what) != RSL_OK;
            }
            for (size_t i = 0; i < COUNT(STATE); i++) {
                rsl_contact_state bad = st;
                poke(&bad, STATE[i].offset, NONFINITE[v]);
                label(what, sizeof what, "accumulate", "state", &STATE[i], v);
                refused += mirror(m, &a, &b, NULL, &base, &bad, what) != RSL_OK;
                refused += mirror(m, &s, NULL, &w, &base, &bad, what) != RSL_OK;
            }
        }
        rsl_contact_input bad = base;
        bad.dt = -1e-3;
        refused += mirror(m, &a, &b, NULL, &bad, &st, "accumulate dt < 0") != RSL_OK;
        bad = base;
        bad.normal_force = NAN;
        refused += mirror(m, &a, &b, NULL, &bad, &st, "accumulate f_n NaN") != RSL_OK;
        bad = base;
        bad.flags |= 1u << 12;
        refused += mirror(m, &a, &b, NULL, &bad, &st, "accumulate unknown flag") != RSL_OK;
        rsl_sphere bs = b;
        bs.position = a.position;
        refused += mirror(m, &a, &bs, NULL, &base, &st, "accumulate coincident") != RSL_OK;
        bs.position = rsl_test_vec(1, 2, 3.05);
        refused += mirror(m, &a, &bs, NULL, &base, &st, "accumulate branch") != RSL_OK;
        bs = s;
        bs.position.z = -1.0;
        refused += mirror(m, &bs, NULL, &w, &base, &fresh, "wall accumulate branch") != RSL_OK;
        /* finite input, overflowing result */
        bad = base;
        bad.normal_force = 1e308;
        rsl_contact_state big = st;
        big.sliding_spring = rsl_test_vec(1e300, 0, 0);
        refused += mirror(m, &a, &b, NULL, &bad, &big, "accumulate overflow") != RSL_OK;
        /* the setup pass (the objective preset does not store: the state stays) */
        bad = base;
        bad.flags |= RSL_INPUT_SETUP;
        accepted += mirror(m, &a, &b, NULL, &bad, &st, "accumulate setup") == RSL_OK;
    }
    /* 2 x (3 x (20 + 10 + 12 + 17 x 2 + 13 x 2) refusals at least, some +inf inputs accepted) */
    CHECK(accepted == 6);
    CHECK(refused >= 2 * 3 * (20 + 10 + 12 + 13 * 2));

    /* one vector passed twice (force1 = force2, torque1 = torque2), both paths: each add reads
     * what the previous one wrote */
    for (int plain = 0; plain < 2; plain++) {
        rsl_contact_input base = in;
        if (plain) base.flags = 0;
        rsl_contact_state s1 = st, s2 = st;
        rsl_contact_loads out;
        rsl_vec3 f = rsl_test_vec(1.0, 2.0, 3.0), t = rsl_test_vec(-1.0, 0.5, 4.0);
        CHECK_STATUS(rsl_contact_step(m, &a, &b, &base, &s1, &out), RSL_OK);
        CHECK_STATUS(rsl_contact_step_accumulate(m, &a, &b, &base, &s2, &f, &t, &f, &t), RSL_OK);
        rsl_vec3 ef = added(added(rsl_test_vec(1.0, 2.0, 3.0), out.force1, 1), out.force1, -1);
        rsl_vec3 et = added(added(rsl_test_vec(-1.0, 0.5, 4.0), out.torque1, 1), out.torque2, 1);
        CHECK(memcmp(&f, &ef, sizeof f) == 0);
        CHECK(memcmp(&t, &et, sizeof t) == 0);
        CHECK(memcmp(&s1, &s2, sizeof s1) == 0);
        rsl_vec3 ft = rsl_test_vec(0.25, -0.5, 8.0);
        s2 = fresh;
        s1 = fresh;
        CHECK_STATUS(rsl_contact_step_wall(m, &s, &w, &base, &s1, &out), RSL_OK);
        CHECK_STATUS(rsl_contact_step_wall_accumulate(m, &s, &w, &base, &s2, &ft, &ft), RSL_OK);
        rsl_vec3 eft = added(added(rsl_test_vec(0.25, -0.5, 8.0), out.force1, 1), out.torque1, 1);
        CHECK(memcmp(&ft, &eft, sizeof ft) == 0);
    }

    /* each pointer argument, NULL and misaligned: the accumulators and state stay */
    rsl_vec3 acc[4], kept_acc[4];
    rsl_contact_state kept = st;
    fill_accumulators(acc);
    fill_accumulators(kept_acc);
    memset(raw, 0, sizeof raw);
#define ACC_FAILS(call, expected, needle)                                                   \
    do {                                                                                    \
        check_failure((call), (expected), (needle), NULL, 0, &st, &kept, sizeof st, #call, \
                      __FILE__, __LINE__);                                                  \
        CHECK(memcmp(acc, kept_acc, sizeof acc) == 0);                                      \
    } while (0)
    ACC_FAILS(rsl_contact_step_accumulate(NULL, &a, &b, &in, &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_NULL_POINTER, "model");
    ACC_FAILS(rsl_contact_step_accumulate(m, NULL, &b, &in, &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_NULL_POINTER, "body1");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, NULL, &in, &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_NULL_POINTER, "body2");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, NULL, &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_NULL_POINTER, "null pointer: contact");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, &in, NULL, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_NULL_POINTER, "state");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, &in, &st, NULL, &acc[1], &acc[2], &acc[3]), RSL_ERR_NULL_POINTER, "force1");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, &in, &st, &acc[0], NULL, &acc[2], &acc[3]), RSL_ERR_NULL_POINTER, "torque1");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, &in, &st, &acc[0], &acc[1], NULL, &acc[3]), RSL_ERR_NULL_POINTER, "force2");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, &in, &st, &acc[0], &acc[1], &acc[2], NULL), RSL_ERR_NULL_POINTER, "torque2");
    ACC_FAILS(rsl_contact_step_accumulate(MIS(rsl_model), &a, &b, &in, &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_MISALIGNED, "model");
    ACC_FAILS(rsl_contact_step_accumulate(m, MIS(rsl_sphere), &b, &in, &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_MISALIGNED, "body1");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, MIS(rsl_sphere), &in, &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_MISALIGNED, "body2");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, MIS(rsl_contact_input), &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_MISALIGNED, "misaligned pointer: contact");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, &in, MIS(rsl_contact_state), &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_MISALIGNED, "state");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, &in, &st, MIS(rsl_vec3), &acc[1], &acc[2], &acc[3]), RSL_ERR_MISALIGNED, "force1");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, &in, &st, &acc[0], MIS(rsl_vec3), &acc[2], &acc[3]), RSL_ERR_MISALIGNED, "torque1");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, &in, &st, &acc[0], &acc[1], MIS(rsl_vec3), &acc[3]), RSL_ERR_MISALIGNED, "force2");
    ACC_FAILS(rsl_contact_step_accumulate(m, &a, &b, &in, &st, &acc[0], &acc[1], &acc[2], MIS(rsl_vec3)), RSL_ERR_MISALIGNED, "torque2");
    ACC_FAILS(rsl_contact_step_wall_accumulate(NULL, &s, &w, &in, &st, &acc[0], &acc[1]), RSL_ERR_NULL_POINTER, "model");
    ACC_FAILS(rsl_contact_step_wall_accumulate(m, NULL, &w, &in, &st, &acc[0], &acc[1]), RSL_ERR_NULL_POINTER, "sphere");
    ACC_FAILS(rsl_contact_step_wall_accumulate(m, &s, NULL, &in, &st, &acc[0], &acc[1]), RSL_ERR_NULL_POINTER, "wall");
    ACC_FAILS(rsl_contact_step_wall_accumulate(m, &s, &w, NULL, &st, &acc[0], &acc[1]), RSL_ERR_NULL_POINTER, "null pointer: contact");
    ACC_FAILS(rsl_contact_step_wall_accumulate(m, &s, &w, MIS(rsl_contact_input), &st, &acc[0], &acc[1]), RSL_ERR_MISALIGNED, "misaligned pointer: contact");
    ACC_FAILS(rsl_contact_step_wall_accumulate(m, &s, &w, &in, NULL, &acc[0], &acc[1]), RSL_ERR_NULL_POINTER, "state");
    ACC_FAILS(rsl_contact_step_wall_accumulate(m, &s, &w, &in, &st, NULL, &acc[1]), RSL_ERR_NULL_POINTER, "force");
    ACC_FAILS(rsl_contact_step_wall_accumulate(m, &s, &w, &in, &st, &acc[0], NULL), RSL_ERR_NULL_POINTER, "torque");
    ACC_FAILS(rsl_contact_step_wall_accumulate(m, &s, &w, &in, &st, MIS(rsl_vec3), &acc[1]), RSL_ERR_MISALIGNED, "force");
    ACC_FAILS(rsl_contact_step_wall_accumulate(m, &s, &w, &in, &st, &acc[0], MIS(rsl_vec3)), RSL_ERR_MISALIGNED, "torque");
    static _Alignas(16) unsigned char fake[4096];
    memset(fake, PATTERN, sizeof fake);
    ACC_FAILS(rsl_contact_step_accumulate((const rsl_model *)(const void *)fake, &a, &b, &in, &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_INVALID_HANDLE, "handle");
    /* The unchecked entries test their pointers and handle as the checked ones do. */
    ACC_FAILS(rsl_contact_step_accumulate_unchecked(NULL, &a, &b, &in, &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_NULL_POINTER, "model");
    ACC_FAILS(rsl_contact_step_accumulate_unchecked(m, &a, NULL, &in, &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_NULL_POINTER, "body2");
    ACC_FAILS(rsl_contact_step_accumulate_unchecked(m, &a, &b, &in, NULL, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_NULL_POINTER, "state");
    ACC_FAILS(rsl_contact_step_accumulate_unchecked(m, &a, &b, &in, &st, &acc[0], &acc[1], &acc[2], MIS(rsl_vec3)), RSL_ERR_MISALIGNED, "torque2");
    ACC_FAILS(rsl_contact_step_accumulate_unchecked((const rsl_model *)(const void *)fake, &a, &b, &in, &st, &acc[0], &acc[1], &acc[2], &acc[3]), RSL_ERR_INVALID_HANDLE, "handle");
    ACC_FAILS(rsl_contact_step_wall_accumulate_unchecked(NULL, &s, &w, &in, &st, &acc[0], &acc[1]), RSL_ERR_NULL_POINTER, "model");
    ACC_FAILS(rsl_contact_step_wall_accumulate_unchecked(m, &s, NULL, &in, &st, &acc[0], &acc[1]), RSL_ERR_NULL_POINTER, "wall");
    ACC_FAILS(rsl_contact_step_wall_accumulate_unchecked(m, &s, &w, MIS(rsl_contact_input), &st, &acc[0], &acc[1]), RSL_ERR_MISALIGNED, "misaligned pointer: contact");
    ACC_FAILS(rsl_contact_step_wall_accumulate_unchecked(m, &s, &w, &in, &st, &acc[0], NULL), RSL_ERR_NULL_POINTER, "torque");
    ACC_FAILS(rsl_contact_step_wall_accumulate_unchecked((const rsl_model *)(const void *)fake, &s, &w, &in, &st, &acc[0], &acc[1]), RSL_ERR_INVALID_HANDLE, "handle");
    {
        rsl_contact_loads out;
        rsl_contact_state kept_out = st;
        memset(&out, PATTERN, sizeof out);
        check_failure(rsl_contact_step_unchecked(m, NULL, &b, &in, &st, &out), RSL_ERR_NULL_POINTER,
                      "body1", &out, sizeof out, &st, &kept_out, sizeof st, "unchecked NULL body1",
                      __FILE__, __LINE__);
        check_failure(rsl_contact_step_unchecked((const rsl_model *)(const void *)fake, &a, &b, &in, &st, &out),
                      RSL_ERR_INVALID_HANDLE, "handle", &out, sizeof out, &st, &kept_out,
                      sizeof st, "unchecked handle", __FILE__, __LINE__);
        CHECK_STATUS(rsl_contact_step_unchecked(m, &a, &b, &in, &st, NULL), RSL_ERR_NULL_POINTER);
        check_failure(rsl_contact_step_wall_unchecked(m, &s, MIS(rsl_wall), &in, &st, &out),
                      RSL_ERR_MISALIGNED, "wall", &out, sizeof out, &st, &kept_out, sizeof st,
                      "unchecked wall mis wall", __FILE__, __LINE__);
        CHECK_STATUS(rsl_contact_step_wall_unchecked(m, &s, &w, &in, &st, NULL), RSL_ERR_NULL_POINTER);
        CHECK(memcmp(&st, &kept_out, sizeof st) == 0);
    }
#undef ACC_FAILS
    /* nothing was written through the misaligned pointers either */
    unsigned char zeros[sizeof raw];
    memset(zeros, 0, sizeof zeros);
    CHECK(memcmp(raw, zeros, sizeof raw) == 0);
    rsl_model_free(m);
}

/* ---- model handle and setters ---------------------------------------------------------- */

/* One step of a fixed contact with `m`: a fingerprint of everything the model does. */
static rsl_contact_loads fingerprint(const rsl_model *m) {
    rsl_sphere a, b;
    pair(&a, &b);
    rsl_contact_input in = full_input();
    in.flags = 0;
    rsl_contact_state st = {{1e-3, -2e-3, 0.5e-3}, {2e-3, 1e-3, -1e-3}, 0.01, {0, 0, 0},
                            {0, 0.6, 0.8}, 0, 0};
    rsl_contact_loads out;
    memset(&out, 0, sizeof out);
    CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &out), RSL_OK);
    return out;
}

#define SETTER_FAILS(call, expected, needle, what)                                                \
    do {                                                                                        \
        rsl_contact_loads before_ = fingerprint(m);                                             \
        rsl_rolling_params rp_before_, rp_after_;                                               \
        CHECK_STATUS(rsl_model_get_rolling(m, &rp_before_), RSL_OK);                            \
        check_failure((call), (expected), (needle), NULL, 0, NULL, NULL, 0, (what), __FILE__,   \
                      __LINE__);                                                                \
        rsl_contact_loads after_ = fingerprint(m);                                              \
        CHECK_STATUS(rsl_model_get_rolling(m, &rp_after_), RSL_OK);                             \
        if (memcmp(&before_, &after_, sizeof before_) != 0 ||                                   \
            memcmp(&rp_before_, &rp_after_, sizeof rp_before_) != 0) {                          \
            fprintf(stderr, "%s:%d: %s: a refused setter changed the model\n", __FILE__,        \
                    __LINE__, (what));                                                          \
            rsl_test_failures++;                                                                \
        }                                                                                       \
    } while (0)

void test_bad_input_model_setters_every_parameter(void) {
    rsl_model *m = full_model();
    char what[160];
    const double bad_values[4] = {NAN, INFINITY, -INFINITY, -1.0};
    const char *bad_names[4] = {"NaN", "+inf", "-inf", "-1"};
    for (int v = 0; v < 4; v++) {
        for (int arg = 0; arg < 3; arg++) {
            double x[3] = {1e3, 0.5, 0.4};
            x[arg] = bad_values[v];
            const char *sl_needle[3] = {"k_t", "gamma_t", "mu_s"};
            const char *tw_needle[3] = {"k_tw", "gamma_tw", "mu_tw"};
            snprintf(what, sizeof what, "set_sliding arg %d = %s", arg, bad_names[v]);
            int inf_friction_ok = (arg == 2 && v == 1);
            if (inf_friction_ok) {
                /* mu = +inf: no limit, accepted (then restored) */
                CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, x[0], x[1], x[2]), RSL_OK);
                CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e3, 0.5, 0.4), RSL_OK);
                CHECK_STATUS(rsl_model_set_twisting(m, RSL_TWISTING_SDS, x[0], x[1], x[2]), RSL_OK);
                CHECK_STATUS(rsl_model_set_twisting(m, RSL_TWISTING_SDS, 50.0, 0.05, 0.05), RSL_OK);
                continue;
            }
            SETTER_FAILS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, x[0], x[1], x[2]),
                         RSL_ERR_INVALID_PARAMETER, sl_needle[arg], what);
            snprintf(what, sizeof what, "set_twisting arg %d = %s", arg, bad_names[v]);
            SETTER_FAILS(rsl_model_set_twisting(m, RSL_TWISTING_SDS, x[0], x[1], x[2]),
                         RSL_ERR_INVALID_PARAMETER, tw_needle[arg], what);
        }
        rsl_rolling_params good;
        CHECK_STATUS(rsl_model_get_rolling(m, &good), RSL_OK);
        for (size_t i = 0; i < COUNT(ROLLING); i++) {
            rsl_rolling_params p = good;
            poke(&p, ROLLING[i].offset, bad_values[v]);
            snprintf(what, sizeof what, "set_rolling %s = %s", ROLLING[i].name, bad_names[v]);
            if (ROLLING[i].offset == offsetof(rsl_rolling_params, friction) && v == 1) {
                CHECK_STATUS(rsl_model_set_rolling(m, &p), RSL_OK); /* no limit */
                CHECK_STATUS(rsl_model_set_rolling(m, &good), RSL_OK);
                continue;
            }
            SETTER_FAILS(rsl_model_set_rolling(m, &p), RSL_ERR_INVALID_PARAMETER,
                         ROLLING[i].needle, what);
        }
    }
    /* cdt: the limit moment must be finite */
    rsl_rolling_params p;
    CHECK_STATUS(rsl_model_get_rolling(m, &p), RSL_OK);
    p.law = RSL_ROLLING_CDT;
    p.friction = INFINITY;
    SETTER_FAILS(rsl_model_set_rolling(m, &p), RSL_ERR_INVALID_PARAMETER, "rolling friction",
                 "cdt infinite friction");
    /* every integer code out of range */
    const int32_t codes[4] = {-1, 4, 99, INT32_MIN};
    for (int c = 0; c < 4; c++) {
        rsl_model *other = NULL;
        CHECK_STATUS(rsl_model_new(codes[c], &other), RSL_ERR_INVALID_PARAMETER);
        CHECK(other == NULL);
        CHECK(strstr(rsl_last_error_message(), "preset") != NULL);
        SETTER_FAILS(rsl_model_set_sliding(m, codes[c] == 4 ? 2 : codes[c], 1, 0, 0.5),
                     RSL_ERR_INVALID_PARAMETER, "sliding law", "sliding law code");
        SETTER_FAILS(rsl_model_set_twisting(m, codes[c] == 4 ? 3 : codes[c], 1, 0, 0.5),
                     RSL_ERR_INVALID_PARAMETER, "twisting law", "twisting law code");
        SETTER_FAILS(rsl_model_set_geometry(m, codes[c], 0), RSL_ERR_INVALID_PARAMETER,
                     "branch_rule", "branch code");
        SETTER_FAILS(rsl_model_set_geometry(m, 0, codes[c]), RSL_ERR_INVALID_PARAMETER,
                     "rolling_radius_rule", "rolling radius code");
        SETTER_FAILS(rsl_model_set_transport(m, codes[c] == 4 ? 5 : codes[c], 0),
                     RSL_ERR_INVALID_PARAMETER, "transport", "sliding transport code");
        SETTER_FAILS(rsl_model_set_transport(m, 0, codes[c] == 4 ? 5 : codes[c]),
                     RSL_ERR_INVALID_PARAMETER, "transport", "rolling transport code");
        SETTER_FAILS(rsl_model_set_energy_tracking(m, codes[c]), RSL_ERR_INVALID_PARAMETER,
                     "energy tracking", "energy flag");
        const char *needles[5] = {"rolling law", "rolling form", "stiffness_rule", "damping_rule",
                                  "damping_mode"};
        for (int k = 0; k < 5; k++) {
            rsl_rolling_params q;
            CHECK_STATUS(rsl_model_get_rolling(m, &q), RSL_OK);
            int32_t code = codes[c] == 4 ? 17 : codes[c];
            switch (k) {
            case 0: q.law = code; break;
            case 1: q.form = code; break;
            case 2: q.stiffness_rule = code; break;
            case 3: q.damping_rule = code; break;
            default: q.damping_mode = code; break;
            }
            snprintf(what, sizeof what, "rolling code %s = %d", needles[k], (int)code);
            SETTER_FAILS(rsl_model_set_rolling(m, &q), RSL_ERR_INVALID_PARAMETER, needles[k],
                         what);
        }
    }
    /* handles that are not live models */
    static _Alignas(16) unsigned char fake[4096];
    rsl_model *zero = (rsl_model *)(void *)fake;
    for (int pattern = 0; pattern < 2; pattern++) {
        memset(fake, pattern ? PATTERN : 0, sizeof fake);
        CHECK_STATUS(rsl_model_set_geometry(zero, 0, 0), RSL_ERR_INVALID_HANDLE);
        CHECK(strstr(rsl_last_error_message(), "handle") != NULL);
        CHECK_STATUS(rsl_model_set_sliding(zero, RSL_SLIDING_LINEAR, 1, 0, 0.5), RSL_ERR_INVALID_HANDLE);
        CHECK_STATUS(rsl_model_set_twisting(zero, RSL_TWISTING_SDS, 1, 0, 0.5), RSL_ERR_INVALID_HANDLE);
        CHECK_STATUS(rsl_model_set_rolling(zero, &p), RSL_ERR_INVALID_HANDLE);
        rsl_rolling_params got;
        memset(&got, PATTERN, sizeof got);
        CHECK_STATUS(rsl_model_get_rolling(zero, &got), RSL_ERR_INVALID_HANDLE);
        CHECK(all_pattern(&got, sizeof got));
        CHECK_STATUS(rsl_model_set_transport(zero, 0, 0), RSL_ERR_INVALID_HANDLE);
        CHECK_STATUS(rsl_model_set_energy_tracking(zero, 1), RSL_ERR_INVALID_HANDLE);
        rsl_model_free(zero); /* not a live model: ignored, the buffer is untouched */
        CHECK(all_pattern(fake, sizeof fake) == pattern);
    }
    rsl_model_free(m);
}

void test_bad_input_time_step_helpers(void) {
    double out;
    const double nf[3] = {NAN, INFINITY, -INFINITY};
    const char *names[4] = {"k_theta", "inertia1", "inertia2", "damping_ratio"};
    for (int v = 0; v < 3; v++) {
        for (int arg = 0; arg < 4; arg++) {
            double x[4] = {4.0, 1.0, 1.0, 0.3};
            x[arg] = nf[v];
            if (arg == 2 && v == 1) {
                CHECK_STATUS(rsl_rotational_critical_time_step(x[0], x[1], x[2], x[3], &out),
                             RSL_OK); /* wall */
                continue;
            }
            FAIL_OUT(rsl_rotational_critical_time_step(x[0], x[1], x[2], x[3], &out),
                     RSL_ERR_NON_FINITE, names[arg], &out, names[arg]);
        }
    }
    FAIL_OUT(rsl_rotational_critical_time_step(-1.0, 1, 1, 0, &out), RSL_ERR_INVALID_ARGUMENT,
             "k_theta", &out, "k_theta < 0");
    FAIL_OUT(rsl_rotational_critical_time_step(1.0, 0.0, 1, 0, &out), RSL_ERR_INVALID_ARGUMENT,
             "inertia1", &out, "I1 = 0");
    FAIL_OUT(rsl_rotational_critical_time_step(1.0, 1, 1, -0.5, &out), RSL_ERR_INVALID_ARGUMENT,
             "damping_ratio", &out, "z < 0");
    /* finite but extreme: w0 underflows to 0 */
    FAIL_OUT(rsl_rotational_critical_time_step(1e-320, 1e300, 1e300, 0, &out), RSL_ERR_NON_FINITE,
             "overflow", &out, "w0 underflow");
    /* large damping ratios stay accurate: dt_c ~ 1/(w0 z) */
    CHECK_STATUS(rsl_rotational_critical_time_step(1.0, 2.0, INFINITY, 1e10, &out), RSL_OK);
    CHECK_CLOSE(out, (2.0 / sqrt(0.5)) / (2e10), 0.0, 1e-12);

    const char *cnames[8] = {"k_t", "k_theta", "mass1", "mass2", "inertia1", "inertia2", "l1", "l2"};
    for (int v = 0; v < 3; v++) {
        for (int arg = 0; arg < 8; arg++) {
            double x[8] = {100.0, 4.0, 1.0, 2.0, 0.5, 0.25, 0.3, 0.2};
            x[arg] = nf[v];
            int wall_ok = v == 1 && (arg == 3 || arg == 5);
            if (wall_ok) {
                CHECK_STATUS(rsl_coupled_critical_time_step(x[0], x[1], x[2], x[3], x[4], x[5],
                                                            x[6], x[7], &out),
                             RSL_OK);
                continue;
            }
            char what[64];
            snprintf(what, sizeof what, "coupled %s", cnames[arg]);
            FAIL_OUT(rsl_coupled_critical_time_step(x[0], x[1], x[2], x[3], x[4], x[5], x[6],
                                                    x[7], &out),
                     RSL_ERR_NON_FINITE, cnames[arg], &out, what);
        }
    }
    FAIL_OUT(rsl_coupled_critical_time_step(0, 0, 1, 1, 1, 1, 1, 1, &out),
             RSL_ERR_INVALID_ARGUMENT, "both 0", &out, "no stiffness");
    FAIL_OUT(rsl_coupled_critical_time_step(1, 1, 1, 1, 1, 1, -1, 1, &out),
             RSL_ERR_INVALID_ARGUMENT, "l1", &out, "l1 < 0");
    FAIL_OUT(rsl_coupled_critical_time_step(1e-320, 0, 1e300, 1e300, 1e300, 1e300, 1e-300,
                                            1e-300, &out),
             RSL_ERR_NON_FINITE, "overflow", &out, "coupled underflow");
}

void test_bad_input_status_codes_are_distinct(void) {
    /* Every status has its own non-empty static description; unknown codes have one too. */
    for (int32_t a = 0; a <= RSL_ERR_INVALID_HANDLE; a++) {
        const char *sa = rsl_status_str(a);
        CHECK(sa != NULL && sa[0] != '\0' && strcmp(sa, "unknown status") != 0);
        for (int32_t b = a + 1; b <= RSL_ERR_INVALID_HANDLE; b++)
            CHECK(strcmp(sa, rsl_status_str(b)) != 0);
    }
    CHECK(strcmp(rsl_status_str(-1), "unknown status") == 0);
    CHECK(strcmp(rsl_status_str(INT32_MAX), "unknown status") == 0);
    CHECK(strcmp(rsl_status_str(INT32_MIN), "unknown status") == 0);
}

/* ---- the batch API: length arguments, and what happens to the other contacts ------------ */

#define NB 12

/* NB contacts of the case-6 pair, shifted apart, with a bad contact at `bad` (if >= 0). */
static void batch_bodies(rsl_sphere *b1, rsl_sphere *b2) {
    for (int c = 0; c < NB; c++) {
        pair(&b1[c], &b2[c]);
        b1[c].position.x += 10.0 * c;
        b2[c].position.x += 10.0 * c;
        b1[c].angular_velocity.z += 0.1 * c;
    }
}

void test_bad_input_batch_lengths_and_other_contacts(void) {
    rsl_model *m = full_model();
    rsl_sphere b1[NB], b2[NB];
    double fn[NB];
    rsl_contact_state st[NB], st_copy[NB];
    rsl_batch_loads out[NB];
    rsl_batch_report rep;
    rsl_batch_options scalar;
    memset(&scalar, 0, sizeof scalar);
    scalar.simd = RSL_SIMD_SCALAR;
    batch_bodies(b1, b2);
    for (int c = 0; c < NB; c++) fn[c] = 10.0 + c;
    memset(st, 0, sizeof st);

    /* n = 0 with NULL arrays: nothing to do, OK */
    CHECK_STATUS(rsl_batch_step_contacts(m, NULL, NULL, 0, NULL, NULL, 1e-3, NULL, NULL, NULL, &rep),
                 RSL_OK);
    CHECK(rep.processed == 0 && rep.failed == 0 && rep.first_failed == RSL_BATCH_NONE);
    /* NULL array with n > 0: each array argument named; nothing written */
    memset(out, PATTERN, sizeof out);
    memcpy(st_copy, st, sizeof st);
    CHECK_STATUS(rsl_batch_step_contacts(m, NULL, b2, NB, fn, NULL, 1e-3, &scalar, st, out, &rep), RSL_ERR_NULL_POINTER);
    CHECK(strstr(rsl_last_error_message(), "body1") != NULL);
    CHECK_STATUS(rsl_batch_step_contacts(m, b1, NULL, NB, fn, NULL, 1e-3, &scalar, st, out, &rep), RSL_ERR_NULL_POINTER);
    CHECK(strstr(rsl_last_error_message(), "body2") != NULL);
    CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, NB, NULL, NULL, 1e-3, &scalar, st, out, &rep), RSL_ERR_NULL_POINTER);
    CHECK(strstr(rsl_last_error_message(), "normal_force") != NULL);
    CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, NB, fn, NULL, 1e-3, &scalar, NULL, out, &rep), RSL_ERR_NULL_POINTER);
    CHECK(strstr(rsl_last_error_message(), "states") != NULL);
    CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, NB, fn, NULL, 1e-3, &scalar, st, NULL, &rep), RSL_ERR_NULL_POINTER);
    CHECK(rep.processed == 0 && rep.failed == 0 && rep.first_status == RSL_ERR_NULL_POINTER);
    /* a length whose byte size overflows: refused before any access */
    CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, SIZE_MAX, fn, NULL, 1e-3, &scalar, st, out, &rep),
                 RSL_ERR_INVALID_ARGUMENT);
    CHECK(strstr(rsl_last_error_message(), "too large") != NULL);
    CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, SIZE_MAX / 2, fn, NULL, 1e-3, &scalar, st, out, &rep),
                 RSL_ERR_INVALID_ARGUMENT);
    /* call-level errors: handle, dt, options */
    static _Alignas(16) unsigned char fake[4096];
    memset(fake, 0, sizeof fake);
    CHECK_STATUS(rsl_batch_step_contacts((const rsl_model *)(const void *)fake, b1, b2, NB, fn, NULL, 1e-3, &scalar, st, out, &rep),
                 RSL_ERR_INVALID_HANDLE);
    CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, NB, fn, NULL, NAN, &scalar, st, out, &rep), RSL_ERR_INVALID_TIME_STEP);
    CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, NB, fn, NULL, 0.0, &scalar, st, out, &rep), RSL_ERR_INVALID_TIME_STEP);
    rsl_batch_options bo = scalar;
    bo.precision = 7;
    CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, NB, fn, NULL, 1e-3, &bo, st, out, &rep), RSL_ERR_INVALID_ARGUMENT);
    bo = scalar;
    bo.simd = 99;
    CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, NB, fn, NULL, 1e-3, &bo, st, out, &rep), RSL_ERR_INVALID_ARGUMENT);
    /* no flag is defined: any set bit is refused (bit 0 was RSL_BATCH_GENERIC before 0.3.0) */
    for (int bit = 0; bit < 32; bit += 31) {
        bo = scalar;
        bo.flags = 1u << bit;
        CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, NB, fn, NULL, 1e-3, &bo, st, out, &rep), RSL_ERR_INVALID_ARGUMENT);
        CHECK(strstr(rsl_last_error_message(), "flags") != NULL);
        CHECK(rep.processed == 0 && rep.failed == 0);
    }
    CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, NB, fn, NULL, 1e-3, MIS(rsl_batch_options), st, out, &rep), RSL_ERR_MISALIGNED);
    CHECK_STATUS(rsl_batch_step_contacts(m, MIS(rsl_sphere), b2, NB, fn, NULL, 1e-3, &scalar, st, out, &rep), RSL_ERR_MISALIGNED);
    CHECK(all_pattern(out, sizeof out));
    CHECK(memcmp(st, st_copy, sizeof st) == 0);

    /* Bad contacts among good ones: 3 (NaN velocity), 7 (coincident centres), 8 (f_n < 0),
     * 11 (NaN state). They are skipped untouched; every other contact gives exactly what
     * rsl_contact_step gives for it; the status and report name the first bad one. */
    for (int round = 0; round < 3; round++) {
        rsl_sphere c1[NB], c2[NB];
        memcpy(c1, b1, sizeof c1);
        memcpy(c2, b2, sizeof c2);
        double f[NB];
        memcpy(f, fn, sizeof f);
        c1[3].velocity.y = NAN;
        c2[7].position = c1[7].position;
        f[8] = NAN;
        rsl_contact_state s[NB], ref_state[NB];
        memcpy(s, st, sizeof s);
        s[11].rolling_spring.z = NAN;
        memcpy(ref_state, s, sizeof s);
        memcpy(st_copy, s, sizeof s);
        memset(out, PATTERN, sizeof out);
        memset(&rep, PATTERN, sizeof rep);
        CHECK_STATUS(rsl_batch_step_contacts(m, c1, c2, NB, f, NULL, 1e-3, &scalar, s, out, &rep), RSL_ERR_NON_FINITE);
        CHECK(rep.processed == NB - 4 && rep.failed == 4 && rep.first_failed == 3 &&
              rep.first_status == RSL_ERR_NON_FINITE);
        for (int c = 0; c < NB; c++) {
            int bad = c == 3 || c == 7 || c == 8 || c == 11;
            if (bad) {
                CHECK(all_pattern(&out[c], sizeof out[c]));
                CHECK(memcmp(&s[c], &st_copy[c], sizeof s[c]) == 0);
                continue;
            }
            rsl_contact_input in;
            memset(&in, 0, sizeof in);
            in.normal_force = f[c];
            in.dt = 1e-3;
            rsl_contact_loads one;
            CHECK_STATUS(rsl_contact_step(m, &c1[c], &c2[c], &in, &ref_state[c], &one), RSL_OK);
            CHECK(memcmp(&s[c], &ref_state[c], sizeof s[c]) == 0);
            CHECK(memcmp(&out[c].force1, &one.force1, sizeof one.force1) == 0);
            CHECK(memcmp(&out[c].torque1, &one.torque1, sizeof one.torque1) == 0);
            CHECK(memcmp(&out[c].torque2, &one.torque2, sizeof one.torque2) == 0);
        }
        memcpy(st, s, sizeof s); /* carry the good contacts' history to the next round */
        st[11].rolling_spring.z = 0.0;
    }

    /* Particle-major: indices out of range are skipped like any bad contact. */
    rsl_sphere parts[2 * NB];
    uint32_t pairs[2 * NB];
    for (int c = 0; c < NB; c++) {
        parts[2 * c] = b1[c];
        parts[2 * c + 1] = b2[c];
        pairs[2 * c] = 2 * c;
        pairs[2 * c + 1] = 2 * c + 1;
    }
    pairs[2 * 5 + 1] = 2 * NB;   /* one past the end */
    pairs[2 * 9] = UINT32_MAX;
    rsl_vec3 force[2 * NB], torque[2 * NB];
    memset(force, 0, sizeof force);
    memset(torque, 0, sizeof torque);
    memset(st, 0, sizeof st);
    memcpy(st_copy, st, sizeof st);
    CHECK_STATUS(rsl_batch_step(m, parts, 2 * NB, pairs, NB, fn, NULL, 1e-3, &scalar, st, force, torque, &rep),
                 RSL_ERR_INVALID_ARGUMENT);
    CHECK(strstr(rsl_last_error_message(), "index") != NULL);
    CHECK(rep.processed == NB - 2 && rep.failed == 2 && rep.first_failed == 5);
    CHECK(memcmp(&st[5], &st_copy[5], sizeof st[5]) == 0 && memcmp(&st[9], &st_copy[9], sizeof st[9]) == 0);
    CHECK(force[10].x == 0.0 && force[11].x == 0.0 && force[18].x == 0.0 && force[19].x == 0.0);
    CHECK(force[0].x != 0.0);
    /* n_particles shorter than the arrays claim: caught as out-of-range indices, not read */
    CHECK_STATUS(rsl_batch_step(m, parts, 4, pairs, NB, fn, NULL, 1e-3, &scalar, st, force, torque, &rep),
                 RSL_ERR_INVALID_ARGUMENT);
    CHECK(rep.processed == 2);
    CHECK_STATUS(rsl_batch_step(m, NULL, 2 * NB, pairs, NB, fn, NULL, 1e-3, &scalar, st, force, torque, &rep),
                 RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_batch_step(m, parts, 2 * NB, NULL, NB, fn, NULL, 1e-3, &scalar, st, force, torque, &rep),
                 RSL_ERR_NULL_POINTER);
    CHECK(strstr(rsl_last_error_message(), "pairs") != NULL);
    CHECK_STATUS(rsl_batch_step(m, parts, SIZE_MAX, pairs, NB, fn, NULL, 1e-3, &scalar, st, force, torque, &rep),
                 RSL_ERR_INVALID_ARGUMENT);

    /* Decomposition batches: the same skipping, and the same bits as rsl_decompose. */
    rsl_decomposition dout[NB], one;
    rsl_sphere c1[NB];
    memcpy(c1, b1, sizeof c1);
    c1[4].radius = -1.0;
    memset(dout, PATTERN, sizeof dout);
    CHECK_STATUS(rsl_batch_decompose_contacts(c1, b2, NB, NULL, &scalar, dout, &rep), RSL_ERR_INVALID_RADIUS);
    CHECK(rep.processed == NB - 1 && rep.failed == 1 && rep.first_failed == 4);
    for (int c = 0; c < NB; c++) {
        if (c == 4) {
            CHECK(all_pattern(&dout[c], sizeof dout[c]));
            continue;
        }
        CHECK_STATUS(rsl_decompose(&c1[c], &b2[c], NULL, &one), RSL_OK);
        CHECK(memcmp(&dout[c], &one, sizeof one) == 0);
    }
    CHECK_STATUS(rsl_batch_decompose_contacts(NULL, NULL, 0, NULL, NULL, NULL, NULL), RSL_OK);
    CHECK_STATUS(rsl_batch_decompose_contacts(c1, b2, NB, NULL, &scalar, NULL, NULL), RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_batch_decompose_contacts(c1, b2, SIZE_MAX, NULL, &scalar, dout, NULL), RSL_ERR_INVALID_ARGUMENT);
    rsl_decompose_options o = rsl_decompose_options_default();
    o.parts = 1u << 20;
    CHECK_STATUS(rsl_batch_decompose_contacts(c1, b2, NB, &o, &scalar, dout, NULL), RSL_ERR_INVALID_ARGUMENT);
    CHECK_STATUS(rsl_batch_decompose(parts, 2 * NB, pairs, NB, NULL, &scalar, dout, &rep), RSL_ERR_INVALID_ARGUMENT);
    CHECK(rep.failed == 2 && rep.first_failed == 5);
    CHECK_STATUS(rsl_batch_decompose(parts, SIZE_MAX, pairs, NB, NULL, &scalar, dout, &rep), RSL_ERR_INVALID_ARGUMENT);
    rsl_model_free(m);
}
