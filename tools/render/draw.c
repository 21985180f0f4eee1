#include "draw.h"
#include "palette.h"

#include <math.h>
#include <stdlib.h>

/* Overlay sizes in pixels, the same at every zoom. */
#define KG_NORMAL_LENGTH 12.0f
#define KG_CONTACT_SIZE 2
#define KG_PARTICLE_RADIUS 1.6f
#define KG_DRAW_STACK_SHAPES 64 /* of one body, on the stack */
#define KG_OUTLINE_MIN_SIZE 7.0f /* smaller shapes are filled only: outlines would hide them */

kg_point kg_camera_to_screen(const kg_camera* camera, kg_vec2 world)
{
    return (kg_point){0.5f * (float)camera->width + (world.x - camera->center.x) * camera->scale,
                      0.5f * (float)camera->height - (world.y - camera->center.y) * camera->scale};
}

kg_vec2 kg_camera_to_world(const kg_camera* camera, kg_point screen)
{
    return (kg_vec2){camera->center.x + (screen.x - 0.5f * (float)camera->width) / camera->scale,
                     camera->center.y - (screen.y - 0.5f * (float)camera->height) / camera->scale};
}

kg_camera kg_camera_fit(kg_aabb box, int width, int height, float margin)
{
    float box_width = fmaxf(box.upper.x - box.lower.x, 1e-3f) * (1.0f + 2.0f * margin);
    float box_height = fmaxf(box.upper.y - box.lower.y, 1e-3f) * (1.0f + 2.0f * margin);
    kg_camera camera;
    camera.center = (kg_vec2){0.5f * (box.lower.x + box.upper.x), 0.5f * (box.lower.y + box.upper.y)};
    camera.scale = fminf((float)width / box_width, (float)height / box_height);
    camera.width = width;
    camera.height = height;
    return camera;
}

void kg_camera_zoom_at(kg_camera* camera, kg_point screen, float factor)
{
    kg_vec2 anchor = kg_camera_to_world(camera, screen);
    camera->scale *= factor;
    kg_vec2 moved = kg_camera_to_world(camera, screen);
    camera->center.x += anchor.x - moved.x;
    camera->center.y += anchor.y - moved.y;
}

static kg_aabb kg_aabb_union(kg_aabb a, kg_aabb b)
{
    return (kg_aabb){{fminf(a.lower.x, b.lower.x), fminf(a.lower.y, b.lower.y)},
                     {fmaxf(a.upper.x, b.upper.x), fmaxf(a.upper.y, b.upper.y)}};
}

/* Handles of every live body; NULL (and *count 0) when there are none or no memory. */
static kg_body* kg_live_bodies(const kg_world* world, int* count)
{
    *count = 0;
    int capacity = kg_world_body_count(world);
    kg_body* bodies = capacity > 0 ? malloc((size_t)capacity * sizeof *bodies) : NULL;
    if (bodies && kg_world_get_bodies(world, bodies, capacity, count) != KG_OK) {
        *count = 0;
    }
    return bodies;
}

/* The union of the AABBs of the bodies that move (all but the static ones). */
static int kg_moving_union(const kg_world* world, const kg_body* bodies, int count, kg_aabb* out)
{
    int found = 0;
    for (int i = 0; i < count; ++i) {
        kg_body_type type;
        kg_aabb box;
        if (kg_body_get_type(world, bodies[i], &type) != KG_OK || type == KG_BODY_STATIC ||
            kg_body_get_aabb(world, bodies[i], &box) != KG_OK) {
            continue;
        }
        *out = found ? kg_aabb_union(*out, box) : box;
        found = 1;
    }
    return found;
}

static int kg_tilemap_box(const kg_world* world, kg_tilemap map, kg_aabb* out)
{
    kg_tilemap_def def;
    if (kg_tilemap_get_def(world, map, &def) != KG_OK) {
        return 0;
    }
    kg_vec2 size = {(float)def.width * def.tile_size.x, (float)def.height * def.tile_size.y};
    *out = (kg_aabb){def.origin, {def.origin.x + size.x, def.origin.y + size.y}};
    return 1;
}

/* The boxes of what does not move: static bodies and tile maps. *count of them; NULL
 * when there are none or no memory. */
static kg_aabb* kg_terrain_boxes(const kg_world* world, const kg_body* bodies, int body_count, int* count)
{
    int map_count = kg_world_tilemap_count(world), capacity = body_count + map_count;
    kg_aabb* boxes = capacity > 0 ? malloc((size_t)capacity * sizeof *boxes) : NULL;
    kg_tilemap* maps = map_count > 0 ? malloc((size_t)map_count * sizeof *maps) : NULL;
    *count = 0;
    for (int i = 0; boxes && i < body_count; ++i) {
        kg_body_type type;
        if (kg_body_get_type(world, bodies[i], &type) == KG_OK && type == KG_BODY_STATIC &&
            kg_body_get_aabb(world, bodies[i], &boxes[*count]) == KG_OK) {
            (*count)++;
        }
    }
    if (boxes && maps && kg_world_get_tilemaps(world, maps, map_count, &map_count) == KG_OK) {
        for (int i = 0; i < map_count; ++i) {
            *count += kg_tilemap_box(world, maps[i], &boxes[*count]);
        }
    }
    free(maps);
    return boxes;
}

/* The terrain that reaches into the moving bodies' box, grown a little sideways and by
 * half its height up and down (to find the floor under a pile), clipped to it. */
static kg_aabb kg_add_nearby_terrain(const kg_aabb* terrain, int count, kg_aabb moving)
{
    float grow_x = 0.1f * (moving.upper.x - moving.lower.x), grow_y = 0.5f * (moving.upper.y - moving.lower.y);
    kg_aabb near = {{moving.lower.x - grow_x, moving.lower.y - grow_y}, {moving.upper.x + grow_x, moving.upper.y + grow_y}};
    kg_aabb view = moving;
    for (int i = 0; i < count; ++i) {
        kg_aabb box = terrain[i];
        kg_aabb clipped = {{fmaxf(box.lower.x, near.lower.x), fmaxf(box.lower.y, near.lower.y)},
                           {fminf(box.upper.x, near.upper.x), fminf(box.upper.y, near.upper.y)}};
        if (clipped.lower.x <= clipped.upper.x && clipped.lower.y <= clipped.upper.y) {
            view = kg_aabb_union(view, clipped);
        }
    }
    return view;
}

int kg_world_view_box(const kg_world* world, kg_aabb* out)
{
    int body_count, terrain_count;
    kg_body* bodies = kg_live_bodies(world, &body_count);
    kg_aabb* terrain = kg_terrain_boxes(world, bodies, body_count, &terrain_count);
    kg_aabb moving = {{0.0f, 0.0f}, {0.0f, 0.0f}}; /* set when found; zeroed for the compiler */
    int found = kg_moving_union(world, bodies, body_count, &moving);
    if (found) {
        *out = kg_add_nearby_terrain(terrain, terrain_count, moving);
    } else if (terrain_count > 0) {
        *out = terrain[0];
        for (int i = 1; i < terrain_count; ++i) {
            *out = kg_aabb_union(*out, terrain[i]);
        }
        found = 1;
    }
    free(terrain);
    free(bodies);
    return found;
}

void kg_body_colors(kg_body_type type, kg_body body, uint8_t* fill, uint8_t* line)
{
    switch (type) {
    case KG_BODY_STATIC:
        *fill = KG_COLOR_STATIC_FILL;
        *line = KG_COLOR_STATIC_LINE;
        break;
    case KG_BODY_KINEMATIC:
        *fill = KG_COLOR_KINEMATIC_FILL;
        *line = KG_COLOR_KINEMATIC_LINE;
        break;
    case KG_BODY_PARTICLE:
        *fill = KG_COLOR_PARTICLE;
        *line = KG_COLOR_PARTICLE;
        break;
    default:
        *fill = kg_hue_fill(body.index);
        *line = kg_hue_line(body.index);
        break;
    }
}

static kg_vec2 kg_transform(const kg_body_state* state, kg_vec2 local)
{
    float c = cosf(state->angle), s = sinf(state->angle);
    return (kg_vec2){state->position.x + c * local.x - s * local.y, state->position.y + s * local.x + c * local.y};
}

static void kg_draw_polygon(kg_canvas* canvas, const kg_camera* camera, const kg_shape_def* shape,
                            const kg_body_state* state, uint8_t fill, uint8_t line)
{
    kg_point points[KG_MAX_POLYGON_VERTICES];
    float left = INFINITY, right = -INFINITY;
    for (int i = 0; i < shape->count; ++i) {
        points[i] = kg_camera_to_screen(camera, kg_transform(state, shape->vertices[i]));
        left = fminf(left, points[i].x);
        right = fmaxf(right, points[i].x);
    }
    kg_canvas_fill_convex(canvas, points, shape->count, fill);
    if (right - left >= KG_OUTLINE_MIN_SIZE) {
        kg_canvas_outline(canvas, points, shape->count, line);
    }
}

/* A circle shows its rotation by a radius drawn to its body's local +x. */
static void kg_draw_circle(kg_canvas* canvas, const kg_camera* camera, const kg_shape_def* shape,
                           const kg_body_state* state, kg_body_type type, uint8_t fill, uint8_t line)
{
    kg_vec2 center = kg_transform(state, shape->center);
    kg_point middle = kg_camera_to_screen(camera, center);
    float radius = shape->radius * camera->scale;
    if (type == KG_BODY_PARTICLE) {
        radius = fmaxf(radius, 1.0f); /* a particle stays visible however far out we zoom */
    }
    kg_canvas_fill_circle(canvas, middle, radius, fill);
    if (type == KG_BODY_PARTICLE || 2.0f * radius < KG_OUTLINE_MIN_SIZE) {
        return;
    }
    kg_canvas_circle(canvas, middle, radius, line);
    kg_vec2 rim = {center.x + shape->radius * cosf(state->angle), center.y + shape->radius * sinf(state->angle)};
    kg_canvas_line(canvas, middle, kg_camera_to_screen(camera, rim), line);
}

/* A capsule drawn as the convex polygon of its outline: each end a half circle of
 * KG_CAPSULE_ARC points, the core's line through the middle showing how it turns. */
#define KG_CAPSULE_ARC 9

static void kg_draw_capsule(kg_canvas* canvas, const kg_camera* camera, const kg_shape_def* shape,
                            const kg_body_state* state, uint8_t fill, uint8_t line)
{
    kg_vec2 c1 = shape->vertices[0], c2 = shape->vertices[1];
    float base = atan2f(c2.y - c1.y, c2.x - c1.x) - 0.5f * 3.14159265f;
    kg_point points[2 * KG_CAPSULE_ARC];
    for (int end = 0; end < 2; ++end) {
        kg_vec2 c = end ? c2 : c1;
        for (int i = 0; i < KG_CAPSULE_ARC; ++i) {
            float a = base + 3.14159265f * ((float)end + (float)i / (float)(KG_CAPSULE_ARC - 1));
            kg_vec2 rim = {c.x - shape->radius * cosf(a), c.y - shape->radius * sinf(a)};
            points[end * KG_CAPSULE_ARC + i] = kg_camera_to_screen(camera, kg_transform(state, rim));
        }
    }
    kg_canvas_fill_convex(canvas, points, 2 * KG_CAPSULE_ARC, fill);
    if (2.0f * shape->radius * camera->scale >= KG_OUTLINE_MIN_SIZE) {
        kg_canvas_outline(canvas, points, 2 * KG_CAPSULE_ARC, line);
        kg_canvas_line(canvas, kg_camera_to_screen(camera, kg_transform(state, c1)),
                       kg_camera_to_screen(camera, kg_transform(state, c2)), line);
    }
}

/* A segment has no area: its line alone, in the outline's colour. */
static void kg_draw_segment(kg_canvas* canvas, const kg_camera* camera, const kg_shape_def* shape,
                            const kg_body_state* state, uint8_t line)
{
    kg_canvas_line(canvas, kg_camera_to_screen(camera, kg_transform(state, shape->vertices[0])),
                   kg_camera_to_screen(camera, kg_transform(state, shape->vertices[1])), line);
}

static void kg_draw_shape(kg_canvas* canvas, const kg_camera* camera, const kg_shape_def* shape,
                          const kg_body_state* state, kg_body_type type, kg_body body)
{
    uint8_t fill, line;
    kg_body_colors(type, body, &fill, &line);
    if (shape->type == KG_SHAPE_POLYGON) {
        kg_draw_polygon(canvas, camera, shape, state, fill, line);
    } else if (shape->type == KG_SHAPE_CIRCLE) {
        kg_draw_circle(canvas, camera, shape, state, type, fill, line);
    } else if (shape->type == KG_SHAPE_CAPSULE) {
        kg_draw_capsule(canvas, camera, shape, state, fill, line);
    } else if (shape->type == KG_SHAPE_SEGMENT) {
        kg_draw_segment(canvas, camera, shape, state, line);
    } else {
        kg_canvas_fill_circle(canvas, kg_camera_to_screen(camera, state->position), KG_PARTICLE_RADIUS, fill);
    }
}

/* Every shape of a body (a compound body has several, a chain one a segment), in the
 * body's colours. Most bodies' shapes fit the stack; a long chain's are allocated. */
static void kg_draw_body_shapes(kg_canvas* canvas, const kg_camera* camera, const kg_world* world, kg_body body,
                                const kg_body_state* state, kg_body_type type)
{
    kg_shape_id on_stack[KG_DRAW_STACK_SHAPES];
    int count = kg_body_shape_count(world, body);
    kg_shape_id* shapes = count <= KG_DRAW_STACK_SHAPES ? on_stack : malloc((size_t)count * sizeof *shapes);
    if (shapes && kg_body_get_shapes(world, body, shapes, count, &count) == KG_OK) {
        for (int k = 0; k < count; ++k) {
            kg_body_shape_def def;
            if (kg_shape_get_def(world, shapes[k], &def) == KG_OK) {
                kg_draw_shape(canvas, camera, &def.geometry, state, type, body);
            }
        }
    }
    if (shapes != on_stack) {
        free(shapes);
    }
}

void kg_draw_body(kg_canvas* canvas, const kg_camera* camera, const kg_world* world, kg_body body)
{
    kg_body_state state;
    kg_body_type type;
    if (kg_body_get_state(world, body, &state) == KG_OK && kg_body_get_type(world, body, &type) == KG_OK) {
        kg_draw_body_shapes(canvas, camera, world, body, &state, type);
    }
}

/* Lines every 10^k metres, k picked so that they are at least 24 pixels apart. Lines
 * are counted with integers: far from the origin a float sum would stop advancing. */
static void kg_draw_grid(kg_canvas* canvas, const kg_camera* camera)
{
    float spacing = powf(10.0f, ceilf(log10f(24.0f / camera->scale)));
    kg_vec2 low = kg_camera_to_world(camera, (kg_point){0.0f, (float)canvas->height});
    kg_vec2 high = kg_camera_to_world(camera, (kg_point){(float)canvas->width, 0.0f});
    double first_x = ceil((double)low.x / spacing), first_y = ceil((double)low.y / spacing);
    int columns = canvas->width / 24 + 2, rows = canvas->height / 24 + 2;
    for (int i = 0; i < columns && (first_x + i) * spacing <= high.x; ++i) {
        float sx = kg_camera_to_screen(camera, (kg_vec2){(float)((first_x + i) * spacing), 0.0f}).x;
        kg_canvas_line(canvas, (kg_point){sx, 0.0f}, (kg_point){sx, (float)canvas->height - 1.0f}, KG_COLOR_GRID);
    }
    for (int i = 0; i < rows && (first_y + i) * spacing <= high.y; ++i) {
        float sy = kg_camera_to_screen(camera, (kg_vec2){0.0f, (float)((first_y + i) * spacing)}).y;
        kg_canvas_line(canvas, (kg_point){0.0f, sy}, (kg_point){(float)canvas->width - 1.0f, sy}, KG_COLOR_GRID);
    }
}

static void kg_draw_contacts(kg_canvas* canvas, const kg_camera* camera, const kg_world* world)
{
    int count = kg_world_contact_count(world);
    for (int i = 0; i < count; ++i) {
        kg_contact_info contact;
        if (kg_world_get_contact(world, i, &contact) != KG_OK) {
            continue;
        }
        for (int p = 0; p < contact.point_count && p < 2; ++p) {
            kg_point at = kg_camera_to_screen(camera, contact.points[p]);
            kg_point tip = {at.x + KG_NORMAL_LENGTH * contact.normal.x, at.y - KG_NORMAL_LENGTH * contact.normal.y};
            kg_canvas_line(canvas, at, tip, KG_COLOR_NORMAL);
            kg_canvas_fill_rect(canvas, (int)floorf(at.x) - KG_CONTACT_SIZE / 2, (int)floorf(at.y) - KG_CONTACT_SIZE / 2,
                                KG_CONTACT_SIZE + 1, KG_CONTACT_SIZE + 1, KG_COLOR_CONTACT);
        }
    }
}

static void kg_draw_aabbs(kg_canvas* canvas, const kg_camera* camera, const kg_world* world, const kg_body* bodies,
                          int count)
{
    for (int i = 0; i < count; ++i) {
        kg_aabb box;
        if (kg_body_get_aabb(world, bodies[i], &box) == KG_OK) {
            kg_canvas_rect(canvas, kg_camera_to_screen(camera, box.lower), kg_camera_to_screen(camera, box.upper),
                           KG_COLOR_AABB);
        }
    }
}

/* All states in one call: the OpenCL backend then copies the pools back only once. */
static void kg_draw_bodies(kg_canvas* canvas, const kg_camera* camera, const kg_world* world, const kg_body* bodies,
                           int count)
{
    kg_body_state* states = count > 0 ? malloc((size_t)count * sizeof *states) : NULL;
    if (!states || kg_world_get_body_states(world, bodies, count, states) != KG_OK) {
        free(states);
        return;
    }
    for (int i = 0; i < count; ++i) {
        kg_body_type type;
        if (kg_body_get_type(world, bodies[i], &type) == KG_OK) {
            kg_draw_body_shapes(canvas, camera, world, bodies[i], &states[i], type);
        }
    }
    free(states);
}

void kg_draw_world(kg_canvas* canvas, const kg_camera* camera, const kg_world* world, const kg_draw_options* options)
{
    kg_canvas_clear(canvas, KG_COLOR_BACKGROUND);
    if (options->grid) {
        kg_draw_grid(canvas, camera);
    }
    for (int i = 0; options->tiles && i < options->tile_layer_count; ++i) {
        kg_draw_tile_layer(canvas, camera, &options->tile_layers[i]);
    }
    int count;
    kg_body* bodies = kg_live_bodies(world, &count);
    kg_draw_bodies(canvas, camera, world, bodies, count);
    if (options->aabbs) {
        kg_draw_aabbs(canvas, camera, world, bodies, count);
    }
    if (options->contacts) {
        kg_draw_contacts(canvas, camera, world);
    }
    free(bodies);
}

/* ---- tiles ---- */

static int kg_tile_id(const kg_tile_layer* layer, int x, int y)
{
    if (x < 0 || y < 0 || x >= layer->width || y >= layer->height) {
        return -1;
    }
    int id = layer->cells[(size_t)y * (size_t)layer->width + (size_t)x];
    return id >= 0 && id < layer->look_count && layer->looks[id].count >= 3 ? id : -1;
}

/* The side of the unit cell that segment a-b lies on (0 left, 1 right, 2 bottom, 3 top)
 * and the part of that side it covers; -1 when it lies inside the cell. */
static int kg_cell_side(kg_vec2 a, kg_vec2 b, float* low, float* high)
{
    const float eps = 1e-4f;
    int side = -1;
    if (fabsf(a.x - b.x) < eps && (fabsf(a.x) < eps || fabsf(a.x - 1.0f) < eps)) {
        side = fabsf(a.x) < eps ? 0 : 1;
        *low = fminf(a.y, b.y);
        *high = fmaxf(a.y, b.y);
    } else if (fabsf(a.y - b.y) < eps && (fabsf(a.y) < eps || fabsf(a.y - 1.0f) < eps)) {
        side = fabsf(a.y) < eps ? 2 : 3;
        *low = fminf(a.x, b.x);
        *high = fmaxf(a.x, b.x);
    }
    return side;
}

/* Whether the tile at (x, y) has an edge on side that covers [low, high] of it. */
static int kg_tile_covers(const kg_tile_layer* layer, int x, int y, int side, float low, float high, int one_way)
{
    const float eps = 1e-4f;
    int id = kg_tile_id(layer, x, y);
    if (id < 0 || layer->looks[id].one_way != one_way) {
        return 0;
    }
    const kg_tile_look* look = &layer->looks[id];
    for (int i = 0; i < look->count; ++i) {
        float other_low = 0.0f, other_high = 0.0f;
        if (kg_cell_side(look->vertices[i], look->vertices[(i + 1) % look->count], &other_low, &other_high) == side &&
            other_low <= low + eps && other_high >= high - eps) {
            return 1;
        }
    }
    return 0;
}

/* An edge on the cell's border is hidden where the neighbour across it has an edge of
 * the same kind (solid or one-way) covering it: the two tiles then read as one piece of
 * terrain, as they collide. */
static int kg_edge_hidden(const kg_tile_layer* layer, int x, int y, int one_way, kg_vec2 a, kg_vec2 b)
{
    static const int kDx[4] = {-1, 1, 0, 0}, kDy[4] = {0, 0, -1, 1}, kOpposite[4] = {1, 0, 3, 2};
    float low = 0.0f, high = 0.0f;
    int side = kg_cell_side(a, b, &low, &high);
    return side >= 0 && kg_tile_covers(layer, x + kDx[side], y + kDy[side], kOpposite[side], low, high, one_way);
}

static kg_point kg_tile_point(const kg_camera* camera, const kg_tile_layer* layer, int x, int y, kg_vec2 unit)
{
    kg_vec2 world = {layer->origin.x + ((float)x + unit.x) * layer->tile_size.x,
                     layer->origin.y + ((float)y + unit.y) * layer->tile_size.y};
    return kg_camera_to_screen(camera, world);
}

static void kg_draw_tile(kg_canvas* canvas, const kg_camera* camera, const kg_tile_layer* layer, int x, int y,
                         const kg_tile_look* look)
{
    kg_point points[KG_MAX_POLYGON_VERTICES];
    for (int i = 0; i < look->count; ++i) {
        points[i] = kg_tile_point(camera, layer, x, y, look->vertices[i]);
    }
    kg_canvas_fill_convex(canvas, points, look->count, look->one_way ? KG_COLOR_ONE_WAY_FILL : KG_COLOR_TILE_FILL);
    uint8_t line = look->one_way ? KG_COLOR_ONE_WAY_LINE : KG_COLOR_TILE_LINE;
    for (int i = 0; i < look->count; ++i) {
        int next = (i + 1) % look->count;
        if (!kg_edge_hidden(layer, x, y, look->one_way, look->vertices[i], look->vertices[next])) {
            kg_canvas_line(canvas, points[i], points[next], line);
        }
    }
}

static int kg_clamp_int(int v, int low, int high) { return v < low ? low : (v > high ? high : v); }

int kg_tile_layer_visible(const kg_camera* camera, const kg_tile_layer* layer, kg_cell_range* out)
{
    if (!layer->cells || layer->tile_size.x <= 0.0f || layer->tile_size.y <= 0.0f) {
        return 0;
    }
    kg_vec2 low = kg_camera_to_world(camera, (kg_point){0.0f, (float)camera->height});
    kg_vec2 high = kg_camera_to_world(camera, (kg_point){(float)camera->width, 0.0f});
    float x0 = floorf((low.x - layer->origin.x) / layer->tile_size.x);
    float x1 = floorf((high.x - layer->origin.x) / layer->tile_size.x);
    float y0 = floorf((low.y - layer->origin.y) / layer->tile_size.y);
    float y1 = floorf((high.y - layer->origin.y) / layer->tile_size.y);
    if (x1 < 0.0f || y1 < 0.0f || x0 >= (float)layer->width || y0 >= (float)layer->height) {
        return 0;
    }
    /* clamped as floats first: far off the map the cell numbers overflow an int */
    out->x0 = kg_clamp_int((int)fmaxf(x0, -1.0f), 0, layer->width - 1);
    out->x1 = kg_clamp_int((int)fminf(x1, (float)layer->width), 0, layer->width - 1);
    out->y0 = kg_clamp_int((int)fmaxf(y0, -1.0f), 0, layer->height - 1);
    out->y1 = kg_clamp_int((int)fminf(y1, (float)layer->height), 0, layer->height - 1);
    return 1;
}

/* Only the cells on screen are visited, so a huge map costs what its visible part does. */
void kg_draw_tile_layer(kg_canvas* canvas, const kg_camera* camera, const kg_tile_layer* layer)
{
    kg_cell_range range;
    if (!kg_tile_layer_visible(camera, layer, &range)) {
        return;
    }
    for (int y = range.y0; y <= range.y1; ++y) {
        for (int x = range.x0; x <= range.x1; ++x) {
            int id = kg_tile_id(layer, x, y);
            if (id >= 0) {
                kg_draw_tile(canvas, camera, layer, x, y, &layer->looks[id]);
            }
        }
    }
}
