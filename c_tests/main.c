/* Runner: `c_tests` runs every test, `c_tests NAME` runs one, `c_tests --list` lists them.
 * Exit status 0 when every check passed. */
#include <stdio.h>
#include <string.h>

#include "rsl_test.h"

int rsl_test_failures = 0;

#define RSL_TEST(name) void test_##name(void);
#include "tests.def"
#undef RSL_TEST

struct rsl_test_entry {
    const char *name;
    void (*fn)(void);
};

static const struct rsl_test_entry tests[] = {
#define RSL_TEST(name) {#name, test_##name},
#include "tests.def"
#undef RSL_TEST
};

static const size_t n_tests = sizeof tests / sizeof tests[0];

int main(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "--list") == 0) {
        for (size_t i = 0; i < n_tests; i++) printf("%s\n", tests[i].name);
        return 0;
    }
    int ran = 0;
    for (size_t i = 0; i < n_tests; i++) {
        if (argc > 1 && strcmp(argv[1], tests[i].name) != 0) continue;
        int before = rsl_test_failures;
        tests[i].fn();
        printf("%s: %s\n", tests[i].name, rsl_test_failures == before ? "ok" : "FAILED");
        ran++;
    }
    if (ran == 0) {
        fprintf(stderr, "no test named %s\n", argc > 1 ? argv[1] : "(none)");
        return 2;
    }
    return rsl_test_failures == 0 ? 0 : 1;
}
