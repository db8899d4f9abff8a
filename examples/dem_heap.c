/*
 * dem_heap: a small discrete element (DEM) program that pours heaps of spheres onto a plate for
 * several rolling friction coefficients mu_r, several pours (random seeds) for each, and measures
 * the angle of repose of each heap: the mean and the spread over the pours for each mu_r.
 *
 *   dem_heap [OUT.svg] [--quick] [--seeds N]
 *
 * OUT.svg defaults to heap.svg; --quick is a small smoke test (800 spheres, 2 values of mu_r);
 * --seeds sets the number of pours per mu_r (default 4, --quick: 3; at most MAXSEEDS).
 *
 * The host (this file) owns what a DEM code usually owns: the particles, a linked-cell search
 * with Verlet neighbour lists, the velocity-Verlet integrator, gravity and the normal force (a
 * linear spring-dashpot). rollslide computes every other contact load:
 * rsl_contact_step_accumulate for each sphere-sphere contact, rsl_contact_step_wall_accumulate
 * for each sphere-plate contact. They step the sliding, rolling and twisting laws, assemble
 * them with the normal force we pass in into the force and torques on both bodies, add those to
 * the host's force and torque arrays, and update the per-contact history (rsl_contact_state,
 * plain data) that the host keeps next to its neighbour list. (rsl_contact_step and
 * rsl_contact_step_wall return the same loads in a struct instead, with the sliding force,
 * rolling moment, twisting torque and energy terms.)
 *
 * Contact laws: sliding spring-dashpot-slider (k_t = 2/7 k_n, mu_s = 0.5); rolling resistance
 * by the elastic-plastic spring-dashpot law (EPSD, "type C" of Ai et al.: k_r = 2.25 k_n mu_r^2,
 * moment limit mu_r R_r f_n, damping ratio 0.3 switched off at the limit); twisting by
 * Marshall's law. The angle of repose of spheres rises with the rolling friction coefficient:
 * Zhou, Xu, Yu & Zulli, "Numerical investigation of the angle of repose of monosized spheres",
 * Phys. Rev. E 64 (2001) 021301, and "An experimental and numerical study of the angle of
 * repose of coarse spheres", Powder Technol. 125 (2002) 45-54; Ai, Chen, Rotter & Ooi,
 * "Assessment of rolling resistance models in discrete element simulations", Powder Technol.
 * 206 (2011) 269-282, who recommend the EPSD law for static piles.
 *
 * The scene: a flat plate z = 0 (a rollslide wall of the same material as the particles) with a
 * ring of fixed spheres of radius R_b = 11 d lying on it. The ring sets the heap's base: the
 * heap grows until its flank reaches the angle of repose, then the surplus spills over the ring
 * and is removed 1.5 d beyond it. Without it, spheres on a flat plate roll away when mu_r is
 * small (with mu_r = 0 a sphere on a plate rolls for ever), the heap keeps spreading and its
 * angle would depend on how long one waits; a rough plate instead would set the foot of the heap
 * by the plate's own roughness. With the ring, the angle comes from the particle contacts alone.
 *
 * Pouring: layers of spheres (diameters uniform in [0.9, 1.1] d) are inserted on a jittered
 * lattice in a vertical stream of radius 3.5 d, 3 d above the heap's top, falling at 3 sqrt(g d),
 * until all 2000 are in; then the heap settles until its kinetic energy is small. The diameters,
 * the jitter and the small sideways velocities come from a xorshift generator seeded per (mu_r,
 * pour): each pour is a different random heap. Granular packing is chaotic (a one-ulp change of
 * the contact normals moves a heap's angle by degrees), so one pour per mu_r says little: the
 * program reports, for each mu_r, the mean angle of its pours, their sample standard deviation
 * and their range.
 *
 * Angle of repose: the heap's surface height h(r) (the highest particle top in each 1 d wide ring
 * and each of 12 sectors, averaged over sectors) is fitted by a straight line between the
 * stream's radius and 1 d inside the ring (the apex, hit by the stream, and the ring itself are
 * left out); angle = atan(-slope).
 *
 * Units: mean diameter d = 1, mass of a d = 1 sphere = 1, gravity g = 1; time in sqrt(d/g)
 * (14 ms for 2 mm glass beads). Stiffness is reduced (k_n = 1000 m g/d: in the settled heaps the
 * mean overlap is 0.25 % of d, the largest 3 %), as is usual in DEM when the result (here a
 * static angle) depends little on it; it allows dt = 0.005, checked below against the
 * library's stability bounds.
 *
 * The pours run in parallel (one per thread) with OpenMP when compiled with -fopenmp; each pour
 * is a separate simulation with its own seed, and the statistics are computed after all of them
 * in a fixed order, so the numbers are the same on every run, with or without OpenMP.
 */
#define _POSIX_C_SOURCE 200112L /* clock_gettime(CLOCK_THREAD_CPUTIME_ID) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rollslide.h"

#ifdef _OPENMP
#include <omp.h>
#endif

#define PI 3.14159265358979323846
#define MAXN 32  /* neighbour-list entries per particle (partners with a larger index) */
#define NSECT 12 /* azimuthal sectors of the height profile */
#define NBIN 24  /* radial rings of width 1 d */
#define FIXED_MASS 1e12 /* mass and inertia passed for the fixed ring spheres ("infinite") */
#define MAXMU 8     /* values of mu_r */
#define MAXSEEDS 8  /* pours per value of mu_r */

/* ---------------------------------------------------------------------------------------- */
/* Parameters                                                                                */

typedef struct {
    int n_particles;     /* spheres poured */
    double ring_radius;  /* R_b */
    double k_n;          /* normal stiffness (m g / d) */
    double restitution;  /* normal coefficient of restitution */
    double mu_s;         /* sliding friction */
    double rolling_damping_ratio;
    double dt;
    double skin;         /* Verlet-list skin */
    double pour_radius, pour_gap, pour_speed, lattice;
    double settle_time_max, t_max;
} params;

static params default_params(int quick) {
    params p;
    p.n_particles = quick ? 800 : 2000;
    p.ring_radius = quick ? 8.0 : 11.0;
    p.k_n = 1000.0;
    p.restitution = 0.3;
    p.mu_s = 0.5;
    p.rolling_damping_ratio = 0.3;
    p.dt = 0.005;
    p.skin = 0.3;
    p.pour_radius = 3.5;
    p.pour_gap = 3.0;
    p.pour_speed = 3.0;
    p.lattice = 1.15;
    p.settle_time_max = 12.0;
    p.t_max = 150.0;
    return p;
}

/* ---------------------------------------------------------------------------------------- */
/* Small helpers                                                                             */

static rsl_vec3 v3(double x, double y, double z) {
    rsl_vec3 v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

/* xorshift64*: a small deterministic generator (each pour has its own, see pour_seed). */
static double rnd(unsigned long long *s) {
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}

/* The generator's state for pour `seed` of the mu_r with index `mu_index`: splitmix64 of the
 * pair, so every (mu_r, pour) has its own stream (never the state 0, which xorshift keeps). */
static unsigned long long pour_seed(int mu_index, int seed) {
    unsigned long long z = (unsigned long long)(1 + MAXSEEDS * mu_index + seed);
    z *= 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return z ? z : 0x9E3779B97F4A7C15ULL;
}

static double now_seconds(void) {
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU time of the calling thread: what a case costs, whatever else runs on the machine. */
static double thread_cpu_seconds(void) {
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return 0.0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void die_status(int32_t status, const char *what) {
    fprintf(stderr, "dem_heap: %s failed: %s (%s)\n", what, rsl_status_str(status),
            rsl_last_error_message());
    exit(1);
}

static void *xcalloc(size_t n, size_t size) {
    void *p = calloc(n, size);
    if (!p) {
        fprintf(stderr, "dem_heap: out of memory\n");
        exit(1);
    }
    return p;
}

/* ---------------------------------------------------------------------------------------- */
/* The simulation state of one case                                                          */

typedef struct {
    int partner;             /* index of body 2 (> this particle's index) */
    int touching;            /* in contact at the last step */
    rsl_contact_state state; /* the library's history of this contact (all zero: fresh) */
} neighbour;

enum { MOBILE = 0, FIXED = 1, GONE = 2 };

typedef struct {
    params p;
    double mu_r;
    double zeta; /* damping ratio of the normal dashpot, from the restitution */
    rsl_model *model;
    rsl_wall plate;
    int n, cap, n_fixed, n_spilled;
    rsl_sphere *s; /* position, velocity, angular velocity, radius: the library's struct */
    rsl_vec3 *force, *torque, *x_listed;
    double *mass, *inertia;
    unsigned char *kind;
    neighbour *nb; /* cap * MAXN */
    int *nnb;
    rsl_contact_state *plate_state;
    unsigned char *on_plate;
    /* linked cells */
    double lo[3], cell;
    int nc[3];
    int *head, *next;
    int relist;
    double time, last_layer_z;
    long steps, contact_calls, rebuilds;
    unsigned long long rng;
} sim;

static void make_model(sim *S) {
    const params *p = &S->p;
    int32_t st = rsl_model_new(RSL_PRESET_OBJECTIVE, &S->model);
    if (st != RSL_OK) die_status(st, "rsl_model_new");
    /* Sliding: k_t = 2/7 k_n (equal normal and tangential periods), gamma_t = half the normal
     * dashpot of two mean spheres, mu_s. */
    double gamma_n = 2.0 * S->zeta * sqrt(0.5 * p->k_n);
    st = rsl_model_set_sliding(S->model, RSL_SLIDING_LINEAR, 2.0 / 7.0 * p->k_n, 0.5 * gamma_n,
                               p->mu_s);
    if (st != RSL_OK) die_status(st, "rsl_model_set_sliding");
    /* Rolling: EPSD in the length form, k_r = 2.25 k_n mu_r^2 (k_n is passed per contact),
     * damping ratio of the critical rolling damping (masses and inertias passed per contact),
     * dashpot off at the limit. */
    rsl_rolling_params r;
    st = rsl_model_get_rolling(S->model, &r);
    if (st != RSL_OK) die_status(st, "rsl_model_get_rolling");
    r.law = RSL_ROLLING_EPSD;
    r.form = RSL_FORM_LENGTH;
    r.stiffness_rule = RSL_STIFFNESS_EPSD;
    r.damping_rule = RSL_DAMPING_RATIO;
    r.damping_mode = RSL_DAMPING_BELOW_LIMIT;
    r.damping = p->rolling_damping_ratio;
    r.friction = S->mu_r;
    st = rsl_model_set_rolling(S->model, &r);
    if (st != RSL_OK) die_status(st, "rsl_model_set_rolling");
    /* Twisting: Marshall's law, from the sliding law and the contact radius. */
    st = rsl_model_set_twisting(S->model, RSL_TWISTING_MARSHALL, 0.0, 0.0, 0.0);
    if (st != RSL_OK) die_status(st, "rsl_model_set_twisting");
}

/* The library's stability bounds for the stiffest contact of the demo: two of the smallest
 * spheres (d = 0.9) with the largest mu_r (0.4). */
static void check_time_step(const params *p) {
    double d = 0.9, m = d * d * d, inertia = 0.1 * m * d * d, r_r = d / 4.0;
    double k_t = 2.0 / 7.0 * p->k_n, k_theta = 2.25 * p->k_n * 0.16 * r_r * r_r;
    double dt_c;
    int32_t st = rsl_coupled_critical_time_step(k_t, k_theta, m, m, inertia, inertia, d / 2,
                                                d / 2, &dt_c);
    if (st != RSL_OK) die_status(st, "rsl_coupled_critical_time_step");
    double dt_n = 2.0 / sqrt(p->k_n * 2.0 / m); /* undamped normal spring of the pair */
    if (p->dt > 0.2 * dt_c || p->dt > 0.2 * dt_n) {
        fprintf(stderr, "dem_heap: dt = %g is above 0.2 of the critical steps (%g, %g)\n", p->dt,
                dt_c, dt_n);
        exit(1);
    }
}

static int add_particle(sim *S, rsl_vec3 x, rsl_vec3 v, double radius, int kind) {
    int i = S->n++;
    S->s[i].position = x;
    S->s[i].velocity = v;
    S->s[i].angular_velocity = v3(0, 0, 0);
    S->s[i].radius = radius;
    S->kind[i] = (unsigned char)kind;
    if (kind == FIXED) {
        S->mass[i] = S->inertia[i] = FIXED_MASS;
    } else {
        S->mass[i] = 8.0 * radius * radius * radius; /* (2 radius)^3: a d = 1 sphere has mass 1 */
        S->inertia[i] = 0.4 * S->mass[i] * radius * radius;
    }
    S->relist = 1;
    return i;
}

static void sim_init(sim *S, const params *p, double mu_r, unsigned long long seed) {
    memset(S, 0, sizeof *S);
    S->p = *p;
    S->mu_r = mu_r;
    double ln_e = log(p->restitution);
    S->zeta = -ln_e / sqrt(PI * PI + ln_e * ln_e);
    make_model(S);
    S->plate.point = v3(0, 0, 0);
    S->plate.normal = v3(0, 0, 1); /* outward: towards the particles */
    S->plate.velocity = v3(0, 0, 0);
    S->plate.angular_velocity = v3(0, 0, 0);
    int n_ring = (int)floor(2.0 * PI * p->ring_radius / 1.02); /* unit spheres, small gaps */
    S->cap = p->n_particles + n_ring;
    size_t cap = (size_t)S->cap;
    S->s = xcalloc(cap, sizeof *S->s);
    S->force = xcalloc(cap, sizeof *S->force);
    S->torque = xcalloc(cap, sizeof *S->torque);
    S->x_listed = xcalloc(cap, sizeof *S->x_listed);
    S->mass = xcalloc(cap, sizeof *S->mass);
    S->inertia = xcalloc(cap, sizeof *S->inertia);
    S->kind = xcalloc(cap, 1);
    S->nb = xcalloc(cap * MAXN, sizeof *S->nb);
    S->nnb = xcalloc(cap, sizeof *S->nnb);
    S->plate_state = xcalloc(cap, sizeof *S->plate_state);
    S->on_plate = xcalloc(cap, 1);
    S->next = xcalloc(cap, sizeof *S->next);
    /* Cells cover the ring plus a margin; the cell size is the largest contact distance plus
     * the skin, so a neighbour is always in one of the 27 cells around a particle. */
    S->cell = 1.1 + p->skin;
    double half = p->ring_radius + 3.0;
    S->lo[0] = S->lo[1] = -half;
    S->lo[2] = -1.0;
    S->nc[0] = S->nc[1] = (int)ceil(2.0 * half / S->cell);
    S->nc[2] = (int)ceil((p->ring_radius + 12.0) / S->cell);
    S->head = xcalloc((size_t)S->nc[0] * (size_t)S->nc[1] * (size_t)S->nc[2], sizeof *S->head);
    S->rng = seed;
    for (int k = 0; k < n_ring; k++) {
        double phi = 2.0 * PI * k / n_ring;
        add_particle(S, v3(p->ring_radius * cos(phi), p->ring_radius * sin(phi), 0.5),
                     v3(0, 0, 0), 0.5, FIXED);
    }
    S->n_fixed = n_ring;
    S->last_layer_z = -1.0;
}

static void sim_free(sim *S) {
    rsl_model_free(S->model);
    free(S->s);
    free(S->force);
    free(S->torque);
    free(S->x_listed);
    free(S->mass);
    free(S->inertia);
    free(S->kind);
    free(S->nb);
    free(S->nnb);
    free(S->plate_state);
    free(S->on_plate);
    free(S->next);
    free(S->head);
}

static int clampi(int i, int n) { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

static void cell_of(const sim *S, rsl_vec3 x, int c[3]) {
    c[0] = clampi((int)floor((x.x - S->lo[0]) / S->cell), S->nc[0]);
    c[1] = clampi((int)floor((x.y - S->lo[1]) / S->cell), S->nc[1]);
    c[2] = clampi((int)floor((x.z - S->lo[2]) / S->cell), S->nc[2]);
}

/* Rebuilds the Verlet lists (pairs closer than r_i + r_j + skin, j > i) from the linked cells,
 * carrying the contact histories of pairs that stay listed. */
static void build_lists(sim *S) {
    int ncell = S->nc[0] * S->nc[1] * S->nc[2];
    for (int c = 0; c < ncell; c++) S->head[c] = -1;
    for (int i = 0; i < S->n; i++) {
        if (S->kind[i] == GONE) continue;
        int c[3];
        cell_of(S, S->s[i].position, c);
        int k = (c[2] * S->nc[1] + c[1]) * S->nc[0] + c[0];
        S->next[i] = S->head[k];
        S->head[k] = i;
    }
    neighbour fresh[MAXN];
    for (int i = 0; i < S->n; i++) {
        S->x_listed[i] = S->s[i].position;
        if (S->kind[i] == GONE) {
            S->nnb[i] = 0;
            continue;
        }
        const rsl_sphere *a = &S->s[i];
        neighbour *old = &S->nb[(size_t)i * MAXN];
        int nfresh = 0, c[3];
        cell_of(S, a->position, c);
        for (int z = c[2] - 1; z <= c[2] + 1; z++) {
            if (z < 0 || z >= S->nc[2]) continue;
            for (int y = c[1] - 1; y <= c[1] + 1; y++) {
                if (y < 0 || y >= S->nc[1]) continue;
                for (int x = c[0] - 1; x <= c[0] + 1; x++) {
                    if (x < 0 || x >= S->nc[0]) continue;
                    for (int j = S->head[(z * S->nc[1] + y) * S->nc[0] + x]; j >= 0;
                         j = S->next[j]) {
                        if (j <= i || (S->kind[i] == FIXED && S->kind[j] == FIXED)) continue;
                        const rsl_sphere *b = &S->s[j];
                        double ex = b->position.x - a->position.x;
                        double ey = b->position.y - a->position.y;
                        double ez = b->position.z - a->position.z;
                        double reach = a->radius + b->radius + S->p.skin;
                        if (ex * ex + ey * ey + ez * ez >= reach * reach) continue;
                        if (nfresh == MAXN) {
                            fprintf(stderr, "dem_heap: more than %d neighbours\n", MAXN);
                            exit(1);
                        }
                        neighbour *e = &fresh[nfresh++];
                        memset(e, 0, sizeof *e);
                        e->partner = j;
                        for (int k = 0; k < S->nnb[i]; k++)
                            if (old[k].partner == j) {
                                *e = old[k];
                                break;
                            }
                    }
                }
            }
        }
        memcpy(old, fresh, (size_t)nfresh * sizeof fresh[0]);
        S->nnb[i] = nfresh;
    }
    S->relist = 0;
    S->rebuilds++;
}

/* Linear spring-dashpot normal force (the host's part), clipped at 0 (no attraction).
 * ddot = n . (v2 - v1) is the library's normal rate; the overlap grows at -ddot. */
static double normal_force(const sim *S, double overlap, double ddot, double m_eff) {
    double f = S->p.k_n * overlap - 2.0 * S->zeta * sqrt(m_eff * S->p.k_n) * ddot;
    return f > 0.0 ? f : 0.0;
}

/* All contact loads: sphere-sphere through rsl_contact_step_accumulate, sphere-plate through
 * rsl_contact_step_wall_accumulate. The history of a contact that opened is reset to a fresh
 * one. */
static void compute_forces(sim *S) {
    for (int i = 0; i < S->n; i++) {
        S->force[i] = v3(0, 0, -S->mass[i]); /* gravity, g = 1 along -z */
        S->torque[i] = v3(0, 0, 0);
    }
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = S->p.dt;
    in.normal_stiffness = S->p.k_n;
    for (int i = 0; i < S->n; i++) {
        if (S->kind[i] == GONE) continue;
        const rsl_sphere *a = &S->s[i];
        neighbour *list = &S->nb[(size_t)i * MAXN];
        for (int k = 0; k < S->nnb[i]; k++) {
            neighbour *e = &list[k];
            int j = e->partner;
            const rsl_sphere *b = &S->s[j];
            double ex = b->position.x - a->position.x;
            double ey = b->position.y - a->position.y;
            double ez = b->position.z - a->position.z;
            double rsum = a->radius + b->radius;
            double d2 = ex * ex + ey * ey + ez * ez;
            if (d2 >= rsum * rsum || S->kind[j] == GONE) {
                if (e->touching) rsl_contact_state_init(&e->state);
                e->touching = 0;
                continue;
            }
            double dist = sqrt(d2);
            double ddot = (ex * (b->velocity.x - a->velocity.x) +
                           ey * (b->velocity.y - a->velocity.y) +
                           ez * (b->velocity.z - a->velocity.z)) /
                          dist;
            double m_eff = S->mass[i] * S->mass[j] / (S->mass[i] + S->mass[j]);
            in.normal_force = normal_force(S, rsum - dist, ddot, m_eff);
            in.mass1 = S->mass[i];
            in.mass2 = S->mass[j];
            in.inertia1 = S->inertia[i];
            in.inertia2 = S->inertia[j];
            /* Adds force1 = -f_n n + F_t (it contains the normal force we passed in) to
             * force[i], subtracts it from force[j], adds the torques to torque[i], torque[j]. */
            int32_t st = rsl_contact_step_accumulate(S->model, a, b, &in, &e->state, &S->force[i],
                                                     &S->torque[i], &S->force[j], &S->torque[j]);
            if (st != RSL_OK) die_status(st, "rsl_contact_step_accumulate");
            e->touching = 1;
            S->contact_calls++;
        }
        if (S->kind[i] != MOBILE) continue;
        /* The plate z = 0. */
        double overlap = a->radius - a->position.z;
        if (overlap > 0.0) {
            if (!S->on_plate[i]) rsl_contact_state_init(&S->plate_state[i]);
            S->on_plate[i] = 1;
            /* The normal rate against the plate: n = -z, ddot = n . (0 - v) = v_z. */
            in.normal_force = normal_force(S, overlap, a->velocity.z, S->mass[i]);
            in.mass1 = S->mass[i];
            in.inertia1 = S->inertia[i];
            int32_t st = rsl_contact_step_wall_accumulate(S->model, a, &S->plate, &in,
                                                          &S->plate_state[i], &S->force[i],
                                                          &S->torque[i]);
            if (st != RSL_OK) die_status(st, "rsl_contact_step_wall_accumulate");
            S->contact_calls++;
        } else {
            S->on_plate[i] = 0;
        }
    }
}

/* The height of the heap's top: the highest particle top that is nearly at rest. */
static double heap_top(const sim *S) {
    double top = 0.0;
    for (int i = S->n_fixed; i < S->n; i++) {
        if (S->kind[i] != MOBILE) continue;
        const rsl_vec3 *v = &S->s[i].velocity;
        double z = S->s[i].position.z + S->s[i].radius;
        if (v->x * v->x + v->y * v->y + v->z * v->z < 0.25 && z > top) top = z;
    }
    return top;
}

/* Pours: inserts a new lattice layer of the stream once the previous one has fallen by one
 * lattice spacing. */
static void pour(sim *S) {
    const params *p = &S->p;
    if (S->n == S->cap) return;
    /* Wait until the last layer has fallen by one spacing (its last sphere tells). */
    if (S->last_layer_z >= 0.0 && S->s[S->n - 1].position.z > S->last_layer_z - p->lattice)
        return;
    double z_layer = heap_top(S) + p->pour_gap;
    if (S->last_layer_z >= 0.0 && z_layer < S->last_layer_z) z_layer = S->last_layer_z;
    int m = (int)floor(p->pour_radius / p->lattice);
    for (int a = -m; a <= m && S->n < S->cap; a++)
        for (int b = -m; b <= m && S->n < S->cap; b++) {
            double x = a * p->lattice + 0.1 * (rnd(&S->rng) - 0.5);
            double y = b * p->lattice + 0.1 * (rnd(&S->rng) - 0.5);
            if (x * x + y * y > p->pour_radius * p->pour_radius) continue;
            double radius = 0.45 + 0.1 * rnd(&S->rng);
            /* Skip a site that overlaps a sphere already there (one thrown up by the stream). */
            int free_site = 1;
            for (int j = S->n_fixed; j < S->n && free_site; j++) {
                const rsl_vec3 *q = &S->s[j].position;
                double ex = q->x - x, ey = q->y - y, ez = q->z - z_layer;
                double reach = S->s[j].radius + radius + 0.05;
                free_site = S->kind[j] != MOBILE || ex * ex + ey * ey + ez * ez >= reach * reach;
            }
            if (!free_site) continue;
            rsl_vec3 v = v3(0.05 * (rnd(&S->rng) - 0.5), 0.05 * (rnd(&S->rng) - 0.5),
                            -p->pour_speed);
            add_particle(S, v3(x, y, z_layer), v, radius, MOBILE);
        }
    S->last_layer_z = z_layer;
}

/* Spheres that went over the ring are removed from the simulation. */
static void drain(sim *S) {
    double out2 = (S->p.ring_radius + 1.5) * (S->p.ring_radius + 1.5);
    for (int i = S->n_fixed; i < S->n; i++) {
        if (S->kind[i] != MOBILE) continue;
        const rsl_vec3 *x = &S->s[i].position;
        if (x->x * x->x + x->y * x->y > out2 || x->z < -1.0) {
            S->kind[i] = GONE;
            S->s[i].velocity = v3(0, 0, 0);
            S->s[i].angular_velocity = v3(0, 0, 0);
            S->n_spilled++;
            S->relist = 1;
        }
    }
}

static double kinetic_energy_per_particle(const sim *S) {
    double e = 0.0;
    int n = 0;
    for (int i = 0; i < S->n; i++) {
        if (S->kind[i] != MOBILE) continue;
        const rsl_sphere *s = &S->s[i];
        e += 0.5 * S->mass[i] *
                 (s->velocity.x * s->velocity.x + s->velocity.y * s->velocity.y +
                  s->velocity.z * s->velocity.z) +
             0.5 * S->inertia[i] *
                 (s->angular_velocity.x * s->angular_velocity.x +
                  s->angular_velocity.y * s->angular_velocity.y +
                  s->angular_velocity.z * s->angular_velocity.z);
        n++;
    }
    return n ? e / n : 0.0;
}

/* One velocity-Verlet step: half kick, drift, forces at the new positions (with the half-step
 * velocities, as LAMMPS does for dissipative forces), half kick. */
static void step(sim *S) {
    const double h = 0.5 * S->p.dt, lim = 0.25 * S->p.skin * S->p.skin;
    for (int i = 0; i < S->n; i++) {
        if (S->kind[i] != MOBILE) continue;
        rsl_sphere *s = &S->s[i];
        double im = h / S->mass[i], ii = h / S->inertia[i];
        s->velocity.x += im * S->force[i].x;
        s->velocity.y += im * S->force[i].y;
        s->velocity.z += im * S->force[i].z;
        s->angular_velocity.x += ii * S->torque[i].x;
        s->angular_velocity.y += ii * S->torque[i].y;
        s->angular_velocity.z += ii * S->torque[i].z;
        s->position.x += S->p.dt * s->velocity.x;
        s->position.y += S->p.dt * s->velocity.y;
        s->position.z += S->p.dt * s->velocity.z;
        /* A sphere that moved half a skin since the lists were built forces a rebuild. */
        double dx = s->position.x - S->x_listed[i].x, dy = s->position.y - S->x_listed[i].y,
               dz = s->position.z - S->x_listed[i].z;
        if (dx * dx + dy * dy + dz * dz > lim) S->relist = 1;
    }
    if (S->relist) build_lists(S);
    compute_forces(S);
    for (int i = 0; i < S->n; i++) {
        if (S->kind[i] != MOBILE) continue;
        rsl_sphere *s = &S->s[i];
        double im = h / S->mass[i], ii = h / S->inertia[i];
        s->velocity.x += im * S->force[i].x;
        s->velocity.y += im * S->force[i].y;
        s->velocity.z += im * S->force[i].z;
        s->angular_velocity.x += ii * S->torque[i].x;
        s->angular_velocity.y += ii * S->torque[i].y;
        s->angular_velocity.z += ii * S->torque[i].z;
    }
    S->time += S->p.dt;
    S->steps++;
}

/* ---------------------------------------------------------------------------------------- */
/* Angle of repose                                                                           */

typedef struct {
    double mu_r;
    double angle_deg;
    double apex;           /* fitted line: h = apex - r tan(angle) */
    double profile[NBIN];  /* h(r) at ring centres r = k + 0.5 (NAN: empty) */
    double fit_lo, fit_hi; /* radii of the fitted range */
    double height;         /* highest particle top */
    double sim_time, cpu_seconds;
    long steps, contact_calls;
    int in_heap, spilled;
} result;

static void measure(const sim *S, result *R) {
    double hmax[NBIN][NSECT];
    for (int b = 0; b < NBIN; b++)
        for (int k = 0; k < NSECT; k++) hmax[b][k] = -1.0;
    R->height = 0.0;
    R->in_heap = 0;
    for (int i = 0; i < S->n; i++) {
        if (S->kind[i] != MOBILE) continue;
        const rsl_sphere *s = &S->s[i];
        double r = sqrt(s->position.x * s->position.x + s->position.y * s->position.y);
        double top = s->position.z + s->radius;
        if (r < S->p.ring_radius) R->in_heap++;
        if (top > R->height) R->height = top;
        int b = (int)r;
        if (b >= NBIN) continue;
        double phi = atan2(s->position.y, s->position.x) + PI;
        int k = clampi((int)(phi / (2.0 * PI) * NSECT), NSECT);
        if (top > hmax[b][k]) hmax[b][k] = top;
    }
    for (int b = 0; b < NBIN; b++) {
        double sum = 0.0;
        int cnt = 0;
        for (int k = 0; k < NSECT; k++)
            if (hmax[b][k] > 0.0) {
                sum += hmax[b][k];
                cnt++;
            }
        /* A ring counts when at least half of its sectors hold a particle. The central disc
         * (b = 0) is too small for sectors: its highest sphere is its height. */
        R->profile[b] = cnt * 2 >= NSECT ? sum / cnt : NAN;
        if (b == 0) {
            double top = -1.0;
            for (int k = 0; k < NSECT; k++)
                if (hmax[0][k] > top) top = hmax[0][k];
            R->profile[0] = top > 0.0 ? top : NAN;
        }
    }
    /* Least squares fit of h = a + b r over the rings between the stream and the ring. */
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int m = 0;
    R->fit_lo = S->p.pour_radius + 0.5;
    R->fit_hi = S->p.ring_radius - 1.0;
    for (int b = 0; b < NBIN; b++) {
        double h = R->profile[b], r = b + 0.5;
        if (isnan(h) || r < R->fit_lo || r > R->fit_hi) continue;
        sx += r;
        sy += h;
        sxx += r * r;
        sxy += r * h;
        m++;
    }
    double slope = m >= 2 ? (m * sxy - sx * sy) / (m * sxx - sx * sx) : 0.0;
    R->apex = m >= 2 ? (sy - slope * sx) / m : 0.0;
    R->angle_deg = atan(-slope) * 180.0 / PI;
}

static void run_case(const params *p, double mu_r, unsigned long long seed, result *R) {
    double t0 = thread_cpu_seconds();
    sim S;
    sim_init(&S, p, mu_r, seed);
    double poured_at = -1.0;
    while (S.time < p->t_max) {
        if (S.n < S.cap) {
            pour(&S);
            if (S.n == S.cap) poured_at = S.time;
        }
        if (S.steps % 50 == 0) drain(&S);
        step(&S);
        /* Settled: everything poured, 3 time units passed, and the kinetic energy per sphere
         * below 2e-4 m g d (mean speeds ~ 0.02 sqrt(g d)); or the time limit. */
        if (poured_at >= 0.0 && S.steps % 50 == 0 && S.time > poured_at + 3.0 &&
            (kinetic_energy_per_particle(&S) < 2e-4 || S.time > poured_at + p->settle_time_max))
            break;
    }
    memset(R, 0, sizeof *R);
    R->mu_r = mu_r;
    measure(&S, R);
    R->sim_time = S.time;
    R->steps = S.steps;
    R->contact_calls = S.contact_calls;
    R->spilled = S.n_spilled;
    R->cpu_seconds = thread_cpu_seconds() - t0;
    sim_free(&S);
}

/* ---------------------------------------------------------------------------------------- */
/* Statistics over the pours of one mu_r                                                     */

typedef struct {
    double mu_r;
    int pours;
    double mean, sd, min, max; /* angle of repose (degrees); sd: sample standard deviation */
    double height, height_sd;  /* highest particle top: mean and sample standard deviation */
    double in_heap, spilled;   /* means */
    double apex;               /* mean of the fitted lines' intercepts */
    double profile[NBIN];      /* mean h(r) over the pours that fill ring b (NAN: under half) */
    double fit_lo, fit_hi;
    double cpu_seconds;        /* summed over the pours */
    long steps_min, steps_max, contact_calls;
} summary;

/* Sample standard deviation (n - 1 in the denominator); 0 for a single pour. */
static double sample_sd(const double *x, int n, double mean) {
    if (n < 2) return 0.0;
    double ss = 0.0;
    for (int i = 0; i < n; i++) ss += (x[i] - mean) * (x[i] - mean);
    return sqrt(ss / (n - 1));
}

static void summarise(const result *r, int n, summary *S) {
    double angle[MAXSEEDS], height[MAXSEEDS];
    memset(S, 0, sizeof *S);
    S->mu_r = r[0].mu_r;
    S->pours = n;
    S->min = S->max = r[0].angle_deg;
    S->steps_min = S->steps_max = r[0].steps;
    S->fit_lo = r[0].fit_lo;
    S->fit_hi = r[0].fit_hi;
    for (int k = 0; k < n; k++) {
        angle[k] = r[k].angle_deg;
        height[k] = r[k].height;
        S->mean += r[k].angle_deg / n;
        S->height += r[k].height / n;
        S->in_heap += (double)r[k].in_heap / n;
        S->spilled += (double)r[k].spilled / n;
        S->apex += r[k].apex / n;
        S->cpu_seconds += r[k].cpu_seconds;
        S->contact_calls += r[k].contact_calls;
        if (r[k].angle_deg < S->min) S->min = r[k].angle_deg;
        if (r[k].angle_deg > S->max) S->max = r[k].angle_deg;
        if (r[k].steps < S->steps_min) S->steps_min = r[k].steps;
        if (r[k].steps > S->steps_max) S->steps_max = r[k].steps;
    }
    S->sd = sample_sd(angle, n, S->mean);
    S->height_sd = sample_sd(height, n, S->height);
    for (int b = 0; b < NBIN; b++) {
        double sum = 0.0;
        int cnt = 0;
        for (int k = 0; k < n; k++)
            if (!isnan(r[k].profile[b])) {
                sum += r[k].profile[b];
                cnt++;
            }
        S->profile[b] = cnt * 2 >= n && cnt > 0 ? sum / cnt : NAN;
    }
}

/* ---------------------------------------------------------------------------------------- */
/* SVG plot: angle of repose vs mu_r (left), the mean heap profiles h(r) (right)             */

static const char *const COLORS[] = {"#1b9e77", "#d95f02", "#7570b3", "#e7298a",
                                     "#66a61e", "#e6ab02", "#a6761d", "#666666"};

static int write_svg(const char *path, const result (*res)[MAXSEEDS], const summary *sum, int n,
                     int seeds, const params *p) {
    FILE *f = fopen(path, "w");
    if (!f) return 0;
    const double W = 960, H = 440;
    fprintf(f,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
            "viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\" font-size=\"13\">\n"
            "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
            W, H, W, H);
    /* Left panel. */
    double x0 = 70, x1 = 430, y0 = 370, y1 = 50;
    double mu_max = 0.0, a_max = 0.0;
    for (int i = 0; i < n; i++) {
        if (sum[i].mu_r > mu_max) mu_max = sum[i].mu_r;
        if (sum[i].max > a_max) a_max = sum[i].max;
        if (sum[i].mean + sum[i].sd > a_max) a_max = sum[i].mean + sum[i].sd;
    }
    mu_max = mu_max > 0.0 ? ceil(mu_max * 10.0 + 1e-9) / 10.0 : 0.1;
    a_max = 10.0 * ceil(a_max / 10.0 + 0.25);
#define PX(mu) (x0 + (mu) / mu_max * (x1 - x0))
#define PY(a) (y0 - (a) / a_max * (y0 - y1))
    fprintf(f, "<text x=\"%.0f\" y=\"24\" text-anchor=\"middle\" font-size=\"15\">Angle of repose "
               "vs rolling friction</text>\n", (x0 + x1) / 2);
    fprintf(f, "<text x=\"%.0f\" y=\"41\" text-anchor=\"middle\" font-size=\"11\" fill=\"#555\">"
               "%d spheres, %d pours per mu_r, mu_s = %.2g, EPSD rolling resistance "
               "(rollslide)</text>\n",
            (x0 + x1) / 2, p->n_particles, seeds, p->mu_s);
    for (int k = 0; 5.0 * k <= a_max; k++) {
        double a = 5.0 * k;
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n",
                x0, PY(a), x1, PY(a));
        if (k % 2 == 0)
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%.0f</text>\n", x0 - 6,
                    PY(a) + 4, a);
    }
    for (int k = 0; k <= (int)(mu_max * 20.0 + 0.5); k++) {
        double mu = 0.05 * k;
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n",
                PX(mu), y0, PX(mu), y1);
        if (k % 2 == 0)
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%.1f</text>\n", PX(mu),
                    y0 + 18, mu);
    }
    fprintf(f, "<rect x=\"%.0f\" y=\"%.0f\" width=\"%.0f\" height=\"%.0f\" fill=\"none\" "
               "stroke=\"black\"/>\n", x0, y1, x1 - x0, y0 - y1);
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">rolling friction "
               "coefficient mu_r</text>\n", (x0 + x1) / 2, y0 + 40);
    fprintf(f, "<text transform=\"translate(%.0f,%.0f) rotate(-90)\" text-anchor=\"middle\">"
               "angle of repose (degrees)</text>\n", x0 - 45, (y0 + y1) / 2);
    fprintf(f, "<polyline fill=\"none\" stroke=\"#333\" stroke-width=\"1.5\" points=\"");
    for (int i = 0; i < n; i++) fprintf(f, "%.1f,%.1f ", PX(sum[i].mu_r), PY(sum[i].mean));
    fprintf(f, "\"/>\n");
    for (int i = 0; i < n; i++) {
        double x = PX(sum[i].mu_r);
        /* Each pour: a small open circle, spread sideways so that equal angles stay visible. */
        for (int k = 0; k < seeds; k++)
            fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"2.5\" fill=\"none\" stroke=\"%s\" "
                       "stroke-width=\"1.2\"/>\n",
                    x + 10.0 + 5.0 * k, PY(res[i][k].angle_deg), COLORS[i % 8]);
        /* The mean and the error bar: one sample standard deviation either side. */
        if (seeds > 1)
            fprintf(f, "<path d=\"M%.1f %.1fV%.1fM%.1f %.1fh10M%.1f %.1fh10\" stroke=\"black\" "
                       "stroke-width=\"1.5\" fill=\"none\"/>\n",
                    x, PY(sum[i].mean - sum[i].sd), PY(sum[i].mean + sum[i].sd), x - 5,
                    PY(sum[i].mean - sum[i].sd), x - 5, PY(sum[i].mean + sum[i].sd));
        fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"5\" fill=\"%s\" stroke=\"black\"/>\n", x,
                PY(sum[i].mean), COLORS[i % 8]);
    }
    /* Legend, top left (the curve rises to the right). */
    {
        double lx = x0 + 14, ly = y1 + 20;
        fprintf(f, "<path d=\"M%.1f %.1fV%.1fM%.1f %.1fh10M%.1f %.1fh10\" stroke=\"black\" "
                   "stroke-width=\"1.5\" fill=\"none\"/>\n"
                   "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"5\" fill=\"#999\" stroke=\"black\"/>\n",
                lx, ly - 11, ly + 3, lx - 5, ly - 11, lx - 5, ly + 3, lx, ly - 4);
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\">mean of the %d pours, bar: "
                   "&#177;1 sample std. dev.</text>\n", lx + 14, ly, seeds);
        ly += 20;
        fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"2.5\" fill=\"none\" stroke=\"#555\" "
                   "stroke-width=\"1.2\"/>\n", lx, ly - 4);
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\">each pour (its own random "
                   "seed)</text>\n", lx + 14, ly);
    }
#undef PX
#undef PY
    /* Right panel: mean h(r) of the pours, with the straight flank at the mean angle. */
    x0 = 530;
    x1 = 930;
    double r_max = 0.0, h_max = 0.0;
    for (int i = 0; i < n; i++)
        for (int b = 0; b < NBIN; b++)
            if (!isnan(sum[i].profile[b])) {
                if (b + 1.0 > r_max) r_max = b + 1.0;
                if (sum[i].profile[b] > h_max) h_max = sum[i].profile[b];
            }
    r_max = 5.0 * ceil(r_max / 5.0);
    h_max = 2.0 * ceil(h_max / 2.0 + 0.6); /* room for the legend */
    /* Same scale on both axes, so the slopes show the true angles. */
    double scale = (x1 - x0) / r_max;
    if ((y0 - y1) / h_max < scale) scale = (y0 - y1) / h_max;
#define QX(r) (x0 + (r) * scale)
#define QY(h) (y0 - (h) * scale)
    fprintf(f, "<text x=\"%.0f\" y=\"24\" text-anchor=\"middle\" font-size=\"15\">Heap surface "
               "h(r), mean of the pours</text>\n", (x0 + x1) / 2);
    fprintf(f, "<text x=\"%.0f\" y=\"41\" text-anchor=\"middle\" font-size=\"11\" fill=\"#555\">"
               "equal axes, unit: mean diameter</text>\n", (x0 + x1) / 2);
    for (int k = 0; k <= (int)r_max; k += 5) {
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n",
                QX(k), y0, QX(k), QY(h_max));
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%d</text>\n", QX(k), y0 + 18,
                k);
    }
    for (int k = 0; k <= (int)h_max; k += 2) {
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n",
                x0, QY(k), QX(r_max), QY(k));
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%d</text>\n", x0 - 6,
                QY(k) + 4, k);
    }
    fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
               "stroke=\"black\"/>\n", x0, QY(h_max), QX(r_max) - x0, y0 - QY(h_max));
    fprintf(f,
            "<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">distance from the axis r</text>\n",
            (x0 + QX(r_max)) / 2, y0 + 40);
    fprintf(f, "<text transform=\"translate(%.0f,%.0f) rotate(-90)\" text-anchor=\"middle\">"
               "height h</text>\n", x0 - 35, (y0 + QY(h_max)) / 2);
    for (int i = 0; i < n; i++) {
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"2\" points=\"",
                COLORS[i % 8]);
        for (int b = 0; b < NBIN; b++)
            if (!isnan(sum[i].profile[b]))
                fprintf(f, "%.1f,%.1f ", QX(b + 0.5), QY(sum[i].profile[b]));
        fprintf(f, "\"/>\n");
        double t = tan(sum[i].mean * PI / 180.0);
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" "
                   "stroke-dasharray=\"5,3\"/>\n",
                QX(sum[i].fit_lo), QY(sum[i].apex - t * sum[i].fit_lo), QX(sum[i].fit_hi),
                QY(sum[i].apex - t * sum[i].fit_hi), COLORS[i % 8]);
        /* Legend: two columns at the top, above the heaps; mean angle and sample std. dev. */
        double lx = x0 + 10 + 180 * (i / 3), ly = QY(h_max) + 18 + 16 * (i % 3);
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" "
                   "stroke-width=\"2\"/>\n", lx, ly - 4, lx + 22, ly - 4, COLORS[i % 8]);
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\">mu_r %.2f: %.1f &#177; "
                   "%.1f&#176;</text>\n", lx + 27, ly, sum[i].mu_r, sum[i].mean, sum[i].sd);
    }
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" font-size=\"11\" fill=\"#555\">dashed: flank at the "
               "mean angle over the fitted range</text>\n", x0 + 10, y0 - 22);
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" font-size=\"11\" fill=\"#555\">the ring of fixed "
               "spheres is at r = %.0f</text>\n", x0 + 10, y0 - 8, p->ring_radius);
#undef QX
#undef QY
    fprintf(f, "</svg>\n");
    return fclose(f) == 0;
}

/* ---------------------------------------------------------------------------------------- */

int main(int argc, char **argv) {
    const char *svg = "heap.svg";
    int quick = 0, seeds = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--quick") == 0)
            quick = 1;
        else if (strcmp(argv[i], "--seeds") == 0 && i + 1 < argc) {
            seeds = atoi(argv[++i]);
            if (seeds < 1 || seeds > MAXSEEDS) {
                fprintf(stderr, "dem_heap: --seeds takes 1 to %d\n", MAXSEEDS);
                return 2;
            }
        } else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            printf("usage: %s [OUT.svg] [--quick] [--seeds N]\n", argv[0]);
            return 0;
        } else
            svg = argv[i];
    }
    if (seeds == 0) seeds = quick ? 3 : 4;
    printf("rollslide %s (header %d.%d.%d)\n", rsl_version(), RSL_VERSION_MAJOR,
           RSL_VERSION_MINOR, RSL_VERSION_PATCH);

    params p = default_params(quick);
    check_time_step(&p);
    static const double full_mu[] = {0.0, 0.05, 0.1, 0.2, 0.3, 0.4};
    static const double quick_mu[] = {0.0, 0.4};
    const double *mus = quick ? quick_mu : full_mu;
    int n = quick ? 2 : (int)(sizeof full_mu / sizeof full_mu[0]);
    static result res[MAXMU][MAXSEEDS];
    summary sum[MAXMU];
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    printf("pouring %d spheres (d in [0.9, 1.1]) into a ring of radius %.0f d on a plate, "
           "%d values of mu_r, %d pours (random seeds) each, %d thread%s\n",
           p.n_particles, p.ring_radius, n, seeds, threads, threads == 1 ? "" : "s");
    fflush(stdout);
    double t0 = now_seconds();
    int tasks = n * seeds;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
#endif
    for (int t = 0; t < tasks; t++) {
        /* The pours with the most rolling friction run longest (taller heaps): start them first. */
        int i = n - 1 - t / seeds, k = t % seeds;
        run_case(&p, mus[i], pour_seed(i, k), &res[i][k]);
    }
    double elapsed = now_seconds() - t0;

    printf("\n%6s  %-29s  %-*s  %14s  %7s  %7s  %7s\n", "", "angle of repose (degrees)",
           6 * seeds - 1, "each pour", "height", "in heap", "spilled", "cpu [s]");
    printf("%6s  %6s  %5s  %6s  %6s  %-*s  %6s  %6s  %7s  %7s  %7s\n", "mu_r", "mean", "sd", "min",
           "max", 6 * seeds - 1, "", "mean", "sd", "mean", "mean", "sum");
    long calls = 0, steps_min = 0, steps_max = 0;
    double cpu = 0.0;
    for (int i = 0; i < n; i++) {
        summarise(res[i], seeds, &sum[i]);
        const summary *s = &sum[i];
        printf("%6.2f  %6.1f  %5.1f  %6.1f  %6.1f ", s->mu_r, s->mean, s->sd, s->min, s->max);
        for (int k = 0; k < seeds; k++) printf(" %5.1f", res[i][k].angle_deg);
        printf("  %6.2f  %6.2f  %7.0f  %7.0f  %7.1f\n", s->height, s->height_sd, s->in_heap,
               s->spilled, s->cpu_seconds);
        calls += s->contact_calls;
        cpu += s->cpu_seconds;
        if (i == 0 || s->steps_min < steps_min) steps_min = s->steps_min;
        if (i == 0 || s->steps_max > steps_max) steps_max = s->steps_max;
    }
    printf("\n%d heaps of %ld to %ld steps; %ld contact steps through rollslide (%.2f us each, "
           "everything included)\n",
           tasks, steps_min, steps_max, calls, 1e6 * cpu / (double)calls);
    printf("wall-clock time %.1f s with %d thread%s (CPU time %.1f s)\n", elapsed, threads,
           threads == 1 ? "" : "s", cpu);

    if (!write_svg(svg, (const result(*)[MAXSEEDS])res, sum, n, seeds, &p)) {
        fprintf(stderr, "dem_heap: cannot write %s\n", svg);
        return 1;
    }
    printf("plot written to %s\n", svg);
    /* The physics check of the demo: the heap must steepen with rolling friction, by more than
     * the scatter between pours. One pour per mu_r is not enough for this: a one-ulp change of
     * the contact normals moves a single heap's angle by several degrees (the quick smoke test's
     * heaps once moved from 13.9 to 21.2 degrees at mu_r = 0 and from 26.2 to 22.3 at
     * mu_r = 0.4). So the check is on the means over the pours: the mean at the largest mu_r must
     * exceed the mean at mu_r = 0 by more than the sum of the two sample standard deviations,
     * and by a floor (5 degrees for the angle). The quick smoke test (800 spheres, a small heap
     * whose angle is a fit over a few dozen surface spheres) checks the mean height instead,
     * which scatters far less; its floor is 20 % of the height at mu_r = 0. */
    const summary *lo = &sum[0], *hi = &sum[n - 1];
    double gain = quick ? hi->height - lo->height : hi->mean - lo->mean;
    double spread = quick ? lo->height_sd + hi->height_sd : lo->sd + hi->sd;
    double floor_ = quick ? 0.2 * lo->height : 5.0;
    int rising = gain > spread && gain > floor_;
    printf("check: %s at mu_r = %.2f minus at mu_r = %.2f = %.2f, must exceed %.2f (the two "
           "sample standard deviations summed) and %.2f: %s\n",
           quick ? "mean height" : "mean angle", hi->mu_r, lo->mu_r, gain, spread, floor_,
           rising ? "passed" : "FAILED");
    if (!rising)
        fprintf(stderr, "dem_heap: the heap did not steepen with mu_r (%s)\n",
                quick ? "height" : "angle of repose");
    return rising ? 0 : 1;
}
