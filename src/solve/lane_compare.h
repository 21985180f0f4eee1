/* The comparisons of the row headers' lanes (contact_row.h, body_row.h,
 * joint_revolute_row.h), each giving a mask, and a store where a mask is set: C's
 * operators, for a float lane (the kernels and the scalar rows) and for GCC's vectors.
 * AVX-512 lanes compare into mask registers instead (contact_vector_lanes.h redefines
 * these). KG_STORE_WHERE(mask, lvalue, value) stores value's lanes where mask is set and
 * leaves the others, through the width's KG_SEL. */
#ifndef KG_LANE_COMPARE_H
#define KG_LANE_COMPARE_H

#define KG_LGT(a, b) ((a) > (b))
#define KG_LLT(a, b) ((a) < (b))
#define KG_LGE(a, b) ((a) >= (b))
#define KG_LEQ(a, b) ((a) == (b))
#define KG_LNE(a, b) ((a) != (b))
#define KG_STORE_WHERE(mask, lvalue, value) ((lvalue) = KG_SEL((mask), (value), (lvalue)))

#endif
