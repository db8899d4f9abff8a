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

/* +INFINITY as "no limit" (rsl_contact_input.limit_force, rolling_friction and
 * twisting_friction): the step equals one with a finite limit too large to be reached, a zero
 * coefficient still gives a zero limit under an infinite limit force, an infinite coefficient
 * stays "no limit" at zero force; where a coefficient is not a limit, +INFINITY is refused
 * and the state is left as it was. */
void test_contact_infinite_limits(void) {
    rsl_model *m = gear_model(); /* objective: EPSD rolling, sliding mu_s 0.5, SDS twisting */
    rsl_sphere a = sphere(0.0, 2.0, 0.7), b = sphere(1.39, -1.0, 0.7);
    a.velocity.y = 0.3;
    a.angular_velocity.x = 0.8; /* some twist */
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = 10.0;
    in.dt = 1e-3;
    rsl_contact_state st;
    rsl_contact_loads inf_out, big_out;
    /* 1. limit_force = +inf against 1e300: no limit is reached in either, same bits. */
    in.flags = RSL_INPUT_LIMIT_FORCE;
    for (int step = 0; step < 2; step++) {
        in.limit_force = step ? 1e300 : INFINITY;
        CHECK_STATUS(rsl_contact_state_init(&st), RSL_OK);
        for (int i = 0; i < 50; i++) {
            CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, step ? &big_out : &inf_out),
                         RSL_OK);
        }
    }
    CHECK(memcmp(&inf_out, &big_out, sizeof inf_out) == 0);
    CHECK(inf_out.slip_flags == 0);
    CHECK(inf_out.sliding_force.y != 0.0 && inf_out.rolling_moment.z != 0.0);
    /* 2. mu_s = 0 under an infinite limit force: zero sliding force (0 inf is not NaN). */
    CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e3, 0.0, 0.0), RSL_OK);
    in.limit_force = INFINITY;
    CHECK_STATUS(rsl_contact_state_init(&st), RSL_OK);
    CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &inf_out), RSL_OK);
    CHECK_VEC(inf_out.sliding_force, 0.0, 0.0, 0.0, 0.0);
    CHECK((inf_out.slip_flags & RSL_SLIP_SLIDING) != 0);
    CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e3, 0.0, 0.5), RSL_OK);
    /* 3. rolling and twisting coefficients +inf at zero limit force (a tensile f_n under the
     * objective rule max(f_n, 0)): unlimited, as a huge finite limit. */
    in.normal_force = -5.0;
    for (int k = 0; k < 2; k++) {
        in.flags = RSL_INPUT_ROLLING_FRICTION | RSL_INPUT_TWISTING_FRICTION;
        in.rolling_friction = INFINITY;
        in.twisting_friction = INFINITY;
        if (k) {
            in.flags |= RSL_INPUT_LIMIT_FORCE;
            in.limit_force = 1e300;
            in.rolling_friction = in.twisting_friction = 1.0;
        }
        CHECK_STATUS(rsl_contact_state_init(&st), RSL_OK);
        for (int i = 0; i < 50; i++) {
            CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, k ? &big_out : &inf_out), RSL_OK);
        }
    }
    CHECK(memcmp(&inf_out.rolling_moment, &big_out.rolling_moment, sizeof(rsl_vec3)) == 0);
    CHECK(memcmp(&inf_out.twisting_torque, &big_out.twisting_torque, sizeof(rsl_vec3)) == 0);
    CHECK(inf_out.rolling_moment.z != 0.0 && inf_out.twisting_torque.x != 0.0);
    CHECK((inf_out.slip_flags & (RSL_SLIP_ROLLING | RSL_SLIP_TWISTING)) == 0);
    /* 4. Refusals where the coefficient is not a limit; state and model untouched. */
    in.normal_force = 10.0;
    in.normal_stiffness = 1e4;
    rsl_rolling_params p;
    CHECK_STATUS(rsl_model_get_rolling(m, &p), RSL_OK);
    rsl_rolling_params derived = p;
    derived.stiffness_rule = RSL_STIFFNESS_EPSD;
    derived.friction = INFINITY;
    CHECK_STATUS(rsl_model_set_rolling(m, &derived), RSL_ERR_INVALID_PARAMETER);
    derived.friction = 0.1;
    CHECK_STATUS(rsl_model_set_rolling(m, &derived), RSL_OK);
    rsl_rolling_params cdt = p;
    cdt.law = RSL_ROLLING_CDT;
    for (int k = 0; k < 3; k++) {
        CHECK_STATUS(rsl_model_set_rolling(m, k == 0 ? &derived : &cdt), RSL_OK);
        in.flags = 0;
        CHECK_STATUS(rsl_contact_state_init(&st), RSL_OK);
        CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &big_out), RSL_OK);
        in.flags = k == 2 ? RSL_INPUT_LIMIT_FORCE : RSL_INPUT_ROLLING_FRICTION;
        in.rolling_friction = INFINITY;
        in.limit_force = INFINITY;
        rsl_contact_state kept = st;
        CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &inf_out),
                     RSL_ERR_INVALID_ARGUMENT);
        CHECK(memcmp(&kept, &st, sizeof st) == 0);
        CHECK(strstr(rsl_last_error_message(), "+inf") != NULL);
    }
    /* The derived stiffness with a per-contact stiffness given: the coefficient is a limit. */
    CHECK_STATUS(rsl_model_set_rolling(m, &derived), RSL_OK);
    in.flags = RSL_INPUT_ROLLING_FRICTION | RSL_INPUT_ROLLING_STIFFNESS;
    in.rolling_stiffness = 50.0;
    CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &inf_out), RSL_OK);
    rsl_model_free(m);
}

/* The end of a contact. The host owns it: a separated pair is still stepped (a cohesive law
 * acts past separation), the decomposition's overlap turns negative, and the host resets the
 * state when it ends the contact. After the reset, the next touch starts exactly as a fresh
 * contact (same bits); without it, the old spring acts again. */
void test_contact_end_and_reset(void) {
    rsl_model *m = gear_model();
    rsl_sphere a = sphere(0.0, 0.0, 1.0), b = sphere(1.99, 0.0, 1.0);
    a.velocity.y = 1.0; /* sliding along y */
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = 10.0;
    in.dt = 1e-3;
    rsl_contact_state st, fresh;
    rsl_contact_loads out, fresh_out;
    CHECK_STATUS(rsl_contact_state_init(&st), RSL_OK);
    for (int i = 0; i < 20; i++) CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &out), RSL_OK);
    /* 20 steps of 1e-3 at 1: |xi| = 0.02, k_t |xi| = 20 > mu_s f_n = 5: at the limit. */
    CHECK_CLOSE(out.sliding_force.y, -5.0, 1e-12, 0);
    /* The spheres separate: the overlap is negative, and a step is still accepted (here with
     * a tensile force, as a cohesive law would give). */
    rsl_sphere apart = b;
    apart.position.x = 2.01;
    rsl_decomposition d;
    CHECK_STATUS(rsl_decompose(&a, &apart, NULL, &d), RSL_OK);
    CHECK_CLOSE(d.overlap, -0.01, 1e-15, 0);
    rsl_contact_state kept = st;
    in.normal_force = -1.0;
    CHECK_STATUS(rsl_contact_step(m, &a, &apart, &in, &kept, &out), RSL_OK);
    in.normal_force = 10.0;
    /* The pair touches again. Without a reset the old spring acts at once (at its limit). */
    kept = st;
    CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &kept, &out), RSL_OK);
    CHECK_CLOSE(out.sliding_force.y, -5.0, 1e-12, 0);
    /* With the reset the host does when the contact ends: a fresh contact, bit for bit. */
    CHECK_STATUS(rsl_contact_state_init(&st), RSL_OK);
    memset(&fresh, 0, sizeof fresh);
    CHECK(memcmp(&st, &fresh, sizeof st) == 0);
    CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &out), RSL_OK);
    CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &fresh, &fresh_out), RSL_OK);
    CHECK(memcmp(&out, &fresh_out, sizeof out) == 0);
    CHECK(memcmp(&st, &fresh, sizeof st) == 0);
    /* One step of 1e-3 at 1: k_t v dt = 1 (the damping is 0). */
    CHECK_CLOSE(out.sliding_force.y, -1.0, 1e-12, 0);
    CHECK_STATUS(rsl_contact_state_init(NULL), RSL_ERR_NULL_POINTER);
    rsl_model_free(m);
}

/* YADE's avoidGranularRatcheting switch: only for the YADE_2023 preset (refused otherwise,
 * and for codes other than 0 and 1). A gear of unequal spheres (R1 w1 = -R2 w2, fixed centres)
 * has no shear increment with YADE's default (full radii), and with the flag 0 the contact
 * points' relative velocity -(delta/2)(w1 + w2) x n: |F_s| = k_t dt (delta/2) |w1 + w2|. */
void test_avoid_granular_ratcheting_switch(void) {
    const int32_t others[3] = {RSL_PRESET_OBJECTIVE, RSL_PRESET_LAMMPS_2021,
                               RSL_PRESET_LIGGGHTS_3_8};
    for (int k = 0; k < 3; k++) {
        rsl_model *m = NULL;
        CHECK_STATUS(rsl_model_new(others[k], &m), RSL_OK);
        CHECK_STATUS(rsl_model_set_avoid_granular_ratcheting(m, 0), RSL_ERR_INVALID_PARAMETER);
        CHECK_STATUS(rsl_model_set_avoid_granular_ratcheting(m, 1), RSL_ERR_INVALID_PARAMETER);
        rsl_model_free(m);
    }
    rsl_model *m = NULL;
    CHECK_STATUS(rsl_model_new(RSL_PRESET_YADE_2023, &m), RSL_OK);
    CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e4, 0.0, 0.5), RSL_OK);
    CHECK_STATUS(rsl_model_set_avoid_granular_ratcheting(m, 2), RSL_ERR_INVALID_PARAMETER);
    CHECK_STATUS(rsl_model_set_avoid_granular_ratcheting(m, -1), RSL_ERR_INVALID_PARAMETER);
    const double r1 = 0.7, r2 = 2.3, delta = 0.01, w1 = 2.0, w2 = -w1 * r1 / r2, dt = 1e-3;
    rsl_sphere a = sphere(0.0, w1, r1), b = sphere(r1 + r2 - delta, w2, r2);
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = 100.0;
    in.dt = dt;
    for (int flag = 1; flag >= 0; flag--) {
        CHECK_STATUS(rsl_model_set_avoid_granular_ratcheting(m, flag), RSL_OK);
        rsl_contact_state st;
        CHECK_STATUS(rsl_contact_state_init(&st), RSL_OK);
        rsl_contact_loads out;
        CHECK_STATUS(rsl_contact_step(m, &a, &b, &in, &st, &out), RSL_OK);
        double want = flag ? 0.0 : 1e4 * dt * 0.5 * delta * fabs(w1 + w2);
        /* The arms' terms R w ~ 1.4 cancel to a few roundings (~1e-15), times k_t dt = 10:
         * 1e-13 absolute leaves a margin of ten; the wanted 0.07 is met to 1e-12 relative. */
        CHECK_CLOSE(fabs(out.sliding_force.y), want, 1e-13, 1e-12);
        CHECK_CLOSE(out.sliding_force.x, 0.0, 1e-15, 0);
        CHECK_CLOSE(out.sliding_force.z, 0.0, 1e-15, 0);
    }
    rsl_model_free(m);
}
