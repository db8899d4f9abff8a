/* The closed-form vectors of kinematics.md section 6 through the C ABI, plus options, the
 * inverse map and the error contract. Tolerance 1e-13: O(1) quantities from fewer than ~20
 * operations round at a few 1e-16; any formula error is O(0.01) or more. */
#include "rollslide.h" /* first: the header must compile on its own */

#include <stdint.h>

#include "rsl_test.h"

#define TOL 1e-13

static rsl_sphere sphere(rsl_vec3 p, rsl_vec3 v, rsl_vec3 w, double r) {
    rsl_sphere s;
    s.position = p;
    s.velocity = v;
    s.angular_velocity = w;
    s.radius = r;
    return s;
}

static const rsl_vec3 ZERO = {0.0, 0.0, 0.0};

void test_decompose_case1_rolling_on_fixed_sphere(void) {
    /* R1 = 0.7, R2 = 2.3, r2 = 3x; v1 = Om x (r1 - r2), w1 = (R1+R2)/R1 Om, Om = 1.3 z. */
    rsl_sphere b1 = sphere(ZERO, rsl_test_vec(0, -3.9, 0), rsl_test_vec(0, 0, 1.3 * 3.0 / 0.7), 0.7);
    rsl_sphere b2 = sphere(rsl_test_vec(3, 0, 0), ZERO, ZERO, 2.3);
    rsl_decomposition d;
    CHECK_STATUS(rsl_decompose(&b1, &b2, NULL, &d), RSL_OK);
    CHECK_VEC(d.sliding_velocity, 0, 0, 0, TOL);
    CHECK_CLOSE(d.normal_rate, 0.0, TOL, 0);
    CHECK_CLOSE(d.twisting_rate, 0.0, TOL, 0);
    CHECK_VEC(d.tumbling, 0, 0, 1.3, TOL);
    CHECK_VEC(d.rolling_velocity, 0, 2.99, 0, TOL);
    CHECK_CLOSE(d.rolling_radius, 0.7 * 2.3 / 3.0, TOL, 0);
    CHECK_VEC(d.contact_velocity, 0, -2.99, 0, TOL);
    rsl_legacy_rolling legacy;
    CHECK_STATUS(rsl_decompose_legacy(&b1, &b2, NULL, &legacy), RSL_OK);
    CHECK_VEC(legacy.iwashita_oda, 0, 1.95, 0, TOL);
}

void test_decompose_case2_ball_on_wall(void) {
    /* Wall z = 0 with outward normal +z (given unnormalised, length 2); ball of R1 = 0.7 on it
     * moving with V = (1.7, -0.4, 0) and rolling: w1 = V x n / R1 with n = -z. */
    double vx = 1.7, vy = -0.4, r = 0.7;
    rsl_sphere ball = sphere(rsl_test_vec(0.3, 0.2, r), rsl_test_vec(vx, vy, 0),
                             rsl_test_vec(-vy / r, vx / r, 0), r);
    rsl_wall wall;
    wall.point = ZERO;
    wall.normal = rsl_test_vec(0, 0, 2.0);
    wall.velocity = ZERO;
    wall.angular_velocity = ZERO;
    rsl_decomposition d;
    CHECK_STATUS(rsl_decompose_wall(&ball, &wall, NULL, &d), RSL_OK);
    CHECK_VEC(d.normal, 0, 0, -1, 0.0);
    CHECK_VEC(d.sliding_velocity, 0, 0, 0, TOL);
    CHECK_VEC(d.rolling_velocity, -vx, -vy, 0, TOL);
    CHECK_CLOSE(d.rolling_radius, r, TOL, 0);
    CHECK(isinf(d.distance) && isinf(d.branch2));
    rsl_wall_velocities back;
    CHECK_STATUS(rsl_compose_wall(&d, NULL, &back), RSL_OK);
    CHECK_VEC(back.velocity1, vx, vy, 0, TOL);
    CHECK_VEC(back.angular_velocity1, -vy / r, vx / r, 0, TOL);
    CHECK_VEC(back.wall_contact_velocity, 0, 0, 0, TOL);
}

void test_decompose_case3_gear(void) {
    rsl_sphere b1 = sphere(ZERO, ZERO, rsl_test_vec(0, 0, 2), 0.7);
    rsl_sphere b2 = sphere(rsl_test_vec(3, 0, 0), ZERO, rsl_test_vec(0, 0, -2 * 0.7 / 2.3), 2.3);
    rsl_decomposition d;
    CHECK_STATUS(rsl_decompose(&b1, &b2, NULL, &d), RSL_OK);
    CHECK_VEC(d.sliding_velocity, 0, 0, 0, TOL);
    CHECK_VEC(d.rolling_velocity, 0, 1.4, 0, TOL);
}

void test_decompose_case4_pure_sliding_and_kuhn_bagi(void) {
    rsl_sphere b1 = sphere(ZERO, ZERO, rsl_test_vec(0, 0, 1), 0.7);
    rsl_sphere b2 = sphere(rsl_test_vec(3, 0, 0), ZERO, rsl_test_vec(0, 0, 1), 2.3);
    rsl_decomposition d;
    CHECK_STATUS(rsl_decompose(&b1, &b2, NULL, &d), RSL_OK);
    CHECK_VEC(d.rolling_velocity, 0, 0, 0, TOL);
    CHECK_VEC(d.sliding_velocity, 0, 3, 0, TOL);
    rsl_legacy_rolling legacy;
    CHECK_STATUS(rsl_decompose_legacy(&b1, &b2, NULL, &legacy), RSL_OK);
    CHECK_VEC(legacy.kuhn_bagi, 0, -0.8, 0, TOL);
}

void test_decompose_case5_pure_twist(void) {
    rsl_sphere b1 = sphere(ZERO, ZERO, rsl_test_vec(3, 0, 0), 0.7);
    rsl_sphere b2 = sphere(rsl_test_vec(3, 0, 0), ZERO, rsl_test_vec(-1, 0, 0), 2.3);
    rsl_decomposition d;
    CHECK_STATUS(rsl_decompose(&b1, &b2, NULL, &d), RSL_OK);
    CHECK_CLOSE(d.twisting_rate, 4.0, TOL, 0);
    CHECK_CLOSE(d.frame_spin, 1.0, TOL, 0);
    CHECK_VEC(d.rolling_velocity, 0, 0, 0, TOL);
    CHECK_VEC(d.sliding_velocity, 0, 0, 0, TOL);
}

static void case6(rsl_sphere *b1, rsl_sphere *b2) {
    *b1 = sphere(rsl_test_vec(1, 2, 3), rsl_test_vec(0.3, -0.2, 0.1), rsl_test_vec(1, -2, 0.5), 1.0);
    *b2 = sphere(rsl_test_vec(1, 2 + 0.6 * 1.49, 3 + 0.8 * 1.49), rsl_test_vec(-0.1, 0.4, 0.2),
                 rsl_test_vec(0.2, 0.3, -1), 0.5);
}

static void superpose(rsl_sphere *s, rsl_vec3 u, rsl_vec3 w, rsl_vec3 x0) {
    rsl_vec3 r = rsl_test_vec(s->position.x - x0.x, s->position.y - x0.y, s->position.z - x0.z);
    s->velocity.x += u.x + w.y * r.z - w.z * r.y;
    s->velocity.y += u.y + w.z * r.x - w.x * r.z;
    s->velocity.z += u.z + w.x * r.y - w.y * r.x;
    s->angular_velocity.x += w.x;
    s->angular_velocity.y += w.y;
    s->angular_velocity.z += w.z;
}

void test_decompose_case6_general_and_objectivity(void) {
    rsl_sphere b1, b2;
    case6(&b1, &b2);
    rsl_decomposition d;
    CHECK_STATUS(rsl_decompose(&b1, &b2, NULL, &d), RSL_OK);
    CHECK_CLOSE(d.distance, 1.49, TOL, 0);
    CHECK_CLOSE(d.overlap, 0.01, TOL, 0);
    CHECK_CLOSE(d.branch1, 0.995, TOL, 0);
    CHECK_CLOSE(d.branch2, 0.495, TOL, 0);
    CHECK_CLOSE(d.rolling_radius, 0.330553691275168, TOL, 0);
    CHECK_CLOSE(d.normal_rate, 0.44, TOL, 0);
    CHECK_VEC(d.sliding_velocity, -1.0747, -1.2112, 0.9084, TOL);
    CHECK_VEC(d.rolling_velocity, -0.905717114093960, -0.211554362416107, 0.158665771812081, TOL);
    CHECK_CLOSE(d.twisting_rate, -0.18, TOL, 0);
    CHECK_VEC(d.tumbling, -0.281879194630873, -0.214765100671141, 0.161073825503356, TOL);
    CHECK_CLOSE(d.frame_spin, -0.71, TOL, 0);

    /* U = (5, -3, 2), W = (-4, 7, 1) about X0 = (10, 0, -5): superposed velocities reach ~80,
     * so the objective parts move by ~80 eps ~ 2e-14; 1e-12 allows for that. */
    rsl_vec3 u = rsl_test_vec(5, -3, 2), w = rsl_test_vec(-4, 7, 1), x0 = rsl_test_vec(10, 0, -5);
    superpose(&b1, u, w, x0);
    superpose(&b2, u, w, x0);
    rsl_decomposition e;
    CHECK_STATUS(rsl_decompose(&b1, &b2, NULL, &e), RSL_OK);
    CHECK_CLOSE(e.normal_rate, d.normal_rate, 1e-12, 0);
    CHECK_VEC(e.sliding_velocity, d.sliding_velocity.x, d.sliding_velocity.y, d.sliding_velocity.z, 1e-12);
    CHECK_VEC(e.rolling_velocity, d.rolling_velocity.x, d.rolling_velocity.y, d.rolling_velocity.z, 1e-12);
    CHECK_CLOSE(e.twisting_rate, d.twisting_rate, 1e-12, 0);
    /* w_rbr changes by W_t = W - (W.n) n, n = (0, 0.6, 0.8): W.n = 5.0. */
    CHECK_VEC(e.tumbling, d.tumbling.x - 4.0, d.tumbling.y + 7.0 - 3.0, d.tumbling.z + 1.0 - 4.0, 1e-12);
}

void test_decompose_parts_subset(void) {
    rsl_sphere b1, b2;
    case6(&b1, &b2);
    rsl_decomposition all, some;
    CHECK_STATUS(rsl_decompose(&b1, &b2, NULL, &all), RSL_OK);
    rsl_decompose_options o = rsl_decompose_options_default();
    CHECK(o.parts == RSL_PART_ALL && o.branch_rule == RSL_BRANCH_MIDPLANE);
    o.parts = RSL_PART_ROLLING | RSL_PART_TWISTING;
    CHECK_STATUS(rsl_decompose(&b1, &b2, &o, &some), RSL_OK);
    CHECK(memcmp(&some.rolling_velocity, &all.rolling_velocity, sizeof(rsl_vec3)) == 0);
    CHECK(some.twisting_rate == all.twisting_rate);
    CHECK(some.sliding_velocity.x == 0.0 && some.normal_rate == 0.0 && some.frame_spin == 0.0);
    /* radii branches and R_eff */
    o = rsl_decompose_options_default();
    o.branch_rule = RSL_BRANCH_RADII;
    o.rolling_radius_rule = RSL_ROLLING_RADIUS_EFFECTIVE;
    CHECK_STATUS(rsl_decompose(&b1, &b2, &o, &some), RSL_OK);
    CHECK(some.branch1 == 1.0 && some.branch2 == 0.5);
    CHECK_CLOSE(some.rolling_radius, 0.5 / 1.5, TOL, 0);
}

void test_compose_round_trip(void) {
    rsl_sphere b1, b2;
    case6(&b1, &b2);
    for (int rule = 0; rule <= 1; rule++) {
        rsl_decompose_options o = rsl_decompose_options_default();
        o.branch_rule = rule;
        rsl_decomposition d;
        rsl_pair_velocities back;
        CHECK_STATUS(rsl_decompose(&b1, &b2, &o, &d), RSL_OK);
        CHECK_STATUS(rsl_compose(&d, &o, &back), RSL_OK);
        CHECK_VEC(back.velocity1, b1.velocity.x, b1.velocity.y, b1.velocity.z, TOL);
        CHECK_VEC(back.velocity2, b2.velocity.x, b2.velocity.y, b2.velocity.z, TOL);
        CHECK_VEC(back.angular_velocity1, b1.angular_velocity.x, b1.angular_velocity.y, b1.angular_velocity.z, TOL);
        CHECK_VEC(back.angular_velocity2, b2.angular_velocity.x, b2.angular_velocity.y, b2.angular_velocity.z, TOL);
    }
}

/* A failing call must leave every output byte as it was. */
static int untouched(const rsl_decomposition *d) {
    unsigned char pattern[sizeof(rsl_decomposition)];
    memset(pattern, 0xA5, sizeof pattern);
    return memcmp(d, pattern, sizeof pattern) == 0;
}

#define EXPECT_FAIL(call, status)             \
    do {                                      \
        memset(&out, 0xA5, sizeof out);       \
        CHECK_STATUS(call, status);           \
        CHECK(untouched(&out));               \
        CHECK(strlen(rsl_last_error_message()) > 0); \
    } while (0)

void test_errors_leave_outputs_untouched(void) {
    rsl_sphere b1, b2, bad;
    case6(&b1, &b2);
    rsl_decomposition out;
    EXPECT_FAIL(rsl_decompose(NULL, &b2, NULL, &out), RSL_ERR_NULL_POINTER);
    EXPECT_FAIL(rsl_decompose(&b1, NULL, NULL, &out), RSL_ERR_NULL_POINTER);
    CHECK_STATUS(rsl_decompose(&b1, &b2, NULL, NULL), RSL_ERR_NULL_POINTER);
    CHECK(strstr(rsl_last_error_message(), "out") != NULL);

    bad = b1;
    bad.angular_velocity.z = NAN;
    EXPECT_FAIL(rsl_decompose(&bad, &b2, NULL, &out), RSL_ERR_NON_FINITE);
    CHECK(strstr(rsl_last_error_message(), "angular velocity of body 1") != NULL);
    bad = b2;
    bad.position.x = INFINITY;
    EXPECT_FAIL(rsl_decompose(&b1, &bad, NULL, &out), RSL_ERR_NON_FINITE);
    bad = b2;
    bad.radius = -1.0;
    EXPECT_FAIL(rsl_decompose(&b1, &bad, NULL, &out), RSL_ERR_INVALID_RADIUS);
    bad = b2;
    bad.position = b1.position;
    EXPECT_FAIL(rsl_decompose(&b1, &bad, NULL, &out), RSL_ERR_COINCIDENT_CENTRES);
    /* d = 0.05 with R1 = 1, R2 = 0.5: delta = 1.45 > 2 min(R), so l2 = R2 - delta/2 < 0. */
    bad = b2;
    bad.position = rsl_test_vec(1, 2, 3.05);
    EXPECT_FAIL(rsl_decompose(&b1, &bad, NULL, &out), RSL_ERR_NONPOSITIVE_BRANCH);

    rsl_decompose_options o = rsl_decompose_options_default();
    o.branch_rule = 7;
    EXPECT_FAIL(rsl_decompose(&b1, &b2, &o, &out), RSL_ERR_INVALID_ARGUMENT);
    CHECK(strstr(rsl_last_error_message(), "branch_rule") != NULL);
    o = rsl_decompose_options_default();
    o.parts = 1u << 9;
    EXPECT_FAIL(rsl_decompose(&b1, &b2, &o, &out), RSL_ERR_INVALID_ARGUMENT);

    rsl_wall wall;
    memset(&wall, 0, sizeof wall);
    EXPECT_FAIL(rsl_decompose_wall(&b1, &wall, NULL, &out), RSL_ERR_INVALID_ARGUMENT);
    CHECK(strstr(rsl_last_error_message(), "wall normal") != NULL);

    /* Misaligned input pointer: refused, not dereferenced. */
    unsigned char raw[sizeof(rsl_sphere) + 8];
    memcpy(raw + 1, &b1, sizeof b1);
    EXPECT_FAIL(rsl_decompose((const rsl_sphere *)(const void *)(raw + 1), &b2, NULL, &out),
                RSL_ERR_MISALIGNED);
}

void test_status_strings_and_version(void) {
    CHECK(strcmp(rsl_status_str(RSL_OK), "ok") == 0);
    CHECK(strcmp(rsl_status_str(RSL_ERR_COINCIDENT_CENTRES), "coincident centres") == 0);
    CHECK(strcmp(rsl_status_str(-12345), "unknown status") == 0);
    char expected[64];
    snprintf(expected, sizeof expected, "%d.%d.%d", RSL_VERSION_MAJOR, RSL_VERSION_MINOR,
             RSL_VERSION_PATCH);
    CHECK(strcmp(rsl_version(), expected) == 0);
}
