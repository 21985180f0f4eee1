/* The rows eight lanes wide, AVX2 (this file alone is built with -mavx2; its rows are
 * used only where the CPU reports AVX2, contact_wide.c). */
#include "solve/contact_wide.h"

typedef float kg_f8 __attribute__((vector_size(32)));
typedef int kg_i8 __attribute__((vector_size(32)));
typedef unsigned kg_u8 __attribute__((vector_size(32)));

/* the lanes of a where mask is set, else of b: bitwise, so the lanes are exact copies */
static inline kg_f8 kg_blend8(kg_i8 mask, kg_f8 a, kg_f8 b) { return (kg_f8)(((kg_i8)a & mask) | ((kg_i8)b & ~mask)); }

#define KG_W 8
#define kg_lane kg_f8
#define kg_lmask kg_i8
#define kg_lindex kg_u8
#define kg_lint kg_i8
#define KG_SEL(mask, a, b) kg_blend8((mask), (a), (b))
#define KG_LZERO ((kg_f8){0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f})
#define KG_LANE_OF(v, lane) ((v)[lane])
#include "solve/contact_wide_impl.h"
