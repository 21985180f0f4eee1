/* The width-1 rows (the scalar constraint of contact_solver.h) and the choice of width. */
#include "solve/contact_wide.h"

#include <stdlib.h>

#define KG_W 1
#define kg_lane float
#define kg_lmask int
#define kg_lindex kg_u32
#define kg_lint kg_i32
#define KG_LANE_OF(v, lane) ((&(v))[lane]) /* lane is always 0 */
#define KG_LZERO 0.0f
#include "solve/contact_wide_impl.h"

extern const kg_contact_rows kg_contact_rows_w4;
#if defined(__x86_64__) || defined(__i386__)
extern const kg_contact_rows kg_contact_rows_w8;
extern const kg_contact_rows kg_contact_rows_w16;
#endif

static int kg_cpu_has_avx2(void)
{
#if defined(__x86_64__) || defined(__i386__)
    return __builtin_cpu_supports("avx2");
#else
    return 0;
#endif
}

static int kg_cpu_has_avx512(void)
{
#if defined(__x86_64__) || defined(__i386__)
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
#else
    return 0;
#endif
}

const kg_contact_rows* kg_contact_rows_of(int width)
{
    if (width == 0) {
        const char* forced = getenv("KGYRO_SIMD_WIDTH");
        width = forced ? atoi(forced) : kg_cpu_has_avx512() ? 16 : kg_cpu_has_avx2() ? 8 : 4;
    }
    switch (width) {
    case 1: return &kg_contact_rows_w1;
    case 4: return &kg_contact_rows_w4;
#if defined(__x86_64__) || defined(__i386__)
    case 8: return kg_cpu_has_avx2() ? &kg_contact_rows_w8 : NULL;
    case 16: return kg_cpu_has_avx512() ? &kg_contact_rows_w16 : NULL;
#endif
    default: return NULL;
    }
}
