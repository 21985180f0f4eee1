/* The rows four lanes wide: SSE2 on x86-64, NEON on ARM, GCC's generic vectors elsewhere. */
#include "solve/contact_wide.h"

typedef float kg_f4 __attribute__((vector_size(16)));
typedef int kg_i4 __attribute__((vector_size(16)));
typedef unsigned kg_u4 __attribute__((vector_size(16)));

/* the lanes of a where mask is set, else of b: bitwise, so the lanes are exact copies */
static inline kg_f4 kg_blend4(kg_i4 mask, kg_f4 a, kg_f4 b) { return (kg_f4)(((kg_i4)a & mask) | ((kg_i4)b & ~mask)); }

#define KG_W 4
#define kg_lane kg_f4
#define kg_lmask kg_i4
#define kg_lindex kg_u4
#define kg_lint kg_i4
#define KG_SEL(mask, a, b) kg_blend4((mask), (a), (b))
#define KG_LZERO ((kg_f4){0.0f, 0.0f, 0.0f, 0.0f})
#define KG_LANE_OF(v, lane) ((v)[lane])
#include "solve/contact_row.h"

#include "solve/contact_wide_impl.h"
