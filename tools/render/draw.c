#include "draw.h"
#include "palette.h"

#include <math.h>
#include <stdlib.h>

/* Overlay sizes in pixels, the same at every zoom. */
#define KG_NORMAL_LENGTH 12.0f
#define KG_CONTACT_SIZE 2
#define KG_PARTICLE_RADIUS 1.6f
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

/* The union of the AABBs of the bodies that are (moving != 0) or are not moving. */
static int kg_union_of(const kg_world* world, const kg_body* bodies, int count, int moving, kg_aabb* out)
{
    int found = 0;
    for (int i = 0; i < count; ++i) {
        kg_body_type type;
        kg_aabb box;
        if (kg_body_get_type(world, bodies[i], &type) != KG_OK || kg_body_get_aabb(world, bodies[i], &box) != KG_OK ||
            (type != KG_BODY_STATIC) != moving) {
            continue;
        }
        *out = found ? kg_aabb_union(*out, box) : box;
        found = 1;
    }
    return found;
}

/* The static bodies that reach into the moving bodies' box, grown a little sideways and
 * by half its height up and down (to find the floor under a pile), clipped to it. */
static kg_aabb kg_add_nearby_statics(const kg_world* world, const kg_body* bodies, int count, kg_aabb moving)
{
    float grow_x = 0.1f * (moving.upper.x - moving.lower.x), grow_y = 0.5f * (moving.upper.y - moving.lower.y);
    kg_aabb near = {{moving.lower.x - grow_x, moving.lower.y - grow_y}, {moving.upper.x + grow_x, moving.upper.y + grow_y}};
    kg_aabb view = moving;
    for (int i = 0; i < count; ++i) {
        kg_body_type type;
        kg_aabb box;
        if (kg_body_get_type(world, bodies[i], &type) != KG_OK || type != KG_BODY_STATIC ||
            kg_body_get_aabb(world, bodies[i], &box) != KG_OK) {
            continue;
        }
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
    int count;
    kg_body* bodies = kg_live_bodies(world, &count);
    kg_aabb moving;
    int found = 1;
    if (kg_union_of(world, bodies, count, 1, &moving)) {
        *out = kg_add_nearby_statics(world, bodies, count, moving);
    } else {
        found = kg_union_of(world, bodies, count, 0, out);
    }
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

static void kg_draw_shape(kg_canvas* canvas, const kg_camera* camera, const kg_shape_def* shape,
                          const kg_body_state* state, kg_body_type type, kg_body body)
{
    uint8_t fill, line;
    kg_body_colors(type, body, &fill, &line);
    if (shape->type == KG_SHAPE_POLYGON) {
        kg_draw_polygon(canvas, camera, shape, state, fill, line);
    } else if (shape->type == KG_SHAPE_CIRCLE) {
        kg_draw_circle(canvas, camera, shape, state, type, fill, line);
    } else {
        kg_canvas_fill_circle(canvas, kg_camera_to_screen(camera, state->position), KG_PARTICLE_RADIUS, fill);
    }
}

void kg_draw_body(kg_canvas* canvas, const kg_camera* camera, const kg_world* world, kg_body body)
{
    kg_body_state state;
    kg_body_type type;
    kg_shape_def shape;
    if (kg_body_get_state(world, body, &state) == KG_OK && kg_body_get_type(world, body, &type) == KG_OK &&
        kg_body_get_shape(world, body, &shape) == KG_OK) {
        kg_draw_shape(canvas, camera, &shape, &state, type, body);
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
        kg_shape_def shape;
        if (kg_body_get_type(world, bodies[i], &type) == KG_OK && kg_body_get_shape(world, bodies[i], &shape) == KG_OK) {
            kg_draw_shape(canvas, camera, &shape, &states[i], type, bodies[i]);
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

/* A full square tile hides the edge its neighbour shares with it. */
static int kg_tile_is_full(const kg_tile_layer* layer, int x, int y)
{
    int id = kg_tile_id(layer, x, y);
    if (id < 0 || layer->looks[id].one_way) {
        return 0;
    }
    const kg_tile_look* look = &layer->looks[id];
    float area = 0.0f;
    for (int i = 0; i < look->count; ++i) {
        kg_vec2 a = look->vertices[i], b = look->vertices[(i + 1) % look->count];
        area += a.x * b.y - b.x * a.y;
    }
    return fabsf(0.5f * fabsf(area) - 1.0f) < 1e-4f;
}

/* Whether a tile edge lies on its cell's border next to a full tile, which hides it. */
static int kg_edge_hidden(const kg_tile_layer* layer, int x, int y, kg_vec2 a, kg_vec2 b)
{
    const float eps = 1e-4f;
    if (fabsf(a.x) < eps && fabsf(b.x) < eps) {
        return kg_tile_is_full(layer, x - 1, y);
    }
    if (fabsf(a.x - 1.0f) < eps && fabsf(b.x - 1.0f) < eps) {
        return kg_tile_is_full(layer, x + 1, y);
    }
    if (fabsf(a.y) < eps && fabsf(b.y) < eps) {
        return kg_tile_is_full(layer, x, y - 1);
    }
    if (fabsf(a.y - 1.0f) < eps && fabsf(b.y - 1.0f) < eps) {
        return kg_tile_is_full(layer, x, y + 1);
    }
    return 0;
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
        if (!kg_edge_hidden(layer, x, y, look->vertices[i], look->vertices[next])) {
            kg_canvas_line(canvas, points[i], points[next], line);
        }
    }
}

static int kg_clamp_int(int v, int low, int high) { return v < low ? low : (v > high ? high : v); }

/* Only the cells on screen are visited, so a huge map costs what its visible part does. */
void kg_draw_tile_layer(kg_canvas* canvas, const kg_camera* camera, const kg_tile_layer* layer)
{
    if (!layer->cells || layer->tile_size.x <= 0.0f || layer->tile_size.y <= 0.0f) {
        return;
    }
    kg_vec2 low = kg_camera_to_world(camera, (kg_point){0.0f, (float)canvas->height});
    kg_vec2 high = kg_camera_to_world(camera, (kg_point){(float)canvas->width, 0.0f});
    float x0 = floorf((low.x - layer->origin.x) / layer->tile_size.x);
    float x1 = floorf((high.x - layer->origin.x) / layer->tile_size.x);
    float y0 = floorf((low.y - layer->origin.y) / layer->tile_size.y);
    float y1 = floorf((high.y - layer->origin.y) / layer->tile_size.y);
    int first_x = kg_clamp_int((int)fmaxf(x0, -1.0f), 0, layer->width - 1);
    int last_x = kg_clamp_int((int)fminf(x1, (float)layer->width), 0, layer->width - 1);
    int first_y = kg_clamp_int((int)fmaxf(y0, -1.0f), 0, layer->height - 1);
    int last_y = kg_clamp_int((int)fminf(y1, (float)layer->height), 0, layer->height - 1);
    if (x1 < 0.0f || y1 < 0.0f || x0 >= (float)layer->width || y0 >= (float)layer->height) {
        return;
    }
    for (int y = first_y; y <= last_y; ++y) {
        for (int x = first_x; x <= last_x; ++x) {
            int id = kg_tile_id(layer, x, y);
            if (id >= 0) {
                kg_draw_tile(canvas, camera, layer, x, y, &layer->looks[id]);
            }
        }
    }
}
