/* Benchmark driver of rollslide's batch kernels (run by `cargo bench --bench batch`).
 *
 * Workload: a jittered cubic packing, each particle overlapping its 6 face neighbours
 * (6 contacts per particle), particle ids randomly permuted and contacts sorted by body 1, so
 * body 2 is gathered from random places (irregular memory access, as in a DEM neighbour list
 * of a well-mixed packing). Previous normals are tilted ~1e-3 rad from the current ones and the
 * histories are non-zero, so every transport and clip branch does real work. Each timed call
 * starts from the same copy of the states (restored untimed).
 *
 * Compared in the same run:
 *   baseline  hand-written C, LAMMPS style inline (linear history + rolling sds + twisting sds,
 *             project-rescale transport): the physics of the LAMMPS_2021 preset
 *   percontact  rsl_contact_step per contact + accumulation by the host
 *   percontact_acc  rsl_contact_step_accumulate per contact (the library accumulates)
 *   batch     rsl_batch_step / rsl_batch_step_contacts / rsl_batch_decompose
 *   floor     streams the same bytes with the same access pattern (reads pairs, f_n, both
 *             particles; reads + writes the state; read-modify-writes force and torque of both)
 *
 * Output: one line per measurement, "name ns_per_contact [maxdiff]".
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rollslide.h"

typedef struct {
    size_t np, nc;
    rsl_sphere *p;
    uint32_t *pairs;
    double *fn;
    rsl_contact_state *st0, *st;
    rsl_vec3 *f, *t;
    rsl_sphere *b1, *b2; /* pre-gathered for the contact-major calls */
    rsl_batch_loads *loads;
    rsl_decomposition *dec;
} scene;

static uint64_t rng_state = 12345;
static double urand(void) {
    rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp_pair(const void *a, const void *b) {
    const uint32_t *x = a, *y = b;
    return (x[0] > y[0]) - (x[0] < y[0]);
}

/* Model parameters shared by the library model and the baseline. */
static const double KT = 2.0e5, GT = 30.0, MU = 0.5;
static const double KR = 1.0e5, GR = 10.0, MUR = 0.1;
static const double KTW = 50.0, GTW = 0.5, MUTW = 0.05;
static const double KN = 1.0e6, DT = 1.0e-5;

static void build(scene *s, size_t nc_target) {
    size_t side = (size_t)ceil(cbrt((double)nc_target / 3.0));
    size_t np = side * side * side;
    size_t *perm = malloc(np * sizeof *perm);
    for (size_t i = 0; i < np; i++) perm[i] = i;
    for (size_t i = np - 1; i > 0; i--) {
        size_t j = (size_t)(urand() * (double)(i + 1));
        size_t tmp = perm[i];
        perm[i] = perm[j];
        perm[j] = tmp;
    }
    s->np = np;
    s->p = calloc(np, sizeof *s->p);
    const double a = 0.97;
    for (size_t x = 0; x < side; x++)
        for (size_t y = 0; y < side; y++)
            for (size_t z = 0; z < side; z++) {
                rsl_sphere *q = &s->p[perm[(x * side + y) * side + z]];
                q->position.x = a * x + 2e-3 * (urand() - 0.5);
                q->position.y = a * y + 2e-3 * (urand() - 0.5);
                q->position.z = a * z + 2e-3 * (urand() - 0.5);
                q->velocity.x = 0.1 * (urand() - 0.5);
                q->velocity.y = 0.1 * (urand() - 0.5);
                q->velocity.z = 0.1 * (urand() - 0.5);
                q->angular_velocity.x = 2 * (urand() - 0.5);
                q->angular_velocity.y = 2 * (urand() - 0.5);
                q->angular_velocity.z = 2 * (urand() - 0.5);
                q->radius = 0.5 - 0.01 * urand();
            }
    uint32_t *pairs = malloc(3 * np * 2 * sizeof *pairs);
    size_t nc = 0;
    for (size_t x = 0; x < side; x++)
        for (size_t y = 0; y < side; y++)
            for (size_t z = 0; z < side; z++) {
                size_t i = perm[(x * side + y) * side + z];
                size_t nb[3][3] = {{x + 1, y, z}, {x, y + 1, z}, {x, y, z + 1}};
                for (int k = 0; k < 3 && nc < nc_target; k++) {
                    if (nb[k][0] >= side || nb[k][1] >= side || nb[k][2] >= side) continue;
                    pairs[2 * nc] = (uint32_t)i;
                    pairs[2 * nc + 1] = (uint32_t)perm[(nb[k][0] * side + nb[k][1]) * side + nb[k][2]];
                    nc++;
                }
            }
    qsort(pairs, nc, 2 * sizeof(uint32_t), cmp_pair);
    s->nc = nc;
    s->pairs = pairs;
    s->fn = malloc(nc * sizeof(double));
    s->st0 = calloc(nc, sizeof *s->st0);
    s->st = calloc(nc, sizeof *s->st);
    s->b1 = malloc(nc * sizeof *s->b1);
    s->b2 = malloc(nc * sizeof *s->b2);
    s->loads = malloc(nc * sizeof *s->loads);
    s->dec = malloc(nc * sizeof *s->dec);
    for (size_t c = 0; c < nc; c++) {
        const rsl_sphere *p1 = &s->p[pairs[2 * c]], *p2 = &s->p[pairs[2 * c + 1]];
        double dx = p2->position.x - p1->position.x, dy = p2->position.y - p1->position.y,
               dz = p2->position.z - p1->position.z;
        double d = sqrt(dx * dx + dy * dy + dz * dz);
        s->fn[c] = KN * (p1->radius + p2->radius - d);
        s->b1[c] = *p1;
        s->b2[c] = *p2;
        /* previous normal tilted by ~1e-3; springs tangent to it */
        double nx = dx / d + 1e-3 * (urand() - 0.5), ny = dy / d + 1e-3 * (urand() - 0.5),
               nz = dz / d + 1e-3 * (urand() - 0.5);
        double nn = sqrt(nx * nx + ny * ny + nz * nz);
        nx /= nn, ny /= nn, nz /= nn;
        rsl_contact_state *st = &s->st0[c];
        st->previous_normal.x = nx, st->previous_normal.y = ny, st->previous_normal.z = nz;
        double u[3] = {urand() - 0.5, urand() - 0.5, urand() - 0.5};
        double un = u[0] * nx + u[1] * ny + u[2] * nz;
        double scale_s = (c % 4 == 0 ? 2.0 : 0.5) * MU * s->fn[c] / KT; /* 1/4 slipping */
        st->sliding_spring.x = scale_s * (u[0] - un * nx);
        st->sliding_spring.y = scale_s * (u[1] - un * ny);
        st->sliding_spring.z = scale_s * (u[2] - un * nz);
        st->rolling_spring.x = 0.1 * scale_s * (u[1] - un * ny);
        st->rolling_spring.y = 0.1 * scale_s * (u[2] - un * nz);
        st->rolling_spring.z = 0.1 * scale_s * (u[0] - un * nx);
        /* rolling spring must be tangent too: project */
        double rn = st->rolling_spring.x * nx + st->rolling_spring.y * ny + st->rolling_spring.z * nz;
        st->rolling_spring.x -= rn * nx, st->rolling_spring.y -= rn * ny, st->rolling_spring.z -= rn * nz;
        st->twisting_angle = 1e-4 * (urand() - 0.5);
    }
    free(perm);
    s->f = calloc(np, sizeof *s->f);
    s->t = calloc(np, sizeof *s->t);
}

static void reset(scene *s) {
    memcpy(s->st, s->st0, s->nc * sizeof *s->st);
    memset(s->f, 0, s->np * sizeof *s->f);
    memset(s->t, 0, s->np * sizeof *s->t);
}

/* ---- (a) hand-written LAMMPS-style baseline (same physics as the LAMMPS_2021 preset) ---- */

#define DOT(a, b) ((a)[0] * (b)[0] + (a)[1] * (b)[1] + (a)[2] * (b)[2])
#define CROSS(o, a, b)                           \
    do {                                         \
        (o)[0] = (a)[1] * (b)[2] - (a)[2] * (b)[1]; \
        (o)[1] = (a)[2] * (b)[0] - (a)[0] * (b)[2]; \
        (o)[2] = (a)[0] * (b)[1] - (a)[1] * (b)[0]; \
    } while (0)

/* LAMMPS project-rescale of a history vector, its threshold rule, then the spring step with
 * LAMMPS' clip (zero-length slipping spring gives no load). */
static inline void lammps_spring(double xi[3], const double n[3], const double rate[3], double k,
                                 double gamma, double limit, double load[3], uint32_t *slipped) {
    double xn = DOT(xi, n);
    double thr = k > 0 ? 1e-10 * limit / k : 0.0;
    double old2 = DOT(xi, xi);
    double p[3] = {xi[0] - xn * n[0], xi[1] - xn * n[1], xi[2] - xn * n[2]};
    double new2 = DOT(p, p);
    if (fabs(xn) > thr && new2 > 0) {
        double sc = sqrt(old2 / new2);
        xi[0] = p[0] * sc, xi[1] = p[1] * sc, xi[2] = p[2] * sc;
    }
    for (int a = 0; a < 3; a++) xi[a] += rate[a] * DT;
    double f[3];
    for (int a = 0; a < 3; a++) f[a] = -k * xi[a] - gamma * rate[a];
    double mag = sqrt(DOT(f, f));
    *slipped = mag > limit;
    if (mag > limit) {
        if (DOT(xi, xi) <= 0) {
            f[0] = f[1] = f[2] = 0;
        } else {
            double sc = limit / mag;
            for (int a = 0; a < 3; a++) {
                f[a] *= sc;
                if (k > 0) xi[a] = -(f[a] + gamma * rate[a]) / k;
            }
        }
    }
    load[0] = f[0], load[1] = f[1], load[2] = f[2];
}

static void baseline(scene *s) {
    const rsl_sphere *P = s->p;
    for (size_t c = 0; c < s->nc; c++) {
        uint32_t i = s->pairs[2 * c], j = s->pairs[2 * c + 1];
        const rsl_sphere *a = &P[i], *b = &P[j];
        double d3[3] = {b->position.x - a->position.x, b->position.y - a->position.y,
                        b->position.z - a->position.z};
        double r = sqrt(DOT(d3, d3));
        double n[3] = {d3[0] / r, d3[1] / r, d3[2] / r};
        double R1 = a->radius, R2 = b->radius;
        double l1 = (r + R1 - R2) * 0.5, l2 = r - l1;
        double reff = R1 * R2 / (R1 + R2);
        double fn = s->fn[c];
        double w1[3] = {a->angular_velocity.x, a->angular_velocity.y, a->angular_velocity.z};
        double w2[3] = {b->angular_velocity.x, b->angular_velocity.y, b->angular_velocity.z};
        double dv[3] = {b->velocity.x - a->velocity.x, b->velocity.y - a->velocity.y,
                        b->velocity.z - a->velocity.z};
        double dvn = DOT(dv, n);
        /* LAMMPS sliding velocity with full radii: -(dv)_t + (R1 w1 + R2 w2) x n */
        double arm[3] = {R1 * w1[0] + R2 * w2[0], R1 * w1[1] + R2 * w2[1], R1 * w1[2] + R2 * w2[2]};
        double vs[3];
        CROSS(vs, arm, n);
        for (int k = 0; k < 3; k++) vs[k] -= dv[k] - dvn * n[k];
        double dw[3] = {w1[0] - w2[0], w1[1] - w2[1], w1[2] - w2[2]};
        double vr[3];
        CROSS(vr, dw, n);
        for (int k = 0; k < 3; k++) vr[k] *= reff;
        double wtw = DOT(dw, n);

        rsl_contact_state *st = &s->st[c];
        double xs[3] = {st->sliding_spring.x, st->sliding_spring.y, st->sliding_spring.z};
        double xr[3] = {st->rolling_spring.x, st->rolling_spring.y, st->rolling_spring.z};
        double ft[3], fr[3];
        uint32_t s1, s2, s3;
        lammps_spring(xs, n, vs, KT, GT, MU * fn, ft, &s1);
        lammps_spring(xr, n, vr, KR, GR, MUR * fn, fr, &s2);
        double th = st->twisting_angle + wtw * DT;
        double mt = -KTW * th - GTW * wtw;
        double lim = MUTW * fn;
        s3 = fabs(mt) > lim;
        if (s3) {
            mt = wtw > 0 ? -lim : (wtw < 0 ? lim : 0.0);
            th = -(mt + GTW * wtw) / KTW;
        }
        double nxft[3], nxfr[3];
        CROSS(nxft, n, ft);
        CROSS(nxfr, n, fr);
        double couple[3];
        for (int k = 0; k < 3; k++) couple[k] = reff * nxfr[k] + mt * n[k];
        double f1[3] = {ft[0] - fn * n[0], ft[1] - fn * n[1], ft[2] - fn * n[2]};
        s->f[i].x += f1[0], s->f[i].y += f1[1], s->f[i].z += f1[2];
        s->f[j].x -= f1[0], s->f[j].y -= f1[1], s->f[j].z -= f1[2];
        s->t[i].x += l1 * nxft[0] + couple[0];
        s->t[i].y += l1 * nxft[1] + couple[1];
        s->t[i].z += l1 * nxft[2] + couple[2];
        s->t[j].x += l2 * nxft[0] - couple[0];
        s->t[j].y += l2 * nxft[1] - couple[1];
        s->t[j].z += l2 * nxft[2] - couple[2];
        st->sliding_spring.x = xs[0], st->sliding_spring.y = xs[1], st->sliding_spring.z = xs[2];
        st->rolling_spring.x = xr[0], st->rolling_spring.y = xr[1], st->rolling_spring.z = xr[2];
        st->twisting_angle = th;
        st->previous_normal.x = n[0], st->previous_normal.y = n[1], st->previous_normal.z = n[2];
        st->slip_flags = s1 | s2 << 1 | s3 << 2;
    }
}

/* ---- (d) memory floor: same bytes, same access pattern, no physics ---- */
static void floor_stream(scene *s) {
    const rsl_sphere *P = s->p;
    for (size_t c = 0; c < s->nc; c++) {
        uint32_t i = s->pairs[2 * c], j = s->pairs[2 * c + 1];
        const double *a = &P[i].position.x, *b = &P[j].position.x;
        double sa = 0, sb = 0;
        for (int k = 0; k < 10; k++) sa += a[k], sb += b[k];
        double x = (sa - sb) * 1e-30 + s->fn[c] * 1e-30;
        rsl_contact_state *st = &s->st[c];
        double *q = &st->sliding_spring.x;
        for (int k = 0; k < 13; k++) q[k] += x;
        st->slip_flags ^= 1;
        s->f[i].x += x, s->f[i].y += x, s->f[i].z += x;
        s->f[j].x -= x, s->f[j].y -= x, s->f[j].z -= x;
        s->t[i].x += x, s->t[i].y += x, s->t[i].z += x;
        s->t[j].x += x, s->t[j].y += x, s->t[j].z += x;
    }
}

/* ---- (b) per-contact C call ---- */
static rsl_model *MODEL;
static void percontact(scene *s) {
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = DT;
    for (size_t c = 0; c < s->nc; c++) {
        uint32_t i = s->pairs[2 * c], j = s->pairs[2 * c + 1];
        rsl_contact_loads out;
        in.normal_force = s->fn[c];
        if (rsl_contact_step(MODEL, &s->p[i], &s->p[j], &in, &s->st[c], &out) != RSL_OK) {
            fprintf(stderr, "rsl_contact_step failed at %zu: %s\n", c, rsl_last_error_message());
            exit(1);
        }
        s->f[i].x += out.force1.x, s->f[i].y += out.force1.y, s->f[i].z += out.force1.z;
        s->f[j].x -= out.force1.x, s->f[j].y -= out.force1.y, s->f[j].z -= out.force1.z;
        s->t[i].x += out.torque1.x, s->t[i].y += out.torque1.y, s->t[i].z += out.torque1.z;
        s->t[j].x += out.torque2.x, s->t[j].y += out.torque2.y, s->t[j].z += out.torque2.z;
    }
}

/* ---- (b') per-contact C call that accumulates itself ---- */
static void percontact_acc(scene *s) {
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = DT;
    for (size_t c = 0; c < s->nc; c++) {
        uint32_t i = s->pairs[2 * c], j = s->pairs[2 * c + 1];
        in.normal_force = s->fn[c];
        if (rsl_contact_step_accumulate(MODEL, &s->p[i], &s->p[j], &in, &s->st[c], &s->f[i],
                                        &s->t[i], &s->f[j], &s->t[j]) != RSL_OK) {
            fprintf(stderr, "rsl_contact_step_accumulate failed at %zu: %s\n", c,
                    rsl_last_error_message());
            exit(1);
        }
    }
}

/* ---- (c) batch ---- */
static rsl_model *BATCH_MODEL; /* the model of the current batch measurement */
static rsl_batch_options OPTS;
static int CONTACT_MAJOR, DECOMPOSE;
static void batch(scene *s) {
    rsl_batch_report rep;
    int32_t status;
    if (DECOMPOSE) {
        status = rsl_batch_decompose(s->p, s->np, s->pairs, s->nc, NULL, &OPTS, s->dec, &rep);
    } else if (CONTACT_MAJOR) {
        status = rsl_batch_step_contacts(BATCH_MODEL, s->b1, s->b2, s->nc, s->fn, NULL, DT, &OPTS,
                                         s->st, s->loads, &rep);
    } else {
        status = rsl_batch_step(BATCH_MODEL, s->p, s->np, s->pairs, s->nc, s->fn, NULL, DT, &OPTS,
                                s->st, s->f, s->t, &rep);
    }
    if (status != RSL_OK) {
        fprintf(stderr, "batch failed: %s (%s), first %llu\n", rsl_status_str(status),
                rsl_last_error_message(), (unsigned long long)rep.first_failed);
        exit(1);
    }
}

/* Optional third argument: only the rows whose name contains it (profiling). */
static const char *ONLY;
static int want(const char *name) { return !ONLY || strstr(name, ONLY) != NULL; }

/* Minimum over `reps` timed calls (states and accumulators restored before each, untimed): the
 * least disturbed run on a shared machine. Small batches repeat the call to time >= 0.4M contacts. */
static double timeit(scene *s, void (*fn)(scene *), int reps) {
    double t[64];
    if (reps > 64) reps = 64;
    int inner = s->nc < 100000 ? (int)(400000 / s->nc) : 1;
    for (int r = 0; r < reps; r++) {
        double acc = 0;
        for (int k = 0; k < inner; k++) {
            reset(s);
            double t0 = now();
            fn(s);
            acc += now() - t0;
        }
        t[r] = acc / inner;
    }
    for (int a = 0; a < reps; a++)
        for (int b = a + 1; b < reps; b++)
            if (t[b] < t[a]) {
                double x = t[a];
                t[a] = t[b];
                t[b] = x;
            }
    return t[0] / (double)s->nc * 1e9;
}

/* Max difference of the accumulated forces/torques against the baseline's, relative to the
 * largest baseline force (torque) component. */
static rsl_vec3 *REF_F, *REF_T;
static double maxdiff(scene *s) {
    double mf = 0, mt = 0, df = 0, dtq = 0;
    for (size_t i = 0; i < s->np; i++) {
        const double *a = &REF_F[i].x, *b = &s->f[i].x, *c = &REF_T[i].x, *d = &s->t[i].x;
        for (int k = 0; k < 3; k++) {
            mf = fmax(mf, fabs(a[k]));
            mt = fmax(mt, fabs(c[k]));
            df = fmax(df, fabs(a[k] - b[k]));
            dtq = fmax(dtq, fabs(c[k] - d[k]));
        }
    }
    return fmax(df / mf, dtq / mt);
}

static void model_laws(rsl_model *m, int rolling, int twisting) {
    rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, KT, GT, MU);
    if (rolling) {
        rsl_rolling_params rp;
        rsl_model_get_rolling(m, &rp);
        rp.law = RSL_ROLLING_EPSD;
        rp.stiffness = KR;
        rp.damping = GR;
        rp.friction = MUR;
        rsl_model_set_rolling(m, &rp);
    }
    if (twisting) rsl_model_set_twisting(m, RSL_TWISTING_SDS, KTW, GTW, MUTW);
}

int main(int argc, char **argv) {
    size_t nc = argc > 1 ? (size_t)atoll(argv[1]) : 1000000;
    int reps = argc > 2 ? atoi(argv[2]) : 5;
    ONLY = argc > 3 ? argv[3] : NULL;
    char name[128];
    scene s;
    build(&s, nc);
    printf("contacts %zu particles %zu bytes_per_contact_state %zu\n", s.nc, s.np,
           sizeof(rsl_contact_state));

    rsl_model_new(RSL_PRESET_LAMMPS_2021, &MODEL);
    model_laws(MODEL, 1, 1);
    rsl_model *models[6];
    const char *scene_names[6] = {"full/lammps", "full/exact", "slide+roll/exact", "sliding/exact",
                                  "sliding/lammps", "generic(full/lammps)"};
    rsl_model_new(RSL_PRESET_LAMMPS_2021, &models[0]);
    model_laws(models[0], 1, 1);
    rsl_model_new(RSL_PRESET_OBJECTIVE, &models[1]);
    model_laws(models[1], 1, 1);
    rsl_model_new(RSL_PRESET_OBJECTIVE, &models[2]);
    model_laws(models[2], 1, 0);
    rsl_model_new(RSL_PRESET_OBJECTIVE, &models[3]);
    model_laws(models[3], 0, 0);
    rsl_model_new(RSL_PRESET_LAMMPS_2021, &models[4]);
    model_laws(models[4], 0, 0);
    models[5] = models[0];

    REF_F = malloc(s.np * sizeof *REF_F);
    REF_T = malloc(s.np * sizeof *REF_T);
    double tb = timeit(&s, baseline, reps);
    memcpy(REF_F, s.f, s.np * sizeof *REF_F);
    memcpy(REF_T, s.t, s.np * sizeof *REF_T);
    printf("baseline_c %.3f 0\n", tb);
    if (want("floor")) printf("floor %.3f -\n", timeit(&s, floor_stream, reps));
    if (want("percontact_c")) {
        double tp = timeit(&s, percontact, reps);
        printf("percontact_c %.3f %.2e\n", tp, maxdiff(&s));
    }
    if (want("percontact_acc_c")) {
        double tp = timeit(&s, percontact_acc, reps);
        printf("percontact_acc_c %.3f %.2e\n", tp, maxdiff(&s));
    }

    uint32_t simd = rsl_batch_simd_support();
    const char *simd_names[4] = {"auto", "scalar", "avx2", "avx512"};
    for (int prec = 0; prec < 2; prec++)
        for (uint32_t lv = RSL_SIMD_SCALAR; lv <= RSL_SIMD_AVX512; lv++) {
            if (!((simd >> lv) & 1)) continue;
            memset(&OPTS, 0, sizeof OPTS);
            OPTS.precision = prec ? RSL_PRECISION_F32 : RSL_PRECISION_F64;
            OPTS.simd = lv;
            for (int sc = 0; sc < 6; sc++) {
                /* the scene table: f64 every SIMD level; f32 only the full LAMMPS set */
                if (prec && sc != 0) continue;
                BATCH_MODEL = models[sc];
                OPTS.flags = sc == 5 ? RSL_BATCH_GENERIC : 0;
                CONTACT_MAJOR = 0;
                DECOMPOSE = 0;
                snprintf(name, sizeof name, "batch_%s_%s_%s", prec ? "f32" : "f64",
                         simd_names[lv], scene_names[sc]);
                if (!want(name)) continue;
                double t = timeit(&s, batch, reps);
                if (sc == 0)
                    printf("%s %.3f %.2e\n", name, t, maxdiff(&s));
                else
                    printf("%s %.3f -\n", name, t);
            }
            OPTS.flags = 0;
            BATCH_MODEL = models[0];
            CONTACT_MAJOR = 1;
            snprintf(name, sizeof name, "contacts_%s_%s_full/lammps", prec ? "f32" : "f64",
                     simd_names[lv]);
            if (want(name)) printf("%s %.3f -\n", name, timeit(&s, batch, reps));
            CONTACT_MAJOR = 0;
            DECOMPOSE = 1;
            snprintf(name, sizeof name, "decompose_%s_%s", prec ? "f32" : "f64", simd_names[lv]);
            if (want(name)) printf("%s %.3f -\n", name, timeit(&s, batch, reps));
            DECOMPOSE = 0;
        }
    return 0;
}
