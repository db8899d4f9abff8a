/* Minimal C test harness for rollslide: checks count failures instead of aborting, so one run
 * reports every failed check of a test function. Tests are registered in tests.def. */
#ifndef RSL_TEST_H
#define RSL_TEST_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rollslide.h"

extern int rsl_test_failures;

#define CHECK(cond)                                                                   \
    do {                                                                              \
        if (!(cond)) {                                                                \
            fprintf(stderr, "%s:%d: CHECK(%s) failed\n", __FILE__, __LINE__, #cond); \
            rsl_test_failures++;                                                      \
        }                                                                             \
    } while (0)

/* |a - b| <= abs_tol + rel_tol |b| */
#define CHECK_CLOSE(a, b, abs_tol, rel_tol)                                                    \
    do {                                                                                       \
        double a_ = (a), b_ = (b);                                                             \
        if (!(fabs(a_ - b_) <= (abs_tol) + (rel_tol) * fabs(b_))) {                            \
            fprintf(stderr, "%s:%d: %s = %.17g, expected %s = %.17g (diff %.3g)\n", __FILE__, \
                    __LINE__, #a, a_, #b, b_, fabs(a_ - b_));                                  \
            rsl_test_failures++;                                                               \
        }                                                                                      \
    } while (0)

#define CHECK_VEC(v, ex, ey, ez, tol)        \
    do {                                     \
        rsl_vec3 v_ = (v);                   \
        CHECK_CLOSE(v_.x, (ex), (tol), 0.0); \
        CHECK_CLOSE(v_.y, (ey), (tol), 0.0); \
        CHECK_CLOSE(v_.z, (ez), (tol), 0.0); \
    } while (0)

#define CHECK_STATUS(call, expected)                                                         \
    do {                                                                                     \
        int32_t s_ = (call);                                                                 \
        if (s_ != (expected)) {                                                              \
            fprintf(stderr, "%s:%d: %s returned %d (%s: %s), expected %s\n", __FILE__,        \
                    __LINE__, #call, (int)s_, rsl_status_str(s_), rsl_last_error_message(), \
                    #expected);                                                              \
            rsl_test_failures++;                                                             \
        }                                                                                    \
    } while (0)

static inline rsl_vec3 rsl_test_vec(double x, double y, double z) {
    rsl_vec3 v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

#endif
