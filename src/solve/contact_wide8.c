/* The rows eight lanes wide, AVX2 (this file alone is built with -mavx2; its rows are
 * used only where the CPU reports AVX2, contact_wide.c). */
#include "solve/contact_wide.h"

#define KG_W 8
#include "solve/contact_vector_lanes.h"
#include "solve/contact_row.h"

#include <immintrin.h>

/* Rows to columns: r[i] holds body i's 8 floats (a kg_solver_body), and after it r[k]
 * holds field k of the 8 bodies. Data movement only: no arithmetic, so the lanes get
 * exactly the floats the scalar gather would give them. */
static inline void kg_transpose8(__m256 r[8])
{
    __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
    __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
    __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
    __m256 s0 = _mm256_shuffle_ps(t0, t2, 0x44), s1 = _mm256_shuffle_ps(t0, t2, 0xEE);
    __m256 s2 = _mm256_shuffle_ps(t1, t3, 0x44), s3 = _mm256_shuffle_ps(t1, t3, 0xEE);
    __m256 s4 = _mm256_shuffle_ps(t4, t6, 0x44), s5 = _mm256_shuffle_ps(t4, t6, 0xEE);
    __m256 s6 = _mm256_shuffle_ps(t5, t7, 0x44), s7 = _mm256_shuffle_ps(t5, t7, 0xEE);
    r[0] = _mm256_permute2f128_ps(s0, s4, 0x20);
    r[1] = _mm256_permute2f128_ps(s1, s5, 0x20);
    r[2] = _mm256_permute2f128_ps(s2, s6, 0x20);
    r[3] = _mm256_permute2f128_ps(s3, s7, 0x20);
    r[4] = _mm256_permute2f128_ps(s0, s4, 0x31);
    r[5] = _mm256_permute2f128_ps(s1, s5, 0x31);
    r[6] = _mm256_permute2f128_ps(s2, s6, 0x31);
    r[7] = _mm256_permute2f128_ps(s3, s7, 0x31);
}

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

static inline void kg_lanes_to_rows8_w8(const kg_vf columns[8], float* rows)
{
    __m256 r[8];
    for (int k = 0; k < 8; ++k) {
        r[k] = (__m256)columns[k];
    }
    kg_transpose8(r);
    for (int lane = 0; lane < 8; ++lane) {
        _mm256_storeu_ps(rows + lane * 8, r[lane]);
    }
}

/* Bit l set where lane l's moves (0 or 1, as gathered) is 1: shifted into the sign bit. */
static inline unsigned kg_movers_w8(kg_vf moves)
{
    return (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_slli_epi32(_mm256_castps_si256((__m256)moves), 31)));
}

static inline void kg_columns_to_rows_w8(kg_solver_body* bodies, kg_vu slots, unsigned movers, const kg_vf columns[4])
{
    __m256 r[8] = {(__m256)columns[0], (__m256)columns[1], (__m256)columns[2], (__m256)columns[3]};
    for (int k = 4; k < 8; ++k) {
        r[k] = _mm256_setzero_ps();
    }
    kg_transpose8(r);
    for (int lane = 0; lane < 8; ++lane) {
        if (movers >> lane & 1u) {
            _mm_storeu_ps((float*)&bodies[slots[lane]], _mm256_castps256_ps128(r[lane]));
        }
    }
}

#define KG_TRANSPOSES
#include "solve/contact_wide_impl.h"
