/*
 * rolling_on_wall: a sphere launched rolling on a flat wall (the floor) with rolling resistance,
 * integrated until it stops; its stopping distance is compared with the closed form, for the
 * constant-moment law (cdt) and the elastic-plastic spring-dashpot law (epsd), both stepped by
 * rsl_contact_step_wall.
 *
 * Closed form. A solid sphere (mass m, radius R, I = 2/5 m R^2) rests on the floor with normal
 * force f_n = m g (overlap delta = m g / k_n). The library takes the contact point at the middle
 * of the overlap: the branch length is l = R - delta/2 and, for a wall, the rolling radius is
 * R_r = l. Rolling without slip means v = w l. The loads on the ball (x forward, w about +y):
 * the friction force F at the contact point and the rolling moment M = mu_r R_r f_n against the
 * rotation (cdt: at once; epsd: once its spring reaches that limit, after a rotation of
 * mu_r R_r f_n / k_theta, here about 1e-4 rad):
 *     m dv/dt = F,        I dw/dt = -l F - mu_r l f_n.
 * With dv/dt = l dw/dt this gives the constant deceleration
 *     a = mu_r g / (1 + I/(m l^2))            (= 5/7 mu_r g for l = R),
 * the stopping distance s = v0^2 / (2 a) (= 7 v0^2 / (10 mu_r g)) and time T = v0 / a. The
 * friction that keeps the ball rolling is F = -m a, i.e. |F| = (5/7) mu_r f_n, so rolling needs
 * sliding friction mu_s >= (5/7) mu_r. The rolling moment alone cannot stop the ball: it is a
 * couple, with no horizontal force. Without sliding friction (mu_s = 0) it only slows the spin
 * and the ball slides on at v0 for ever; the third run below shows that.
 *
 * Tolerance (relative error of the stopping distance): 1e-6; the runs give about 1e-8. The
 * friction and the normal force act at the contact point, so the ball's angular momentum about
 * the line of contact points falls at exactly mu_r l f_n whatever the springs do: the elastic
 * start of the tangential spring (and of the epsd rolling spring) only makes the speed oscillate
 * by about a/omega (omega ~ 1e4 rad/s), and the ball stops where the closed form says up to
 * O(a/omega^2)/s ~ 1e-9. The time step is 1/20 of the stability bound and the stop is found
 * exactly inside the last step. 1e-6 leaves two orders of margin and still catches an error of
 * order delta/R = 2.6e-5, such as using R instead of the rolling radius R_r = R - delta/2.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rollslide.h"

/* A 1 cm glass ball (SI units). */
static const double R = 0.005, DENSITY = 2500.0, G = 9.81;
static const double V0 = 0.5;    /* launch speed (m/s), rolling without slip */
static const double MU_R = 0.05; /* rolling friction coefficient (length form, dimensionless) */
static const double K_N = 1e5;   /* normal stiffness (N/m) */
static const double TOLERANCE = 1e-6;

#define PI 3.14159265358979323846

typedef struct {
    double distance, time; /* where and when v first reached 0 (or the end of the run) */
    double v_end, w_end;   /* velocity and spin at the end of the run */
} outcome;

static int check(int32_t status, const char *what) {
    if (status != RSL_OK)
        fprintf(stderr, "%s: %s (%s)\n", what, rsl_status_str(status), rsl_last_error_message());
    return status == RSL_OK;
}

/* Integrates the ball with velocity Verlet until it stops (or until t_end). */
static int roll(int rolling_law, double mu_s, double t_end, outcome *out) {
    const double m = 4.0 / 3.0 * PI * R * R * R * DENSITY, inertia = 0.4 * m * R * R;
    const double delta0 = m * G / K_N, l = R - 0.5 * delta0;
    const double k_t = 2.0 / 7.0 * K_N;
    /* Damping ratios 0.5 (normal, on m) and 0.5 (tangential, on the rolling ball's tangential
     * mass m I / (I + m l^2)). */
    const double gamma_n = 2.0 * 0.5 * sqrt(m * K_N);
    const double gamma_t = 2.0 * 0.5 * sqrt(m * inertia / (inertia + m * l * l) * k_t);

    rsl_model *model = NULL;
    if (!check(rsl_model_new(RSL_PRESET_OBJECTIVE, &model), "rsl_model_new")) return 0;
    rsl_rolling_params r;
    int ok = check(rsl_model_set_sliding(model, RSL_SLIDING_LINEAR, k_t, gamma_t, mu_s),
                   "rsl_model_set_sliding") &&
             check(rsl_model_get_rolling(model, &r), "rsl_model_get_rolling");
    if (ok) {
        r.law = rolling_law;
        r.form = RSL_FORM_LENGTH;
        r.friction = MU_R;
        r.rate_threshold = 0.0;
        if (rolling_law == RSL_ROLLING_EPSD) {
            r.stiffness_rule = RSL_STIFFNESS_EPSD; /* k_theta = 2.25 k_n mu_r^2 R_r^2 */
            r.damping_rule = RSL_DAMPING_RATIO;
            r.damping = 0.3;
            r.damping_mode = RSL_DAMPING_BELOW_LIMIT;
        }
        ok = check(rsl_model_set_rolling(model, &r), "rsl_model_set_rolling");
    }
    /* The time step: 1/20 of the library's stability bound for this contact. */
    double dt_c = 0.0;
    double k_theta = rolling_law == RSL_ROLLING_EPSD ? 2.25 * K_N * MU_R * MU_R * l * l : 0.0;
    ok = ok && check(rsl_coupled_critical_time_step(k_t, k_theta, m, INFINITY, inertia, INFINITY,
                                                    l, 0.0, &dt_c),
                     "rsl_coupled_critical_time_step");
    if (!ok) {
        rsl_model_free(model);
        return 0;
    }
    const double dt = dt_c / 20.0;

    rsl_wall floor_wall;
    memset(&floor_wall, 0, sizeof floor_wall);
    floor_wall.normal.z = 1.0; /* outward, towards the ball */
    rsl_sphere ball;
    memset(&ball, 0, sizeof ball);
    ball.radius = R;
    ball.position.z = R - delta0; /* at rest on its normal spring: f_n = m g */
    ball.velocity.x = V0;
    ball.angular_velocity.y = V0 / l; /* rolling without slip */
    rsl_contact_state state;
    rsl_contact_state_init(&state);
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = dt;
    in.normal_stiffness = K_N;
    in.mass1 = m;
    in.inertia1 = inertia;
    rsl_contact_loads loads;
    memset(&loads, 0, sizeof loads);
    rsl_vec3 force = {0.0, 0.0, 0.0}, torque = {0.0, 0.0, 0.0};

    out->distance = out->time = -1.0;
    double t = 0.0;
    int first = 1;
    while (t < t_end) {
        double x_old = ball.position.x, v_old = ball.velocity.x;
        if (!first) { /* half kick, drift */
            ball.velocity.x += 0.5 * dt * force.x / m;
            ball.velocity.y += 0.5 * dt * force.y / m;
            ball.velocity.z += 0.5 * dt * force.z / m;
            ball.angular_velocity.x += 0.5 * dt * torque.x / inertia;
            ball.angular_velocity.y += 0.5 * dt * torque.y / inertia;
            ball.angular_velocity.z += 0.5 * dt * torque.z / inertia;
            ball.position.x += dt * ball.velocity.x;
            ball.position.y += dt * ball.velocity.y;
            ball.position.z += dt * ball.velocity.z;
        }
        /* Forces: gravity, the normal spring-dashpot (ours), and the library's contact loads. */
        double delta = R - ball.position.z;
        double f_n = K_N * delta - gamma_n * ball.velocity.z; /* ddot = n.(0 - v) = v_z */
        in.normal_force = f_n > 0.0 ? f_n : 0.0;
        if (!check(rsl_contact_step_wall(model, &ball, &floor_wall, &in, &state, &loads),
                   "rsl_contact_step_wall")) {
            rsl_model_free(model);
            return 0;
        }
        force = loads.force1;
        force.z -= m * G;
        torque = loads.torque1;
        if (first) {
            first = 0;
            continue; /* forces at t = 0 only */
        }
        ball.velocity.x += 0.5 * dt * force.x / m; /* half kick */
        ball.velocity.y += 0.5 * dt * force.y / m;
        ball.velocity.z += 0.5 * dt * force.z / m;
        ball.angular_velocity.x += 0.5 * dt * torque.x / inertia;
        ball.angular_velocity.y += 0.5 * dt * torque.y / inertia;
        ball.angular_velocity.z += 0.5 * dt * torque.z / inertia;
        t += dt;
        double v_new = ball.velocity.x;
        if (out->time < 0.0 && v_old > 0.0 && v_new <= 0.0) {
            /* Constant deceleration inside the step: stop at v = 0 exactly. */
            double a = (v_old - v_new) / dt;
            out->time = t - dt + v_old / a;
            out->distance = x_old + v_old * v_old / (2.0 * a);
            break;
        }
    }
    if (out->time < 0.0) {
        out->time = t;
        out->distance = ball.position.x;
    }
    out->v_end = ball.velocity.x;
    out->w_end = ball.angular_velocity.y;
    rsl_model_free(model);
    return 1;
}

int main(void) {
    const double m = 4.0 / 3.0 * PI * R * R * R * DENSITY, inertia = 0.4 * m * R * R;
    const double l = R - 0.5 * m * G / K_N;
    const double a = MU_R * G / (1.0 + inertia / (m * l * l));
    const double s_exact = V0 * V0 / (2.0 * a), t_exact = V0 / a;

    printf("ball R = %g m rolling at %g m/s on a floor, mu_r = %g, mu_s = 0.5 (>= 5/7 mu_r)\n", R,
           V0, MU_R);
    printf("closed form: a = mu_r g / (1 + I/(m l^2)) = %.6f m/s^2, s = v0^2/(2a) = %.6f m, "
           "T = %.6f s\n\n",
           a, s_exact, t_exact);
    printf("%-5s  %14s  %14s  %10s  %10s\n", "law", "distance [m]", "closed form [m]", "rel. error",
           "time error");
    const int laws[2] = {RSL_ROLLING_CDT, RSL_ROLLING_EPSD};
    const char *names[2] = {"cdt", "epsd"};
    int failed = 0;
    for (int k = 0; k < 2; k++) {
        outcome o;
        if (!roll(laws[k], 0.5, 3.0 * t_exact, &o)) return 1;
        double err = fabs(o.distance - s_exact) / s_exact;
        double terr = fabs(o.time - t_exact) / t_exact;
        printf("%-5s  %14.6f  %14.6f  %10.2e  %10.2e%s\n", names[k], o.distance, s_exact, err, terr,
               err > TOLERANCE ? "  FAILED" : "");
        failed |= err > TOLERANCE;
    }

    /* No sliding friction: after 2 T the ball still translates at v0, its spin stopped. */
    outcome o;
    if (!roll(RSL_ROLLING_CDT, 0.0, 2.0 * t_exact, &o)) return 1;
    int slides_on = fabs(o.v_end - V0) < 1e-9 * V0 && fabs(o.w_end) * l < 1e-2 * V0;
    printf("\nmu_s = 0, cdt: after %.3f s, v = %.9f m/s (launched at %g), w l = %.2e m/s: %s\n",
           2.0 * t_exact, o.v_end, V0, o.w_end * l,
           slides_on ? "the ball slides on, spin gone" : "UNEXPECTED");
    failed |= !slides_on;

    if (failed) {
        fprintf(stderr, "rolling_on_wall: error above the tolerance %g\n", TOLERANCE);
        return 1;
    }
    printf("all within the tolerance %g\n", TOLERANCE);
    return 0;
}
