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

KG_STATIC_ASSERT(sizeof(kg_solver_body) == 8 * sizeof(float), solver_body_is_eight_floats);

static const kg_solver_body kg_still_body = {{{0.0f, 0.0f}, 0.0f, {0.0f, 0.0f}, {1.0f, 0.0f}}, 0u};

/* The bodies of a block's lanes, each a whole solver body, transposed into fields. */
static kg_body_motion_w8 kg_gather_w8(const kg_solver_body* bodies, const kg_contact_constraint_w8* r, int is_b)
{
    __m256 rows[8];
    for (int lane = 0; lane < 8; ++lane) {
        kg_u32 slot = is_b ? r->b[lane] : r->a[lane];
        const kg_solver_body* body = slot == KG_NULL_INDEX ? &kg_still_body : &bodies[slot];
        rows[lane] = _mm256_loadu_ps((const float*)body);
    }
    kg_transpose8(rows);
    kg_body_motion_w8 m;
    m.v.x = (kg_vf)rows[0];
    m.v.y = (kg_vf)rows[1];
    m.w = (kg_vf)rows[2];
    m.dp.x = (kg_vf)rows[3];
    m.dp.y = (kg_vf)rows[4];
    m.dq.c = (kg_vf)rows[5];
    m.dq.s = (kg_vf)rows[6];
    return m;
}

/* Back to the bodies that take impulses: their first four floats, the velocities and
 * dp.x, which is what was gathered. */
static void kg_scatter_w8(kg_solver_body* bodies, const kg_contact_constraint_w8* r, int is_b,
                          const kg_body_motion_w8* m)
{
    __m256 rows[8] = {(__m256)m->v.x, (__m256)m->v.y, (__m256)m->w,  (__m256)m->dp.x,
                      (__m256)m->dp.y, (__m256)m->dq.c, (__m256)m->dq.s, _mm256_setzero_ps()};
    kg_transpose8(rows);
    for (int lane = 0; lane < 8; ++lane) {
        kg_u32 slot = is_b ? r->b[lane] : r->a[lane];
        if (slot != KG_NULL_INDEX && bodies[slot].moves) {
            _mm_storeu_ps((float*)&bodies[slot], _mm256_castps256_ps128(rows[lane]));
        }
    }
}

#define KG_GATHER_TRANSPOSED
#include "solve/contact_wide_impl.h"
