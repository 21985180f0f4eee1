/* The shapes of a body that has many (a chain's segments), sorted so that those whose
 * bounds reach a box are a binary search and a short walk back instead of a test of
 * each: shared by the CPU's pair expansion (collide/shape_index.c, which makes them) and
 * continuous collision (collide/continuous.h). Each body's shapes' world bounds sorted
 * by their lower bound along the body's longer extent (x, or y for a wall), each with
 * reach, the largest upper bound of the entries up to it. */
#ifndef KG_SORTED_SHAPES_H
#define KG_SORTED_SHAPES_H

#include "collide/aabb.h"

typedef struct kg_sorted_shape {
    kg_aabb box;  /* the shape's world bounds, as kg_shape_aabb gives them */
    kg_u32 slot;  /* the shape's */
    float reach;  /* the largest upper bound on the axis of the body's entries up to this one */
    kg_u32 pad[2];
} kg_sorted_shape;

/* A body's entries: [first, first + count), sorted along axis (0: x, 1: y). */
typedef struct kg_sorted_span {
    int first;
    int count;
    int axis;
    int pad;
} kg_sorted_span;

KG_STATIC_ASSERT(sizeof(kg_sorted_shape) == 32, sorted_shape_size);
KG_STATIC_ASSERT(sizeof(kg_sorted_span) == 16, sorted_span_size);

KG_FN float kg_lower_on(kg_aabb box, int axis) { return axis ? box.lower.y : box.lower.x; }
KG_FN float kg_upper_on(kg_aabb box, int axis) { return axis ? box.upper.y : box.upper.x; }

/* A bound widened by a little more than float rounding can move it: the search is a
 * sieve, the callers' own tests decide. */
KG_FN float kg_widened(float v, float sign) { return v + sign * (1e-5f * fabsf(v) + 1e-6f); }

/* One past the last of span's entries whose lower bound is not past box's upper bound:
 * the search walks back from there while kg_sorted_may_reach. */
KG_FN int kg_sorted_end(KG_GLOBAL const kg_sorted_shape* e, kg_sorted_span span, kg_aabb box)
{
    float hi = kg_widened(kg_upper_on(box, span.axis), 1.0f);
    int lo = span.first, end = span.first + span.count;
    while (lo < end) {
        int mid = lo + (end - lo) / 2;
        if (kg_lower_on(e[mid].box, span.axis) <= hi) {
            lo = mid + 1;
        } else {
            end = mid;
        }
    }
    return lo;
}

/* Whether entry k, or one before it, may reach box (walking back, stop at the first no). */
KG_FN int kg_sorted_may_reach(KG_GLOBAL const kg_sorted_shape* e, int k, kg_sorted_span span, kg_aabb box)
{
    return k >= span.first && e[k].reach >= kg_widened(kg_lower_on(box, span.axis), -1.0f);
}

/* Whether entry k itself may reach box on the span's axis. */
KG_FN int kg_sorted_reaches(KG_GLOBAL const kg_sorted_shape* e, int k, kg_sorted_span span, kg_aabb box)
{
    return kg_upper_on(e[k].box, span.axis) >= kg_widened(kg_lower_on(box, span.axis), -1.0f);
}

#endif
