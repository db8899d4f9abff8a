// Tests of include/rollslide.hpp, the C++ wrapper: ownership and moves of a model, errors as
// exceptions carrying the status and the message, and every wrapped step giving the bits of the
// C call it wraps. Compiled by tests/c_tests.rs as C++11 and C++17 with
// -Wall -Wextra -pedantic -Werror, with g++ and (where installed) clang++.
#include "rollslide.hpp"

// The numeric version macro works in preprocessor tests.
#if !defined(RSL_VERSION_NUMBER) ||                                                           \
    RSL_VERSION_NUMBER != RSL_VERSION_MAJOR * 10000 + RSL_VERSION_MINOR * 100 + RSL_VERSION_PATCH
#error "RSL_VERSION_NUMBER is missing or does not match RSL_VERSION_MAJOR/MINOR/PATCH"
#endif

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

static int failures = 0;

#define EXPECT(cond)                                                                           \
    do {                                                                                       \
        if (!(cond)) {                                                                         \
            std::fprintf(stderr, "%s:%d: expected %s\n", __FILE__, __LINE__, #cond);           \
            ++failures;                                                                        \
        }                                                                                      \
    } while (0)

template <class T> static bool same_bits(const T &a, const T &b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

static rsl_sphere sphere(double x, double y, double z, double vx, double wz, double r) {
    rsl_sphere s;
    std::memset(&s, 0, sizeof s);
    s.position.x = x;
    s.position.y = y;
    s.position.z = z;
    s.velocity.x = vx;
    s.angular_velocity.z = wz;
    s.radius = r;
    return s;
}

static rsl_contact_input input(double f_n, double dt) {
    rsl_contact_input in;
    std::memset(&in, 0, sizeof in);
    in.normal_force = f_n;
    in.dt = dt;
    return in;
}

static rollslide::model lammps_model() {
    rollslide::model m(RSL_PRESET_LAMMPS_2021);
    m.set_sliding(RSL_SLIDING_LINEAR, 1e5, 5.0, 0.5).set_twisting(RSL_TWISTING_SDS, 2e2, 0.1, 0.3);
    rsl_rolling_params p = m.rolling();
    p.law = RSL_ROLLING_CDT;
    m.set_rolling(p);
    return m; // moved out: the handle changes owner, nothing is freed twice
}

static void test_model_ownership() {
    rollslide::model a = lammps_model();
    EXPECT(a.get() != nullptr);
    const rsl_model *handle = a.get();
    rollslide::model b(std::move(a));
    EXPECT(a.get() == nullptr);
    EXPECT(b.get() == handle);
    rollslide::model c;
    c = std::move(b);
    EXPECT(b.get() == nullptr);
    EXPECT(c.get() == handle);
    EXPECT(c.rolling().law == RSL_ROLLING_CDT);
}

static void test_errors_are_exceptions() {
    rollslide::model m;
    bool thrown = false;
    try {
        m.set_sliding(99, 1.0, 0.0, 0.5);
    } catch (const rollslide::error &e) {
        thrown = true;
        EXPECT(e.status() == RSL_ERR_INVALID_PARAMETER);
        EXPECT(std::string(e.what()).find("rsl_model_set_sliding") != std::string::npos);
    }
    EXPECT(thrown);
    // A refused step leaves the state untouched, as in C.
    rsl_sphere a = sphere(0, 0, 0, 0, 0, 1.0), b = sphere(1.9, 0, 0, 0, 0, 1.0);
    rsl_contact_state state = rollslide::fresh_state();
    state.twisting_angle = 0.25;
    const rsl_contact_state before = state;
    thrown = false;
    try {
        m.step(a, b, input(1.0, -1e-4), state);
    } catch (const rollslide::error &e) {
        thrown = true;
        EXPECT(e.status() == RSL_ERR_INVALID_TIME_STEP);
    }
    EXPECT(thrown);
    EXPECT(same_bits(state, before));
    thrown = false;
    try {
        rollslide::decompose(a, sphere(0, 0, 0, 0, 0, 1.0));
    } catch (const rollslide::error &e) {
        thrown = true;
        EXPECT(e.status() == RSL_ERR_COINCIDENT_CENTRES);
    }
    EXPECT(thrown);
}

static void test_steps_give_the_c_bits() {
    const rollslide::model m = lammps_model();
    rsl_sphere a = sphere(0, 0, 0, 0.3, 2.0, 1.0), b = sphere(1.95, 0.1, 0, -0.2, -1.0, 0.8);
    rsl_wall wall;
    std::memset(&wall, 0, sizeof wall);
    wall.normal.y = 1.0;
    wall.point.y = -0.95;
    const rsl_contact_input in = input(10.0, 1e-4);

    rsl_contact_state s_cpp = rollslide::fresh_state(), s_c = rollslide::fresh_state();
    for (int k = 0; k < 5; ++k) {
        rsl_contact_loads l_cpp = m.step(a, b, in, s_cpp);
        rsl_contact_loads l_c;
        EXPECT(rsl_contact_step(m.get(), &a, &b, &in, &s_c, &l_c) == RSL_OK);
        EXPECT(same_bits(l_cpp, l_c));
        EXPECT(same_bits(s_cpp, s_c));
    }
    rsl_vec3 f1 = {0, 0, 0}, t1 = {0, 0, 0}, f2 = {0, 0, 0}, t2 = {0, 0, 0};
    rsl_vec3 g1 = f1, u1 = f1, g2 = f1, u2 = f1;
    m.step_accumulate(a, b, in, s_cpp, f1, t1, f2, t2);
    EXPECT(rsl_contact_step_accumulate(m.get(), &a, &b, &in, &s_c, &g1, &u1, &g2, &u2) == RSL_OK);
    EXPECT(same_bits(f1, g1) && same_bits(t1, u1) && same_bits(f2, g2) && same_bits(t2, u2));
    EXPECT(same_bits(s_cpp, s_c));
    EXPECT(f1.x != 0.0);

    // swap_state is rsl_contact_state_swap, and the mirrored state steps the swapped pair.
    rsl_contact_state m_cpp = s_cpp, m_c = s_c;
    m.swap_state(m_cpp);
    EXPECT(rsl_contact_state_swap(m.get(), &m_c) == RSL_OK);
    EXPECT(same_bits(m_cpp, m_c));
    EXPECT(m_cpp.sliding_spring.x == -s_cpp.sliding_spring.x && s_cpp.sliding_spring.x != 0.0);
    rsl_contact_state forward = s_cpp;
    const rsl_contact_loads l12 = m.step(a, b, in, forward);
    const rsl_contact_loads l21 = m.step(b, a, in, m_cpp);
    EXPECT(std::fabs(l21.force1.x + l12.force1.x) <= 1e-12 * std::fabs(l12.force1.x));
    EXPECT(std::fabs(l21.torque1.z - l12.torque2.z) <= 1e-12 * std::fabs(l12.torque2.z) + 1e-300);

    rsl_contact_loads w_cpp = m.step(a, wall, in, s_cpp);
    rsl_contact_loads w_c;
    EXPECT(rsl_contact_step_wall(m.get(), &a, &wall, &in, &s_c, &w_c) == RSL_OK);
    EXPECT(same_bits(w_cpp, w_c) && same_bits(s_cpp, s_c));

    rsl_decomposition d_cpp = rollslide::decompose(a, b);
    rsl_decomposition d_c;
    EXPECT(rsl_decompose(&a, &b, nullptr, &d_c) == RSL_OK);
    EXPECT(same_bits(d_cpp, d_c));
    rsl_pair_velocities back = rollslide::compose(d_cpp);
    EXPECT(std::fabs(back.velocity1.x - a.velocity.x) < 1e-12);
}

static void test_batch_reports_skipped_contacts_and_throws_call_errors() {
    const rollslide::model m = lammps_model();
    rsl_sphere particles[3] = {sphere(0, 0, 0, 0.1, 0, 1.0), sphere(1.9, 0, 0, 0, 0, 1.0),
                               sphere(0, 1.9, 0, 0, 1.0, 1.0)};
    const uint32_t pairs[6] = {0, 1, 0, 2, 1, 7}; // the third contact's index is out of range
    const double f_n[3] = {5.0, 5.0, 5.0};
    rsl_contact_state states[3] = {rollslide::fresh_state(), rollslide::fresh_state(),
                                   rollslide::fresh_state()};
    rsl_vec3 force[3], torque[3];
    std::memset(force, 0, sizeof force);
    std::memset(torque, 0, sizeof torque);
    rsl_batch_report r = m.batch_step(particles, 3, pairs, 3, f_n, nullptr, 1e-4, states, force,
                                      torque);
    EXPECT(r.processed == 2 && r.failed == 1 && r.first_failed == 2);
    EXPECT(r.first_status == RSL_ERR_INVALID_ARGUMENT);
    bool thrown = false;
    try {
        m.batch_step(particles, 3, pairs, 2, f_n, nullptr, 0.0, states, force, torque);
    } catch (const rollslide::error &e) {
        thrown = true;
        EXPECT(e.status() == RSL_ERR_INVALID_TIME_STEP);
    }
    EXPECT(thrown);
}

// The batch calls with per-contact sliding coefficients give the C calls' bits; a contact with
// a negative k_t is reported as skipped, not thrown.
static void test_batch_params_give_the_c_bits() {
    const rollslide::model m = lammps_model();
    rsl_sphere particles[3] = {sphere(0, 0, 0, 0.1, 0, 1.0), sphere(1.9, 0, 0, 0, 0, 1.0),
                               sphere(0, 1.9, 0, 0, 1.0, 1.0)};
    const uint32_t pairs[4] = {0, 1, 0, 2};
    const double f_n[2] = {5.0, 4.0};
    double k_t[2] = {3e4, 5e4};
    const double gamma_t[2] = {2.0, 0.5};
    const rsl_batch_contact_params params = {k_t, gamma_t, nullptr, nullptr};
    rsl_contact_state s_cpp[2] = {rollslide::fresh_state(), rollslide::fresh_state()};
    rsl_contact_state s_c[2] = {rollslide::fresh_state(), rollslide::fresh_state()};
    rsl_vec3 f_cpp[3], t_cpp[3], f_c[3], t_c[3];
    std::memset(f_cpp, 0, sizeof f_cpp);
    std::memset(t_cpp, 0, sizeof t_cpp);
    std::memset(f_c, 0, sizeof f_c);
    std::memset(t_c, 0, sizeof t_c);
    rsl_batch_report r = m.batch_step(particles, 3, pairs, 2, f_n, nullptr, 1e-4, s_cpp, f_cpp,
                                      t_cpp, nullptr, &params);
    EXPECT(r.processed == 2 && r.failed == 0);
    EXPECT(rsl_batch_step_params(m.get(), particles, 3, pairs, 2, f_n, nullptr, &params, 1e-4,
                                 nullptr, s_c, f_c, t_c, nullptr) == RSL_OK);
    EXPECT(std::memcmp(f_cpp, f_c, sizeof f_c) == 0 && std::memcmp(t_cpp, t_c, sizeof t_c) == 0);
    EXPECT(same_bits(s_cpp[0], s_c[0]) && same_bits(s_cpp[1], s_c[1]));

    const rsl_sphere body1[2] = {particles[0], particles[0]};
    const rsl_sphere body2[2] = {particles[1], particles[2]};
    rsl_batch_loads out_cpp[2], out_c[2];
    k_t[1] = -1.0;
    r = m.batch_step_contacts(body1, body2, 2, f_n, nullptr, 1e-4, s_cpp, out_cpp, nullptr,
                              &params);
    EXPECT(r.processed == 1 && r.failed == 1 && r.first_failed == 1);
    EXPECT(r.first_status == RSL_ERR_INVALID_ARGUMENT);
    EXPECT(rsl_batch_step_contacts_params(m.get(), body1, body2, 2, f_n, nullptr, &params, 1e-4,
                                          nullptr, s_c, out_c, nullptr) ==
           RSL_ERR_INVALID_ARGUMENT);
    EXPECT(std::memcmp(&out_cpp[0], &out_c[0], sizeof out_c[0]) == 0);
    EXPECT(same_bits(s_cpp[0], s_c[0]) && same_bits(s_cpp[1], s_c[1]));
}

int main() {
    test_model_ownership();
    test_errors_are_exceptions();
    test_steps_give_the_c_bits();
    test_batch_reports_skipped_contacts_and_throws_call_errors();
    test_batch_params_give_the_c_bits();
    if (failures != 0) {
        std::fprintf(stderr, "%d failure(s)\n", failures);
        return 1;
    }
    std::printf("rollslide.hpp: all checks passed (C++%ld)\n", static_cast<long>(__cplusplus));
    return 0;
}
