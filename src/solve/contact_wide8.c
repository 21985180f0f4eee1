/* The rows eight lanes wide, AVX2 (this file alone is built with -mavx2; its rows are
 * used only where the CPU reports AVX2, contact_wide.c). */
#include "solve/contact_wide.h"

#define KG_W 8
#include "solve/contact_vector_lanes.h"
#include "solve/contact_row.h"

#include "solve/contact_transpose8.h"

/* Lanes from rows: lane l of out[k] is rows[l][k]. */
static inline void kg_rows_to_lanes_w8(const float* const rows[8], kg_vf out[8])
{
    __m256 r[8];
    for (int lane = 0; lane < 8; ++lane) {
        r[lane] = _mm256_loadu_ps(rows[lane]);
    }
    kg_transpose8(r);
    for (int k = 0; k < 8; ++k) {
        out[k] = (kg_vf)r[k];
    }
}

/* Bit l set where lane l's moves (0 or 1, as gathered) is 1: shifted into the sign bit. */
static inline unsigned kg_movers_w8(kg_vf moves)
{
    return (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_slli_epi32(_mm256_castps_si256((__m256)moves), 31)));
}

static inline void kg_columns_to_rows_w8(kg_solver_body* bodies, kg_vu slots, unsigned movers, const kg_vf columns[4],
                                         int offset)
{
    __m256 r[8] = {(__m256)columns[0], (__m256)columns[1], (__m256)columns[2], (__m256)columns[3]};
    for (int k = 4; k < 8; ++k) {
        r[k] = _mm256_setzero_ps();
    }
    kg_transpose8(r);
    for (int lane = 0; lane < 8; ++lane) {
        if (movers >> lane & 1u) {
            _mm_storeu_ps((float*)&bodies[slots[lane]] + offset, _mm256_castps256_ps128(r[lane]));
        }
    }
}

#define KG_TRANSPOSES
#include "solve/contact_wide_impl.h"
