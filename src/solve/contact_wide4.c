/* The rows four lanes wide: SSE2 on x86-64, NEON on ARM, GCC's generic vectors elsewhere. */
#include "solve/contact_wide.h"

#define KG_W 4
#include "solve/contact_vector_lanes.h"
#include "solve/contact_row.h"

#if defined(__SSE2__)
#include <emmintrin.h>

/* The solver bodies of slots (two halves of four floats each) into the columns of their
 * motions: data movement only. */
static inline void kg_rows_to_columns_w4(const kg_solver_body* bodies, kg_vu slots, kg_vf columns[7])
{
    __m128 low[4], high[4];
    for (int lane = 0; lane < 4; ++lane) {
        const float* row = kg_gather_source(bodies, slots[lane]);
        low[lane] = _mm_loadu_ps(row);
        high[lane] = _mm_loadu_ps(row + 4);
    }
    _MM_TRANSPOSE4_PS(low[0], low[1], low[2], low[3]);
    _MM_TRANSPOSE4_PS(high[0], high[1], high[2], high[3]);
    for (int k = 0; k < 4; ++k) {
        columns[k] = (kg_vf)low[k];
    }
    for (int k = 4; k < 7; ++k) {
        columns[k] = (kg_vf)high[k - 4];
    }
}

static inline void kg_columns_to_rows_w4(kg_solver_body* bodies, kg_vu slots, const kg_vf columns[4])
{
    __m128 r[4] = {(__m128)columns[0], (__m128)columns[1], (__m128)columns[2], (__m128)columns[3]};
    _MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
    for (int lane = 0; lane < 4; ++lane) {
        float* row = kg_scatter_target(bodies, slots[lane]);
        if (row) {
            _mm_storeu_ps(row, r[lane]);
        }
    }
}

#define KG_TRANSPOSES
#endif

#include "solve/contact_wide_impl.h"
