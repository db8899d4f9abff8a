// rolling_pair.cpp: the C++ wrapper (rollslide.hpp) in a C++17 program. Two equal spheres in
// contact, body 1 spinning; rolling resistance (EPSD: a spring with a limit) and sliding (linear), objective model.
// Prints how the rolling moment builds up to its limit mu_r f_n R_r (the rolling radius R_r of
// the decomposition), and shows that a bad call throws rollslide::error with the status and the
// library's message.
#include "rollslide.hpp"

#include <cmath>
#include <cstdio>

int main() {
    rollslide::model model; // RSL_PRESET_OBJECTIVE
    model.set_sliding(RSL_SLIDING_LINEAR, 2e4, 0.0, 0.5);
    rsl_rolling_params rolling = model.rolling();
    rolling.law = RSL_ROLLING_EPSD;
    rolling.form = RSL_FORM_LENGTH;
    rolling.stiffness_rule = RSL_STIFFNESS_GIVEN;
    rolling.damping_rule = RSL_DAMPING_GIVEN;
    rolling.stiffness = 40.0; // the limit is reached after about 1000 steps
    rolling.damping = 0.0;
    rolling.friction = 0.1;
    model.set_rolling(rolling);

    const double radius = 0.5, f_n = 10.0, dt = 1e-4;
    rsl_sphere body1{{0, 0, 0}, {0, 0, 0}, {0, 0, 1.0}, radius};
    rsl_sphere body2{{0.99, 0, 0}, {0, 0, 0}, {0, 0, 0}, radius};
    rsl_contact_input input{};
    input.normal_force = f_n;
    input.dt = dt;
    rsl_contact_state state = rollslide::fresh_state();

    const double r_r = rollslide::decompose(body1, body2).rolling_radius;
    const double limit = rolling.friction * f_n * r_r;
    std::printf("rolling radius %.4f, rolling moment limit mu_r f_n R_r = %.4f\n", r_r, limit);
    double moment = 0.0;
    for (int step = 1; step <= 1500; ++step) {
        rsl_contact_loads loads = model.step(body1, body2, input, state);
        const rsl_vec3 &m = loads.rolling_moment;
        moment = std::sqrt(m.x * m.x + m.y * m.y + m.z * m.z);
        if (step % 250 == 0)
            std::printf("step %4d  |rolling moment| %.4f  slipping %s\n", step, moment,
                        (state.slip_flags & RSL_SLIP_ROLLING) ? "yes" : "no");
    }
    if (std::fabs(moment - limit) > 1e-9 * limit) {
        std::printf("the moment should have reached its limit\n");
        return 1;
    }
    try {
        input.dt = -1.0;
        model.step(body1, body2, input, state);
        return 1;
    } catch (const rollslide::error &e) {
        std::printf("a bad time step throws: status %d, \"%s\"\n", static_cast<int>(e.status()),
                    e.what());
    }
    return 0;
}
