/*
 * calibration: the worked examples of docs/calibration.md.
 *
 * For two materials (2 mm glass beads, 1 mm sand grains) it computes every contact parameter
 * with the guide's formulas, builds the model through the C API (every status checked), asks
 * the library's time-step helpers for the stable step, and checks what the guide claims:
 *
 *   - the normal damping gamma_n gives the target restitution coefficient: recomputed from
 *     gamma_n in closed form (to 1e-12), and measured in a head-on collision integrated with
 *     velocity Verlet at the chosen time step (to 1e-2: the step is a tenth of the stability
 *     bound, and velocity Verlet's error in e at that step is of order 1e-3);
 *   - a contact rolled at a constant rate reaches the steady rolling moment mu_r R_r f_n (to
 *     1e-12 relative; the clip makes it exact up to rounding);
 *   - the library's EPSD rules (stiffness 2.25 k_n mu_r^2, damping as a ratio of
 *     2 sqrt(I_r k_theta)) give, at every step, the moments of a model given the k_r and
 *     gamma_r that the guide computes by hand (to 1e-12 of the limit moment; the two differ by
 *     rounding only).
 *
 * It exits with status 1 if a check fails or a call is refused. SI units throughout.
 * docs/calibration.md quotes this program's output, and tests/calibration_guide.rs fails if the
 * two differ.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rollslide.h"

#define PI 3.14159265358979323846

/* The safety factor on the smallest critical time step (see the guide). */
static const double SAFETY = 0.1;

/* How k_n and k_t are chosen. */
enum { KN_HERTZ_MATCHED, KN_ALLOWED_OVERLAP };
enum { KT_HERTZ_MINDLIN, KT_TWO_SEVENTHS };

typedef struct {
    const char *title;
    double radius;      /* R (m); both spheres of a pair alike */
    double density;     /* rho (kg/m^3) */
    int kn_rule;        /* KN_HERTZ_MATCHED: from E and nu; KN_ALLOWED_OVERLAP: overlap_max */
    double youngs;      /* E (Pa), KN_HERTZ_MATCHED */
    double poisson;     /* nu, KN_HERTZ_MATCHED and KT_HERTZ_MINDLIN */
    double overlap_max; /* largest overlap at v_ref, as a fraction of R (KN_ALLOWED_OVERLAP) */
    double v_ref;       /* reference impact speed (m/s) */
    int kt_rule;        /* KT_HERTZ_MINDLIN or KT_TWO_SEVENTHS */
    double restitution; /* e */
    double mu_s;        /* sliding friction coefficient */
    double mu_r;        /* rolling friction coefficient (length form: of R_r) */
    double eta_r;       /* EPSD rolling damping ratio (of the critical 2 sqrt(I_r k_theta)) */
    int32_t twisting;   /* RSL_TWISTING_SDS (coefficients computed as Marshall's) or _MARSHALL */
} material;

static int check(int32_t status, const char *what) {
    if (status != RSL_OK)
        fprintf(stderr, "%s: %s (%s)\n", what, rsl_status_str(status), rsl_last_error_message());
    return status == RSL_OK;
}

static double norm3(rsl_vec3 v) { return sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

/* Restitution coefficient of the linear spring-dashpot with damping ratio zeta < 1 (the
 * contact ends when the overlap returns to zero). */
static double restitution_of(double zeta) {
    return exp(-PI * zeta / sqrt(1.0 - zeta * zeta));
}

/* A head-on collision of the normal spring-dashpot alone (m_eff x'' = -k_n x - gamma_n x'),
 * integrated with velocity Verlet at step dt (the dashpot reads the half-step velocity, as DEM
 * codes do), from first touch with overlap rate v0: returns the rebound speed over v0. */
static double simulated_restitution(double m_eff, double k_n, double gamma_n, double v0,
                                    double dt) {
    double x = 0.0, v = v0, a = -gamma_n * v0 / m_eff;
    for (long step = 0; step < 100000000L; step++) {
        double v_half = v + 0.5 * dt * a;
        x += dt * v_half;
        if (x <= 0.0) return -v_half / v0; /* the contact ended in this drift: no more force */
        a = -(k_n * x + gamma_n * v_half) / m_eff;
        v = v_half + 0.5 * dt * a;
    }
    return NAN;
}

typedef struct {
    rsl_model *model;
    rsl_contact_state state;
    rsl_contact_loads loads;
} stepped_model;

/* Prints one case; returns 1 if every check held, 0 if one failed or a call was refused. */
static int run_case(const material *mat) {
    int ok = 1; /* the checks so far */
    const double R = mat->radius;
    const double m = 4.0 / 3.0 * PI * R * R * R * mat->density;
    const double inertia = 0.4 * m * R * R; /* solid sphere */
    const double m_eff = m * m / (m + m), r_eff = R * R / (R + R);
    const double inertia_eff = inertia * inertia / (inertia + inertia);

    printf("== %s\n", mat->title);
    printf("input     R = %g m, rho = %g kg/m^3, v_ref = %g m/s\n", R, mat->density, mat->v_ref);
    printf("          e = %g, mu_s = %g, mu_r = %g, eta_r = %g\n", mat->restitution, mat->mu_s,
           mat->mu_r, mat->eta_r);
    printf("particle  m = %.4g kg, I = 2/5 m R^2 = %.4g kg m^2\n", m, inertia);
    printf("pair      m_eff = %.4g kg, R_eff = %.4g m\n", m_eff, r_eff);

    /* Normal stiffness (the host's): the linear spring with the same largest overlap at v_ref
     * as Hertz, or the one that overlaps a chosen fraction of R at v_ref (undamped). */
    double k_n, overlap_ref;
    if (mat->kn_rule == KN_HERTZ_MATCHED) {
        const double e_star = mat->youngs / (2.0 * (1.0 - mat->poisson * mat->poisson));
        overlap_ref = pow(15.0 * m_eff * mat->v_ref * mat->v_ref / (16.0 * e_star * sqrt(r_eff)),
                          0.4);
        k_n = m_eff * (mat->v_ref / overlap_ref) * (mat->v_ref / overlap_ref);
        printf("normal    E = %g Pa, nu = %g: E* = E/(2(1 - nu^2)) = %.4g Pa\n", mat->youngs,
               mat->poisson, e_star);
        printf("          Hertz overlap at v_ref = %.4g m\n", overlap_ref);
        printf("          k_n = m_eff (v_ref/overlap)^2 = %.4g N/m (same largest overlap)\n", k_n);
    } else {
        overlap_ref = mat->overlap_max * R;
        k_n = m_eff * (mat->v_ref / overlap_ref) * (mat->v_ref / overlap_ref);
        printf("normal    allowed overlap at v_ref = %g R = %.4g m\n", mat->overlap_max,
               overlap_ref);
        printf("          k_n = m_eff (v_ref/overlap)^2 = %.4g N/m\n", k_n);
    }

    /* Normal damping from the restitution coefficient (the host's dashpot). */
    const double log_e = log(mat->restitution);
    const double zeta = -log_e / sqrt(PI * PI + log_e * log_e);
    const double gamma_n = 2.0 * zeta * sqrt(m_eff * k_n);
    const double e_back = restitution_of(gamma_n / (2.0 * sqrt(m_eff * k_n)));
    const int e_ok = fabs(e_back - mat->restitution) <= 1e-12;
    ok &= e_ok;
    printf("damping   zeta = -ln e/sqrt(pi^2 + ln^2 e) = %.4g\n", zeta);
    printf("          gamma_n = 2 zeta sqrt(m_eff k_n) = %.4g N s/m\n", gamma_n);
    printf("          e from gamma_n = %.12f (%s)\n", e_back,
           e_ok ? "the target within 1e-12" : "FAILED: not the target");

    /* Sliding. */
    double k_t;
    if (mat->kt_rule == KT_HERTZ_MINDLIN) {
        k_t = 2.0 * (1.0 - mat->poisson) / (2.0 - mat->poisson) * k_n;
        printf("sliding   k_t = 2(1 - nu)/(2 - nu) k_n = %.4g N/m\n", k_t);
    } else {
        k_t = 2.0 / 7.0 * k_n;
        printf("sliding   k_t = 2/7 k_n = %.4g N/m\n", k_t);
    }
    const double gamma_t = 2.0 * zeta * sqrt(2.0 / 7.0 * m_eff * k_t);
    printf("          gamma_t = 2 zeta sqrt(2/7 m_eff k_t) = %.4g N s/m, mu_s = %g\n", gamma_t,
           mat->mu_s);

    /* The reference contact: the two spheres at the overlap of a collision at v_ref. */
    rsl_sphere b1, b2;
    memset(&b1, 0, sizeof b1);
    memset(&b2, 0, sizeof b2);
    b1.radius = b2.radius = R;
    b2.position.x = 2.0 * R - overlap_ref;
    rsl_decomposition geo;
    if (!check(rsl_decompose(&b1, &b2, NULL, &geo), "rsl_decompose")) return 0;
    const double r_r = geo.rolling_radius;
    const double f_n = k_n * geo.overlap;
    printf("contact   overlap = %.4g m, f_n = k_n overlap = %.4g N\n", geo.overlap, f_n);
    printf("          rsl_decompose: R_r = %.6g m, l1 = l2 = %.6g m\n", r_r, geo.branch1);

    /* Rolling: EPSD (type C), length form. */
    const double k_r = 2.25 * k_n * mat->mu_r * mat->mu_r;
    const double k_theta = k_r * r_r * r_r;
    const double inertia_r = 1.0 / (2.0 / (inertia + m * R * R));
    const double c_crit = 2.0 * sqrt(inertia_r * k_theta);
    const double c_theta = mat->eta_r * c_crit;
    const double gamma_r = c_theta / (r_r * r_r);
    const double moment_limit = mat->mu_r * r_r * f_n;
    const double rotation_limit = mat->mu_r * f_n / (k_r * r_r);
    printf("rolling   k_r = 2.25 k_n mu_r^2 = %.4g N/m, k_theta = k_r R_r^2 = %.4g N m/rad\n", k_r,
           k_theta);
    printf("          I_r = %.4g kg m^2, critical damping 2 sqrt(I_r k_theta) = %.4g N m s/rad\n",
           inertia_r, c_crit);
    printf("          c_theta = eta_r x critical = %.4g N m s/rad\n", c_theta);
    printf("          gamma_r = c_theta/R_r^2 = %.4g N s/m; angle form: eta = mu_r R_r = %.4g m\n",
           gamma_r, mat->mu_r * r_r);
    printf("          limit mu_r R_r f_n = %.4g N m, reached after mu_r f_n/(k_r R_r) = %.4g rad\n",
           moment_limit, rotation_limit);

    /* Twisting: Marshall's coefficients at the reference contact radius. */
    const double a = sqrt(geo.overlap * r_eff);
    const double k_tw = k_t * a * a / 2.0;
    const double gamma_tw = gamma_t * a * a / 2.0;
    const double mu_tw = 2.0 / 3.0 * a * mat->mu_s;
    printf("twisting  a = sqrt(overlap R_eff) = %.4g m\n", a);
    printf("          k_tw = k_t a^2/2 = %.4g N m/rad, gamma_tw = gamma_t a^2/2 = %.4g N m s/rad\n",
           k_tw, gamma_tw);
    printf("          mu_tw = 2/3 a mu_s = %.4g m; model: %s\n", mu_tw,
           mat->twisting == RSL_TWISTING_SDS ? "RSL_TWISTING_SDS with these three"
                                             : "RSL_TWISTING_MARSHALL");

    /* Time step. The normal spring-dashpot is the host's; its bound has the rotational one's
     * form, (2/w0)(sqrt(1 + z^2) - z) with w0 = sqrt(k (1/m1 + 1/m2)), so the rotational helper
     * evaluates it when given k_n, the masses and zeta. The rotational damping ratios are taken
     * relative to the centroidal inertia I1 I2/(I1 + I2) that the helper uses. */
    const double omega_n = sqrt(k_n / m_eff);
    double dt_normal = 0.0, dt_coupled = 0.0, dt_rolling = 0.0, dt_twisting = 0.0;
    const double z_rolling = c_theta / (2.0 * sqrt(k_theta * inertia_eff));
    const double z_twisting = gamma_tw / (2.0 * sqrt(k_tw * inertia_eff));
    if (!check(rsl_rotational_critical_time_step(k_n, m, m, zeta, &dt_normal),
               "rsl_rotational_critical_time_step (normal)") ||
        !check(rsl_coupled_critical_time_step(k_t, k_theta, m, m, inertia, inertia, geo.branch1,
                                              geo.branch2, &dt_coupled),
               "rsl_coupled_critical_time_step") ||
        !check(rsl_rotational_critical_time_step(k_theta, inertia, inertia, z_rolling,
                                                 &dt_rolling),
               "rsl_rotational_critical_time_step (rolling)") ||
        !check(rsl_rotational_critical_time_step(k_tw, inertia, inertia, z_twisting,
                                                 &dt_twisting),
               "rsl_rotational_critical_time_step (twisting)"))
        return 0;
    double smallest = dt_normal;
    const char *limiting = "normal";
    if (dt_coupled < smallest) {
        smallest = dt_coupled;
        limiting = "sliding + rolling";
    }
    if (dt_rolling < smallest) {
        smallest = dt_rolling;
        limiting = "rolling";
    }
    if (dt_twisting < smallest) {
        smallest = dt_twisting;
        limiting = "twisting";
    }
    const double dt = SAFETY * smallest;
    const double t_collision = PI / (omega_n * sqrt(1.0 - zeta * zeta));
    printf("time step normal: rsl_rotational_critical_time_step(k_n, m, m, zeta) = %.4g s\n",
           dt_normal);
    printf("          sliding + rolling: rsl_coupled_critical_time_step = %.4g s\n", dt_coupled);
    printf("          rolling: rsl_rotational_critical_time_step, z = %.4g: %.4g s\n", z_rolling,
           dt_rolling);
    printf("          twisting: rsl_rotational_critical_time_step, z = %.4g: %.4g s\n",
           z_twisting, dt_twisting);
    printf("          dt = %g x %.4g s (%s) = %.4g s\n", SAFETY, smallest, limiting, dt);
    printf("          a collision lasts pi/(w0 sqrt(1 - zeta^2)) = %.4g s = %.1f steps\n",
           t_collision, t_collision / dt);

    /* Check: the collision at this time step. */
    const double e_sim = simulated_restitution(m_eff, k_n, gamma_n, mat->v_ref, dt);
    const int sim_ok = fabs(e_sim - mat->restitution) <= 1e-2;
    ok &= sim_ok;
    printf("check     collision integrated at dt: e = %.4f (target %g, %s)\n", e_sim,
           mat->restitution, sim_ok ? "within 1e-2" : "FAILED: off by more than 1e-2");

    /* The model, twice: [0] with the library's EPSD rules (stiffness from k_n and mu_r,
     * damping as a ratio), [1] given the k_r and gamma_r computed above. */
    stepped_model runs[2];
    memset(runs, 0, sizeof runs);
    int api = 1; /* every call accepted */
    for (int k = 0; k < 2 && api; k++) {
        api = check(rsl_model_new(RSL_PRESET_OBJECTIVE, &runs[k].model), "rsl_model_new");
        rsl_rolling_params p;
        api = api &&
              check(rsl_model_set_sliding(runs[k].model, RSL_SLIDING_LINEAR, k_t, gamma_t,
                                          mat->mu_s),
                    "rsl_model_set_sliding") &&
              check(rsl_model_set_twisting(runs[k].model, mat->twisting, k_tw, gamma_tw, mu_tw),
                    "rsl_model_set_twisting") &&
              check(rsl_model_get_rolling(runs[k].model, &p), "rsl_model_get_rolling");
        if (!api) break;
        p.law = RSL_ROLLING_EPSD;
        p.form = RSL_FORM_LENGTH;
        p.damping_mode = RSL_DAMPING_ALWAYS;
        p.friction = mat->mu_r;
        if (k == 0) {
            p.stiffness_rule = RSL_STIFFNESS_EPSD; /* k_theta = 2.25 k_n mu_r^2 R_r^2 */
            p.stiffness = 0.0;
            p.damping_rule = RSL_DAMPING_RATIO; /* c_theta = eta_r 2 sqrt(I_r k_theta) */
            p.damping = mat->eta_r;
        } else {
            p.stiffness_rule = RSL_STIFFNESS_GIVEN;
            p.stiffness = k_r;
            p.damping_rule = RSL_DAMPING_GIVEN;
            p.damping = gamma_r;
        }
        api = check(rsl_model_set_rolling(runs[k].model, &p), "rsl_model_set_rolling");
        rsl_contact_state_init(&runs[k].state);
    }

    /* Check: roll the reference contact at a constant rate (gear-like, w2 = -w1: no sliding)
     * that turns it by the limit rotation in one period of the rolling oscillation,
     * 2 pi sqrt(I_r/k_theta), and on for as long again. */
    const double period = 2.0 * PI * sqrt(inertia_r / k_theta);
    const int n_steps = 2 * (int)ceil(period / dt);
    const double w = rotation_limit / (2.0 * period);
    b1.angular_velocity.z = w;
    b2.angular_velocity.z = -w;
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = f_n;
    in.dt = dt;
    in.normal_stiffness = k_n; /* read by RSL_STIFFNESS_EPSD */
    in.mass1 = in.mass2 = m;   /* read by RSL_DAMPING_RATIO */
    in.inertia1 = in.inertia2 = inertia;
    int first_slip = -1, rules_agree = 1;
    for (int step = 1; step <= n_steps && api; step++) {
        for (int k = 0; k < 2 && api; k++)
            api = check(rsl_contact_step(runs[k].model, &b1, &b2, &in, &runs[k].state,
                                         &runs[k].loads),
                        "rsl_contact_step");
        if (!api) break;
        const double ma = norm3(runs[0].loads.rolling_moment);
        const double mb = norm3(runs[1].loads.rolling_moment);
        rules_agree &= fabs(ma - mb) <= 1e-12 * moment_limit;
        if (first_slip < 0 && (runs[0].loads.slip_flags & RSL_SLIP_ROLLING)) first_slip = step;
    }
    for (int k = 0; k < 2; k++) rsl_model_free(runs[k].model);
    if (!api) return 0;
    const double moment = norm3(runs[0].loads.rolling_moment);
    const int limit_ok = (runs[0].loads.slip_flags & RSL_SLIP_ROLLING) &&
                         fabs(moment - moment_limit) <= 1e-12 * moment_limit;
    ok &= limit_ok && rules_agree;
    printf("check     rolled at w1 = -w2 = %.4g rad/s: the limit rotation in %.4g s\n", w,
           period);
    printf("          (one period 2 pi sqrt(I_r/k_theta)); slipping from step %d of %d\n",
           first_slip, n_steps);
    printf("          then |M| = %.4g N m (%s)\n", moment,
           limit_ok ? "mu_r R_r f_n within 1e-12" : "FAILED: not mu_r R_r f_n");
    printf("check     RSL_STIFFNESS_EPSD + RSL_DAMPING_RATIO against the given k_r, gamma_r:\n");
    printf("          %s\n\n", rules_agree ? "the same moments at every step within 1e-12"
                                        : "FAILED: different moments");
    return ok;
}

int main(void) {
    const material cases[2] = {
        {"2 mm glass beads (soda-lime glass): k_n from Young's modulus", 1e-3, 2500.0,
         KN_HERTZ_MATCHED, 63e9, 0.22, 0.0, 1.0, KT_HERTZ_MINDLIN, 0.9, 0.1, 0.01, 0.3,
         RSL_TWISTING_SDS},
        {"1 mm sand grains (quartz), softened: k_n from an allowed overlap", 0.5e-3, 2650.0,
         KN_ALLOWED_OVERLAP, 0.0, 0.0, 0.01, 1.0, KT_TWO_SEVENTHS, 0.6, 0.5, 0.3, 0.3,
         RSL_TWISTING_MARSHALL},
    };
    int ok = 1;
    for (int c = 0; c < 2; c++) ok &= run_case(&cases[c]);
    if (!ok) {
        fprintf(stderr, "calibration: a check failed or a call was refused\n");
        return 1;
    }
    printf("all checks passed\n");
    return 0;
}
