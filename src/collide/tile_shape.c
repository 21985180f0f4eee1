/* Tile shapes: the standard ones (built in tile coordinates for the tile with its right
 * angle or solid side at the bottom right, then mirrored), validation and compilation. */
#include "collide/tile_shape.h"
#include "collide/shape.h"
#include "core/error.h"

#include <math.h>
#include <string.h>

kg_tile_shape kg_tile_empty(void)
{
    kg_tile_shape shape;
    memset(&shape, 0, sizeof shape);
    return shape;
}

kg_tile_shape kg_tile_polygon(const kg_vec2* vertices, int count)
{
    kg_tile_shape shape = kg_tile_empty();
    shape.type = KG_TILE_SHAPE_POLYGON;
    shape.count = count;
    for (int i = 0; vertices && i < count && i < KG_MAX_POLYGON_VERTICES; ++i) {
        shape.vertices[i] = vertices[i];
    }
    return shape;
}

kg_tile_shape kg_tile_circle(kg_vec2 center, float radius)
{
    kg_tile_shape shape = kg_tile_empty();
    shape.type = KG_TILE_SHAPE_CIRCLE;
    shape.center = center;
    shape.radius = radius;
    return shape;
}

static kg_tile_shape kg_tile_quad(float x0, float y0, float x1, float y1)
{
    kg_vec2 v[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    return kg_tile_polygon(v, 4);
}

kg_tile_shape kg_tile_box(void) { return kg_tile_quad(0.0f, 0.0f, 1.0f, 1.0f); }

kg_tile_shape kg_tile_half(kg_tile_side side)
{
    switch (side) {
    case KG_TILE_SIDE_RIGHT: return kg_tile_quad(0.5f, 0.0f, 1.0f, 1.0f);
    case KG_TILE_SIDE_TOP: return kg_tile_quad(0.0f, 0.5f, 1.0f, 1.0f);
    case KG_TILE_SIDE_LEFT: return kg_tile_quad(0.0f, 0.0f, 0.5f, 1.0f);
    default: return kg_tile_quad(0.0f, 0.0f, 1.0f, 0.5f);
    }
}

kg_tile_shape kg_tile_platform(void)
{
    kg_tile_shape shape = kg_tile_half(KG_TILE_SIDE_TOP);
    shape.one_way = 1;
    return shape;
}

/* Moves a shape drawn for the bottom-right corner to corner: mirrored left-right for the
 * left corners, top-bottom for the top ones. */
static kg_tile_shape kg_tile_to_corner(kg_tile_shape shape, kg_tile_corner corner)
{
    int mirror_x = corner == KG_TILE_BOTTOM_LEFT || corner == KG_TILE_TOP_LEFT;
    int mirror_y = corner == KG_TILE_TOP_LEFT || corner == KG_TILE_TOP_RIGHT;
    for (int i = 0; i < shape.count; ++i) {
        kg_vec2* v = &shape.vertices[i];
        v->x = mirror_x ? 1.0f - v->x : v->x;
        v->y = mirror_y ? 1.0f - v->y : v->y;
    }
    return shape;
}

kg_tile_shape kg_tile_slope(kg_tile_corner corner)
{
    kg_vec2 v[3] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}};
    return kg_tile_to_corner(kg_tile_polygon(v, 3), corner);
}

kg_tile_shape kg_tile_slope_low(kg_tile_corner corner)
{
    kg_vec2 v[3] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 0.5f}};
    return kg_tile_to_corner(kg_tile_polygon(v, 3), corner);
}

kg_tile_shape kg_tile_slope_high(kg_tile_corner corner)
{
    kg_vec2 v[4] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 0.5f}};
    return kg_tile_to_corner(kg_tile_polygon(v, 4), corner);
}

/* ---- compiling ---- */

#define KG_TILE_SNAP 1.0e-4f

/* Puts a coordinate that is within KG_TILE_SNAP of the cell's border exactly on it, so
 * edges along a side are recognised as such; fails for one outside the cell. */
static int kg_snap_to_cell(float* v)
{
    if (!isfinite(*v) || *v < -KG_TILE_SNAP || *v > 1.0f + KG_TILE_SNAP) {
        return 0;
    }
    *v = *v < KG_TILE_SNAP ? 0.0f : (*v > 1.0f - KG_TILE_SNAP ? 1.0f : *v);
    return 1;
}

static kg_result kg_build_tile_polygon(const kg_tile_shape* shape, kg_vec2 tile_size, kg_tile_template* out)
{
    if (shape->count < 3 || shape->count > KG_MAX_POLYGON_VERTICES) {
        return kg_fail(KG_ERROR_DEGENERATE_SHAPE, "a tile polygon needs 3 to %d vertices (got %d)",
                       KG_MAX_POLYGON_VERTICES, shape->count);
    }
    kg_vec2 points[KG_MAX_POLYGON_VERTICES];
    for (int i = 0; i < shape->count; ++i) {
        points[i] = shape->vertices[i];
        if (!kg_snap_to_cell(&points[i].x) || !kg_snap_to_cell(&points[i].y)) {
            return kg_fail(KG_ERROR_INVALID_ARGUMENT, "tile polygon vertex %d (%g, %g) is outside the cell [0, 1]^2",
                           i, (double)shape->vertices[i].x, (double)shape->vertices[i].y);
        }
    }
    kg_shape_def def = kg_polygon_shape(points, shape->count);
    kg_shape hull;
    kg_result r = kg_shape_build(&def, &hull);
    if (r != KG_OK) {
        return r;
    }
    kg_shape* s = &out->proto.shape;
    s->count = hull.count;
    for (int i = 0; i < hull.count; ++i) {
        out->unit[i] = hull.vertices[i];
        s->vertices[i] = kg_v2(hull.vertices[i].x * tile_size.x, hull.vertices[i].y * tile_size.y);
    }
    for (int i = 0; i < hull.count; ++i) {
        s->normals[i] = kg_normalize(kg_right_perp(kg_sub(s->vertices[(i + 1) % hull.count], s->vertices[i])));
    }
    s->centroid = kg_shape_mass_of(s, 1.0f).center;
    out->proto.flags = shape->one_way ? KG_TILE_FLAG_ONE_WAY : 0u;
    return KG_OK;
}

static kg_result kg_build_tile_circle(const kg_tile_shape* shape, kg_vec2 tile_size, kg_tile_template* out)
{
    kg_vec2 c = shape->center;
    float r = shape->radius;
    if (!isfinite(c.x) || !isfinite(c.y) || !isfinite(r) || !(r > 0.0f)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "a tile circle needs a finite centre and a radius > 0");
    }
    if (c.x - r < -KG_TILE_SNAP || c.y - r < -KG_TILE_SNAP || c.x + r > 1.0f + KG_TILE_SNAP ||
        c.y + r > 1.0f + KG_TILE_SNAP) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "tile circle (centre (%g, %g), radius %g) reaches outside the cell",
                       (double)c.x, (double)c.y, (double)r);
    }
    if (tile_size.x != tile_size.y) {
        return kg_fail(KG_ERROR_UNSUPPORTED, "tile circles need square tiles (tile size %g x %g)",
                       (double)tile_size.x, (double)tile_size.y);
    }
    if (shape->one_way) {
        return kg_fail(KG_ERROR_UNSUPPORTED, "only polygon tiles can be one-way");
    }
    kg_shape* s = &out->proto.shape;
    s->count = 1;
    s->vertices[0] = kg_scale(tile_size.x, c);
    s->centroid = s->vertices[0];
    s->radius = r * tile_size.x;
    return KG_OK;
}

kg_result kg_tile_template_build(const kg_tile_shape* shape, kg_vec2 tile_size, kg_tile_template* out)
{
    memset(out, 0, sizeof *out);
    switch (shape->type) {
    case KG_TILE_SHAPE_EMPTY: return KG_OK;
    case KG_TILE_SHAPE_POLYGON: return kg_build_tile_polygon(shape, tile_size, out);
    case KG_TILE_SHAPE_CIRCLE: return kg_build_tile_circle(shape, tile_size, out);
    }
    return kg_fail(KG_ERROR_INVALID_ARGUMENT, "unknown tile shape type %d", (int)shape->type);
}

kg_result kg_tile_shape_check(const kg_tile_shape* shape)
{
    if (!shape) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_tile_shape_check: NULL shape");
    }
    kg_tile_template t;
    return kg_tile_template_build(shape, kg_v2(1.0f, 1.0f), &t);
}

int kg_tile_edge_side(kg_vec2 a, kg_vec2 b)
{
    if (a.y == 0.0f && b.y == 0.0f) {
        return KG_TILE_SIDE_BOTTOM;
    }
    if (a.x == 1.0f && b.x == 1.0f) {
        return KG_TILE_SIDE_RIGHT;
    }
    if (a.y == 1.0f && b.y == 1.0f) {
        return KG_TILE_SIDE_TOP;
    }
    if (a.x == 0.0f && b.x == 0.0f) {
        return KG_TILE_SIDE_LEFT;
    }
    return -1;
}

int kg_tile_template_is_solid(const kg_tile_template* t)
{
    return t->proto.shape.count >= 3 && (t->proto.flags & KG_TILE_FLAG_ONE_WAY) == 0u;
}
