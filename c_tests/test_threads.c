/* Thread safety (issue #7): one shared model, N threads each stepping their own contacts (pairs
 * and walls, every law on, energy tracked) for many steps, compared bit for bit (memcmp of the
 * loads and of the states) with the same contacts stepped serially on one thread. Each thread
 * also makes failing calls on purpose and checks that its thread-local error message is its own
 * (rsl_last_error_message is the library's only global mutable state: one slot per thread).
 *
 * scripts/sanitizers.sh also runs it under ASan/UBSan and under valgrind's memcheck. */
#define _POSIX_C_SOURCE 200809L
#include "rollslide.h" /* first: the header must compile on its own */

#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>

#include "rsl_test.h"

#define N_THREADS 8
#define CONTACTS_PER_THREAD 16
#define STEPS 400
#define N_CONTACTS (N_THREADS * CONTACTS_PER_THREAD)

typedef struct {
    rsl_contact_state state;
    rsl_contact_loads last;  /* loads of the last step */
    rsl_contact_loads sum;   /* running sum of every load field (catches a difference at any step) */
    int failures;            /* unexpected statuses */
} contact_result;

static rsl_model *shared_model;

/* Deterministic motion of contact c at step k: a pair orbiting and spinning, or a ball on a wall. */
static void bodies(int c, int k, rsl_sphere *a, rsl_sphere *b, rsl_wall *w) {
    double t = 1e-3 * k, ph = 0.37 * c;
    double r1 = 0.5 + 0.01 * (c % 7), r2 = 0.8 + 0.02 * (c % 5);
    double d = (r1 + r2) * (1.0 - 1e-3);
    double om = 0.5 + 0.05 * (c % 3);
    memset(a, 0, sizeof *a);
    memset(b, 0, sizeof *b);
    memset(w, 0, sizeof *w);
    a->radius = r1;
    b->radius = r2;
    a->position = rsl_test_vec(0.1 * c, 0, 0);
    b->position = rsl_test_vec(0.1 * c + d * cos(om * t + ph), d * sin(om * t + ph), 0.01 * sin(t));
    a->velocity = rsl_test_vec(0.01 * c, -0.02, 0.0);
    b->velocity = rsl_test_vec(-d * om * sin(om * t + ph), d * om * cos(om * t + ph), 0.01 * cos(t));
    a->angular_velocity = rsl_test_vec(0.3, -0.1 * c, 1.0 + sin(3 * t));
    b->angular_velocity = rsl_test_vec(-0.2, 0.4, -1.0 + cos(2 * t));
    w->normal = rsl_test_vec(0, 0, 1);
    w->velocity = rsl_test_vec(0.05, 0, 0);
    w->angular_velocity = rsl_test_vec(0, 0, 0.1);
}

static void add_loads(rsl_contact_loads *sum, const rsl_contact_loads *x) {
    double *s = (double *)(void *)sum;
    const double *v = (const double *)(const void *)x;
    size_t n = offsetof(rsl_contact_loads, slip_flags) / sizeof(double);
    for (size_t i = 0; i < n; i++) s[i] += v[i];
    sum->slip_flags |= x->slip_flags;
}

/* Steps contact c for every step; the same code runs on worker threads and serially. */
static void run_contact(int c, contact_result *r) {
    memset(r, 0, sizeof *r);
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = 5.0 + c;
    in.dt = 1e-3;
    in.normal_stiffness = 1e4;
    for (int k = 0; k < STEPS; k++) {
        rsl_sphere a, b;
        rsl_wall w;
        bodies(c, k, &a, &b, &w);
        int32_t s;
        if (c % 4 == 3) {
            a.position = rsl_test_vec(0.1 * c, 0.2, a.radius * (1.0 - 1e-3));
            s = rsl_contact_step_wall(shared_model, &a, &w, &in, &r->state, &r->last);
        } else {
            s = rsl_contact_step(shared_model, &a, &b, &in, &r->state, &r->last);
        }
        if (s != RSL_OK) r->failures++;
        add_loads(&r->sum, &r->last);
        if (k % 50 == 0) {
            /* A failing call of this thread: its message must name this thread's bad field. */
            rsl_contact_input bad = in;
            if (c % 2) {
                bad.dt = -1.0;
                if (rsl_contact_step(shared_model, &a, &b, &bad, &r->state, &r->last) !=
                        RSL_ERR_INVALID_TIME_STEP ||
                    strstr(rsl_last_error_message(), "dt") == NULL)
                    r->failures++;
            } else {
                bad.normal_force = NAN;
                if (rsl_contact_step(shared_model, &a, &b, &bad, &r->state, &r->last) !=
                        RSL_ERR_NON_FINITE ||
                    strstr(rsl_last_error_message(), "normal force") == NULL)
                    r->failures++;
            }
        }
    }
}

static contact_result threaded[N_CONTACTS];
static contact_result serial[N_CONTACTS];

static void *worker(void *arg) {
    int t = (int)(intptr_t)arg;
    for (int i = 0; i < CONTACTS_PER_THREAD; i++) {
        /* interleave: thread t owns contacts t, t + N, t + 2N... */
        int c = t + i * N_THREADS;
        run_contact(c, &threaded[c]);
    }
    return NULL;
}

void test_threads_shared_model_bitwise_equal_to_serial(void) {
    CHECK_STATUS(rsl_model_new(RSL_PRESET_OBJECTIVE, &shared_model), RSL_OK);
    CHECK_STATUS(rsl_model_set_sliding(shared_model, RSL_SLIDING_LINEAR, 2e3, 1.0, 0.3), RSL_OK);
    rsl_rolling_params p;
    CHECK_STATUS(rsl_model_get_rolling(shared_model, &p), RSL_OK);
    p.law = RSL_ROLLING_EPSD;
    p.stiffness = 200.0;
    p.damping = 0.5;
    p.friction = 0.05;
    CHECK_STATUS(rsl_model_set_rolling(shared_model, &p), RSL_OK);
    CHECK_STATUS(rsl_model_set_twisting(shared_model, RSL_TWISTING_SDS, 100.0, 0.1, 0.02), RSL_OK);
    CHECK_STATUS(rsl_model_set_energy_tracking(shared_model, 1), RSL_OK);

    pthread_t th[N_THREADS];
    for (int t = 0; t < N_THREADS; t++)
        CHECK(pthread_create(&th[t], NULL, worker, (void *)(intptr_t)t) == 0);
    for (int t = 0; t < N_THREADS; t++) CHECK(pthread_join(th[t], NULL) == 0);

    for (int c = 0; c < N_CONTACTS; c++) run_contact(c, &serial[c]);

    int differ = 0, failed = 0, slipped = 0;
    for (int c = 0; c < N_CONTACTS; c++) {
        if (memcmp(&threaded[c], &serial[c], sizeof serial[c]) != 0) differ++;
        failed += threaded[c].failures + serial[c].failures;
        slipped += serial[c].sum.slip_flags != 0;
    }
    printf("threads: %d threads x %d contacts x %d steps; %d contacts differ, %d bad statuses, "
           "%d contacts slipped\n",
           N_THREADS, CONTACTS_PER_THREAD, STEPS, differ, failed, slipped);
    CHECK(differ == 0);
    CHECK(failed == 0);
    /* the run exercises the limits, not only the elastic branch */
    CHECK(slipped > 0);
    /* the sums are not trivially zero */
    CHECK(serial[0].sum.force1.x != 0.0 && serial[3].sum.torque1.z != 0.0);
    rsl_model_free(shared_model);
    shared_model = NULL;
}

/* Each thread's last error message is its own: thread A fails with one message, thread B with
 * another, in lock step; each then reads its own. */
static pthread_barrier_t barrier;

static void *message_worker(void *arg) {
    int t = (int)(intptr_t)arg;
    rsl_sphere a, b;
    rsl_wall w;
    bodies(0, 0, &a, &b, &w);
    rsl_decomposition out;
    int bad = 0;
    for (int i = 0; i < 200; i++) {
        if (t == 0) {
            a.radius = -1.0;
            if (rsl_decompose(&a, &b, NULL, &out) != RSL_ERR_INVALID_RADIUS) bad++;
        } else {
            if (rsl_decompose(&a, NULL, NULL, &out) != RSL_ERR_NULL_POINTER) bad++;
        }
        pthread_barrier_wait(&barrier); /* both have failed; now both read */
        const char *msg = rsl_last_error_message();
        if (strstr(msg, t == 0 ? "radius" : "null pointer: body2") == NULL) bad++;
        pthread_barrier_wait(&barrier);
    }
    return (void *)(intptr_t)bad;
}

void test_threads_last_error_is_thread_local(void) {
    CHECK(pthread_barrier_init(&barrier, NULL, 2) == 0);
    pthread_t th[2];
    for (int t = 0; t < 2; t++)
        CHECK(pthread_create(&th[t], NULL, message_worker, (void *)(intptr_t)t) == 0);
    for (int t = 0; t < 2; t++) {
        void *bad = NULL;
        CHECK(pthread_join(th[t], &bad) == 0);
        CHECK((intptr_t)bad == 0);
    }
    pthread_barrier_destroy(&barrier);
}
