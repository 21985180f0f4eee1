/* The rows four lanes wide: SSE2 on x86-64, NEON on ARM, GCC's generic vectors elsewhere. */
#include "solve/contact_wide.h"

#define KG_W 4
#include "solve/contact_vector_lanes.h"
#include "solve/contact_row.h"

#if defined(__SSE2__)
#include <emmintrin.h>

KG_STATIC_ASSERT(sizeof(kg_solver_body) == 8 * sizeof(float), solver_body_is_eight_floats);

static const kg_solver_body kg_still_body = {{{0.0f, 0.0f}, 0.0f, {0.0f, 0.0f}, {1.0f, 0.0f}}, 0u};

/* The bodies of a block's lanes, each a whole solver body (two halves of four floats),
 * transposed into fields: data movement only, so the lanes get exactly the floats the
 * scalar gather would give them. */
static kg_body_motion_w4 kg_gather_w4(const kg_solver_body* bodies, const kg_contact_constraint_w4* r, int is_b)
{
    __m128 low[4], high[4];
    for (int lane = 0; lane < 4; ++lane) {
        kg_u32 slot = is_b ? r->b[lane] : r->a[lane];
        const float* body = (const float*)(slot == KG_NULL_INDEX ? &kg_still_body : &bodies[slot]);
        low[lane] = _mm_loadu_ps(body);
        high[lane] = _mm_loadu_ps(body + 4);
    }
    _MM_TRANSPOSE4_PS(low[0], low[1], low[2], low[3]);
    _MM_TRANSPOSE4_PS(high[0], high[1], high[2], high[3]);
    kg_body_motion_w4 m;
    m.v.x = (kg_vf)low[0];
    m.v.y = (kg_vf)low[1];
    m.w = (kg_vf)low[2];
    m.dp.x = (kg_vf)low[3];
    m.dp.y = (kg_vf)high[0];
    m.dq.c = (kg_vf)high[1];
    m.dq.s = (kg_vf)high[2];
    return m;
}

/* Back to the bodies that take impulses: their first four floats, the velocities and
 * dp.x, which is what was gathered. */
static void kg_scatter_w4(kg_solver_body* bodies, const kg_contact_constraint_w4* r, int is_b,
                          const kg_body_motion_w4* m)
{
    __m128 rows[4] = {(__m128)m->v.x, (__m128)m->v.y, (__m128)m->w, (__m128)m->dp.x};
    _MM_TRANSPOSE4_PS(rows[0], rows[1], rows[2], rows[3]);
    for (int lane = 0; lane < 4; ++lane) {
        kg_u32 slot = is_b ? r->b[lane] : r->a[lane];
        if (slot != KG_NULL_INDEX && bodies[slot].moves) {
            _mm_storeu_ps((float*)&bodies[slot], rows[lane]);
        }
    }
}

#define KG_GATHER_TRANSPOSED
#endif

#include "solve/contact_wide_impl.h"
