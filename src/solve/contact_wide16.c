/* The rows sixteen lanes wide, AVX-512 (this file alone is built with -mavx512f
 * -mavx512vl; its rows are used only where the CPU reports AVX-512F, contact_wide.c).
 * A lane is a float, so sixteen lanes are wider than a body's 8 floats: the gathers and
 * scatters are 8x8 transposes of each half of the lanes, data movement only. */
#include "solve/contact_wide.h"

#define KG_W 16
#include "solve/contact_vector_lanes.h"
#include "solve/contact_row.h"

#include "solve/contact_transpose8.h"

/* Lanes 0-7 from lo and 8-15 from hi. */
static inline kg_vf kg_join_w16(__m256 lo, __m256 hi)
{
    __m512d joined = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_castps_pd(lo)), _mm256_castps_pd(hi), 1);
    return (kg_vf)_mm512_castpd_ps(joined);
}

/* Eight columns from 16 rows at offset: lane l of out[k] is rows[l][offset + k], k < 8. */
static inline void kg_rows8_to_lanes_w16(const float* const rows[16], int offset, kg_vf out[8])
{
    __m256 lo[8], hi[8];
    for (int lane = 0; lane < 8; ++lane) {
        lo[lane] = _mm256_loadu_ps(rows[lane] + offset);
        hi[lane] = _mm256_loadu_ps(rows[lane + 8] + offset);
    }
    kg_transpose8(lo);
    kg_transpose8(hi);
    for (int k = 0; k < 8; ++k) {
        out[k] = kg_join_w16(lo[k], hi[k]);
    }
}

/* Lanes from rows: lane l of out[k] is rows[l][k]. */
static inline void kg_rows_to_lanes_w16(const float* const rows[16], kg_vf out[16])
{
    kg_rows8_to_lanes_w16(rows, 0, out);
    kg_rows8_to_lanes_w16(rows, 8, out + 8);
}

/* The bodies of slots into the columns of their motions (contact_wide_impl.h): one
 * transpose, where narrower lanes take a body's floats W at a time. */
static inline void kg_rows_to_columns_w16(const kg_solver_body* bodies, kg_vu slots, kg_vf columns[KG_BODY_FLOATS])
{
    const float* rows[16];
    for (int lane = 0; lane < 16; ++lane) {
        rows[lane] = (const float*)&bodies[slots[lane]];
    }
    kg_rows8_to_lanes_w16(rows, 0, columns);
}

/* Bit l set where lane l's moves (as gathered) is not zero. */
static inline unsigned kg_movers_w16(kg_vf moves)
{
    return (unsigned)_mm512_test_epi32_mask((__m512i)moves, (__m512i)moves);
}

/* The 4x4 transposes within each 128-bit quarter: quarter q of r[i] is lane 4q + i's
 * four floats (columns[0..3] of it), so a lane's scatter is one 16-byte store. */
static inline void kg_columns_to_rows_w16(kg_solver_body* bodies, kg_vu slots, unsigned movers, const kg_vf columns[4],
                                          int offset)
{
    __m512 t0 = _mm512_unpacklo_ps((__m512)columns[0], (__m512)columns[1]);
    __m512 t1 = _mm512_unpackhi_ps((__m512)columns[0], (__m512)columns[1]);
    __m512 t2 = _mm512_unpacklo_ps((__m512)columns[2], (__m512)columns[3]);
    __m512 t3 = _mm512_unpackhi_ps((__m512)columns[2], (__m512)columns[3]);
    __m512 r[4] = {_mm512_shuffle_ps(t0, t2, 0x44), _mm512_shuffle_ps(t0, t2, 0xEE), _mm512_shuffle_ps(t1, t3, 0x44),
                   _mm512_shuffle_ps(t1, t3, 0xEE)};
    for (int i = 0; i < 4; ++i) {
        __m128 quarter[4] = {_mm512_castps512_ps128(r[i]), _mm512_extractf32x4_ps(r[i], 1),
                             _mm512_extractf32x4_ps(r[i], 2), _mm512_extractf32x4_ps(r[i], 3)};
        for (int q = 0; q < 4; ++q) {
            int lane = 4 * q + i;
            if (movers >> lane & 1u) {
                _mm_storeu_ps((float*)&bodies[slots[lane]] + offset, quarter[q]);
            }
        }
    }
}

#define KG_TRANSPOSES
#define KG_ROWS8_TO_LANES
#include "solve/contact_wide_impl.h"
