/* Contact events: begin, end and hit events checked against free fall, the total normal
 * impulse of a step against a resting weight, destroyed bodies, and the same events with
 * any thread count and on both backends. */
#include "kg_test.h"
#include "kg_twin.h"
#include "kgyro/kgyro.h"
#include "kg_test_world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DT (1.0f / 60.0f)


/* A static ground box whose top is at y = 0. */
static kg_body add_ground(kg_world* w)
{
    kg_body_def bd = kg_default_body_def();
    bd.type = KG_BODY_STATIC;
    bd.position = (kg_vec2){0.0f, -0.5f};
    bd.shape = kg_box_shape(40.0f, 1.0f);
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    return b;
}

static kg_body add_body(kg_world* w, kg_shape_def shape, kg_vec2 at, void* user_data)
{
    kg_body_def bd = kg_default_body_def();
    bd.position = at;
    bd.shape = shape;
    bd.user_data = user_data;
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    return b;
}

/* A ball dropped from rest, its bottom h above the ground: it begins touching the ground
 * within a step of when free fall reaches it, and its hit reports sqrt(2 g h). */
static void test_ball_lands_when_free_fall_says(void)
{
    kg_world* w = kg_test_world(KG_BACKEND_CPU, 1);
    kg_body ground = add_ground(w);
    const float h = 19.5f, r = 0.25f, g = 10.0f;
    kg_body ball = add_body(w, kg_circle_shape(r), (kg_vec2){0.0f, h + r}, NULL);
    int begin_step = -1, hit_step = -1, hits = 0;
    float approach = 0.0f;
    for (int step = 1; step <= 200; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_contact_events ev = kg_world_get_contact_events(w);
        for (int i = 0; i < ev.begin_count; ++i) {
            KG_CHECK(kg_test_same_body(ev.begin[i].a, ground) && kg_test_same_body(ev.begin[i].b, ball));
            KG_CHECK(ev.begin[i].point_count == 1);
            begin_step = begin_step < 0 ? step : begin_step;
        }
        for (int i = 0; i < ev.hit_count; ++i) {
            hits += 1;
            hit_step = step;
            approach = ev.hit[i].approach_speed;
            KG_CHECK_NEAR(ev.hit[i].normal.y, 1.0f, 1e-6f);
            KG_CHECK_NEAR(ev.hit[i].point.y, 0.0f, 0.02f);
        }
        KG_CHECK(ev.end_count == 0);
    }
    float fall_step = sqrtf(2.0f * h / g) / DT; /* 118.5: free fall reaches the ground in step 119 */
    float expected = sqrtf(2.0f * g * h);
    measured("begin at step %d, hit at step %d (free fall: during step %.0f), approach %.4f m/s against %.4f (%.3f%%)",
             begin_step, hit_step, ceilf(fall_step), (double)approach, (double)expected,
             100.0 * (approach - expected) / expected);
    KG_CHECK(abs(begin_step - (int)ceilf(fall_step)) <= 1);
    KG_CHECK(abs(hit_step - (int)ceilf(fall_step)) <= 1);
    KG_CHECK(hits == 1);
    KG_CHECK(fabsf(approach - expected) <= 0.01f * expected);
    kg_destroy_world(w);
}

/* A resting box's contact carries its weight over the whole step: m g dt in all, where the
 * last sub-step's impulse alone is a quarter of it. */
static void test_total_impulse_carries_the_weight(void)
{
    kg_world* w = kg_test_world(KG_BACKEND_CPU, 1);
    add_ground(w);
    kg_body box = add_body(w, kg_box_shape(1.0f, 1.0f), (kg_vec2){0.0f, 0.5f}, NULL);
    for (int step = 0; step < 120; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_contact_info info[2];
    int n = 0;
    KG_CHECK_OK(kg_body_get_contacts(w, box, info, 2, &n));
    KG_CHECK(n == 1);
    float total = info[0].total_normal_impulses[0] + info[0].total_normal_impulses[1];
    float last = info[0].normal_impulses[0] + info[0].normal_impulses[1];
    float weight = 1.0f * 10.0f * DT;
    measured("total normal impulse %.6f N s against m g dt = %.6f (last sub-step's %.6f)", (double)total,
             (double)weight, (double)last);
    KG_CHECK(fabsf(total - weight) <= 0.01f * weight);
    KG_CHECK(fabsf(last - weight / 4.0f) <= 0.02f * weight);
    kg_contact_events ev = kg_world_get_contact_events(w);
    KG_CHECK(ev.begin_count == 0 && ev.end_count == 0 && ev.hit_count == 0); /* at rest: nothing happens */
    kg_destroy_world(w);
}

/* Every event names live bodies, or the null body in place of one destroyed. */
static void check_no_dead_body(kg_world* w, const kg_contact_event* e, int count)
{
    kg_body none = KG_NULL_BODY_INIT;
    for (int i = 0; i < count; ++i) {
        KG_CHECK(kg_body_is_valid(w, e[i].a) || kg_test_same_body(e[i].a, none));
        KG_CHECK(kg_body_is_valid(w, e[i].b) || kg_test_same_body(e[i].b, none));
    }
}

/* The top box of a stack destroyed: its contact ends with the next step's events, the dead
 * body's handle null and its user data as it was; nothing names it after. */
static void test_destroyed_body_ends_its_contacts(void)
{
    kg_world* w = kg_test_world(KG_BACKEND_CPU, 1);
    kg_body ground = add_ground(w);
    static int bottom_tag, top_tag;
    kg_body bottom = add_body(w, kg_box_shape(1.0f, 1.0f), (kg_vec2){0.0f, 0.5f}, &bottom_tag);
    kg_body top = add_body(w, kg_box_shape(1.0f, 1.0f), (kg_vec2){0.0f, 1.5f}, &top_tag);
    for (int step = 0; step < 60; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_contact_info info[4];
    int n = 0;
    KG_CHECK_OK(kg_body_get_contacts(w, bottom, info, 4, &n));
    KG_CHECK(n == 2);
    KG_CHECK(kg_body_get_contacts(w, (kg_body){top.index, top.generation + 1u}, info, 4, &n) ==
             KG_ERROR_INVALID_HANDLE);
    KG_CHECK_OK(kg_destroy_body(w, top));
    KG_CHECK(kg_world_get_contact_events(w).end_count == 0); /* still the last step's events */
    KG_CHECK_OK(kg_world_step(w, DT));
    kg_contact_events ev = kg_world_get_contact_events(w);
    KG_CHECK(ev.end_count == 1);
    KG_CHECK(ev.begin_count == 0);
    if (ev.end_count == 1) {
        KG_CHECK(kg_test_same_body(ev.end[0].a, bottom));
        KG_CHECK(ev.end[0].b.generation == 0u && ev.end[0].shape_b.generation == 0u);
        KG_CHECK(ev.end[0].user_data_a == &bottom_tag && ev.end[0].user_data_b == &top_tag);
    }
    check_no_dead_body(w, ev.end, ev.end_count);
    KG_CHECK_OK(kg_world_step(w, DT));
    ev = kg_world_get_contact_events(w);
    KG_CHECK(ev.end_count == 0 && ev.begin_count == 0);
    KG_CHECK_OK(kg_body_get_contacts(w, bottom, info, 4, &n));
    KG_CHECK(n == 1 && kg_test_same_body(info[0].a, ground));
    kg_destroy_world(w);
}

/* A box slid off a ledge: the contact ends while it falls, and begins again below. */
static void test_sliding_off_a_ledge_ends_and_begins(void)
{
    kg_world* w = kg_test_world(KG_BACKEND_CPU, 1);
    kg_body_def bd = kg_default_body_def();
    bd.type = KG_BODY_STATIC;
    bd.position = (kg_vec2){0.0f, 2.0f};
    bd.shape = kg_box_shape(2.0f, 0.2f);
    kg_body ledge = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &ledge));
    kg_body ground = add_ground(w);
    kg_body box = add_body(w, kg_box_shape(0.5f, 0.5f), (kg_vec2){0.0f, 2.35f}, NULL);
    KG_CHECK_OK(kg_body_set_velocity(w, box, (kg_vec2){6.0f, 0.0f})); /* friction stops it 3 m on */
    int ends = 0, ground_begins = 0, ledge_begins = 0;
    for (int step = 0; step < 120; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_contact_events ev = kg_world_get_contact_events(w);
        for (int i = 0; i < ev.end_count; ++i) {
            ends += kg_test_same_body(ev.end[i].a, ledge) && kg_test_same_body(ev.end[i].b, box);
        }
        for (int i = 0; i < ev.begin_count; ++i) {
            ground_begins += kg_test_same_body(ev.begin[i].a, ground) || kg_test_same_body(ev.begin[i].b, ground);
            ledge_begins += kg_test_same_body(ev.begin[i].a, ledge);
        }
    }
    KG_CHECK(ledge_begins == 1);
    KG_CHECK(ends == 1);
    KG_CHECK(ground_begins >= 1);
    kg_destroy_world(w);
}

/* A ball dropped on a tile map: the begin event names the map and the cell. */
static void test_tile_contact_names_its_cell(void)
{
    kg_world* w = kg_test_world(KG_BACKEND_CPU, 1);
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 16;
    def.height = 4;
    def.tile_size = (kg_vec2){1.0f, 1.0f};
    def.shapes = shapes;
    def.shape_count = 2;
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(w, &def, &map));
    for (int x = 0; x < 16; ++x) {
        KG_CHECK_OK(kg_tilemap_set_tile(w, map, 0, x, 0, 1));
    }
    kg_body ball = add_body(w, kg_circle_shape(0.25f), (kg_vec2){5.5f, 3.0f}, NULL);
    int begins = 0;
    for (int step = 0; step < 90; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_contact_events ev = kg_world_get_contact_events(w);
        for (int i = 0; i < ev.begin_count; ++i) {
            begins += 1;
            KG_CHECK(kg_test_same_body(ev.begin[i].a, ball) && ev.begin[i].b.generation == 0u);
            KG_CHECK(ev.begin[i].map.index == map.index && ev.begin[i].map.generation == map.generation);
            KG_CHECK(ev.begin[i].layer == 0 && ev.begin[i].x == 5 && ev.begin[i].y == 0);
        }
    }
    KG_CHECK(begins == 1);
    kg_destroy_world(w);
}

/* A ball resting on a tile of layer 1 destroyed: its end event names that layer and cell. */
static void test_destroyed_body_on_a_tile_names_the_layer(void)
{
    kg_world* w = kg_test_world(KG_BACKEND_CPU, 1);
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
    kg_tilemap_def def = kg_default_tilemap_def();
    def.width = 8;
    def.height = 2;
    def.layer_count = 2;
    def.tile_size = (kg_vec2){1.0f, 1.0f};
    def.shapes = shapes;
    def.shape_count = 2;
    kg_tilemap map;
    KG_CHECK_OK(kg_create_tilemap(w, &def, &map));
    KG_CHECK_OK(kg_tilemap_set_tile(w, map, 1, 3, 0, 1));
    kg_body ball = add_body(w, kg_circle_shape(0.25f), (kg_vec2){3.5f, 1.25f}, NULL);
    for (int step = 0; step < 30; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    KG_CHECK_OK(kg_destroy_body(w, ball));
    KG_CHECK_OK(kg_world_step(w, DT));
    kg_contact_events ev = kg_world_get_contact_events(w);
    KG_CHECK(ev.end_count == 1);
    if (ev.end_count == 1) {
        KG_CHECK(ev.end[0].a.generation == 0u && ev.end[0].map.index == map.index);
        KG_CHECK(ev.end[0].layer == 1 && ev.end[0].x == 3 && ev.end[0].y == 0);
    }
    kg_destroy_world(w);
}

/* ---- the same events everywhere ---- */

#define MAX_LOG 20000

typedef struct event_log {
    int count;
    unsigned char bytes[MAX_LOG][48];
} event_log;

static void log_events(event_log* log, int step, const kg_contact_event* e, int count)
{
    for (int i = 0; i < count && log->count < MAX_LOG; ++i) {
        unsigned char* out = log->bytes[log->count++];
        memset(out, 0, 48);
        int kind = (int)e[i].kind;
        memcpy(out, &step, 4);
        memcpy(out + 4, &kind, 4);
        kg_body a = kg_untagged_body(e[i].a), b = kg_untagged_body(e[i].b);
        memcpy(out + 8, &a, 8);
        memcpy(out + 16, &b, 8);
        memcpy(out + 24, &e[i].point, 8);
        memcpy(out + 32, &e[i].normal, 8);
        memcpy(out + 40, &e[i].approach_speed, 4);
        memcpy(out + 44, &e[i].normal_impulse, 4);
    }
}

/* 80 boxes and balls rained on the ground, 150 steps: every event, in order. */
static void rain_events(kg_world* w, event_log* log)
{
    add_ground(w);
    unsigned seed = 7u;
    for (int i = 0; i < 80; ++i) {
        seed = seed * 1664525u + 1013904223u;
        float x = -8.0f + 16.0f * (float)(seed >> 8) / 16777216.0f;
        kg_shape_def shape = i % 2 ? kg_circle_shape(0.3f) : kg_box_shape(0.6f, 0.4f);
        add_body(w, shape, (kg_vec2){x, 1.0f + 0.8f * (float)i}, NULL);
    }
    log->count = 0;
    for (int step = 1; step <= 150; ++step) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_contact_events ev = kg_world_get_contact_events(w);
        log_events(log, step, ev.begin, ev.begin_count);
        log_events(log, step, ev.end, ev.end_count);
        log_events(log, step, ev.hit, ev.hit_count);
    }
}

static event_log g_logs[2];

static void test_events_same_with_any_thread_count(void)
{
    kg_world* one = kg_test_world(KG_BACKEND_CPU, 1);
    kg_world* four = kg_test_world(KG_BACKEND_CPU, 4);
    rain_events(one, &g_logs[0]);
    rain_events(four, &g_logs[1]);
    measured("%d events over 150 steps", g_logs[0].count);
    KG_CHECK(g_logs[0].count > 100 && g_logs[0].count < MAX_LOG);
    KG_CHECK(g_logs[0].count == g_logs[1].count);
    KG_CHECK(memcmp(g_logs[0].bytes, g_logs[1].bytes, (size_t)g_logs[0].count * 48) == 0);
    kg_destroy_world(one);
    kg_destroy_world(four);
}

static void test_events_same_on_opencl(void)
{
    int bitwise = 0;
    if (!kg_test_opencl_ready(&bitwise)) {
        return;
    }
    kg_world* cpu = kg_test_world(KG_BACKEND_CPU, 1);
    kg_world* cl = kg_test_world(KG_BACKEND_OPENCL, 1);
    rain_events(cpu, &g_logs[0]);
    rain_events(cl, &g_logs[1]);
    KG_CHECK(kg_world_backend(cl) == KG_BACKEND_OPENCL);
    KG_CHECK(g_logs[0].count == g_logs[1].count);
    if (bitwise) {
        KG_CHECK(memcmp(g_logs[0].bytes, g_logs[1].bytes, (size_t)g_logs[0].count * 48) == 0);
    }
    kg_destroy_world(cpu);
    kg_destroy_world(cl);
}

KG_TEST_MAIN(KG_TEST(test_ball_lands_when_free_fall_says), KG_TEST(test_total_impulse_carries_the_weight),
             KG_TEST(test_destroyed_body_ends_its_contacts), KG_TEST(test_sliding_off_a_ledge_ends_and_begins),
             KG_TEST(test_tile_contact_names_its_cell),
             KG_TEST(test_destroyed_body_on_a_tile_names_the_layer), KG_TEST(test_events_same_with_any_thread_count),
             KG_TEST(test_events_same_on_opencl))
