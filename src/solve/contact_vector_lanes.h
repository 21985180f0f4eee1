/* The lane types of contact_row.h for the CPU's SIMD widths: GCC/Clang vectors of KG_W
 * floats; masks, what the comparisons KG_LGT and the like give (KG_W ints, or with
 * AVX-512 a mask register); and a select that copies lanes bitwise. Define KG_W (4, 8
 * or 16), then include this, then contact_row.h and contact_wide_impl.h; once per file. */
#ifndef KG_CONTACT_VECTOR_LANES_H
#define KG_CONTACT_VECTOR_LANES_H

typedef float kg_vf __attribute__((vector_size(4 * KG_W)));
typedef int kg_vi __attribute__((vector_size(4 * KG_W)));
typedef unsigned kg_vu __attribute__((vector_size(4 * KG_W)));

#include <math.h>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#define kg_lane kg_vf
#define kg_lindex kg_vu
#define kg_lint kg_vi
#define KG_LZERO ((kg_vf){0.0f}) /* the other lanes are zeroed too */
#define KG_LANE_OF(v, lane) ((v)[lane])

#include "solve/lane_compare.h"

#if KG_W == 16 && defined(__AVX512F__)
/* AVX-512 compares into a mask register, a bit a lane, and blends by one: a select is
 * one instruction, where the vector masks of the other widths made it two (a masked xor
 * and an xor) after the comparison. The predicates are C's: ordered (false with a NaN)
 * but for !=. A store where a mask is set is a masked store: no lane set, no write. */
#undef KG_LGT
#undef KG_LLT
#undef KG_LGE
#undef KG_LEQ
#undef KG_LNE
#undef KG_STORE_WHERE
#define kg_lmask __mmask16
#define KG_SEL(mask, a, b) ((kg_vf)_mm512_mask_blend_ps((mask), (__m512)(b), (__m512)(a)))
#define KG_LGT(a, b) _mm512_cmp_ps_mask((__m512)(a), (__m512)(b), _CMP_GT_OQ)
#define KG_LLT(a, b) _mm512_cmp_ps_mask((__m512)(a), (__m512)(b), _CMP_LT_OQ)
#define KG_LGE(a, b) _mm512_cmp_ps_mask((__m512)(a), (__m512)(b), _CMP_GE_OQ)
#define KG_LEQ(a, b) _mm512_cmp_ps_mask((__m512)(a), (__m512)(b), _CMP_EQ_OQ)
#define KG_LNE(a, b) _mm512_cmp_ps_mask((__m512)(a), (__m512)(b), _CMP_NEQ_UQ)
#define KG_STORE_WHERE(mask, lvalue, value) _mm512_mask_storeu_ps((void*)&(lvalue), (mask), (__m512)(value))
#else
/* the lanes of a where mask is set, else of b: bitwise, so the lanes are exact copies */
static inline kg_vf kg_blend(kg_vi mask, kg_vf a, kg_vf b) { return (kg_vf)(((kg_vi)a & mask) | ((kg_vi)b & ~mask)); }

#define kg_lmask kg_vi
#define KG_SEL(mask, a, b) kg_blend((mask), (a), (b))
#endif

/* a > b ? a : b and a < b ? a : b in one instruction each on x86, whose MAXPS and MINPS
 * are defined as exactly that (the second operand where the comparison fails: NaN, and
 * zeros of either sign), so the bits are those of the select (contact_row.h's kg_lmax).
 * The select is a comparison and two or three bitwise operations; the row's pass has
 * ten of them. Elsewhere (NEON's max returns NaN) the select. */
#if KG_W == 16 && defined(__AVX512F__)
#define KG_LMAX(a, b) ((kg_vf)_mm512_max_ps((__m512)(a), (__m512)(b)))
#define KG_LMIN(a, b) ((kg_vf)_mm512_min_ps((__m512)(a), (__m512)(b)))
#elif KG_W == 8 && defined(__AVX__)
#define KG_LMAX(a, b) ((kg_vf)_mm256_max_ps((__m256)(a), (__m256)(b)))
#define KG_LMIN(a, b) ((kg_vf)_mm256_min_ps((__m256)(a), (__m256)(b)))
#elif KG_W == 4 && defined(__SSE__)
#define KG_LMAX(a, b) ((kg_vf)_mm_max_ps((__m128)(a), (__m128)(b)))
#define KG_LMIN(a, b) ((kg_vf)_mm_min_ps((__m128)(a), (__m128)(b)))
#endif

/* The correctly rounded square root of each lane (IEEE, as sqrtf): one instruction where
 * the width has it. */
static inline kg_vf kg_vsqrt(kg_vf x)
{
#if KG_W == 16 && defined(__AVX512F__)
    return (kg_vf)_mm512_sqrt_ps((__m512)x);
#elif KG_W == 8 && defined(__AVX__)
    return (kg_vf)_mm256_sqrt_ps((__m256)x);
#elif KG_W == 4 && defined(__SSE__)
    return (kg_vf)_mm_sqrt_ps((__m128)x);
#else
    for (int lane = 0; lane < KG_W; ++lane) {
        x[lane] = sqrtf(x[lane]);
    }
    return x;
#endif
}

#endif
