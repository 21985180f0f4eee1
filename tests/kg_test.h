/* Minimal test harness: KG_CHECK records failures without stopping, KG_TEST_MAIN runs the
 * listed tests and prints "N passed, N failed" (one per test function). Exit code 1 on
 * any failure. Numbers are printed on failure so a failing physics test says by how much. */
#ifndef KG_TEST_H
#define KG_TEST_H

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int kg_test_failures;

#define KG_CHECK(cond)                                                                  \
    do {                                                                                \
        if (!(cond)) {                                                                  \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);    \
            kg_test_failures++;                                                         \
        }                                                                               \
    } while (0)

/* |a - b| <= tol, printing both values when not. */
#define KG_CHECK_NEAR(a, b, tol)                                                        \
    do {                                                                                \
        double kg_a_ = (double)(a), kg_b_ = (double)(b), kg_t_ = (double)(tol);         \
        if (!(fabs(kg_a_ - kg_b_) <= kg_t_)) {                                          \
            fprintf(stderr, "%s:%d: %s = %.9g, expected %s = %.9g within %.3g (off by %.3g)\n", \
                    __FILE__, __LINE__, #a, kg_a_, #b, kg_b_, kg_t_, fabs(kg_a_ - kg_b_)); \
            kg_test_failures++;                                                         \
        }                                                                               \
    } while (0)

#define KG_CHECK_OK(expr)                                                               \
    do {                                                                                \
        int kg_r_ = (int)(expr);                                                        \
        if (kg_r_ != 0) {                                                               \
            fprintf(stderr, "%s:%d: %s returned %d: %s\n", __FILE__, __LINE__, #expr,   \
                    kg_r_, kg_last_error());                                            \
            kg_test_failures++;                                                         \
        }                                                                               \
    } while (0)

/* The OpenCL device the worlds that ask for OpenCL get: KGYRO_OPENCL_DEVICE's, as the
 * library reads it (backend/backend.c), else 0. A GPU machine may list a CPU device
 * first: `make device-check` sets it to the first GPU. */
static inline int kg_test_opencl_device(void)
{
    const char* device = getenv("KGYRO_OPENCL_DEVICE");
    return device && *device ? atoi(device) : 0;
}

/* Prints a measured figure at once (flushed), so a run's numbers can be quoted even if
 * a later check aborts. */
#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
static inline void measured(const char* format, ...)
{
    va_list args;
    va_start(args, format);
    vprintf(format, args);
    va_end(args);
    fflush(stdout);
}

typedef struct kg_test_case {
    const char* name;
    void (*fn)(void);
} kg_test_case;

#define KG_TEST(fn) {#fn, fn}

static inline int kg_run_tests(const kg_test_case* tests, int count)
{
    int passed = 0, failed = 0;
    for (int i = 0; i < count; ++i) {
        int before = kg_test_failures;
        tests[i].fn();
        if (kg_test_failures == before) {
            passed++;
            printf("ok   %s\n", tests[i].name);
        } else {
            failed++;
            printf("FAIL %s\n", tests[i].name);
        }
    }
    printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}

#define KG_MAX_CHOSEN_TESTS 64

/* With no argument, the first `quick` tests; else the tests named on the command line
 * ("all": every one), in the order named. An unknown name lists the tests, exit 2. */
static inline int kg_run_chosen_tests(const kg_test_case* tests, int count, int quick, int argc, char** argv)
{
    if (argc < 2) {
        return kg_run_tests(tests, quick);
    }
    kg_test_case chosen[KG_MAX_CHOSEN_TESTS];
    int n = 0;
    for (int a = 1; a < argc; ++a) {
        int all = strcmp(argv[a], "all") == 0, found = 0;
        for (int i = 0; i < count; ++i) {
            if (all || strcmp(argv[a], tests[i].name) == 0) {
                found = 1;
                if (n < KG_MAX_CHOSEN_TESTS) {
                    chosen[n++] = tests[i];
                }
            }
        }
        if (!found) {
            fprintf(stderr, "unknown test %s; the tests are:\n", argv[a]);
            for (int i = 0; i < count; ++i) {
                fprintf(stderr, "  %s\n", tests[i].name);
            }
            return 2;
        }
    }
    return kg_run_tests(chosen, n);
}

#define KG_TEST_MAIN(...)                                                                           \
    int main(int argc, char** argv)                                                                 \
    {                                                                                               \
        static const kg_test_case tests[] = {__VA_ARGS__};                                          \
        int count = (int)(sizeof tests / sizeof tests[0]);                                          \
        return kg_run_chosen_tests(tests, count, count, argc, argv);                                \
    }

#endif
