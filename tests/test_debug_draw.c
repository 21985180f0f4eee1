/* Debug draw (kgyro/debug_draw.h): the exact calls kg_world_draw makes for every shape
 * kind, tile maps, sensors, bounds, contacts and overlays, their colours by body state,
 * and its errors. Expected positions are computed here from each body's state as a game
 * reads it (kg_body_get_state), not from the library's transforms. */
#include "kg_test.h"
#include "kg_test_world.h"

#include "debug_draw_recorder.h"

#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define KG_TOLERANCE 1e-6

/* A point of body's frame in the world, from its state as the API gives it. */
static kg_vec2 kg_body_point(const kg_world* world, kg_body body, kg_vec2 local)
{
    kg_body_state s;
    KG_CHECK_OK(kg_body_get_state(world, body, &s));
    kg_transform xf = {s.position, cosf(s.angle), sinf(s.angle)};
    return kg_apply(xf, local);
}

/* ---- expected calls ---- */

static kg_call* kg_expect(kg_recorder* want, kg_call_kind kind, kg_color color)
{
    return kg_record(want, kind, color);
}

static void kg_expect_polygon(kg_recorder* want, kg_call_kind kind, const kg_world* world, kg_body body,
                              const kg_shape_def* shape, kg_color color)
{
    kg_call* c = kg_expect(want, kind, color);
    for (int i = 0; i < shape->count; ++i) {
        c->points[c->count++] = kg_body_point(world, body, shape->vertices[i]);
    }
}

static void kg_expect_circle(kg_recorder* want, kg_call_kind kind, const kg_world* world, kg_body body,
                             kg_vec2 center, float radius, kg_color color)
{
    kg_call* c = kg_expect(want, kind, color);
    c->points[0] = kg_body_point(world, body, center);
    c->count = 1;
    c->radius = radius;
}

static void kg_expect_two(kg_recorder* want, kg_call_kind kind, kg_vec2 p1, kg_vec2 p2, float radius, kg_color color)
{
    kg_call* c = kg_expect(want, kind, color);
    c->points[0] = p1;
    c->points[1] = p2;
    c->count = 2;
    c->radius = radius;
}

static void kg_expect_point(kg_recorder* want, kg_vec2 at, float size, kg_color color)
{
    kg_call* c = kg_expect(want, KG_CALL_POINT, color);
    c->points[0] = at;
    c->count = 1;
    c->radius = size;
}

/* Whether got made exactly want's calls, in order: kinds, colours, counts, and points
 * and radii within tolerance. Prints the first difference. */
static int kg_same_calls(const kg_recorder* got, const kg_recorder* want, double tolerance)
{
    if (got->count != want->count || got->overflow || want->overflow) {
        printf("  %d calls drawn, %d expected\n", got->count, want->count);
        return 0;
    }
    for (int i = 0; i < got->count; ++i) {
        const kg_call *g = &got->calls[i], *w = &want->calls[i];
        int same = g->kind == w->kind && g->color == w->color && g->count == w->count &&
                   fabs((double)g->radius - (double)w->radius) <= tolerance;
        for (int k = 0; same && k < g->count; ++k) {
            same = fabs((double)g->points[k].x - (double)w->points[k].x) <= tolerance &&
                   fabs((double)g->points[k].y - (double)w->points[k].y) <= tolerance;
        }
        if (!same) {
            printf("  call %d: kind %d colour %06x count %d, expected kind %d colour %06x count %d\n", i, (int)g->kind,
                   (unsigned)g->color, g->count, (int)w->kind, (unsigned)w->color, w->count);
            return 0;
        }
    }
    return 1;
}

/* ---- tests ---- */

/* One body of each kind and shape, in slot order: each drawn once, where it is, in the
 * colour of its state. */
static void test_every_shape_kind(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_recorder* want = calloc(2, sizeof *want);
    kg_recorder* got = want + 1;
    kg_shape_def box = kg_offset_box_shape(2.0f, 1.0f, (kg_vec2){0.2f, -0.1f}, 0.25f);
    kg_body b_static = kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.5f, -3.0f}, 0.3f, box);
    kg_shape_def circle = kg_circle_shape(0.5f);
    circle.center = (kg_vec2){0.1f, 0.2f};
    kg_body b_kinematic = kg_test_add(world, KG_BODY_KINEMATIC, (kg_vec2){3.0f, 0.5f}, 0.5f, circle);
    kg_shape_def capsule = kg_capsule_shape((kg_vec2){-0.5f, 0.0f}, (kg_vec2){0.5f, 0.1f}, 0.25f);
    kg_body b_capsule = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){-3.0f, 2.0f}, 0.7f, capsule);
    kg_shape_def segment = kg_segment_shape((kg_vec2){-1.0f, 0.0f}, (kg_vec2){1.0f, 0.5f});
    kg_body b_segment = kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -1.5f}, -0.2f, segment);
    kg_body b_particle = kg_test_add(world, KG_BODY_PARTICLE, (kg_vec2){2.0f, 2.0f}, 0.0f, (kg_shape_def){0});
    kg_body_def bullet_def = kg_default_body_def();
    bullet_def.position = (kg_vec2){-1.0f, 3.0f};
    bullet_def.angle = -0.4f;
    bullet_def.shape = kg_box_shape(0.4f, 0.2f);
    bullet_def.bullet = 1;
    kg_body b_bullet;
    KG_CHECK_OK(kg_create_body(world, &bullet_def, &b_bullet));
    /* a chain on a shapeless static body: one segment each */
    kg_body b_chain = kg_test_add(world, KG_BODY_STATIC, (kg_vec2){-2.0f, -2.0f}, 0.1f, (kg_shape_def){0});
    static const kg_vec2 chain_points[4] = {{0, 0}, {1, 0.2f}, {2, 0}, {3, 0.5f}};
    kg_chain_def chain = kg_default_chain_def();
    chain.points = chain_points;
    chain.count = 4;
    KG_CHECK_OK(kg_create_chain(world, b_chain, &chain, NULL));
    /* a compound body: a box, a circle, and a sensor polygon */
    kg_body b_compound = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){1.0f, 1.0f}, 1.1f, kg_box_shape(0.6f, 0.6f));
    kg_body_shape_def extra = kg_default_body_shape_def();
    extra.geometry = kg_circle_shape(0.3f);
    extra.geometry.center = (kg_vec2){0.6f, 0.0f};
    kg_shape_id added;
    KG_CHECK_OK(kg_create_shape(world, b_compound, &extra, &added));
    kg_body_shape_def sensor = kg_default_body_shape_def();
    sensor.geometry = kg_offset_box_shape(1.0f, 0.5f, (kg_vec2){0.0f, 0.8f}, 0.0f);
    sensor.is_sensor = 1;
    KG_CHECK_OK(kg_create_shape(world, b_compound, &sensor, &added));

    kg_debug_draw draw = kg_recording_draw(got, KG_DEBUG_DRAW_SHAPES);
    KG_CHECK_OK(kg_world_draw(world, &draw));

    kg_shape_def hull;
    KG_CHECK_OK(kg_body_get_shape(world, b_static, &hull)); /* the polygon as the library orders it */
    kg_expect_polygon(want, KG_CALL_SOLID_POLYGON, world, b_static, &hull, KG_DEBUG_COLOR_STATIC);
    kg_expect_circle(want, KG_CALL_SOLID_CIRCLE, world, b_kinematic, circle.center, 0.5f, KG_DEBUG_COLOR_KINEMATIC);
    kg_expect_two(want, KG_CALL_CAPSULE, kg_body_point(world, b_capsule, capsule.vertices[0]),
                  kg_body_point(world, b_capsule, capsule.vertices[1]), 0.25f, KG_DEBUG_COLOR_DYNAMIC);
    kg_expect_two(want, KG_CALL_SEGMENT, kg_body_point(world, b_segment, segment.vertices[0]),
                  kg_body_point(world, b_segment, segment.vertices[1]), 0.0f, KG_DEBUG_COLOR_STATIC);
    kg_expect_point(want, kg_body_point(world, b_particle, (kg_vec2){0, 0}), KG_DEBUG_PARTICLE_SIZE,
                    KG_DEBUG_COLOR_PARTICLE);
    KG_CHECK_OK(kg_body_get_shape(world, b_bullet, &hull));
    kg_expect_polygon(want, KG_CALL_SOLID_POLYGON, world, b_bullet, &hull, KG_DEBUG_COLOR_BULLET);
    for (int i = 0; i < 3; ++i) {
        kg_expect_two(want, KG_CALL_SEGMENT, kg_body_point(world, b_chain, chain_points[i]),
                      kg_body_point(world, b_chain, chain_points[i + 1]), 0.0f, KG_DEBUG_COLOR_STATIC);
    }
    kg_shape_id shapes[3];
    int shape_count = 0;
    KG_CHECK_OK(kg_body_get_shapes(world, b_compound, shapes, 3, &shape_count));
    KG_CHECK(shape_count == 3);
    kg_body_shape_def first;
    KG_CHECK_OK(kg_shape_get_def(world, shapes[0], &first));
    kg_expect_polygon(want, KG_CALL_SOLID_POLYGON, world, b_compound, &first.geometry, KG_DEBUG_COLOR_DYNAMIC);
    kg_expect_circle(want, KG_CALL_SOLID_CIRCLE, world, b_compound, extra.geometry.center, 0.3f,
                     KG_DEBUG_COLOR_DYNAMIC);
    kg_body_shape_def sensor_built;
    KG_CHECK_OK(kg_shape_get_def(world, shapes[2], &sensor_built));
    kg_expect_polygon(want, KG_CALL_POLYGON, world, b_compound, &sensor_built.geometry, KG_DEBUG_COLOR_SENSOR);

    KG_CHECK(kg_same_calls(got, want, KG_TOLERANCE));
    /* a solid shape's transform is its body's, a circle's moved to its centre */
    kg_body_state s;
    KG_CHECK_OK(kg_body_get_state(world, b_kinematic, &s));
    const kg_call* turned = &got->calls[1];
    KG_CHECK_NEAR(turned->transform.c, cosf(s.angle), KG_TOLERANCE);
    KG_CHECK_NEAR(turned->transform.s, sinf(s.angle), KG_TOLERANCE);
    free(want);
    kg_destroy_world(world);
}

static kg_color kg_tint(kg_body body, kg_color state_color, void* context)
{
    (void)context;
    return body.index == 0 ? 0x123456u : state_color;
}

/* A body at rest falls asleep and turns grey; body_color changes what it says. */
static void test_colours_follow_the_state(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_recorder* got = calloc(1, sizeof *got);
    kg_body resting = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 0.0f, kg_box_shape(1.0f, 1.0f));
    kg_body spinning = kg_test_add(world, KG_BODY_KINEMATIC, (kg_vec2){5.0f, 0.0f}, 0.0f, kg_box_shape(1.0f, 1.0f));
    KG_CHECK_OK(kg_body_set_angular_velocity(world, spinning, 1.0f));
    kg_debug_draw draw = kg_recording_draw(got, KG_DEBUG_DRAW_SHAPES);
    KG_CHECK_OK(kg_world_draw(world, &draw));
    KG_CHECK(got->count == 2 && got->calls[0].color == KG_DEBUG_COLOR_DYNAMIC);
    for (int i = 0; i < 120 && kg_body_is_awake(world, resting); ++i) {
        KG_CHECK_OK(kg_world_step(world, 1.0f / 60.0f));
    }
    KG_CHECK(!kg_body_is_awake(world, resting));
    draw = kg_recording_draw(got, KG_DEBUG_DRAW_SHAPES);
    KG_CHECK_OK(kg_world_draw(world, &draw));
    KG_CHECK(got->count == 2);
    KG_CHECK(got->calls[0].color == KG_DEBUG_COLOR_ASLEEP);
    KG_CHECK(got->calls[1].color == KG_DEBUG_COLOR_KINEMATIC);
    draw = kg_recording_draw(got, KG_DEBUG_DRAW_SHAPES);
    draw.body_color = kg_tint;
    KG_CHECK_OK(kg_world_draw(world, &draw));
    KG_CHECK(got->count == 2 && got->calls[0].color == 0x123456u && got->calls[1].color == KG_DEBUG_COLOR_KINEMATIC);
    /* an overflowing force freezes a body: red */
    KG_CHECK_OK(kg_body_apply_force_to_center(world, resting, (kg_vec2){FLT_MAX, FLT_MAX}));
    KG_CHECK_OK(kg_body_apply_force_to_center(world, resting, (kg_vec2){FLT_MAX, FLT_MAX}));
    KG_CHECK_OK(kg_world_step(world, 1.0f / 60.0f));
    KG_CHECK(kg_body_is_frozen(world, resting));
    draw = kg_recording_draw(got, KG_DEBUG_DRAW_SHAPES);
    KG_CHECK_OK(kg_world_draw(world, &draw));
    KG_CHECK(got->count == 2 && got->calls[0].color == KG_DEBUG_COLOR_FROZEN);
    free(got);
    kg_destroy_world(world);
}

/* A map of a full square, a slope falling away from it and a one-way platform: each tile's polygon where its
 * cell is, and only the edges that collide. */
static void test_tiles_and_their_edges(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_recorder* got = calloc(1, sizeof *got);
    kg_tile_shape shapes[4] = {kg_tile_empty(), kg_tile_box(), kg_tile_slope(KG_TILE_BOTTOM_LEFT),
                               kg_tile_platform()};
    static const uint16_t cells[4] = {1, 2, 0, 3};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 4;
    def.height = 1;
    def.tile_size = (kg_vec2){0.5f, 0.5f};
    def.origin = (kg_vec2){-1.0f, 2.0f};
    def.shapes = shapes;
    def.shape_count = 4;
    def.tiles = cells;
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(world, &def, &map));
    kg_debug_draw draw = kg_recording_draw(got, KG_DEBUG_DRAW_TILES);
    KG_CHECK_OK(kg_world_draw(world, &draw));
    KG_CHECK(got->per_kind[KG_CALL_SOLID_POLYGON] == 3);
    /* box: left, bottom, top (its right side meets the slope's full left side, hidden
     * both ways); slope: bottom and diagonal; platform: its top only */
    KG_CHECK(got->per_kind[KG_CALL_SEGMENT] == 6);
    int tiles = 0, one_way_edges = 0;
    for (int i = 0; i < got->count; ++i) {
        const kg_call* c = &got->calls[i];
        if (c->kind == KG_CALL_SOLID_POLYGON) {
            int cell = tiles == 2 ? 3 : tiles;
            kg_color want = cell == 3 ? KG_DEBUG_COLOR_ONE_WAY : KG_DEBUG_COLOR_TILE;
            KG_CHECK(c->color == want);
            for (int k = 0; k < c->count; ++k) { /* inside its cell */
                KG_CHECK(c->points[k].x >= -1.0f + 0.5f * (float)cell - 1e-6f);
                KG_CHECK(c->points[k].x <= -1.0f + 0.5f * (float)(cell + 1) + 1e-6f);
                KG_CHECK(c->points[k].y >= 2.0f - 1e-6f && c->points[k].y <= 2.5f + 1e-6f);
            }
            tiles++;
        } else if (c->color == KG_DEBUG_COLOR_ONE_WAY_EDGE) {
            one_way_edges++;
            KG_CHECK_NEAR(c->points[0].y, 2.5f, 1e-6); /* the platform's top */
            KG_CHECK_NEAR(c->points[1].y, 2.5f, 1e-6);
        }
    }
    KG_CHECK(one_way_edges == 1);
    /* the box's vertices exactly: cell (0, 0) at the origin */
    const kg_call* first = &got->calls[0];
    KG_CHECK(first->kind == KG_CALL_SOLID_POLYGON && first->count == 4);
    for (int k = 0; k < first->count; ++k) {
        KG_CHECK(first->points[k].x == -1.0f || first->points[k].x == -0.5f);
        KG_CHECK(first->points[k].y == 2.0f || first->points[k].y == 2.5f);
    }
    free(got);
    kg_destroy_world(world);
}

/* With bounds, a body outside is not drawn, and a 1000 x 1000 map of full squares costs
 * the 16 cells inside: their fills, and the map's left and bottom borders as edges. */
static void test_bounds_cull(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_recorder* got = calloc(1, sizeof *got);
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
    uint16_t* cells = malloc(1000u * 1000u * sizeof *cells);
    for (int i = 0; i < 1000 * 1000; ++i) {
        cells[i] = 1;
    }
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 1000;
    def.height = 1000;
    def.shapes = shapes;
    def.shape_count = 2;
    def.tiles = cells;
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(world, &def, &map));
    free(cells);
    kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){2.0f, 2.0f}, 0.0f, kg_box_shape(0.5f, 0.5f));
    kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){50.0f, 2.0f}, 0.0f, kg_box_shape(0.5f, 0.5f));
    kg_debug_draw draw = kg_recording_draw(got, KG_DEBUG_DRAW_TILES | KG_DEBUG_DRAW_SHAPES | KG_DEBUG_DRAW_AABBS);
    draw.use_bounds = 1;
    draw.bounds = (kg_aabb){{0.5f, 0.5f}, {3.5f, 3.5f}};
    KG_CHECK_OK(kg_world_draw(world, &draw));
    KG_CHECK(got->per_kind[KG_CALL_SOLID_POLYGON] == 16 + 1); /* 16 tiles, 1 body */
    KG_CHECK(got->per_kind[KG_CALL_SEGMENT] == 8);
    KG_CHECK(got->per_kind[KG_CALL_POLYGON] == 1); /* the body's box */
    const kg_call* body = &got->calls[got->count - 2];
    KG_CHECK(body->kind == KG_CALL_SOLID_POLYGON && body->color == KG_DEBUG_COLOR_DYNAMIC);
    KG_CHECK_NEAR(body->transform.position.x, 2.0f, 1e-6);
    /* the body's AABB is the one the API gives */
    kg_body bodies[2];
    int n = 0;
    KG_CHECK_OK(kg_world_get_bodies(world, bodies, 2, &n));
    kg_aabb box;
    KG_CHECK_OK(kg_body_get_aabb(world, bodies[0], &box));
    const kg_call* aabb = &got->calls[got->count - 1];
    KG_CHECK(aabb->color == KG_DEBUG_COLOR_AABB && aabb->count == 4);
    KG_CHECK(aabb->points[0].x == box.lower.x && aabb->points[0].y == box.lower.y);
    KG_CHECK(aabb->points[2].x == box.upper.x && aabb->points[2].y == box.upper.y);
    free(got);
    kg_destroy_world(world);
}

/* A box resting on the ground: a point and a normal per contact point, as
 * kg_world_get_contact reports them; centres of mass as transforms. */
static void test_contacts_and_mass(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, -10.0f});
    kg_recorder* got = calloc(1, sizeof *got);
    kg_test_add(world, KG_BODY_STATIC, (kg_vec2){0.0f, -0.5f}, 0.0f, kg_box_shape(10.0f, 1.0f));
    kg_body box = kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.5f}, 0.0f,
                         kg_offset_box_shape(1.0f, 1.0f, (kg_vec2){0.3f, 0.0f}, 0.0f));
    for (int i = 0; i < 30; ++i) {
        KG_CHECK_OK(kg_world_step(world, 1.0f / 60.0f));
    }
    kg_debug_draw draw = kg_recording_draw(got, KG_DEBUG_DRAW_CONTACT_POINTS | KG_DEBUG_DRAW_CONTACT_NORMALS |
                                                    KG_DEBUG_DRAW_MASS);
    draw.normal_length = 0.5f;
    KG_CHECK_OK(kg_world_draw(world, &draw));
    kg_contact_info contact;
    KG_CHECK(kg_world_contact_count(world) == 1);
    KG_CHECK_OK(kg_world_get_contact(world, 0, &contact));
    KG_CHECK(contact.point_count == 2);
    KG_CHECK(got->count == 1 + 2 * contact.point_count);
    const kg_call* mass = &got->calls[0];
    kg_mass_data md;
    KG_CHECK_OK(kg_body_get_mass_data(world, box, &md));
    kg_vec2 center = kg_body_point(world, box, md.center);
    KG_CHECK(mass->kind == KG_CALL_TRANSFORM);
    KG_CHECK_NEAR(mass->points[0].x, center.x, KG_TOLERANCE);
    KG_CHECK_NEAR(mass->points[0].y, center.y, KG_TOLERANCE);
    for (int p = 0; p < contact.point_count; ++p) {
        const kg_call* normal = &got->calls[1 + 2 * p];
        const kg_call* point = &got->calls[2 + 2 * p];
        KG_CHECK(normal->kind == KG_CALL_SEGMENT && normal->color == KG_DEBUG_COLOR_CONTACT_NORMAL);
        KG_CHECK(point->kind == KG_CALL_POINT && point->color == KG_DEBUG_COLOR_CONTACT_POINT);
        KG_CHECK(point->points[0].x == contact.points[p].x && point->points[0].y == contact.points[p].y);
        KG_CHECK_NEAR(normal->points[1].x, contact.points[p].x + 0.5f * contact.normal.x, KG_TOLERANCE);
        KG_CHECK_NEAR(normal->points[1].y, contact.points[p].y + 0.5f * contact.normal.y, KG_TOLERANCE);
    }
    free(got);
    kg_destroy_world(world);
}

static int g_circles;
static void kg_count_circle(kg_transform xf, float radius, kg_color color, void* context)
{
    (void)xf, (void)radius, (void)color, (void)context;
    g_circles++;
}

/* Only the callbacks set are called; none set draws nothing and succeeds. */
static void test_null_callbacks_skipped(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 0.0f, kg_box_shape(1.0f, 1.0f));
    kg_test_add(world, KG_BODY_DYNAMIC, (kg_vec2){2.0f, 0.0f}, 0.0f, kg_circle_shape(0.5f));
    kg_test_add(world, KG_BODY_PARTICLE, (kg_vec2){4.0f, 0.0f}, 0.0f, (kg_shape_def){0});
    kg_debug_draw draw = kg_default_debug_draw();
    draw.flags = 0xFFFFFFFFu;
    KG_CHECK_OK(kg_world_draw(world, &draw));
    draw.draw_solid_circle = kg_count_circle;
    g_circles = 0;
    KG_CHECK_OK(kg_world_draw(world, &draw));
    KG_CHECK(g_circles == 1);
    draw.flags = KG_DEBUG_DRAW_TILES; /* shapes not asked for */
    KG_CHECK_OK(kg_world_draw(world, &draw));
    KG_CHECK(g_circles == 1);
    kg_destroy_world(world);
}

static void test_bad_input(void)
{
    kg_world* world = kg_test_cpu_world((kg_vec2){0.0f, 0.0f});
    kg_debug_draw draw = kg_default_debug_draw();
    KG_CHECK(kg_world_draw(NULL, &draw) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strstr(kg_last_error(), "NULL world") != NULL);
    KG_CHECK(kg_world_draw(world, NULL) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strstr(kg_last_error(), "NULL draw") != NULL);
    draw.use_bounds = 1;
    draw.bounds.upper.x = NAN;
    KG_CHECK(kg_world_draw(world, &draw) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strstr(kg_last_error(), "bounds") != NULL);
    draw = kg_default_debug_draw();
    draw.normal_length = -1.0f;
    KG_CHECK(kg_world_draw(world, &draw) == KG_ERROR_INVALID_ARGUMENT);
    kg_destroy_world(world);
}

KG_TEST_MAIN(KG_TEST(test_every_shape_kind), KG_TEST(test_colours_follow_the_state),
             KG_TEST(test_tiles_and_their_edges), KG_TEST(test_bounds_cull), KG_TEST(test_contacts_and_mass),
             KG_TEST(test_null_callbacks_skipped), KG_TEST(test_bad_input))
