/* Debug draw (kgyro/debug_draw.h): the world's shapes, tiles and contacts handed to a
 * game's callbacks. Bodies are read from the pool the getters read (synced from the
 * OpenCL device first), shapes from their compiled geometry, tiles from the same arrays
 * the tile pass collides with, so what is drawn is what collides. */
#include "collide/tilemap.h"
#include "core/error.h"
#include "core/joint.h"
#include "core/world.h"
#include "kgyro/collision.h"
#include "kgyro/debug_draw.h"

#include <math.h>

kg_debug_draw kg_default_debug_draw(void)
{
    kg_debug_draw draw = {0};
    draw.flags = KG_DEBUG_DRAW_SHAPES | KG_DEBUG_DRAW_TILES | KG_DEBUG_DRAW_JOINTS;
    draw.normal_length = 0.3f;
    return draw;
}

static kg_transform kg_public_xf(kg_xf xf) { return (kg_transform){xf.p, xf.q.c, xf.q.s}; }

static int kg_in_bounds(const kg_debug_draw* draw, kg_aabb box)
{
    return !draw->use_bounds || kg_aabb_overlap(draw->bounds, box);
}

static kg_aabb kg_point_box(kg_vec2 p) { return (kg_aabb){p, p}; }

/* ---- bodies ---- */

/* The colour of body slot i's state: the first of frozen, asleep, bullet, its type. */
static kg_color kg_state_color(const kg_body_pool* p, int i)
{
    static const kg_color kByType[4] = {KG_DEBUG_COLOR_STATIC, KG_DEBUG_COLOR_DYNAMIC, KG_DEBUG_COLOR_KINEMATIC,
                                        KG_DEBUG_COLOR_PARTICLE};
    kg_u32 f = p->flags[i];
    if (f & KG_FLAG_FROZEN) {
        return KG_DEBUG_COLOR_FROZEN;
    }
    if (f & KG_FLAG_ASLEEP) {
        return KG_DEBUG_COLOR_ASLEEP;
    }
    return (f & KG_FLAG_BULLET) ? KG_DEBUG_COLOR_BULLET : kByType[kg_flags_type(f)];
}

static kg_color kg_body_color(const kg_debug_draw* draw, const kg_body_pool* p, int i)
{
    kg_color color = kg_state_color(p, i);
    kg_body body = {(uint32_t)i, p->generation[i]};
    return draw->body_color ? draw->body_color(body, color, draw->context) : color;
}

/* A solid shape: count 1 a circle (a point when its radius is 0), 2 a capsule (a segment
 * when its radius is 0), more a polygon. */
static void kg_draw_solid_shape(const kg_debug_draw* d, const kg_shape* shape, kg_xf xf, kg_color color)
{
    if (shape->count == 1 && shape->radius > 0.0f) {
        if (d->draw_solid_circle) {
            kg_xf at = {kg_xf_point(xf, shape->vertices[0]), xf.q};
            d->draw_solid_circle(kg_public_xf(at), shape->radius, color, d->context);
        }
    } else if (shape->count == 1) {
        if (d->draw_point) {
            d->draw_point(kg_xf_point(xf, shape->vertices[0]), KG_DEBUG_PARTICLE_SIZE, color, d->context);
        }
    } else if (shape->count == 2) {
        kg_vec2 p1 = kg_xf_point(xf, shape->vertices[0]), p2 = kg_xf_point(xf, shape->vertices[1]);
        if (shape->radius > 0.0f && d->draw_capsule) {
            d->draw_capsule(p1, p2, shape->radius, color, d->context);
        } else if (shape->radius == 0.0f && d->draw_segment) {
            d->draw_segment(p1, p2, color, d->context);
        }
    } else if (d->draw_solid_polygon) {
        d->draw_solid_polygon(kg_public_xf(xf), shape->vertices, shape->count, shape->radius, color, d->context);
    }
}

/* A sensor shape in outline: a capsule as its two sides and its end circles. */
static void kg_draw_sensor_shape(const kg_debug_draw* d, const kg_shape* shape, kg_xf xf)
{
    const kg_color color = KG_DEBUG_COLOR_SENSOR;
    kg_vec2 points[KG_MAX_VERTS];
    for (int k = 0; k < shape->count; ++k) {
        points[k] = kg_xf_point(xf, shape->vertices[k]);
    }
    if (shape->count >= 3 && d->draw_polygon) {
        d->draw_polygon(points, shape->count, color, d->context);
    }
    if (shape->count <= 2 && shape->radius > 0.0f && d->draw_circle) {
        for (int k = 0; k < shape->count; ++k) {
            d->draw_circle(points[k], shape->radius, color, d->context);
        }
    }
    if (shape->count == 2 && d->draw_segment) {
        kg_vec2 side = kg_scale(shape->radius, kg_rotate(xf.q, shape->normals[0]));
        d->draw_segment(kg_add(points[0], side), kg_add(points[1], side), color, d->context);
        if (shape->radius > 0.0f) {
            d->draw_segment(kg_sub(points[0], side), kg_sub(points[1], side), color, d->context);
        }
    }
}

/* Every shape of body slot i; a particle made without a shape is its point. */
static void kg_draw_body_shapes(const kg_debug_draw* d, const kg_world* world, const kg_body_pool* p, int i)
{
    const kg_shape_pool* sp = &world->shapes;
    kg_color color = kg_body_color(d, p, i);
    if (p->first_shape[i] == KG_NULL_INDEX && kg_pool_type(p, i) == KG_BODY_PARTICLE) {
        kg_draw_solid_shape(d, &p->shape[i], p->xf[i], color);
    }
    for (kg_u32 s = p->first_shape[i]; s != KG_NULL_INDEX; s = sp->next[s]) {
        const kg_shape* shape = kg_shape_geometry(p, sp, s);
        if (kg_shape_is_sensor(sp, s)) {
            kg_draw_sensor_shape(d, shape, p->xf[i]);
        } else {
            kg_draw_solid_shape(d, shape, p->xf[i], color);
        }
    }
}

static void kg_draw_box(const kg_debug_draw* d, kg_aabb box, kg_color color)
{
    kg_vec2 corners[4] = {box.lower, {box.upper.x, box.lower.y}, box.upper, {box.lower.x, box.upper.y}};
    d->draw_polygon(corners, 4, color, d->context);
}

/* The transform at the body's centre of mass, turned as the body. */
static void kg_draw_mass(const kg_debug_draw* d, const kg_body_pool* p, int i)
{
    if (kg_pool_type(p, i) == KG_BODY_DYNAMIC || kg_pool_type(p, i) == KG_BODY_PARTICLE) {
        d->draw_transform(kg_public_xf((kg_xf){p->center[i], p->rot[i]}), d->context);
    }
}

/* One pass over the bodies per layer, so that a layer lies on the one below it. */
static void kg_draw_bodies(const kg_debug_draw* d, const kg_world* world, unsigned layer)
{
    const kg_body_pool* p = kg_world_read_pool(world);
    for (int i = 0; i < p->high_water; ++i) {
        if (!kg_pool_alive(p, i) || !kg_in_bounds(d, p->aabb[i])) {
            continue;
        }
        if (layer == KG_DEBUG_DRAW_SHAPES) {
            kg_draw_body_shapes(d, world, p, i);
        } else if (layer == KG_DEBUG_DRAW_AABBS) {
            kg_draw_box(d, p->aabb[i], KG_DEBUG_COLOR_AABB);
        } else {
            kg_draw_mass(d, p, i);
        }
    }
}

/* ---- tile maps ---- */

/* The cells of map m inside the bounds (all of them without bounds); 0 when none. */
static int kg_visible_cells(const kg_debug_draw* d, const kg_tile_map_info* m, int* x0, int* y0, int* x1, int* y1)
{
    if (!d->use_bounds) {
        *x0 = 0;
        *y0 = 0;
        *x1 = m->width - 1;
        *y1 = m->height - 1;
        return 1;
    }
    kg_vec2 low = d->bounds.lower, high = d->bounds.upper;
    return kg_tile_span((low.x - m->origin.x) / m->tile_size.x, (high.x - m->origin.x) / m->tile_size.x, m->width,
                        x0, x1) &&
           kg_tile_span((low.y - m->origin.y) / m->tile_size.y, (high.y - m->origin.y) / m->tile_size.y, m->height,
                        y0, y1);
}

/* The edges of a polygon tile that collide (collide/tile_collide.h's exposure bits). */
static void kg_draw_tile_edges(const kg_debug_draw* d, const kg_shape* shape, kg_xf cell, kg_u32 word, kg_color color)
{
    for (int k = 0; k < shape->count; ++k) {
        if (kg_cell_collidable(word, k)) {
            kg_vec2 a = kg_xf_point(cell, shape->vertices[k]);
            kg_vec2 b = kg_xf_point(cell, shape->vertices[(k + 1) % shape->count]);
            d->draw_segment(a, b, color, d->context);
        }
    }
}

static void kg_draw_tile(const kg_debug_draw* d, const kg_tile_proto* proto, kg_xf cell, kg_u32 word)
{
    int one_way = (proto->flags & KG_TILE_FLAG_ONE_WAY) != 0u;
    kg_draw_solid_shape(d, &proto->shape, cell, one_way ? KG_DEBUG_COLOR_ONE_WAY : KG_DEBUG_COLOR_TILE);
    if (proto->shape.count >= 3 && d->draw_segment) {
        kg_color edge = one_way ? KG_DEBUG_COLOR_ONE_WAY_EDGE : KG_DEBUG_COLOR_TILE_EDGE;
        kg_draw_tile_edges(d, &proto->shape, cell, word, edge);
    }
}

/* Only the cells inside the bounds are visited: a huge map costs what is visible. */
static void kg_draw_tilemap(const kg_debug_draw* d, const kg_tilemap_arrays* arrays, const kg_tile_map_info* m)
{
    int x0, y0, x1, y1;
    if (!kg_visible_cells(d, m, &x0, &y0, &x1, &y1)) {
        return;
    }
    for (int layer = 0; layer < m->layer_count; ++layer) {
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                kg_u32 word = arrays->cells[m->cell_offset + kg_tile_cell_index(m, layer, x, y)];
                const kg_tile_proto* proto = &arrays->protos[m->proto_offset + kg_cell_id(word)];
                kg_vec2 corner = {m->origin.x + (float)x * m->tile_size.x, m->origin.y + (float)y * m->tile_size.y};
                if (proto->shape.count > 0) {
                    kg_draw_tile(d, proto, (kg_xf){corner, kg_rot_identity()}, word);
                }
            }
        }
    }
}

static void kg_draw_tilemaps(const kg_debug_draw* d, const kg_world* world)
{
    if (kg_tilemaps_live_count(world) == 0) {
        return;
    }
    kg_tilemap_arrays arrays;
    kg_tilemaps_arrays(world, &arrays);
    for (int m = 0; m < arrays.map_count; ++m) {
        kg_draw_tilemap(d, &arrays, &arrays.maps[m]);
    }
}

/* ---- joints ---- */

/* Through the public getters: a segment between the anchors, a dot at each. */
static void kg_draw_joints(const kg_debug_draw* d, const kg_world* world)
{
    int n = kg_world_joint_count(world);
    for (uint32_t i = 0; n > 0 && world->joints && i < (uint32_t)kg_joints_slots(world); ++i) {
        kg_joint j = kg_joint_of_slot(world, i);
        kg_vec2 a, b;
        if (j.generation == 0u || kg_joint_get_world_anchors(world, j, &a, &b) != KG_OK) {
            continue;
        }
        kg_aabb box = {kg_vmin(a, b), kg_vmax(a, b)};
        if (!kg_in_bounds(d, box)) {
            continue;
        }
        if (d->draw_segment) {
            d->draw_segment(a, b, KG_DEBUG_COLOR_JOINT, d->context);
        }
        if (d->draw_point) {
            d->draw_point(a, KG_DEBUG_CONTACT_SIZE, KG_DEBUG_COLOR_JOINT, d->context);
            d->draw_point(b, KG_DEBUG_CONTACT_SIZE, KG_DEBUG_COLOR_JOINT, d->context);
        }
    }
}

/* ---- contacts ---- */

/* Through the public getter, which reads the OpenCL backend's contacts back. */
static void kg_draw_contacts(const kg_debug_draw* d, const kg_world* world)
{
    int points = (d->flags & KG_DEBUG_DRAW_CONTACT_POINTS) && d->draw_point;
    int normals = (d->flags & KG_DEBUG_DRAW_CONTACT_NORMALS) && d->draw_segment;
    int count = points || normals ? kg_world_contact_count(world) : 0;
    for (int c = 0; c < count; ++c) {
        kg_contact_info contact;
        if (kg_world_get_contact(world, c, &contact) != KG_OK) {
            continue;
        }
        for (int k = 0; k < contact.point_count && k < 2; ++k) {
            kg_vec2 at = contact.points[k];
            if (!kg_in_bounds(d, kg_point_box(at))) {
                continue;
            }
            if (normals) {
                d->draw_segment(at, kg_mul_add(at, d->normal_length, contact.normal), KG_DEBUG_COLOR_CONTACT_NORMAL,
                                d->context);
            }
            if (points) {
                d->draw_point(at, KG_DEBUG_CONTACT_SIZE, KG_DEBUG_COLOR_CONTACT_POINT, d->context);
            }
        }
    }
}

static kg_result kg_check_draw(const kg_world* world, const kg_debug_draw* draw)
{
    if (!world || !draw) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_draw: NULL %s", world ? "draw" : "world");
    }
    kg_aabb b = draw->bounds;
    if (draw->use_bounds && !(kg_vec_is_finite(b.lower) && kg_vec_is_finite(b.upper))) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_draw: bounds must be finite");
    }
    if (!(draw->normal_length >= 0.0f) || !isfinite(draw->normal_length)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_draw: normal_length must be finite and >= 0 (got %g)",
                       (double)draw->normal_length);
    }
    return KG_OK;
}

kg_result kg_world_draw(const kg_world* world, const kg_debug_draw* draw)
{
    KG_TRY(kg_check_draw(world, draw));
    if (draw->flags & KG_DEBUG_DRAW_TILES) {
        kg_draw_tilemaps(draw, world);
    }
    if (draw->flags & KG_DEBUG_DRAW_SHAPES) {
        kg_draw_bodies(draw, world, KG_DEBUG_DRAW_SHAPES);
    }
    if ((draw->flags & KG_DEBUG_DRAW_AABBS) && draw->draw_polygon) {
        kg_draw_bodies(draw, world, KG_DEBUG_DRAW_AABBS);
    }
    if ((draw->flags & KG_DEBUG_DRAW_MASS) && draw->draw_transform) {
        kg_draw_bodies(draw, world, KG_DEBUG_DRAW_MASS);
    }
    if (draw->flags & KG_DEBUG_DRAW_JOINTS) {
        kg_draw_joints(draw, world);
    }
    kg_draw_contacts(draw, world);
    return KG_OK;
}
