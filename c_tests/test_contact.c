/* The per-contact step through the C ABI: model handle and setters, a gear-rolling ramp
 * against its closed form, walls, and the error contract (bad input leaves state and outputs
 * byte-for-byte untouched; bad parameters leave the model unchanged). */
#include "rollslide.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "rsl_test.h"

static rsl_sphere sphere(double x, double wz, double r) {
    rsl_sphere s;
    memset(&s, 0, sizeof s);
    s.position.x = x;
    s.angular_velocity.z = wz;
    s.radius = r;
    return s;
}

static rsl_model *gear_model(void) {
    rsl_model *m = NULL;
    CHECK_STATUS(rsl_model_new(RSL_PRESET_OBJECTIVE, &m), RSL_OK);
    rsl_rolling_params p;
    CHECK_STATUS(rsl_model_get_rolling(m, &p), RSL_OK);
    p.law = RSL_ROLLING_EPSD;
    p.stiffness = 50.0;
    p.friction = 0.1;
    CHECK_STATUS(rsl_model_set_rolling(m, &p), RSL_OK);
    CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e3, 0.0, 0.5), RSL_OK);
    CHECK_STATUS(rsl_model_set_twisting(m, RSL_TWISTING_SDS, 10.0, 0.0, 0.01), RSL_OK);
    return m;
}

/* Gear at fixed centres (kinematics.md case 3): v_r = (0, 1.4, 0); the rolling spring grows by
 * v_r dt until k_r |xi| = mu_r f_n (step 15), then the moment stays at mu_r R_r f_n. */
void test_contact_gear_ramp_and_clip(void) {
    rsl_model *m = gear_model();
    rsl_sphere a = sphere(0.0, 2.0, 0.7), b = sphere(3.0, -2.0 * 0.7 / 2.3, 2.3);
    rsl_contact_state st;
    CHECK_STATUS(rsl_contact_state_init(&st), RSL_OK);
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = 10.0;
    in.dt = 1e-3;
    double r_r = 0.7 * 2.3 / 3.0;
    for (int step = 1; step <= 30; step++) {
        rsl_contact_loads out;
        CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &out), RSL_OK);
        double xi = 1.4 * step * 1e-3, f = 50.0 * xi;
        if (f > 1.0) f = 1.0; /* mu_r f_n */
        /* F_r = -f y; moment R_r n x F_r = -R_r f z (n = +x). 1e-12: step*dt rounding. */
        CHECK_CLOSE(out.rolling_moment.z, -r_r * f, 1e-12, 1e-12);
        CHECK_CLOSE(out.torque2.z, r_r * f, 1e-12, 1e-12);
        CHECK(((out.slip_flags & RSL_SLIP_ROLLING) != 0) == (step >= 15));
        CHECK(st.slip_flags == out.slip_flags);
        CHECK_CLOSE(out.force1.x, -10.0, 1e-12, 0); /* -f_n n: body 1 is pushed away from body 2 */
    }
    rsl_model_free(m);
}

void test_contact_wall_step_and_setup(void) {
    rsl_model *m = gear_model();
    rsl_sphere ball = sphere(0.0, 0.0, 0.5);
    ball.position.z = 0.499;
    ball.velocity.x = 1.0;
    ball.angular_velocity.y = 2.0; /* rolling: w = V x n / R with n = -z */
    rsl_wall wall;
    memset(&wall, 0, sizeof wall);
    wall.normal.z = 1.0;
    rsl_contact_state st, before;
    memset(&st, 0, sizeof st);
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = 1.0;
    in.dt = 1e-3;
    rsl_contact_loads out;
    /* The setup pass computes loads and leaves the state as it was (objective preset). */
    in.flags = RSL_INPUT_SETUP;
    before = st;
    CHECK_STATUS(rsl_contact_step_wall(m, &ball, &wall, &in, &st, &out), RSL_OK);
    CHECK(memcmp(&st, &before, sizeof st) == 0);
    in.flags = 0;
    CHECK_STATUS(rsl_contact_step_wall(m, &ball, &wall, &in, &st, &out), RSL_OK);
    /* Rolled distance after one step: (l1/R) V dt along -x, l1 = R - delta/2. */
    CHECK_CLOSE(st.rolling_spring.x, -(0.4995 / 0.5) * 1e-3, 1e-15, 1e-12);
    CHECK_CLOSE(st.previous_normal.z, -1.0, 0, 0);
    rsl_model_free(m);
}

#define EXPECT_STEP_FAIL(call, status)                              \
    do {                                                            \
        memset(&out, 0xA5, sizeof out);                             \
        rsl_contact_state copy_ = st;                               \
        CHECK_STATUS(call, status);                                 \
        CHECK(memcmp(&copy_, &st, sizeof st) == 0);                 \
        unsigned char pat_[sizeof out];                             \
        memset(pat_, 0xA5, sizeof pat_);                            \
        CHECK(memcmp(&out, pat_, sizeof out) == 0);                 \
    } while (0)

void test_contact_bad_input_leaves_state_untouched(void) {
    rsl_model *m = gear_model();
    rsl_sphere a = sphere(0.0, 2.0, 0.7), b = sphere(2.99, -1.0, 2.3);
    rsl_contact_state st;
    memset(&st, 0, sizeof st);
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = 10.0;
    in.dt = 1e-3;
    rsl_contact_loads out;
    for (int i = 0; i < 5; i++) CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &out), RSL_OK);

    rsl_contact_input bad = in;
    bad.dt = 0.0;
    EXPECT_STEP_FAIL(rsl_contact_step(m, &a, &b, &bad, &st, &out), RSL_ERR_INVALID_TIME_STEP);
    bad = in;
    bad.normal_force = NAN;
    EXPECT_STEP_FAIL(rsl_contact_step(m, &a, &b, &bad, &st, &out), RSL_ERR_NON_FINITE);
    bad = in;
    bad.flags = 1u << 30;
    EXPECT_STEP_FAIL(rsl_contact_step(m, &a, &b, &bad, &st, &out), RSL_ERR_INVALID_ARGUMENT);
    rsl_sphere nan_sphere = a;
    nan_sphere.velocity.y = INFINITY;
    EXPECT_STEP_FAIL(rsl_contact_step(m, &nan_sphere, &b, &in, &st, &out), RSL_ERR_NON_FINITE);
    rsl_sphere same = b;
    same.position = a.position;
    EXPECT_STEP_FAIL(rsl_contact_step(m, &a, &same, &in, &st, &out), RSL_ERR_COINCIDENT_CENTRES);
    EXPECT_STEP_FAIL(rsl_contact_step(NULL, &a, &b, &in, &st, &out), RSL_ERR_NULL_POINTER);
    EXPECT_STEP_FAIL(rsl_contact_step(m, &a, &b, NULL, &st, &out), RSL_ERR_NULL_POINTER);
    /* A corrupted state (NaN history) is refused, not propagated. */
    rsl_contact_state corrupt = st;
    corrupt.rolling_spring.y = NAN;
    rsl_contact_state corrupt_copy = corrupt;
    CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &corrupt, &out), RSL_ERR_NON_FINITE);
    CHECK(memcmp(&corrupt, &corrupt_copy, sizeof corrupt) == 0);
    /* A pointer that is not a model (all zero bytes) is refused as an invalid handle. */
    _Alignas(16) unsigned char not_a_model[1024];
    memset(not_a_model, 0, sizeof not_a_model);
    EXPECT_STEP_FAIL(rsl_contact_step((const rsl_model *)(const void *)not_a_model, &a, &b, &in, &st, &out),
                     RSL_ERR_INVALID_HANDLE);
    rsl_model_free(m);
    rsl_model_free(NULL); /* accepted */
}

void test_model_setters_validate_and_keep_the_model(void) {
    rsl_model *m = NULL;
    CHECK_STATUS(rsl_model_new(99, &m), RSL_ERR_INVALID_PARAMETER);
    CHECK(m == NULL);
    CHECK_STATUS(rsl_model_new(RSL_PRESET_LIGGGHTS_3_8, &m), RSL_OK);
    rsl_rolling_params p, kept;
    CHECK_STATUS(rsl_model_get_rolling(m, &p), RSL_OK);
    /* The LIGGGHTS preset's conventions show through the getter. */
    CHECK(p.form == RSL_FORM_ANGLE && p.damping_mode == RSL_DAMPING_BELOW_LIMIT);
    p.law = RSL_ROLLING_EPSD;
    p.stiffness = 3.0;
    CHECK_STATUS(rsl_model_set_rolling(m, &p), RSL_OK);
    kept = p;
    p.stiffness = -1.0;
    CHECK_STATUS(rsl_model_set_rolling(m, &p), RSL_ERR_INVALID_PARAMETER);
    CHECK(strstr(rsl_last_error_message(), "rolling stiffness") != NULL);
    p = kept;
    p.law = 17;
    CHECK_STATUS(rsl_model_set_rolling(m, &p), RSL_ERR_INVALID_PARAMETER);
    CHECK(strstr(rsl_last_error_message(), "rolling law") != NULL);
    p = kept;
    p.stiffness_rule = RSL_STIFFNESS_EPSD3;
    p.stiffness_factor = 0.0;
    CHECK_STATUS(rsl_model_set_rolling(m, &p), RSL_ERR_INVALID_PARAMETER);
    CHECK(strstr(rsl_last_error_message(), "stiffness_factor") != NULL);
    rsl_rolling_params now;
    CHECK_STATUS(rsl_model_get_rolling(m, &now), RSL_OK);
    CHECK(memcmp(&now, &kept, sizeof now) == 0);
    CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1.0, NAN, 0.5), RSL_ERR_INVALID_PARAMETER);
    CHECK(strstr(rsl_last_error_message(), "gamma_t") != NULL);
    CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1.0, 0.0, INFINITY), RSL_OK);
    CHECK_STATUS(rsl_model_set_twisting(m, 5, 1.0, 0.0, 0.1), RSL_ERR_INVALID_PARAMETER);
    CHECK_STATUS(rsl_model_set_transport(m, RSL_TRANSPORT_EXACT, 9), RSL_ERR_INVALID_PARAMETER);
    CHECK_STATUS(rsl_model_set_geometry(m, RSL_BRANCH_RADII, 4), RSL_ERR_INVALID_PARAMETER);
    CHECK_STATUS(rsl_model_set_energy_tracking(m, 2), RSL_ERR_INVALID_PARAMETER);
    CHECK_STATUS(rsl_model_set_energy_tracking(m, 1), RSL_OK);
    rsl_model_free(m);
}

void test_critical_time_steps(void) {
    double dt = 0.0;
    CHECK_STATUS(rsl_rotational_critical_time_step(4.0, 1.0, INFINITY, 0.0, &dt), RSL_OK);
    CHECK_CLOSE(dt, 1.0, 0, 1e-15); /* w0 = 2: dt = 2/w0 */
    CHECK_STATUS(rsl_rotational_critical_time_step(4.0, 0.0, 1.0, 0.0, &dt), RSL_ERR_INVALID_ARGUMENT);
    CHECK_CLOSE(dt, 1.0, 0, 0); /* untouched on error */
    CHECK_STATUS(rsl_coupled_critical_time_step(1.0, 0.0, 1.0, INFINITY, 1.0, INFINITY, 1.0, 1.0, &dt), RSL_OK);
    CHECK_CLOSE(dt, 2.0 / sqrt(2.0), 0, 1e-15); /* k_t (1/m1 + l1^2/I1) = 2 */
}

/* LIGGGHTS' `torsionTorque on` through the C ABI. cdt, LIGGGHTS_3_8 preset, eta = 0.1 (angle
 * form: a length), k_n = 1000, overlap 0.01 (radii 1 and 2, centres 2.99 apart along +x = n):
 * the moment magnitude is eta k_n delta = 1. With w1 = (0.3, 0.4, 0), w2 = 0, LIGGGHTS without
 * the switch takes w/|w| = (0.6, 0.8, 0) and removes its normal part: M1 = -(0, 0.8, 0); with
 * it, M1 = -(0.6, 0.8, 0). A pure twist (0.3, 0, 0) gives 0 without and -(1, 0, 0) with.
 * Tolerance 1e-13 relative: the overlap 3 - 2.99 carries the rounding of 2.99 (about 2e-16,
 * 2e-14 of the overlap). */
void test_liggghts_torsion_torque(void) {
    rsl_model *m = NULL;
    CHECK_STATUS(rsl_model_new(RSL_PRESET_LIGGGHTS_3_8, &m), RSL_OK);
    rsl_rolling_params p;
    CHECK_STATUS(rsl_model_get_rolling(m, &p), RSL_OK);
    p.law = RSL_ROLLING_CDT;
    p.friction = 0.1;
    CHECK_STATUS(rsl_model_set_rolling(m, &p), RSL_OK);
    rsl_sphere a = sphere(0.0, 0.0, 1.0), b = sphere(2.99, 0.0, 2.0);
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = 10.0;
    in.normal_stiffness = 1000.0;
    in.dt = 1e-3;
    rsl_contact_state st;
    CHECK_STATUS(rsl_contact_state_init(&st), RSL_OK);
    rsl_contact_loads out;
    const double spins[2][2] = {{0.3, 0.4}, {0.3, 0.0}};
    const double off[2][2] = {{0.0, -0.8}, {0.0, 0.0}};
    const double on[2][2] = {{-0.6, -0.8}, {-1.0, 0.0}};
    for (int on_flag = 0; on_flag <= 1; on_flag++) {
        CHECK_STATUS(rsl_model_set_torsion_torque(m, on_flag), RSL_OK);
        for (int k = 0; k < 2; k++) {
            a.angular_velocity.x = spins[k][0];
            a.angular_velocity.y = spins[k][1];
            CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &out), RSL_OK);
            const double *want = on_flag ? on[k] : off[k];
            CHECK_CLOSE(out.rolling_moment.x, want[0], 1e-14, 1e-13);
            CHECK_CLOSE(out.rolling_moment.y, want[1], 1e-14, 1e-13);
            CHECK_CLOSE(out.rolling_moment.z, 0.0, 1e-14, 0);
            /* Body 2 gets the opposite moment, body 1 the moment itself (no sliding law). */
            CHECK_CLOSE(out.torque1.x, want[0], 1e-14, 1e-13);
            CHECK_CLOSE(out.torque2.x, -want[0], 1e-14, 1e-13);
        }
    }
    /* Refused (model unchanged): a flag other than 0/1, the length form while it is on, and any
     * preset but LIGGGHTS_3_8. */
    CHECK_STATUS(rsl_model_set_torsion_torque(m, 2), RSL_ERR_INVALID_PARAMETER);
    rsl_rolling_params length = p;
    length.form = RSL_FORM_LENGTH;
    CHECK_STATUS(rsl_model_set_rolling(m, &length), RSL_ERR_INVALID_PARAMETER);
    CHECK(strstr(rsl_last_error_message(), "torsion torque") != NULL);
    rsl_rolling_params now;
    CHECK_STATUS(rsl_model_get_rolling(m, &now), RSL_OK);
    CHECK(now.form == RSL_FORM_ANGLE);
    CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &out), RSL_OK);
    CHECK_CLOSE(out.rolling_moment.x, -1.0, 1e-14, 1e-13); /* still on */
    rsl_model_free(m);
    CHECK_STATUS(rsl_model_new(RSL_PRESET_LAMMPS_2021, &m), RSL_OK);
    CHECK_STATUS(rsl_model_set_torsion_torque(m, 1), RSL_ERR_INVALID_PARAMETER);
    CHECK(strstr(rsl_last_error_message(), "LIGGGHTS_3_8") != NULL);
    CHECK_STATUS(rsl_model_set_torsion_torque(m, 0), RSL_OK);
    rsl_model_free(m);
}

/* A tensile normal force is applied as given, and the limits follow the preset's rule or the
 * limit force. Spheres of radius 1 at 0 and 1.99 x (n = +x), body 1 sliding at (0, 1, 0): after
 * one step of 1e-3 the trial sliding force is -k_t v dt = -10 along y; mu_s = 0.5, f_n = -10.
 * Objective: limit max(f_n, 0) mu = 0, so F_t = 0. LAMMPS_2021: |f_n| mu = 5 (its Fncrit).
 * Both: body 1 gets -f_n n = +10 x (pulled toward body 2). With limit_force 4: limit 2. */
void test_contact_tensile_normal_force(void) {
    const int32_t presets[2] = {RSL_PRESET_OBJECTIVE, RSL_PRESET_LAMMPS_2021};
    const double want_ft[2] = {0.0, -5.0};
    for (int k = 0; k < 2; k++) {
        rsl_model *m = NULL;
        CHECK_STATUS(rsl_model_new(presets[k], &m), RSL_OK);
        CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e4, 0.0, 0.5), RSL_OK);
        rsl_sphere a = sphere(0.0, 0.0, 1.0), b = sphere(1.99, 0.0, 1.0);
        a.velocity.y = 1.0;
        rsl_contact_input in;
        memset(&in, 0, sizeof in);
        in.normal_force = -10.0;
        in.dt = 1e-3;
        for (int with_limit = 0; with_limit <= 1; with_limit++) {
            rsl_contact_state st;
            CHECK_STATUS(rsl_contact_state_init(&st), RSL_OK);
            in.flags = with_limit ? RSL_INPUT_LIMIT_FORCE : 0;
            in.limit_force = 4.0;
            rsl_contact_loads out;
            CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &out), RSL_OK);
            /* 1e-12: k_t v dt and the clip's scale are a few roundings of numbers of order 10. */
            CHECK_CLOSE(out.force1.x, 10.0, 1e-12, 0);
            CHECK_CLOSE(out.force1.y, with_limit ? -2.0 : want_ft[k], 1e-12, 0);
            CHECK_CLOSE(out.sliding_force.y, with_limit ? -2.0 : want_ft[k], 1e-12, 0);
            CHECK((out.slip_flags & RSL_SLIP_SLIDING) != 0);
        }
        rsl_model_free(m);
    }
}
