#include "draw.h"
#include "palette.h"

#include <math.h>
#include <stdlib.h>

/* Sizes in pixels, the same at every zoom. */
#define KG_NORMAL_LENGTH 12.0f
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

/* Grows *view (empty while *found is 0) to hold box. */
static void kg_view_add(kg_aabb* view, int* found, kg_aabb box)
{
    *view = *found ? kg_aabb_union(*view, box) : box;
    *found = 1;
}

/* The union of every body's box, static ones included. */
static int kg_bodies_box(const kg_world* world, kg_aabb* view)
{
    int count, found = 0;
    kg_body* bodies = kg_live_bodies(world, &count);
    for (int i = 0; i < count; ++i) {
        kg_aabb box;
        if (kg_body_get_aabb(world, bodies[i], &box) == KG_OK) {
            kg_view_add(view, &found, box);
        }
    }
    free(bodies);
    return found;
}

int kg_world_view_box(const kg_world* world, kg_aabb* out)
{
    int found = kg_bodies_box(world, out);
    int map_count = kg_world_tilemap_count(world);
    kg_tilemap* maps = map_count > 0 ? malloc((size_t)map_count * sizeof *maps) : NULL;
    if (maps && kg_world_get_tilemaps(world, maps, map_count, &map_count) == KG_OK) {
        for (int i = 0; i < map_count; ++i) {
            kg_aabb box;
            if (kg_tilemap_box(world, maps[i], &box)) {
                kg_view_add(out, &found, box);
            }
        }
    }
    free(maps);
    return found;
}

/* ---- the world through kg_world_draw: its callbacks rasterise into the canvas ---- */

typedef struct kg_raster {
    kg_canvas* canvas;
    const kg_camera* camera;
    const kg_world* world;
} kg_raster;

typedef struct kg_palette_pair {
    kg_color color;
    uint8_t fill, line;
} kg_palette_pair;

/* The library's colours in the renderer's palette. Dynamic bodies come as their hue's
 * outline colour (kg_raster_body_color) and are looked up among the hues. */
static const kg_palette_pair kPairs[] = {
    {KG_DEBUG_COLOR_STATIC, KG_COLOR_STATIC_FILL, KG_COLOR_STATIC_LINE},
    {KG_DEBUG_COLOR_KINEMATIC, KG_COLOR_KINEMATIC_FILL, KG_COLOR_KINEMATIC_LINE},
    {KG_DEBUG_COLOR_PARTICLE, KG_COLOR_PARTICLE, KG_COLOR_PARTICLE},
    {KG_DEBUG_COLOR_SENSOR, KG_COLOR_SENSOR, KG_COLOR_SENSOR},
    {KG_DEBUG_COLOR_TILE, KG_COLOR_TILE_FILL, KG_COLOR_TILE_LINE},
    {KG_DEBUG_COLOR_TILE_EDGE, KG_COLOR_TILE_LINE, KG_COLOR_TILE_LINE},
    {KG_DEBUG_COLOR_ONE_WAY, KG_COLOR_ONE_WAY_FILL, KG_COLOR_ONE_WAY_LINE},
    {KG_DEBUG_COLOR_ONE_WAY_EDGE, KG_COLOR_ONE_WAY_LINE, KG_COLOR_ONE_WAY_LINE},
    {KG_DEBUG_COLOR_AABB, KG_COLOR_AABB, KG_COLOR_AABB},
    {KG_DEBUG_COLOR_CONTACT_POINT, KG_COLOR_CONTACT, KG_COLOR_CONTACT},
    {KG_DEBUG_COLOR_CONTACT_NORMAL, KG_COLOR_NORMAL, KG_COLOR_NORMAL},
};

static kg_color kg_rgb_color(kg_rgb rgb) { return ((kg_color)rgb.r << 16) | ((kg_color)rgb.g << 8) | rgb.b; }

static kg_palette_pair kg_pair_of(kg_color color)
{
    for (size_t i = 0; i < sizeof kPairs / sizeof kPairs[0]; ++i) {
        if (kPairs[i].color == color) {
            return kPairs[i];
        }
    }
    for (uint8_t line = KG_COLOR_HUE_FIRST + 1; line < KG_COLOR_HUE_FIRST + 2 * KG_HUE_COUNT; line += 2) {
        if (kg_rgb_color(kg_palette_color(line)) == color) {
            return (kg_palette_pair){color, (uint8_t)(line - 1), line};
        }
    }
    return (kg_palette_pair){color, KG_COLOR_TEXT, KG_COLOR_TEXT}; /* a state this palette has no entry for */
}

/* Bodies keep the renderer's colours by type (not by sleep), a dynamic body its own hue
 * by handle index, so neighbours in a pile stand apart. */
static kg_color kg_raster_body_color(kg_body body, kg_color state_color, void* context)
{
    const kg_raster* r = context;
    kg_body_type type;
    if (kg_body_get_type(r->world, body, &type) != KG_OK) {
        return state_color;
    }
    switch (type) {
    case KG_BODY_STATIC: return KG_DEBUG_COLOR_STATIC;
    case KG_BODY_KINEMATIC: return KG_DEBUG_COLOR_KINEMATIC;
    case KG_BODY_PARTICLE: return KG_DEBUG_COLOR_PARTICLE;
    default: return kg_rgb_color(kg_palette_color(kg_hue_line(body.index)));
    }
}

static int kg_is_tile_color(kg_color color)
{
    return color == KG_DEBUG_COLOR_TILE || color == KG_DEBUG_COLOR_ONE_WAY;
}

static kg_point kg_raster_point(const kg_raster* r, kg_transform xf, kg_vec2 local)
{
    kg_vec2 world = {xf.position.x + xf.c * local.x - xf.s * local.y, xf.position.y + xf.s * local.x + xf.c * local.y};
    return kg_camera_to_screen(r->camera, world);
}

static void kg_raster_polygon(const kg_vec2* vertices, int count, kg_color color, void* context)
{
    const kg_raster* r = context;
    kg_point points[KG_MAX_POLYGON_VERTICES];
    for (int i = 0; i < count && i < KG_MAX_POLYGON_VERTICES; ++i) {
        points[i] = kg_camera_to_screen(r->camera, vertices[i]);
    }
    kg_canvas_outline(r->canvas, points, count < KG_MAX_POLYGON_VERTICES ? count : KG_MAX_POLYGON_VERTICES,
                      kg_pair_of(color).line);
}

/* A tile is filled only: the library outlines the edges that collide as segments, so two
 * tiles side by side read as one piece of terrain. */
static void kg_raster_solid_polygon(kg_transform xf, const kg_vec2* vertices, int count, float radius, kg_color color,
                                    void* context)
{
    const kg_raster* r = context;
    kg_palette_pair pair = kg_pair_of(color);
    kg_point points[KG_MAX_POLYGON_VERTICES];
    float left = INFINITY, right = -INFINITY;
    count = count < KG_MAX_POLYGON_VERTICES ? count : KG_MAX_POLYGON_VERTICES;
    (void)radius; /* polygons of users and tiles are sharp */
    for (int i = 0; i < count; ++i) {
        points[i] = kg_raster_point(r, xf, vertices[i]);
        left = fminf(left, points[i].x);
        right = fmaxf(right, points[i].x);
    }
    kg_canvas_fill_convex(r->canvas, points, count, pair.fill);
    if (!kg_is_tile_color(color) && right - left >= KG_OUTLINE_MIN_SIZE) {
        kg_canvas_outline(r->canvas, points, count, pair.line);
    }
}

static void kg_raster_circle(kg_vec2 center, float radius, kg_color color, void* context)
{
    const kg_raster* r = context;
    kg_canvas_circle(r->canvas, kg_camera_to_screen(r->camera, center), radius * r->camera->scale,
                     kg_pair_of(color).line);
}

/* A body's circle shows its rotation by a radius drawn to its body's local +x (a tile's
 * never turns); a particle stays a dot however far out we zoom. */
static void kg_raster_solid_circle(kg_transform xf, float radius, kg_color color, void* context)
{
    const kg_raster* r = context;
    kg_palette_pair pair = kg_pair_of(color);
    kg_point middle = kg_camera_to_screen(r->camera, xf.position);
    float pixels = radius * r->camera->scale;
    int particle = color == KG_DEBUG_COLOR_PARTICLE;
    kg_canvas_fill_circle(r->canvas, middle, particle ? fmaxf(pixels, 1.0f) : pixels, pair.fill);
    if (particle || 2.0f * pixels < KG_OUTLINE_MIN_SIZE) {
        return;
    }
    kg_canvas_circle(r->canvas, middle, pixels, pair.line);
    if (!kg_is_tile_color(color)) {
        kg_canvas_line(r->canvas, middle, kg_raster_point(r, xf, (kg_vec2){radius, 0.0f}), pair.line);
    }
}

/* A capsule drawn as the convex polygon of its outline: each end a half circle of
 * KG_CAPSULE_ARC points, the core's line through the middle showing how it turns. */
#define KG_CAPSULE_ARC 9

static void kg_raster_capsule(kg_vec2 p1, kg_vec2 p2, float radius, kg_color color, void* context)
{
    const kg_raster* r = context;
    kg_palette_pair pair = kg_pair_of(color);
    float base = atan2f(p2.y - p1.y, p2.x - p1.x) - 0.5f * 3.14159265f;
    kg_point points[2 * KG_CAPSULE_ARC];
    for (int end = 0; end < 2; ++end) {
        kg_vec2 c = end ? p2 : p1;
        for (int i = 0; i < KG_CAPSULE_ARC; ++i) {
            float a = base + 3.14159265f * ((float)end + (float)i / (float)(KG_CAPSULE_ARC - 1));
            kg_vec2 rim = {c.x - radius * cosf(a), c.y - radius * sinf(a)};
            points[end * KG_CAPSULE_ARC + i] = kg_camera_to_screen(r->camera, rim);
        }
    }
    kg_canvas_fill_convex(r->canvas, points, 2 * KG_CAPSULE_ARC, pair.fill);
    if (2.0f * radius * r->camera->scale >= KG_OUTLINE_MIN_SIZE) {
        kg_canvas_outline(r->canvas, points, 2 * KG_CAPSULE_ARC, pair.line);
        kg_canvas_line(r->canvas, kg_camera_to_screen(r->camera, p1), kg_camera_to_screen(r->camera, p2), pair.line);
    }
}

/* A segment has no area: its line alone, in the outline's colour. */
static void kg_raster_segment(kg_vec2 p1, kg_vec2 p2, kg_color color, void* context)
{
    const kg_raster* r = context;
    kg_canvas_line(r->canvas, kg_camera_to_screen(r->camera, p1), kg_camera_to_screen(r->camera, p2),
                   kg_pair_of(color).line);
}

/* Particles are round dots, contact points square ones. */
static void kg_raster_point_mark(kg_vec2 point, float size, kg_color color, void* context)
{
    const kg_raster* r = context;
    kg_point at = kg_camera_to_screen(r->camera, point);
    if (color == KG_DEBUG_COLOR_PARTICLE) {
        kg_canvas_fill_circle(r->canvas, at, 0.5f * size, kg_pair_of(color).fill);
        return;
    }
    int side = (int)size;
    kg_canvas_fill_rect(r->canvas, (int)floorf(at.x) - side / 2, (int)floorf(at.y) - side / 2, side, side,
                        kg_pair_of(color).fill);
}

/* What the camera shows, in world metres: kg_world_draw culls everything else. */
static kg_aabb kg_camera_view(const kg_camera* camera)
{
    return (kg_aabb){kg_camera_to_world(camera, (kg_point){0.0f, (float)camera->height}),
                     kg_camera_to_world(camera, (kg_point){(float)camera->width, 0.0f})};
}

static kg_debug_draw kg_raster_draw(kg_raster* raster, const kg_draw_options* options)
{
    kg_debug_draw draw = kg_default_debug_draw();
    draw.draw_polygon = kg_raster_polygon;
    draw.draw_solid_polygon = kg_raster_solid_polygon;
    draw.draw_circle = kg_raster_circle;
    draw.draw_solid_circle = kg_raster_solid_circle;
    draw.draw_capsule = kg_raster_capsule;
    draw.draw_segment = kg_raster_segment;
    draw.draw_point = kg_raster_point_mark;
    draw.body_color = kg_raster_body_color;
    draw.flags = KG_DEBUG_DRAW_SHAPES | KG_DEBUG_DRAW_JOINTS | (options->tiles ? KG_DEBUG_DRAW_TILES : 0u) |
                 (options->aabbs ? KG_DEBUG_DRAW_AABBS : 0u) |
                 (options->contacts ? KG_DEBUG_DRAW_CONTACT_POINTS | KG_DEBUG_DRAW_CONTACT_NORMALS : 0u);
    draw.use_bounds = 1;
    draw.bounds = kg_camera_view(raster->camera);
    draw.normal_length = KG_NORMAL_LENGTH / raster->camera->scale;
    draw.context = raster;
    return draw;
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


void kg_draw_world(kg_canvas* canvas, const kg_camera* camera, const kg_world* world, const kg_draw_options* options)
{
    kg_canvas_clear(canvas, KG_COLOR_BACKGROUND);
    if (options->grid) {
        kg_draw_grid(canvas, camera);
    }
    kg_raster raster = {canvas, camera, world};
    kg_debug_draw draw = kg_raster_draw(&raster, options);
    kg_world_draw(world, &draw);
}
