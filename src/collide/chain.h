/* Chains: polylines and loops of one-sided segments for static outlines (terrain drawn as
 * a line, Tiled polylines and polygons), shared by the CPU backend and the kernels. A chain
 * is collided the way a tile map's exposed edges are (collide/tile_collide.h): each of its
 * segments knows the points before and after it (its ghosts), so a body sliding along the
 * chain meets no corner inside a straight run (a "ghost collision"), and contacts keep
 * their normals in the segment's Voronoi region.
 *
 * Solid is on a segment's left, its normal on its right: a loop listed counter-clockwise
 * keeps bodies outside, one listed clockwise keeps them inside. A body whose centre is
 * behind a segment gets nothing from it (Box2D's one-sided rule), so a body that has
 * crossed a chain is let go rather than pulled back through it. An open chain's two ends
 * have no ghost: each is a free end with a virtual side at right angles, as the end of a
 * one-way platform in a tile map.
 *
 * A chain segment is a kg_shape with count 2 (p1 and p2 in vertices[0] and [1], radius 0)
 * and KG_CHAIN_SEGMENT in its chain flags; the ghost before p1 is in vertices[2] when
 * KG_CHAIN_GHOST1 is set, the one after p2 in vertices[3] when KG_CHAIN_GHOST2 is. */
#ifndef KG_CHAIN_H
#define KG_CHAIN_H

#include "collide/tile_collide.h"

#define KG_CHAIN_SEGMENT 0x1u
#define KG_CHAIN_GHOST1 0x2u
#define KG_CHAIN_GHOST2 0x4u

KG_FN int kg_is_chain_segment(const kg_shape* shape) { return (shape->chain & KG_CHAIN_SEGMENT) != 0u; }

/* How the chain goes on at an end of a segment: from the direction arriving at the end to
 * the one leaving it, a left turn is a convex corner (the neighbour's normal is a ghost
 * axis), a straight run or a right turn is flat or concave (the segment's own normal
 * serves). A left turn of nearly 180 degrees (a spike's tip) has a small sine too, but
 * it is a corner, not a straight run: told by the cosine, else neither segment owned the
 * tip. *ghost_normal gets the neighbour's normal. */
KG_FN kg_segment_end kg_chain_end(kg_vec2 arriving, kg_vec2 leaving, kg_vec2 neighbour, kg_vec2* ghost_normal)
{
    *ghost_normal = kg_right_perp(neighbour);
    float sine = kg_cross(arriving, leaving);
    int hairpin = sine >= 0.0f && kg_dot(arriving, leaving) < 0.0f;
    return sine > KG_TILE_ANGLE_TOLERANCE || hairpin ? KG_END_CORNER : KG_END_FLAT;
}

/* The chain segment as a tile segment, in its body's frame shifted to origin. */
KG_FN kg_tile_segment kg_chain_segment_of(const kg_shape* chain, kg_vec2 origin)
{
    kg_tile_segment s;
    s.p1 = kg_sub(chain->vertices[0], origin);
    s.p2 = kg_sub(chain->vertices[1], origin);
    s.length = kg_distance(s.p1, s.p2);
    s.direction = kg_scale(1.0f / s.length, kg_sub(s.p2, s.p1));
    s.normal = kg_right_perp(s.direction);
    s.vertex1 = 0u;
    s.vertex2 = 1u;
    s.edge = 0u;
    s.end1 = (kg_i32)KG_END_FREE;
    s.normal0 = kg_neg(s.direction);
    if (chain->chain & KG_CHAIN_GHOST1) {
        kg_vec2 before = kg_normalize(kg_sub(chain->vertices[0], chain->vertices[2]));
        s.end1 = (kg_i32)kg_chain_end(before, s.direction, before, &s.normal0);
    }
    s.end2 = (kg_i32)KG_END_FREE;
    s.normal2 = s.direction;
    if (chain->chain & KG_CHAIN_GHOST2) {
        kg_vec2 after = kg_normalize(kg_sub(chain->vertices[3], chain->vertices[1]));
        s.end2 = (kg_i32)kg_chain_end(s.direction, after, after, &s.normal2);
    }
    if (s.end1 == KG_END_FLAT) {
        s.normal0 = s.normal;
    }
    if (s.end2 == KG_END_FLAT) {
        s.normal2 = s.normal;
    }
    return s;
}

/* The manifold of a chain segment (a) and a body's shape (b), normal from a to b: computed
 * in the segment's frame shifted to p1, where coordinates stay small, then moved to the
 * world frame. */
KG_FN kg_manifold kg_collide_chain_segment(const kg_shape* chain, kg_xf xfa, const kg_shape* body, kg_xf xfb,
                                           float speculative_distance)
{
    kg_vec2 origin = chain->vertices[0];
    kg_tile_segment s = kg_chain_segment_of(chain, origin);
    kg_shape moved;
    kg_shape_in_frame(&moved, body, kg_relative_xf(xfa, origin, xfb));
    kg_tile_hit hit = moved.count >= 2
                          ? kg_tile_collide_rounded(&s, &moved, 0, speculative_distance)
                          : kg_tile_collide_circle(&s, moved.vertices[0], moved.radius, 0, speculative_distance);
    for (int i = 0; i < hit.manifold.point_count; ++i) { /* the tile code names (body, segment): a is the segment */
        kg_u32 id = hit.manifold.points[i].id;
        hit.manifold.points[i].id = KG_FEATURE_ID(id & 0xFFu, id >> 8);
    }
    return kg_manifold_to_world(hit.manifold, xfa, origin, xfb, speculative_distance);
}

/* ---- dispatch ---- */

/* The contact manifold of shapes a and b of any kind (in their bodies' frames) with the
 * bodies at xfa and xfb: normal from a to b, up to two points with separation <=
 * speculative_distance. Two chain segments never touch: chains outline what does not move. */
KG_FN kg_manifold kg_collide_shapes(const kg_shape* a, kg_xf xfa, const kg_shape* b, kg_xf xfb, float speculative_distance)
{
    if (kg_is_chain_segment(a)) {
        return kg_is_chain_segment(b) ? kg_empty_manifold()
                                      : kg_collide_chain_segment(a, xfa, b, xfb, speculative_distance);
    }
    if (kg_is_chain_segment(b)) {
        return kg_flip_manifold(kg_collide_chain_segment(b, xfb, a, xfa, speculative_distance));
    }
    return kg_collide_convex(a, xfa, b, xfb, speculative_distance);
}

#endif
