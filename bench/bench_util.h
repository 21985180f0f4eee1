/* What the benchmark programs share: a monotonic clock, a seeded random number in a
 * range, and sorting timings for their median. Header-only; each program is one file. */
#ifndef KG_BENCH_UTIL_H
#define KG_BENCH_UTIL_H

#include <stdint.h>
#include <stdlib.h>
#include <time.h>

static inline double bench_now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return 1000.0 * (double)t.tv_sec + 1.0e-6 * (double)t.tv_nsec;
}

/* A float in [lo, hi) from the xorshift state *rng (the same sequence on every machine). */
static inline float bench_random_range(uint32_t* rng, float lo, float hi)
{
    *rng ^= *rng << 13;
    *rng ^= *rng >> 17;
    *rng ^= *rng << 5;
    return lo + (hi - lo) * (float)(*rng >> 8) * (1.0f / 16777216.0f);
}

static inline int bench_compare_doubles(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

/* values[0, count) in ascending order. */
static inline void bench_sort(double* values, int count)
{
    qsort(values, (size_t)count, sizeof *values, bench_compare_doubles);
}

/* The median of values[0, count), which it sorts. */
static inline double bench_median(double* values, int count)
{
    bench_sort(values, count);
    return count % 2 ? values[count / 2] : 0.5 * (values[count / 2 - 1] + values[count / 2]);
}

#endif
