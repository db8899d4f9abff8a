/*
 * parallel_forces: the contact force loop of ONE DEM simulation on T threads, and a check that
 * the threaded result is the serial one.
 *
 *   parallel_forces [M [STEPS [TMAX]]]
 *
 *   M      lattice sites per edge of the packing (default 20: 4,000 spheres, 19,386 contacts;
 *          M = 30: 13,500 spheres, 70,476 contacts; M = 40: 32,000 spheres, 173,166 contacts)
 *   STEPS  time steps (default 3)
 *   TMAX   the largest thread count checked (default 4): T = 1, 2, 4, ... up to TMAX
 *
 * The packing: spheres (diameters uniform in [0.99, 1.01]) on a jittered face-centred cubic
 * lattice whose nearest-neighbour distance (0.96) is shorter than a diameter, so that every
 * sphere presses on its 12 neighbours. The outer layer of the cube is held fixed (a container);
 * the inner spheres start with small random velocities and fast random spins, so that the
 * sliding, rolling and twisting springs load from the first step and contacts reach each of the
 * three limits within the first steps (the program prints how many). The neighbour list is
 * built once, with linked cells, in the usual order: sorted by body 1 (the smaller index), each
 * pair once. Every pair listed touches and keeps touching (the container holds the packing
 * together); the program checks it at every step. A host whose contacts open and close also
 * resets the state of a contact that ends (see rsl_contact_state in rollslide.h), which this
 * packing never needs.
 *
 * The host computes the normal force (a linear spring-dashpot, clipped at 0); rollslide steps
 * every other law: the LAMMPS_2021 preset with its linear history sliding, the rolling
 * spring-dashpot-slider and the twisting spring-dashpot-slider (one shared, read-only model).
 *
 * The patterns, all for one time step of one simulation:
 *
 *  serial   one thread: rsl_batch_step over the whole neighbour list (particle-major: loads
 *           added to force[] and torque[] in contact order), and the same loop written with
 *           rsl_contact_step_accumulate. The reference.
 *
 *  A. contact-major (the pattern whose result does not depend on T): each of T threads steps
 *           its own contiguous range of
 *           contacts with rsl_batch_step_contacts (states are per contact: nothing is shared),
 *           gathering the two spheres of each contact into a small per-thread block first, and
 *           writes each contact's loads to loads[c]. Then, after a barrier, each thread owns a
 *           range of particles and adds, for each of its particles, the loads of the contacts
 *           touching it in increasing contact order (a CSR list of contacts per particle, built
 *           once per neighbour-list rebuild). No two threads write the same place, and every
 *           particle's sum is formed from the same numbers in the same order as the serial
 *           rsl_batch_step forms it: the forces, torques and states are BIT FOR BIT the serial
 *           ones whatever T. The program checks that with memcmp after every step, and the
 *           positions and velocities after the integration too (each T runs its own
 *           simulation). The price: the spheres are copied per contact and the loads written
 *           to memory and read back, which the particle-major call does not do.
 *
 *  B. per-thread accumulators: each thread calls rsl_batch_step on its own contiguous range of
 *           contacts with its own zeroed force and torque arrays (one per thread, of length N),
 *           then the arrays are added, thread 0 first, particle by particle. The states are
 *           bitwise the serial ones (each contact is stepped once, from the same inputs), but a
 *           particle's sum is now formed in another order (the partial sums of the threads
 *           added together), so the forces and torques differ from the serial ones in the last
 *           bits, and depend on T: NOT bitwise reproducible across thread counts (it is
 *           reproducible for one fixed T, which the program also checks). The program
 *           checks it from the serial run's inputs at every step, against the rounding bound of
 *           a sum of k terms taken in any order: two orders differ by at most
 *           2 gamma_(k-1) sum|x_i| <= k DBL_EPSILON sum|x_i|, per component. Over a run these
 *           last-bit differences are carried into the trajectory, and grow as any rounding does.
 *
 * The integration (semi-implicit Euler for the inner spheres) runs on one thread in every run
 * and is not timed: the timings are the force computation alone (host normal forces, rollslide,
 * the sums). They are printed, never checked: the machine may be shared. Exit status 0 when
 * every check passes, 1 otherwise.
 *
 * Units: diameter 1, mass of a d = 1 sphere 1; k_n = 1000, dt = 5e-4 (1/280 of the normal
 * oscillation period of a pair).
 */
#define _POSIX_C_SOURCE 200809L /* pthread_barrier_t, clock_gettime */
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rollslide.h"

#define K_N 1000.0     /* normal stiffness */
#define GAMMA_N 5.0    /* normal dashpot */
#define DT 5e-4        /* time step */
#define SPACING 0.96   /* nearest-neighbour distance of the lattice */
#define JITTER 0.003   /* lattice jitter, each coordinate uniform in [-JITTER, JITTER] */
#define SKIN 0.1       /* neighbour-list skin */
#define BLOCK 256      /* contacts gathered per rsl_batch_step_contacts call */
#define MAX_THREADS 64

/* ---------------------------------------------------------------------------------------- */
/* Small helpers                                                                             */

static void die(const char *what) {
    fprintf(stderr, "parallel_forces: %s\n", what);
    exit(1);
}

static void die_status(int32_t status, const char *what, const char *message) {
    fprintf(stderr, "parallel_forces: %s failed: %s (%s)\n", what, rsl_status_str(status),
            message);
    exit(1);
}

static void *xcalloc(size_t n, size_t size) {
    void *p = calloc(n ? n : 1, size);
    if (!p) die("out of memory");
    return p;
}

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* xorshift64*: a small deterministic generator. */
static double rnd(uint64_t *s) {
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}

static double sym(uint64_t *s) { return 2.0 * rnd(s) - 1.0; }

/* ---------------------------------------------------------------------------------------- */
/* The packing and its neighbour list (shared, read-only, by every run)                      */

typedef struct {
    size_t n;                  /* spheres */
    size_t nc;                 /* contacts (neighbour-list pairs) */
    rsl_sphere *initial;       /* the spheres at t = 0 */
    double *mass, *inertia;
    unsigned char *fixed;      /* the container: never moved */
    uint32_t *pairs;           /* 2 nc: body 1 < body 2, sorted by body 1, then body 2 */
    size_t *first;             /* CSR: sphere p's contacts are touching[first[p] .. first[p+1]) */
    uint32_t *touching;        /* 2 c + (1 if p is body 2 of contact c), c increasing */
} packing;

static int cmp_u32(const void *a, const void *b) {
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

static void make_packing(packing *pk, int m) {
    /* fcc sites: integer (i, j, k) in [0, m)^3 with i + j + k even, at h (i, j, k) with
     * h = SPACING / sqrt(2): nearest neighbours at distance SPACING. */
    double h = SPACING / sqrt(2.0);
    size_t cap = (size_t)m * (size_t)m * (size_t)m / 2 + 1;
    pk->initial = xcalloc(cap, sizeof *pk->initial);
    pk->mass = xcalloc(cap, sizeof *pk->mass);
    pk->inertia = xcalloc(cap, sizeof *pk->inertia);
    pk->fixed = xcalloc(cap, 1);
    uint64_t seed = 0x9E3779B97F4A7C15ULL;
    size_t n = 0;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < m; j++)
            for (int k = 0; k < m; k++) {
                if ((i + j + k) % 2) continue;
                rsl_sphere *s = &pk->initial[n];
                int wall = i == 0 || j == 0 || k == 0 || i == m - 1 || j == m - 1 || k == m - 1;
                s->position.x = h * i + JITTER * sym(&seed);
                s->position.y = h * j + JITTER * sym(&seed);
                s->position.z = h * k + JITTER * sym(&seed);
                s->radius = 0.495 + 0.01 * rnd(&seed);
                if (!wall) {
                    s->velocity.x = 0.05 * sym(&seed);
                    s->velocity.y = 0.05 * sym(&seed);
                    s->velocity.z = 0.05 * sym(&seed);
                    s->angular_velocity.x = 8.0 * sym(&seed);
                    s->angular_velocity.y = 8.0 * sym(&seed);
                    s->angular_velocity.z = 8.0 * sym(&seed);
                }
                double r = s->radius;
                pk->mass[n] = 8.0 * r * r * r; /* (2r)^3: a d = 1 sphere has mass 1 */
                pk->inertia[n] = 0.4 * pk->mass[n] * r * r;
                pk->fixed[n] = (unsigned char)wall;
                n++;
            }
    pk->n = n;
    if (n >= UINT32_MAX / 16) die("too many spheres for uint32_t indices");

    /* Linked cells of size >= the largest reach (1.01 + SKIN); each pair once, j > i. */
    double cell = 1.01 + SKIN, lo = -0.5;
    int nc1 = (int)ceil((h * (m - 1) + 1.0) / cell) + 1;
    size_t ncell = (size_t)nc1 * (size_t)nc1 * (size_t)nc1;
    int *head = xcalloc(ncell, sizeof *head), *next = xcalloc(n, sizeof *next);
    for (size_t c = 0; c < ncell; c++) head[c] = -1;
    int(*where)[3] = xcalloc(n, sizeof *where);
    for (size_t p = 0; p < n; p++) {
        const rsl_vec3 *x = &pk->initial[p].position;
        where[p][0] = (int)floor((x->x - lo) / cell);
        where[p][1] = (int)floor((x->y - lo) / cell);
        where[p][2] = (int)floor((x->z - lo) / cell);
        size_t c = ((size_t)where[p][2] * (size_t)nc1 + (size_t)where[p][1]) * (size_t)nc1 +
                   (size_t)where[p][0];
        next[p] = head[c];
        head[c] = (int)p;
    }
    size_t cap_pairs = 8 * n + 16, np = 0;
    uint32_t *pairs = xcalloc(2 * cap_pairs, sizeof *pairs);
    uint32_t partner[64];
    for (size_t i = 0; i < n; i++) {
        const rsl_sphere *a = &pk->initial[i];
        int count = 0;
        for (int z = where[i][2] - 1; z <= where[i][2] + 1; z++)
            for (int y = where[i][1] - 1; y <= where[i][1] + 1; y++)
                for (int x = where[i][0] - 1; x <= where[i][0] + 1; x++) {
                    if (x < 0 || y < 0 || z < 0 || x >= nc1 || y >= nc1 || z >= nc1) continue;
                    size_t c = ((size_t)z * (size_t)nc1 + (size_t)y) * (size_t)nc1 + (size_t)x;
                    for (int j = head[c]; j >= 0; j = next[j]) {
                        if ((size_t)j <= i || (pk->fixed[i] && pk->fixed[j])) continue;
                        const rsl_sphere *b = &pk->initial[j];
                        double ex = b->position.x - a->position.x;
                        double ey = b->position.y - a->position.y;
                        double ez = b->position.z - a->position.z;
                        double reach = a->radius + b->radius + SKIN;
                        if (ex * ex + ey * ey + ez * ez >= reach * reach) continue;
                        if (count == 64) die("more than 64 neighbours");
                        partner[count++] = (uint32_t)j;
                    }
                }
        qsort(partner, (size_t)count, sizeof partner[0], cmp_u32);
        for (int k = 0; k < count; k++) {
            if (np == cap_pairs) die("neighbour list overflow");
            pairs[2 * np] = (uint32_t)i;
            pairs[2 * np + 1] = partner[k];
            np++;
        }
    }
    pk->nc = np;
    pk->pairs = pairs;
    free(head);
    free(next);
    free(where);

    /* The CSR list of contacts per sphere: filled in increasing contact order, so each
     * sphere's contacts are listed in the order rsl_batch_step adds their loads. */
    pk->first = xcalloc(n + 1, sizeof *pk->first);
    for (size_t c = 0; c < np; c++) {
        pk->first[pairs[2 * c] + 1]++;
        pk->first[pairs[2 * c + 1] + 1]++;
    }
    for (size_t p = 0; p < n; p++) pk->first[p + 1] += pk->first[p];
    pk->touching = xcalloc(2 * np, sizeof *pk->touching);
    size_t *fill = xcalloc(n, sizeof *fill);
    for (size_t c = 0; c < np; c++)
        for (int b = 0; b < 2; b++) {
            uint32_t p = pairs[2 * c + b];
            pk->touching[pk->first[p] + fill[p]++] = (uint32_t)(2 * c + (size_t)b);
        }
    free(fill);
}

static void free_packing(packing *pk) {
    free(pk->initial);
    free(pk->mass);
    free(pk->inertia);
    free(pk->fixed);
    free(pk->pairs);
    free(pk->first);
    free(pk->touching);
}

/* ---------------------------------------------------------------------------------------- */
/* One simulation: what a step changes                                                        */

typedef struct {
    rsl_sphere *p;
    rsl_contact_state *state;
    rsl_vec3 *force, *torque;
} sim;

static void sim_init(sim *s, const packing *pk) {
    s->p = xcalloc(pk->n, sizeof *s->p);
    memcpy(s->p, pk->initial, pk->n * sizeof *s->p);
    s->state = xcalloc(pk->nc, sizeof *s->state); /* all zero: fresh contacts */
    s->force = xcalloc(pk->n, sizeof *s->force);
    s->torque = xcalloc(pk->n, sizeof *s->torque);
}

static void sim_copy(sim *to, const sim *from, const packing *pk) {
    memcpy(to->p, from->p, pk->n * sizeof *to->p);
    memcpy(to->state, from->state, pk->nc * sizeof *to->state);
}

static void sim_free(sim *s) {
    free(s->p);
    free(s->state);
    free(s->force);
    free(s->torque);
}

/* The host's normal force of a contact: linear spring-dashpot, clipped at 0. Every run calls
 * this one function, so f_n has the same bits in every run. Counts the pair in *apart when the
 * spheres do not overlap (never, in this packing). */
static double normal_force(const rsl_sphere *a, const rsl_sphere *b, size_t *apart) {
    double ex = b->position.x - a->position.x;
    double ey = b->position.y - a->position.y;
    double ez = b->position.z - a->position.z;
    double d = sqrt(ex * ex + ey * ey + ez * ez);
    double overlap = a->radius + b->radius - d;
    /* ddot = n . (v2 - v1): the overlap grows at -ddot */
    double ddot = (ex * (b->velocity.x - a->velocity.x) + ey * (b->velocity.y - a->velocity.y) +
                   ez * (b->velocity.z - a->velocity.z)) /
                  d;
    double f = K_N * overlap - GAMMA_N * ddot;
    *apart += overlap <= 0.0;
    return f > 0.0 ? f : 0.0;
}

/* The normal forces of contacts [c0, c1) into out[0 .. c1 - c0). */
static size_t normal_forces(const packing *pk, const rsl_sphere *p, size_t c0, size_t c1,
                            double *out) {
    size_t apart = 0;
    for (size_t c = c0; c < c1; c++)
        out[c - c0] = normal_force(&p[pk->pairs[2 * c]], &p[pk->pairs[2 * c + 1]], &apart);
    return apart;
}

/* Semi-implicit Euler for the inner spheres (one thread, the same code for every run). */
static void integrate(const packing *pk, sim *s) {
    for (size_t i = 0; i < pk->n; i++) {
        if (pk->fixed[i]) continue;
        rsl_sphere *q = &s->p[i];
        double a = DT / pk->mass[i], b = DT / pk->inertia[i];
        q->velocity.x += a * s->force[i].x;
        q->velocity.y += a * s->force[i].y;
        q->velocity.z += a * s->force[i].z;
        q->angular_velocity.x += b * s->torque[i].x;
        q->angular_velocity.y += b * s->torque[i].y;
        q->angular_velocity.z += b * s->torque[i].z;
        q->position.x += DT * q->velocity.x;
        q->position.y += DT * q->velocity.y;
        q->position.z += DT * q->velocity.z;
    }
}

/* ---------------------------------------------------------------------------------------- */
/* Serial references                                                                          */

static size_t serial_batch(const packing *pk, const rsl_model *model, sim *s, double *f_n) {
    size_t apart = normal_forces(pk, s->p, 0, pk->nc, f_n);
    memset(s->force, 0, pk->n * sizeof *s->force);
    memset(s->torque, 0, pk->n * sizeof *s->torque);
    rsl_batch_report report;
    int32_t st = rsl_batch_step(model, s->p, pk->n, pk->pairs, pk->nc, f_n, NULL, DT, NULL,
                                s->state, s->force, s->torque, &report);
    if (st != RSL_OK) die_status(st, "rsl_batch_step", rsl_last_error_message());
    return apart;
}

static size_t serial_accumulate(const packing *pk, const rsl_model *model, sim *s, double *f_n) {
    size_t apart = normal_forces(pk, s->p, 0, pk->nc, f_n);
    memset(s->force, 0, pk->n * sizeof *s->force);
    memset(s->torque, 0, pk->n * sizeof *s->torque);
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = DT;
    for (size_t c = 0; c < pk->nc; c++) {
        uint32_t i = pk->pairs[2 * c], j = pk->pairs[2 * c + 1];
        in.normal_force = f_n[c];
        int32_t st = rsl_contact_step_accumulate(model, &s->p[i], &s->p[j], &in, &s->state[c],
                                                 &s->force[i], &s->torque[i], &s->force[j],
                                                 &s->torque[j]);
        if (st != RSL_OK) die_status(st, "rsl_contact_step_accumulate", rsl_last_error_message());
    }
    return apart;
}

/* ---------------------------------------------------------------------------------------- */
/* A pool of T threads (the caller is thread 0): pool_run runs fn(arg, t, T) on each and     */
/* returns when all are done (the barriers also order the memory accesses of the phases).    */

typedef void (*job_fn)(void *arg, int t, int nt);

typedef struct pool pool;
typedef struct {
    pool *owner;
    int t;
} worker_arg;

struct pool {
    int nt;
    pthread_t thread[MAX_THREADS];
    worker_arg args[MAX_THREADS];
    pthread_barrier_t start, done;
    job_fn fn;
    void *arg;
    int quit;
};

static void *pool_worker(void *p) {
    worker_arg *w = p;
    pool *P = w->owner;
    for (;;) {
        pthread_barrier_wait(&P->start);
        if (P->quit) return NULL;
        P->fn(P->arg, w->t, P->nt);
        pthread_barrier_wait(&P->done);
    }
}

static void pool_init(pool *P, int nt) {
    memset(P, 0, sizeof *P);
    P->nt = nt;
    if (pthread_barrier_init(&P->start, NULL, (unsigned)nt) != 0 ||
        pthread_barrier_init(&P->done, NULL, (unsigned)nt) != 0)
        die("pthread_barrier_init failed");
    for (int t = 1; t < nt; t++) {
        P->args[t].owner = P;
        P->args[t].t = t;
        if (pthread_create(&P->thread[t], NULL, pool_worker, &P->args[t]) != 0)
            die("pthread_create failed");
    }
}

static void pool_run(pool *P, job_fn fn, void *arg) {
    P->fn = fn;
    P->arg = arg;
    pthread_barrier_wait(&P->start);
    fn(arg, 0, P->nt);
    pthread_barrier_wait(&P->done);
}

static void pool_free(pool *P) {
    P->quit = 1;
    pthread_barrier_wait(&P->start);
    for (int t = 1; t < P->nt; t++) pthread_join(P->thread[t], NULL);
    pthread_barrier_destroy(&P->start);
    pthread_barrier_destroy(&P->done);
}

/* [range(n, t, nt), range(n, t + 1, nt)) is thread t's share of n items. */
static size_t range(size_t n, int t, int nt) { return n * (size_t)t / (size_t)nt; }

/* ---------------------------------------------------------------------------------------- */
/* The threaded force computations                                                            */

typedef struct {
    rsl_sphere body1[BLOCK], body2[BLOCK]; /* pattern A: the gathered spheres of a block */
    double f_n[BLOCK];
    rsl_vec3 *force, *torque; /* pattern B: this thread's own accumulators (n each) */
    size_t apart;
    int32_t status;
    char message[256];
} thread_work;

typedef struct {
    const packing *pk;
    const rsl_model *model;
    sim *s;
    rsl_batch_loads *loads; /* pattern A: per contact */
    double *f_n;            /* pattern B: per contact */
    thread_work *work;      /* one per thread */
} job;

static void note_failure(thread_work *w, int32_t st) {
    if (st == RSL_OK || w->status != RSL_OK) return;
    w->status = st;
    snprintf(w->message, sizeof w->message, "%s", rsl_last_error_message());
}

/* Pattern A, phase 1: thread t steps contacts [c0, c1), a block at a time, and writes each
 * contact's loads to loads[c]. */
static void contacts_phase(void *arg, int t, int nt) {
    job *J = arg;
    const packing *pk = J->pk;
    thread_work *w = &J->work[t];
    size_t c0 = range(pk->nc, t, nt), c1 = range(pk->nc, t + 1, nt);
    for (size_t b = c0; b < c1; b += BLOCK) {
        size_t len = c1 - b < BLOCK ? c1 - b : BLOCK;
        for (size_t k = 0; k < len; k++) {
            w->body1[k] = J->s->p[pk->pairs[2 * (b + k)]];
            w->body2[k] = J->s->p[pk->pairs[2 * (b + k) + 1]];
            w->f_n[k] = normal_force(&w->body1[k], &w->body2[k], &w->apart);
        }
        rsl_batch_report report;
        int32_t st = rsl_batch_step_contacts(J->model, w->body1, w->body2, len, w->f_n, NULL, DT,
                                             NULL, &J->s->state[b], &J->loads[b], &report);
        note_failure(w, st);
    }
}

/* Pattern A, phase 2: thread t owns spheres [p0, p1) and adds the loads of their contacts in
 * increasing contact order: the order in which rsl_batch_step adds them. */
static void particles_phase(void *arg, int t, int nt) {
    job *J = arg;
    const packing *pk = J->pk;
    size_t p0 = range(pk->n, t, nt), p1 = range(pk->n, t + 1, nt);
    for (size_t p = p0; p < p1; p++) {
        rsl_vec3 f = {0.0, 0.0, 0.0}, m = {0.0, 0.0, 0.0};
        for (size_t k = pk->first[p]; k < pk->first[p + 1]; k++) {
            const rsl_batch_loads *l = &J->loads[pk->touching[k] >> 1];
            if (!(pk->touching[k] & 1)) { /* body 1 */
                f.x += l->force1.x;
                f.y += l->force1.y;
                f.z += l->force1.z;
                m.x += l->torque1.x;
                m.y += l->torque1.y;
                m.z += l->torque1.z;
            } else { /* body 2 */
                f.x -= l->force1.x;
                f.y -= l->force1.y;
                f.z -= l->force1.z;
                m.x += l->torque2.x;
                m.y += l->torque2.y;
                m.z += l->torque2.z;
            }
        }
        J->s->force[p] = f;
        J->s->torque[p] = m;
    }
}

/* Pattern B, phase 1: thread t steps contacts [c0, c1) with rsl_batch_step into its own
 * zeroed arrays. */
static void own_arrays_phase(void *arg, int t, int nt) {
    job *J = arg;
    const packing *pk = J->pk;
    thread_work *w = &J->work[t];
    size_t c0 = range(pk->nc, t, nt), c1 = range(pk->nc, t + 1, nt);
    memset(w->force, 0, pk->n * sizeof *w->force);
    memset(w->torque, 0, pk->n * sizeof *w->torque);
    w->apart += normal_forces(pk, J->s->p, c0, c1, &J->f_n[c0]);
    rsl_batch_report report;
    int32_t st = rsl_batch_step(J->model, J->s->p, pk->n, &pk->pairs[2 * c0], c1 - c0, &J->f_n[c0],
                                NULL, DT, NULL, &J->s->state[c0], w->force, w->torque, &report);
    note_failure(w, st);
}

/* Pattern B, phase 2: thread t owns spheres [p0, p1) and adds the threads' arrays, thread 0
 * first. */
static void reduce_phase(void *arg, int t, int nt) {
    job *J = arg;
    const packing *pk = J->pk;
    size_t p0 = range(pk->n, t, nt), p1 = range(pk->n, t + 1, nt);
    for (size_t p = p0; p < p1; p++) {
        rsl_vec3 f = J->work[0].force[p], m = J->work[0].torque[p];
        for (int u = 1; u < nt; u++) {
            const rsl_vec3 *g = &J->work[u].force[p], *n = &J->work[u].torque[p];
            f.x += g->x;
            f.y += g->y;
            f.z += g->z;
            m.x += n->x;
            m.y += n->y;
            m.z += n->z;
        }
        J->s->force[p] = f;
        J->s->torque[p] = m;
    }
}

static size_t collect(job *J, int nt, const char *what) {
    size_t apart = 0;
    for (int t = 0; t < nt; t++) {
        thread_work *w = &J->work[t];
        if (w->status != RSL_OK) die_status(w->status, what, w->message);
        apart += w->apart;
        w->apart = 0;
    }
    return apart;
}

/* ---------------------------------------------------------------------------------------- */
/* Checks                                                                                     */

static int failures = 0;

static void fail(const char *what, int t, int step) {
    fprintf(stderr, "MISMATCH: %s, T = %d, step %d\n", what, t, step);
    failures++;
}

static int same(const void *a, const void *b, size_t bytes) { return memcmp(a, b, bytes) == 0; }

/* The per-thread-accumulator sums against the serial ones: for each component of each sphere's
 * force and torque, |got - want| <= k DBL_EPSILON sum|x_i|, with x_i its k contact terms (two
 * summation orders of the same k terms each differ from the exact sum by at most
 * gamma_(k-1) sum|x_i|, gamma_j = j u / (1 - j u), u = DBL_EPSILON / 2). Returns the number of
 * spheres whose sums differ at all; *worst gets the largest |got - want| / bound. */
static size_t check_reordered(const packing *pk, const rsl_batch_loads *loads, const sim *got,
                              const sim *want, double *worst, int t, int step) {
    size_t differ = 0;
    for (size_t p = 0; p < pk->n; p++) {
        double af[3] = {0, 0, 0}, am[3] = {0, 0, 0};
        for (size_t k = pk->first[p]; k < pk->first[p + 1]; k++) {
            const rsl_batch_loads *l = &loads[pk->touching[k] >> 1];
            const rsl_vec3 *m = pk->touching[k] & 1 ? &l->torque2 : &l->torque1;
            af[0] += fabs(l->force1.x);
            af[1] += fabs(l->force1.y);
            af[2] += fabs(l->force1.z);
            am[0] += fabs(m->x);
            am[1] += fabs(m->y);
            am[2] += fabs(m->z);
        }
        double k = (double)(pk->first[p + 1] - pk->first[p]);
        const double g[6] = {got->force[p].x,  got->force[p].y,  got->force[p].z,
                             got->torque[p].x, got->torque[p].y, got->torque[p].z};
        const double w[6] = {want->force[p].x,  want->force[p].y,  want->force[p].z,
                             want->torque[p].x, want->torque[p].y, want->torque[p].z};
        const double sum_abs[6] = {af[0], af[1], af[2], am[0], am[1], am[2]};
        int d = 0;
        for (int q = 0; q < 6; q++) {
            double bound = k * DBL_EPSILON * sum_abs[q];
            double err = fabs(g[q] - w[q]);
            d |= g[q] != w[q];
            if (err > bound) {
                fprintf(stderr, "sphere %zu component %d: %.17g against %.17g, bound %.3g\n", p,
                        q, g[q], w[q], bound);
                fail("per-thread accumulators outside the rounding bound", t, step);
            }
            if (bound > 0 && err / bound > *worst) *worst = err / bound;
        }
        differ += (size_t)d;
    }
    return differ;
}

/* ---------------------------------------------------------------------------------------- */

/* Wall-clock seconds of each timed step of one run. */
typedef struct {
    double *seconds;
    int count;
} timer;

/* The first step is not timed when there are others: it pays for the first touch of the
 * arrays (page faults) and cold caches. */
static int timing = 0;

static void timed(timer *tm, double seconds) {
    if (timing) tm->seconds[tm->count++] = seconds;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sorts the times; then [0] is the best and [count / 2] the median. */
static double median(timer *tm) {
    qsort(tm->seconds, (size_t)tm->count, sizeof *tm->seconds, cmp_double);
    return tm->seconds[tm->count / 2];
}

static void print_time(timer *tm, const char *what, int t, double reference) {
    double med = median(tm);
    printf("  %-40s T = %-2d %8.3f ms %8.3f ms", what, t, 1e3 * med, 1e3 * tm->seconds[0]);
    if (reference > 0.0) printf("   %.2fx", reference / med);
    printf("\n");
}

static rsl_model *make_model(void) {
    rsl_model *m = NULL;
    int32_t st = rsl_model_new(RSL_PRESET_LAMMPS_2021, &m);
    if (st != RSL_OK) die_status(st, "rsl_model_new", rsl_last_error_message());
    /* Sliding: linear history, k_t = 2/7 k_n, mu_s = 0.3. */
    st = rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 2.0 / 7.0 * K_N, 2.0, 0.3);
    if (st != RSL_OK) die_status(st, "rsl_model_set_sliding", rsl_last_error_message());
    /* Rolling: LAMMPS' rolling sds (EPSD, length form, given stiffness and damping). */
    rsl_rolling_params r;
    st = rsl_model_get_rolling(m, &r);
    if (st != RSL_OK) die_status(st, "rsl_model_get_rolling", rsl_last_error_message());
    r.law = RSL_ROLLING_EPSD;
    r.stiffness_rule = RSL_STIFFNESS_GIVEN;
    r.damping_rule = RSL_DAMPING_GIVEN;
    r.stiffness = 2.25 * K_N * 0.1 * 0.1;
    r.damping = 2.0;
    r.friction = 0.05;
    st = rsl_model_set_rolling(m, &r);
    if (st != RSL_OK) die_status(st, "rsl_model_set_rolling", rsl_last_error_message());
    /* Twisting: LAMMPS' twisting sds. */
    st = rsl_model_set_twisting(m, RSL_TWISTING_SDS, 5.0, 0.2, 0.02);
    if (st != RSL_OK) die_status(st, "rsl_model_set_twisting", rsl_last_error_message());
    return m;
}

static long arg_or(int argc, char **argv, int k, long fallback, long lo, long hi) {
    if (argc <= k) return fallback;
    char *end = NULL;
    long v = strtol(argv[k], &end, 10);
    if (*end != '\0' || v < lo || v > hi) {
        fprintf(stderr, "usage: parallel_forces [M [STEPS [TMAX]]] (M in [4, 400], STEPS in "
                        "[1, 100000], TMAX in [1, %d])\n",
                MAX_THREADS);
        exit(2);
    }
    return v;
}

int main(int argc, char **argv) {
    int m = (int)arg_or(argc, argv, 1, 20, 4, 400);
    int steps = (int)arg_or(argc, argv, 2, 3, 1, 100000);
    int tmax = (int)arg_or(argc, argv, 3, 4, 1, MAX_THREADS);

    packing pk;
    make_packing(&pk, m);
    rsl_model *model = make_model();
    printf("parallel_forces: %zu spheres, %zu contacts, %d steps; rollslide %s\n", pk.n, pk.nc,
           steps, rsl_version());

    /* Thread counts 1, 2, 4, ... up to tmax. */
    int counts[8], ncounts = 0;
    for (int t = 1; t <= tmax && ncounts < 8; t *= 2) counts[ncounts++] = t;

    sim ref, acc, pre, own, own2, cm[8];
    sim_init(&ref, &pk);
    sim_init(&acc, &pk);
    sim_init(&pre, &pk);
    sim_init(&own, &pk);
    sim_init(&own2, &pk);
    rsl_batch_loads *loads[8];
    pool pools[8];
    for (int k = 0; k < ncounts; k++) {
        sim_init(&cm[k], &pk);
        loads[k] = xcalloc(pk.nc, sizeof *loads[k]);
        pool_init(&pools[k], counts[k]);
    }
    thread_work *work = xcalloc((size_t)tmax, sizeof *work);
    for (int t = 0; t < tmax; t++) {
        work[t].force = xcalloc(pk.n, sizeof *work[t].force);
        work[t].torque = xcalloc(pk.n, sizeof *work[t].torque);
    }
    double *f_n = xcalloc(pk.nc, sizeof *f_n);

    timer t_batch, t_acc, t_cm[8], t_own[8];
    timer *timers[18] = {&t_batch, &t_acc};
    for (int k = 0; k < 8; k++) {
        timers[2 + k] = &t_cm[k];
        timers[10 + k] = &t_own[k];
    }
    for (int k = 0; k < 18; k++) {
        timers[k]->seconds = xcalloc((size_t)steps, sizeof(double));
        timers[k]->count = 0;
    }
    size_t apart = 0, own_differ = 0;
    double worst = 0.0;

    for (int step = 0; step < steps; step++) {
        timing = step > 0 || steps == 1;
        sim_copy(&pre, &ref, &pk); /* the inputs of this step, for pattern B */

        double t0 = now_seconds();
        apart += serial_batch(&pk, model, &ref, f_n);
        timed(&t_batch, now_seconds() - t0);

        t0 = now_seconds();
        apart += serial_accumulate(&pk, model, &acc, f_n);
        timed(&t_acc, now_seconds() - t0);
        if (!same(acc.force, ref.force, pk.n * sizeof *ref.force) ||
            !same(acc.torque, ref.torque, pk.n * sizeof *ref.torque) ||
            !same(acc.state, ref.state, pk.nc * sizeof *ref.state))
            fail("rsl_contact_step_accumulate loop against rsl_batch_step", 1, step);

        /* Pattern A on 1, 2, 4... threads: each its own simulation, bitwise the serial one. */
        for (int k = 0; k < ncounts; k++) {
            job J = {&pk, model, &cm[k], loads[k], NULL, work};
            t0 = now_seconds();
            pool_run(&pools[k], contacts_phase, &J);
            pool_run(&pools[k], particles_phase, &J);
            timed(&t_cm[k], now_seconds() - t0);
            apart += collect(&J, counts[k], "rsl_batch_step_contacts");
            if (!same(cm[k].force, ref.force, pk.n * sizeof *ref.force))
                fail("contact-major forces", counts[k], step);
            if (!same(cm[k].torque, ref.torque, pk.n * sizeof *ref.torque))
                fail("contact-major torques", counts[k], step);
            if (!same(cm[k].state, ref.state, pk.nc * sizeof *ref.state))
                fail("contact-major states", counts[k], step);
        }

        /* Pattern B on 2, 4... threads, from this step's serial inputs. */
        for (int k = 1; k < ncounts; k++) {
            job J = {&pk, model, &own, NULL, f_n, work};
            sim_copy(&own, &pre, &pk);
            t0 = now_seconds();
            pool_run(&pools[k], own_arrays_phase, &J);
            pool_run(&pools[k], reduce_phase, &J);
            timed(&t_own[k], now_seconds() - t0);
            apart += collect(&J, counts[k], "rsl_batch_step");
            if (!same(own.state, ref.state, pk.nc * sizeof *ref.state))
                fail("per-thread accumulators: states", counts[k], step);
            /* loads[0] holds this step's per-contact loads (pattern A, bitwise the serial). */
            own_differ += check_reordered(&pk, loads[0], &own, &ref, &worst, counts[k], step);
            if (step == 0) { /* the same T again: the same bits */
                job J2 = {&pk, model, &own2, NULL, f_n, work};
                sim_copy(&own2, &pre, &pk);
                pool_run(&pools[k], own_arrays_phase, &J2);
                pool_run(&pools[k], reduce_phase, &J2);
                apart += collect(&J2, counts[k], "rsl_batch_step");
                if (!same(own2.force, own.force, pk.n * sizeof *own.force) ||
                    !same(own2.torque, own.torque, pk.n * sizeof *own.torque))
                    fail("per-thread accumulators run twice with the same T", counts[k], step);
            }
        }

        integrate(&pk, &ref);
        integrate(&pk, &acc);
        if (!same(acc.p, ref.p, pk.n * sizeof *ref.p))
            fail("rsl_contact_step_accumulate loop: spheres after the step", 1, step);
        for (int k = 0; k < ncounts; k++) {
            integrate(&pk, &cm[k]);
            if (!same(cm[k].p, ref.p, pk.n * sizeof *ref.p))
                fail("contact-major: spheres after the step", counts[k], step);
        }
    }
    if (apart != 0) {
        fprintf(stderr, "parallel_forces: %zu listed pairs came apart (the packing should hold)\n",
                apart);
        failures++;
    }

    size_t slip[3] = {0, 0, 0};
    for (size_t c = 0; c < pk.nc; c++) {
        slip[0] += (ref.state[c].slip_flags & RSL_SLIP_SLIDING) != 0;
        slip[1] += (ref.state[c].slip_flags & RSL_SLIP_ROLLING) != 0;
        slip[2] += (ref.state[c].slip_flags & RSL_SLIP_TWISTING) != 0;
    }
    printf("last step: %zu contacts at the sliding limit, %zu at the rolling limit, %zu at the "
           "twisting limit\n",
           slip[0], slip[1], slip[2]);

    printf("wall clock per step, force computation only (median, best of %d steps; speed-up "
           "against the serial rsl_batch_step, medians):\n",
           t_batch.count);
    double base = median(&t_batch);
    print_time(&t_batch, "serial rsl_batch_step (reference)", 1, 0.0);
    print_time(&t_acc, "serial rsl_contact_step_accumulate loop", 1, base);
    for (int k = 0; k < ncounts; k++)
        print_time(&t_cm[k], "A. contact-major + per-particle sums", counts[k], base);
    for (int k = 1; k < ncounts; k++)
        print_time(&t_own[k], "B. per-thread accumulators + reduction", counts[k], base);

    printf("A (contact-major): forces, torques, states and spheres bitwise equal to the serial "
           "run for T =");
    for (int k = 0; k < ncounts; k++) printf(" %d", counts[k]);
    printf(" over %d steps\n", steps);
    if (ncounts > 1)
        printf("B (per-thread accumulators): states bitwise equal; %zu sphere sums (of %zu) "
               "differ from the serial ones, worst %.3g of the rounding bound\n",
               own_differ, pk.n * (size_t)(ncounts - 1) * (size_t)steps, worst);

    for (int k = 0; k < ncounts; k++) {
        pool_free(&pools[k]);
        sim_free(&cm[k]);
        free(loads[k]);
    }
    for (int t = 0; t < tmax; t++) {
        free(work[t].force);
        free(work[t].torque);
    }
    free(work);
    free(f_n);
    for (int k = 0; k < 18; k++) free(timers[k]->seconds);
    sim_free(&ref);
    sim_free(&acc);
    sim_free(&pre);
    sim_free(&own);
    sim_free(&own2);
    rsl_model_free(model);
    free_packing(&pk);
    if (failures) {
        fprintf(stderr, "parallel_forces: %d check(s) failed\n", failures);
        return 1;
    }
    printf("parallel_forces: all checks passed\n");
    return 0;
}
