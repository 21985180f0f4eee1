/* Sensors: a ball falling through a sensor band onto a floor (sensor and contact events at
 * the free-fall steps, the hit's approach speed), what a sensor sees (static, kinematic and
 * dynamic bodies, tiles; never sensors, its own body or what its filter refuses), a
 * destroyed visitor, a Tiled object with sensor = true, and the same events with any
 * thread count and on both backends. */
#include "kg_test.h"
#include "kg_twin.h"
#include "kgyro/kgyro.h"
#include "kg_test_world.h"
#include "kgyro/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DT (1.0f / 60.0f)
#define G 10.0f


static kg_body add(kg_world* w, kg_body_type type, kg_shape_def shape, kg_vec2 at, int sensor, void* user_data)
{
    kg_body_def bd = kg_default_body_def();
    bd.type = type;
    bd.position = at;
    bd.shape = shape;
    bd.is_sensor = sensor;
    bd.user_data = user_data;
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    return b;
}

/* The first step (1, 2, ...) at whose end free fall from rest has gone distance d. */
static int fall_step(float d) { return (int)ceilf(sqrtf(2.0f * d / G) / DT); }

/* A ball (radius 0.25, bottom at 10) falls through a static sensor band (y 5 to 6) onto a
 * floor whose top is at y = 0. */
static void test_ball_through_a_sensor_band(void)
{
    kg_world* w = kg_test_world(KG_BACKEND_CPU, 1);
    static int band_tag, ball_tag;
    kg_body floor = add(w, KG_BODY_STATIC, kg_box_shape(20.0f, 1.0f), (kg_vec2){0.0f, -0.5f}, 0, NULL);
    kg_body band = add(w, KG_BODY_STATIC, kg_box_shape(4.0f, 1.0f), (kg_vec2){0.0f, 5.5f}, 1, &band_tag);
    kg_body ball = add(w, KG_BODY_DYNAMIC, kg_circle_shape(0.25f), (kg_vec2){0.0f, 10.25f}, 0, &ball_tag);
    int sensor_begin = -1, sensor_end = -1, contact_begin = -1, sensor_events = 0;
    float approach = 0.0f;
    for (int step = 1; step <= 240; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_sensor_events se = kg_world_get_sensor_events(w);
        for (int i = 0; i < se.begin_count + se.end_count; ++i) {
            const kg_contact_event* e = i < se.begin_count ? &se.begin[i] : &se.end[i - se.begin_count];
            KG_CHECK(kg_test_same_body(e->a, band) && kg_test_same_body(e->b, ball));
            KG_CHECK(e->user_data_a == &band_tag && e->user_data_b == &ball_tag);
            KG_CHECK(e->kind == (i < se.begin_count ? KG_EVENT_SENSOR_BEGIN : KG_EVENT_SENSOR_END));
            sensor_events += 1;
        }
        sensor_begin = se.begin_count && sensor_begin < 0 ? step : sensor_begin;
        sensor_end = se.end_count && sensor_end < 0 ? step : sensor_end;
        kg_contact_events ce = kg_world_get_contact_events(w);
        for (int i = 0; i < ce.begin_count; ++i) {
            KG_CHECK(kg_test_same_body(ce.begin[i].a, floor) && kg_test_same_body(ce.begin[i].b, ball)); /* never the band */
            contact_begin = contact_begin < 0 ? step : contact_begin;
        }
        for (int i = 0; i < ce.hit_count; ++i) {
            approach = ce.hit[i].approach_speed;
        }
    }
    float expected = sqrtf(2.0f * G * 10.0f);
    measured("sensor begin at step %d (free fall: %d), end at %d (%d), floor contact at %d (%d), hit %.4f m/s "
             "against %.4f (%.3f%%)",
             sensor_begin, fall_step(4.0f), sensor_end, fall_step(5.5f), contact_begin, fall_step(10.0f),
             (double)approach, (double)expected, 100.0 * (approach - expected) / expected);
    KG_CHECK(sensor_events == 2);
    KG_CHECK(abs(sensor_begin - fall_step(4.0f)) <= 1);  /* the ball's bottom reaches y = 6 */
    KG_CHECK(abs(sensor_end - fall_step(5.5f)) <= 1);    /* its top leaves y = 5 */
    KG_CHECK(abs(contact_begin - fall_step(10.0f)) <= 1);
    KG_CHECK(fabsf(approach - expected) <= 0.01f * expected);
    kg_destroy_world(w);
}

typedef struct seen {
    int statics, kinematics, dynamics, tiles, sensors, own;
} seen;

static void count_visitors(kg_world* w, kg_body sensor_body, const kg_body* kinds, seen* s)
{
    kg_sensor_events se = kg_world_get_sensor_events(w);
    for (int i = 0; i < se.begin_count; ++i) {
        const kg_contact_event* e = &se.begin[i];
        KG_CHECK(kg_test_same_body(e->a, sensor_body));
        s->tiles += e->b.generation == 0u && kg_tilemap_is_valid(w, e->map);
        s->statics += kg_test_same_body(e->b, kinds[0]);
        s->kinematics += kg_test_same_body(e->b, kinds[1]);
        s->dynamics += kg_test_same_body(e->b, kinds[2]);
        s->sensors += kg_test_same_body(e->b, kinds[3]);
        s->own += kg_test_same_body(e->b, sensor_body);
    }
}

/* A kinematic sensor with a solid shape of its own sweeps over a static box, a kinematic
 * box, a resting dynamic box, another sensor and a row of tiles: it sees each once. */
static void test_what_a_sensor_sees(void)
{
    kg_world* w = kg_test_world(KG_BACKEND_CPU, 1);
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
    kg_tilemap_def md = kg_default_tilemap_def();
    md.width = 40;
    md.height = 4;
    md.tile_size = (kg_vec2){1.0f, 1.0f};
    md.origin = (kg_vec2){-5.0f, -1.0f};
    md.shapes = shapes;
    md.shape_count = 2;
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(w, &md, &map));
    for (int x = 0; x < 40; ++x) {
        KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, x, 0, 1)); /* the ground: cells y = -1..0 */
    }
    kg_body kinds[4];
    kinds[0] = add(w, KG_BODY_STATIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){4.0f, 0.5f}, 0, NULL);
    kinds[1] = add(w, KG_BODY_KINEMATIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){8.0f, 2.5f}, 0, NULL);
    kinds[2] = add(w, KG_BODY_DYNAMIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){12.0f, 0.5f}, 0, NULL);
    kinds[3] = add(w, KG_BODY_STATIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){16.0f, 1.0f}, 1, NULL);
    kg_body_def bd = kg_default_body_def();
    bd.type = KG_BODY_KINEMATIC;
    bd.position = (kg_vec2){0.0f, 1.5f};
    bd.shape = kg_box_shape(1.0f, 3.2f); /* from y = -0.1 (into the tiles) to 3.1 */
    bd.is_sensor = 1;
    bd.velocity = (kg_vec2){6.0f, 0.0f};
    kg_body sweeper;
    KG_CHECK_OK(kg_create_body(w, &bd, &sweeper));
    kg_body_shape_def solid = kg_default_body_shape_def();
    solid.geometry = kg_offset_box_shape(0.2f, 0.2f, (kg_vec2){0.0f, 3.5f}, 0.0f); /* its own, never seen */
    kg_shape_id solid_id;
    KG_CHECK_OK(kg_create_shape(w, sweeper, &solid, &solid_id));
    seen s;
    memset(&s, 0, sizeof s);
    for (int step = 0; step < 180; ++step) { /* 18 m */
        KG_CHECK_OK(kg_world_step(w, DT));
        count_visitors(w, sweeper, kinds, &s);
    }
    measured("a kinematic sensor saw %d static, %d kinematic, %d dynamic, %d tiles, %d sensors, %d of its own",
             s.statics, s.kinematics, s.dynamics, s.tiles, s.sensors, s.own);
    KG_CHECK(s.statics == 1 && s.kinematics == 1 && s.dynamics == 1);
    KG_CHECK(s.tiles >= 18 && s.tiles <= 21); /* the cells it crosses, each once */
    KG_CHECK(s.sensors == 0 && s.own == 0);
    kg_vec2 p;
    KG_CHECK_OK(kg_body_get_position(w, kinds[2], &p));
    KG_CHECK_NEAR(p.x, 12.0f, 1e-4f); /* a sensor pushes nothing */
    kg_destroy_world(w);
}

/* A filter the sensor's shape has: a mask without the box's category sees nothing. */
static void test_sensor_filter(void)
{
    kg_world* w = kg_test_world(KG_BACKEND_CPU, 1);
    kg_body_def bd = kg_default_body_def();
    bd.type = KG_BODY_STATIC;
    bd.shape = kg_box_shape(2.0f, 2.0f);
    bd.is_sensor = 1;
    bd.mask = 0x2u;
    kg_body sensor;
    KG_CHECK_OK(kg_create_body(w, &bd, &sensor));
    kg_body box = add(w, KG_BODY_DYNAMIC, kg_box_shape(0.5f, 0.5f), (kg_vec2){0.0f, 0.0f}, 0, NULL);
    KG_CHECK_OK(kg_world_step(w, DT));
    KG_CHECK(kg_world_get_sensor_events(w).begin_count == 0);
    KG_CHECK_OK(kg_body_set_filter(w, box, 0x2u, 0xFFFFFFFFu));
    KG_CHECK_OK(kg_world_step(w, DT));
    KG_CHECK(kg_world_get_sensor_events(w).begin_count == 1);
    kg_destroy_world(w);
}

/* A visitor destroyed inside the sensor ends its visit; the end names no dead body. */
static void test_destroyed_visitor_ends_its_visit(void)
{
    kg_world* w = kg_test_world(KG_BACKEND_CPU, 1);
    static int box_tag;
    kg_body sensor = add(w, KG_BODY_STATIC, kg_box_shape(4.0f, 4.0f), (kg_vec2){0.0f, 0.0f}, 1, NULL);
    kg_body box = add(w, KG_BODY_KINEMATIC, kg_box_shape(0.5f, 0.5f), (kg_vec2){0.0f, 0.0f}, 0, &box_tag);
    KG_CHECK_OK(kg_world_step(w, DT));
    KG_CHECK(kg_world_get_sensor_events(w).begin_count == 1);
    KG_CHECK_OK(kg_destroy_body(w, box));
    KG_CHECK_OK(kg_world_step(w, DT));
    kg_sensor_events se = kg_world_get_sensor_events(w);
    KG_CHECK(se.begin_count == 0 && se.end_count == 1);
    if (se.end_count == 1) {
        KG_CHECK(kg_test_same_body(se.end[0].a, sensor) && se.end[0].b.generation == 0u);
        KG_CHECK(se.end[0].user_data_b == &box_tag);
    }
    kg_destroy_world(w);
}

/* tests/data/tiled/sensor.tmj: a static "trigger" rectangle with the bool property sensor =
 * true (y 5 to 6) over a floor (top at y = 1); a 1 m crate falls from a bottom at y = 8. */
static void test_tiled_object_with_sensor_property(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_load_tiled(KG_SOURCE_DIR "/tests/data/tiled/sensor.tmj", &scene));
    if (!scene) {
        return;
    }
    int trigger = -1, crate = -1;
    for (int i = 0; i < kg_scene_body_count(scene); ++i) {
        trigger = strncmp(kg_scene_body_name(scene, i), "trigger", 7) == 0 ? i : trigger;
        crate = strncmp(kg_scene_body_name(scene, i), "crate", 5) == 0 ? i : crate;
    }
    KG_CHECK(trigger >= 0 && crate >= 0 && kg_scene_body_def(scene, trigger)->is_sensor);
    kg_world_def def = *kg_scene_world_def(scene);
    def.backend = KG_BACKEND_CPU;
    kg_world* w = NULL;
    kg_body bodies[8];
    KG_CHECK_OK(kg_scene_instantiate(scene, &def, &w, bodies));
    int begin = -1, end = -1;
    for (int step = 1; step <= 120; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_sensor_events se = kg_world_get_sensor_events(w);
        begin = se.begin_count == 1 && kg_test_same_body(se.begin[0].a, bodies[trigger]) ? step : begin;
        end = se.end_count == 1 && kg_test_same_body(se.end[0].b, bodies[crate]) ? step : end;
    }
    kg_vec2 p;
    KG_CHECK_OK(kg_body_get_position(w, bodies[crate], &p));
    measured("Tiled trigger: begin at step %d (%d), end at %d (%d); the crate rests at y = %.3f (1.5)", begin,
             fall_step(2.0f), end, fall_step(4.0f), (double)p.y);
    KG_CHECK(abs(begin - fall_step(2.0f)) <= 1 && abs(end - fall_step(4.0f)) <= 1);
    KG_CHECK_NEAR(p.y, 1.5f, 0.02f); /* it fell through the trigger onto the floor */
    kg_destroy_world(w);
    kg_scene_destroy(scene);
}

/* ---- the same events everywhere ---- */

#define MAX_LOG 4000

typedef struct sensor_log {
    int count;
    unsigned char bytes[MAX_LOG][32];
} sensor_log;

/* 60 boxes and balls rained through three sensor bands onto the ground, 150 steps. */
static void rain_through_sensors(kg_world* w, sensor_log* log)
{
    add(w, KG_BODY_STATIC, kg_box_shape(40.0f, 1.0f), (kg_vec2){0.0f, -0.5f}, 0, NULL);
    for (int k = 0; k < 3; ++k) {
        add(w, KG_BODY_STATIC, kg_box_shape(5.0f, 0.5f), (kg_vec2){-6.0f + 6.0f * (float)k, 3.0f}, 1, NULL);
    }
    unsigned seed = 11u;
    for (int i = 0; i < 60; ++i) {
        seed = seed * 1664525u + 1013904223u;
        float x = -9.0f + 18.0f * (float)(seed >> 8) / 16777216.0f;
        kg_shape_def shape = i % 2 ? kg_circle_shape(0.3f) : kg_box_shape(0.6f, 0.4f);
        add(w, KG_BODY_DYNAMIC, shape, (kg_vec2){x, 5.0f + 0.7f * (float)i}, 0, NULL);
    }
    log->count = 0;
    for (int step = 1; step <= 150; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_sensor_events se = kg_world_get_sensor_events(w);
        for (int i = 0; i < se.begin_count + se.end_count && log->count < MAX_LOG; ++i) {
            const kg_contact_event* e = i < se.begin_count ? &se.begin[i] : &se.end[i - se.begin_count];
            unsigned char* out = log->bytes[log->count++];
            int kind = (int)e->kind;
            memset(out, 0, 32);
            memcpy(out, &step, 4);
            memcpy(out + 4, &kind, 4);
            kg_body a = kg_untagged_body(e->a), b = kg_untagged_body(e->b);
            kg_shape_id shape_b = kg_untagged_shape(e->shape_b);
            memcpy(out + 8, &a, 8);
            memcpy(out + 16, &b, 8);
            memcpy(out + 24, &shape_b, 8);
        }
    }
}

static sensor_log g_logs[2];

static void test_sensor_events_same_everywhere(void)
{
    kg_world* one = kg_test_world(KG_BACKEND_CPU, 1);
    kg_world* four = kg_test_world(KG_BACKEND_CPU, 4);
    rain_through_sensors(one, &g_logs[0]);
    rain_through_sensors(four, &g_logs[1]);
    measured("%d sensor events over 150 steps", g_logs[0].count);
    KG_CHECK(g_logs[0].count >= 60 && g_logs[0].count < MAX_LOG);
    KG_CHECK(g_logs[0].count == g_logs[1].count);
    KG_CHECK(memcmp(g_logs[0].bytes, g_logs[1].bytes, (size_t)g_logs[0].count * 32) == 0);
    kg_destroy_world(one);
    kg_destroy_world(four);
    int bitwise = 0;
    if (!kg_test_opencl_ready(&bitwise)) {
        return;
    }
    kg_world* cl = kg_test_world(KG_BACKEND_OPENCL, 1);
    rain_through_sensors(cl, &g_logs[1]);
    KG_CHECK(kg_world_backend(cl) == KG_BACKEND_OPENCL);
    if (bitwise) {
        KG_CHECK(g_logs[0].count == g_logs[1].count);
        KG_CHECK(memcmp(g_logs[0].bytes, g_logs[1].bytes, (size_t)g_logs[0].count * 32) == 0);
    }
    kg_destroy_world(cl);
}

KG_TEST_MAIN(KG_TEST(test_ball_through_a_sensor_band), KG_TEST(test_what_a_sensor_sees), KG_TEST(test_sensor_filter),
             KG_TEST(test_destroyed_visitor_ends_its_visit), KG_TEST(test_tiled_object_with_sensor_property),
             KG_TEST(test_sensor_events_same_everywhere))
