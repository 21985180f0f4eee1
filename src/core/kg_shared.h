/* Portability layer for code compiled both as C (CPU backend) and as OpenCL C (kernels).
 * Everything included after this header must stay within what both languages accept:
 * pointers to global memory only as KG_GLOBAL, no libc beyond sqrtf, fabsf, fminf, fmaxf
 * and floorf, no double. */
#ifndef KG_SHARED_H
#define KG_SHARED_H

#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#pragma OPENCL FP_CONTRACT OFF
typedef uint kg_u32;
typedef ulong kg_u64;
typedef int kg_i32;
#define KG_FN static inline
#define KG_FN_INLINE static inline
#define KG_FN_NOINLINE static inline
#define KG_GLOBAL __global
#define sqrtf sqrt
#define fabsf fabs
#define fminf fmin
#define fmaxf fmax
#define floorf floor
#define KG_FLT_MAX 3.402823466e+38f
#define kg_lowest_bit(x) ((int)popcount(((x) & (0u - (x))) - 1u)) /* ctz is OpenCL 2.0 */
#define KG_PRIVATE_VIEW(type, name, element) \
    type name##_copy = (element);           \
    const type* name = &name##_copy
/* a work-group's shared variable, barrier, atomic minima (of floats never negative:
 * their bits order as they do) and atomic or */
#define KG_LOCAL __local
#define kg_group_barrier() barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE)
#define kg_atomic_min_u32(p, v) atomic_min((p), (v))
#define kg_atomic_or_u32(p, v) atomic_or((p), (v))
#define kg_atomic_min_unsigned_float(p, v) atomic_min((__global uint*)(p), as_uint(v))
typedef struct kg_vec2 {
    float x, y;
} kg_vec2;
typedef struct kg_aabb {
    kg_vec2 lower, upper;
} kg_aabb;
#else
#include <math.h>
#include <stdint.h>
#include <float.h>
#include "kgyro/types.h"
typedef uint32_t kg_u32;
typedef uint64_t kg_u64;
typedef int32_t kg_i32;
#define KG_FN static inline
/* a KG_FN that a hot CPU loop needs inlined where gcc's size limits would not */
#define KG_FN_INLINE static inline __attribute__((always_inline))
/* a KG_FN that a hot CPU loop should call rather than inline: the tile pass's cell, which
 * most cells leave at once, keeps the loop over the cells small (0.6 M instructions of 36
 * on 100 steps of demo_platformer) */
#define KG_FN_NOINLINE static __attribute__((noinline))
/* A hot CPU function built twice, for AVX2 and for the baseline, the one the CPU runs
 * chosen when the library loads (an ifunc). Scalar code gains from AVX2's wider moves
 * and three-operand forms alone: no FMA (that is another instruction set, and the build
 * says -ffp-contract=off), so the two give the same bits. */
#if defined(__x86_64__) && defined(__linux__) && !defined(KG_NO_TARGET_CLONES)
#define KG_CPU_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define KG_CPU_CLONES
#endif
#define KG_GLOBAL
#define KG_FLT_MAX FLT_MAX
#define kg_lowest_bit(x) __builtin_ctz(x) /* the index of x's lowest set bit; x != 0 */
/* A pointer to an array element for a shared function that takes a private pointer: in a
 * kernel a private copy of the global element, in C the element itself. */
#define KG_PRIVATE_VIEW(type, name, element) const type* name = &(element)
/* A work-group's code run in C as a group of one work-item: there is nothing to wait for,
 * and nothing races. */
#define KG_LOCAL
#define kg_group_barrier() ((void)0)
static inline void kg_atomic_min_u32(kg_u32* p, kg_u32 v) { *p = v < *p ? v : *p; }
static inline void kg_atomic_or_u32(kg_u32* p, kg_u32 v) { *p |= v; }
static inline void kg_atomic_min_unsigned_float(float* p, float v) { *p = v < *p ? v : *p; }
#endif

/* A compile-time check usable in C99 and OpenCL C alike; both sides assert the same
 * sizes so the host and device agree on every shared struct. */
#define KG_STATIC_ASSERT(cond, name) typedef char kg_static_assert_##name[(cond) ? 1 : -1]

#endif
