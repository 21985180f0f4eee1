/* The rows four lanes wide: SSE2 on x86-64, NEON on ARM, GCC's generic vectors elsewhere. */
#include "solve/contact_wide.h"

#define KG_W 4
#include "solve/contact_vector_lanes.h"
#include "solve/contact_row.h"

#if defined(__SSE2__)
#include <emmintrin.h>

/* Lanes from rows: lane l of out[k] is rows[l][k]. */
static inline void kg_rows_to_lanes_w4(const float* const rows[4], kg_vf out[4])
{
    __m128 r[4];
    for (int lane = 0; lane < 4; ++lane) {
        r[lane] = _mm_loadu_ps(rows[lane]);
    }
    _MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
    for (int k = 0; k < 4; ++k) {
        out[k] = (kg_vf)r[k];
    }
}

/* Bit l set where lane l's moves (0 or 1, as gathered) is 1: shifted into the sign bit. */
static inline unsigned kg_movers_w4(kg_vf moves)
{
    return (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_slli_epi32(_mm_castps_si128((__m128)moves), 31)));
}

static inline void kg_columns_to_rows_w4(kg_solver_body* bodies, kg_vu slots, unsigned movers, const kg_vf columns[4],
                                         int offset)
{
    __m128 r[4] = {(__m128)columns[0], (__m128)columns[1], (__m128)columns[2], (__m128)columns[3]};
    _MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
    for (int lane = 0; lane < 4; ++lane) {
        if (movers >> lane & 1u) {
            _mm_storeu_ps((float*)&bodies[slots[lane]] + offset, r[lane]);
        }
    }
}

#define KG_TRANSPOSES
#endif

#include "solve/contact_wide_impl.h"
