/* Acceptance test of the contact solver (issues 4 and 13): the same scene stepped with 1,
 * 2, 3 and 4 CPU threads (kg_world_def.threads), and with the contact rows 1, 4, 8 and
 * 16 lanes wide (KGYRO_SIMD_WIDTH; 8 and 16 where the CPU has AVX2 and AVX-512; a width
 * the CPU lacks is skipped), ends in bitwise identical
 * states: the raw float bits of every body's position, angle, velocity and angular
 * velocity, and of every contact's impulses. Threads 4 is run twice, to catch
 * scheduling-dependent results.
 *
 * The scenes are big enough that the parallel loops are really split: more than 256
 * bodies (the body loops' grain) and colours of more than 64 constraints (the constraint
 * loops' grain), and they are violent (fast impacts, many new contacts every step); one
 * small scene has a body with more contacts than there are colours, so that the overflow
 * (solved serially, one constraint a block) is compared too.
 *
 *   test_determinism          the quick set (also run by the sanitizer build)
 *   test_determinism NAME...  the named tests (tests/cases/solver_slow.cmake runs the rest)
 *
 * Identical bits prove nothing if the threads are never started, so the test also checks
 * (white box, core/world.h) that a world made with threads > 1 has its worker pool, and
 * prints the process CPU time over the wall time of each run (above 1 when workers ran).
 *
 * Every run prints a hash of its final state ("measured: ..."). */
#include "kg_test.h"
#include "core/world.h"         /* white box: whether the world really has worker threads */
#include "solve/contact_wide.h" /* white box: which SIMD widths this CPU runs */
#include "kgyro/kgyro.h"

#include <math.h>
#include <stdint.h>
#include <string.h>
#include <time.h>
#include <stdarg.h>

/* Prints a line of measured numbers and flushes it, so that it comes out before the
 * harness's failure messages (on stderr) about the same numbers. */

#define DT (1.0f / 60.0f)

typedef struct snapshot {
    int body_count;
    int contact_count;
    uint32_t* words; /* 6 per body, then 4 per contact */
    int word_count;
    uint64_t hash;
    double moved;    /* the largest distance a body travelled */
    int moved_count; /* bodies that travelled more than 0.5 m: proof that the scene did something */
    int has_pool;    /* the world had a worker thread pool */
    double cpu_over_wall;
} snapshot;

static uint64_t fnv1a(const uint32_t* words, int count)
{
    uint64_t h = 1469598103934665603ull;
    for (int i = 0; i < count; ++i) {
        for (int k = 0; k < 4; ++k) {
            h ^= (words[i] >> (8 * k)) & 0xffu;
            h *= 1099511628211ull;
        }
    }
    return h;
}

static uint32_t bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static kg_body add(kg_world* w, kg_body_type type, kg_shape_def shape, kg_vec2 pos, float angle, kg_vec2 vel,
                   float density)
{
    kg_body_def bd = kg_default_body_def();
    bd.type = type;
    bd.shape = shape;
    bd.position = pos;
    bd.angle = angle;
    bd.velocity = vel;
    bd.density = density;
    bd.restitution = 0.1f;
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    return b;
}

typedef void scene_fn(kg_world* w);

/* A pyramid of base boxes of 1 m on the ground, struck at 40 m/s at a third of its height
 * by a heavy ball (radius 1.5, density 5) coming from the left, 0.15 s before impact. */
static void pyramid_and_ball(kg_world* w, int base)
{
    add(w, KG_BODY_STATIC, kg_box_shape(200.0f, 1.0f), (kg_vec2){0.0f, -0.5f}, 0.0f, (kg_vec2){0, 0}, 1.0f);
    const float h = 0.5f;
    for (int i = 0; i < base; ++i) {
        float y = (2.0f * (float)i + 1.0f) * h;
        for (int j = i; j < base; ++j) {
            float x = ((float)i + 1.0f) * h + 2.0f * (float)(j - i) * h - h * (float)base;
            add(w, KG_BODY_DYNAMIC, kg_box_shape(1.0f, 1.0f), (kg_vec2){x, y}, 0.0f, (kg_vec2){0, 0}, 1.0f);
        }
    }
    float y = (float)base / 3.0f;
    float x = -0.5f * ((float)base - y) - 1.5f - 6.0f; /* the pyramid's flank at height y, minus 6 m */
    add(w, KG_BODY_DYNAMIC, kg_circle_shape(1.5f), (kg_vec2){x, y}, 0.0f, (kg_vec2){40.0f, 0.0f}, 5.0f);
}

/* 300 boxes: more than the body loops' grain of 256 */
static void pyramid_24_and_ball(kg_world* w) { pyramid_and_ball(w, 24); }
static void pyramid_40_and_ball(kg_world* w) { pyramid_and_ball(w, 40); }

static uint32_t rng_state;
static float rnd(void) /* [0, 1), xorshift32 */
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return (float)(rng_state >> 8) * (1.0f / 16777216.0f);
}

/* The pile of test_stacking (seed 1234): 1000 boxes and circles dropped into a container. */
static void pile_of_1000(kg_world* w)
{
    const int count = 1000, cols = 40;
    const float cell = 1.2f, width = (float)cols * cell;
    add(w, KG_BODY_STATIC, kg_box_shape(width + 2.0f, 1.0f), (kg_vec2){0.0f, -0.5f}, 0.0f, (kg_vec2){0, 0}, 1.0f);
    add(w, KG_BODY_STATIC, kg_box_shape(1.0f, 80.0f), (kg_vec2){-0.5f * width - 0.5f, 39.0f}, 0.0f, (kg_vec2){0, 0},
        1.0f);
    add(w, KG_BODY_STATIC, kg_box_shape(1.0f, 80.0f), (kg_vec2){0.5f * width + 0.5f, 39.0f}, 0.0f, (kg_vec2){0, 0},
        1.0f);
    rng_state = 1234u;
    for (int i = 0; i < count; ++i) {
        int row = i / cols, col = i % cols;
        kg_vec2 p = {-0.5f * width + ((float)col + 0.5f) * cell + 0.1f * (rnd() - 0.5f),
                     1.0f + 0.5f * cell + (float)row * cell};
        float angle = 6.2831853f * rnd();
        kg_shape_def shape = (i % 2 == 0) ? kg_box_shape(0.4f + 0.6f * rnd(), 0.4f + 0.6f * rnd())
                                          : kg_circle_shape(0.2f + 0.3f * rnd());
        add(w, KG_BODY_DYNAMIC, shape, p, angle, (kg_vec2){0, 0}, 1.0f);
    }
}

/* A hub with more contacts than colours: a disc of radius 4 held 1 m above the ground,
 * ringed by 48 small circles touching it, so that half of its contacts go to the overflow
 * (solved serially, one constraint a block) until the ring falls away. */
static void hub_and_ring(kg_world* w)
{
    add(w, KG_BODY_STATIC, kg_box_shape(40.0f, 1.0f), (kg_vec2){0.0f, -0.5f}, 0.0f, (kg_vec2){0, 0}, 1.0f);
    add(w, KG_BODY_DYNAMIC, kg_circle_shape(4.0f), (kg_vec2){0.0f, 5.0f}, 0.0f, (kg_vec2){0, 0}, 1.0f);
    for (int i = 0; i < 48; ++i) {
        float angle = 6.2831853f * (float)i / 48.0f;
        kg_vec2 p = {4.25f * cosf(angle), 5.0f + 4.25f * sinf(angle)};
        add(w, KG_BODY_DYNAMIC, kg_circle_shape(0.25f), p, 0.0f, (kg_vec2){0, 0}, 1.0f);
    }
}

/* One run: threads, and the SIMD width of the contact rows (0: the widest). */
typedef struct run_config {
    int threads, width;
} run_config;

static snapshot run(scene_fn* scene, run_config config, int steps)
{
    snapshot s;
    memset(&s, 0, sizeof s);
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.threads = config.threads;
    char width[8];
    snprintf(width, sizeof width, "%d", config.width);
    if (config.width > 0) {
        setenv("KGYRO_SIMD_WIDTH", width, 1); /* read when the world is made */
    }
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    unsetenv("KGYRO_SIMD_WIDTH");
    if (!w) {
        return s;
    }
    s.has_pool = w->threads != NULL;
    scene(w);
    int n = kg_world_body_count(w);
    kg_body* bodies = malloc((size_t)n * sizeof *bodies);
    kg_body_state* states = malloc((size_t)n * sizeof *states);
    kg_vec2* start = malloc((size_t)n * sizeof *start);
    KG_CHECK(bodies && states && start);
    if (bodies && states && start) {
        int got = 0;
        KG_CHECK_OK(kg_world_get_bodies(w, bodies, n, &got));
        KG_CHECK(got == n);
        KG_CHECK_OK(kg_world_get_body_states(w, bodies, n, states));
        for (int i = 0; i < n; ++i) {
            start[i] = states[i].position;
        }
        struct timespec t0, t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        clock_t c0 = clock();
        for (int step = 0; step < steps; ++step) {
            KG_CHECK_OK(kg_world_step(w, DT));
        }
        clock_t c1 = clock();
        clock_gettime(CLOCK_MONOTONIC, &t1);
        double wall = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
        s.cpu_over_wall = wall > 0.0 ? (double)(c1 - c0) / CLOCKS_PER_SEC / wall : 0.0;
        KG_CHECK_OK(kg_world_get_body_states(w, bodies, n, states));
        int contacts = kg_world_contact_count(w);
        s.body_count = n;
        s.contact_count = contacts;
        s.words = malloc(((size_t)n * 6 + (size_t)contacts * 4) * sizeof *s.words);
        KG_CHECK(s.words != NULL);
        if (s.words) {
            for (int i = 0; i < n; ++i) {
                const kg_body_state* b = &states[i];
                uint32_t* o = s.words + 6 * i;
                o[0] = bits(b->position.x);
                o[1] = bits(b->position.y);
                o[2] = bits(b->angle);
                o[3] = bits(b->velocity.x);
                o[4] = bits(b->velocity.y);
                o[5] = bits(b->angular_velocity);
                double d = hypot((double)b->position.x - start[i].x, (double)b->position.y - start[i].y);
                s.moved = d > s.moved ? d : s.moved;
                s.moved_count += d > 0.5;
            }
            for (int k = 0; k < contacts; ++k) {
                kg_contact_info ci;
                memset(&ci, 0, sizeof ci);
                KG_CHECK_OK(kg_world_get_contact(w, k, &ci));
                uint32_t* o = s.words + 6 * n + 4 * k;
                o[0] = bits(ci.normal_impulses[0]);
                o[1] = bits(ci.normal_impulses[1]);
                o[2] = bits(ci.tangent_impulses[0]);
                o[3] = bits(ci.tangent_impulses[1]);
            }
            s.word_count = 6 * n + 4 * contacts;
            s.hash = fnv1a(s.words, s.word_count);
        }
    }
    free(bodies);
    free(states);
    free(start);
    kg_destroy_world(w);
    return s;
}

static void same_bits_for_every_thread_count(const char* label, scene_fn* scene, int steps, int min_moved)
{
    static const run_config configs[] = {{1, 1}, {2, 0}, {3, 0}, {4, 0}, {4, 0},
                                         {1, 4}, {2, 4}, {1, 8}, {1, 16}, {2, 16}};
    enum { RUNS = (int)(sizeof configs / sizeof configs[0]) };
    snapshot ref = run(scene, configs[0], steps);
    measured(
        "measured: %s, %d steps: threads 1, 1 lane: %d bodies, %d contacts, %d bodies travelled over 0.5 m (up to %.2f m), "
        "state hash %016llx, cpu/wall %.2f\n",
        label, steps, ref.body_count, ref.contact_count, ref.moved_count, ref.moved, (unsigned long long)ref.hash,
        ref.cpu_over_wall);
    KG_CHECK(ref.words != NULL && ref.moved_count >= min_moved);
    for (int r = 1; r < RUNS; ++r) {
        if (configs[r].width > 0 && !kg_contact_rows_of(configs[r].width)) {
            measured("measured: %s: %d lanes not run here (the CPU lacks them)\n", label, configs[r].width);
            continue;
        }
        snapshot s = run(scene, configs[r], steps);
        int differing_bodies = 0, differing_words = 0;
        if (s.words && ref.words && s.word_count == ref.word_count) {
            for (int i = 0; i < s.word_count; ++i) {
                differing_words += s.words[i] != ref.words[i];
            }
            for (int i = 0; i < s.body_count; ++i) {
                differing_bodies += memcmp(s.words + 6 * i, ref.words + 6 * i, 6 * sizeof *s.words) != 0;
            }
        }
        int lanes = configs[r].width > 0 ? configs[r].width : kg_contact_rows_of(0)->width;
        measured("measured: %s, %d steps: threads %d, %d lanes: %d bodies, %d contacts, state hash %016llx, %d of %d "
                 "bodies and %d of %d words differ from threads 1, 1 lane; worker pool %s, cpu/wall %.2f\n",
                 label, steps, configs[r].threads, lanes, s.body_count, s.contact_count, (unsigned long long)s.hash,
                 differing_bodies, s.body_count, differing_words, s.word_count, s.has_pool ? "present" : "ABSENT",
                 s.cpu_over_wall);
        KG_CHECK(s.has_pool || configs[r].threads == 1); /* threads > 1 must start workers, or this proves nothing */
        KG_CHECK(s.words != NULL);
        KG_CHECK(s.body_count == ref.body_count);
        KG_CHECK(s.contact_count == ref.contact_count);
        KG_CHECK(s.word_count == ref.word_count);
        KG_CHECK(differing_words == 0);
        KG_CHECK(s.hash == ref.hash);
        free(s.words);
    }
    free(ref.words);
}

static void test_pyramid_24_hit_by_ball_same_bits_with_1_to_4_threads(void)
{
    same_bits_for_every_thread_count("pyramid base 24 hit by a ball", pyramid_24_and_ball, 60, 20);
}

static void test_pyramid_40_hit_by_ball_same_bits_with_1_to_4_threads(void)
{
    same_bits_for_every_thread_count("pyramid base 40 hit by a ball", pyramid_40_and_ball, 120, 50);
}

/* 240 steps: the pile lands at about 1.4 s and is still churning at 4 s */
static void test_pile_of_1000_same_bits_with_1_to_4_threads(void)
{
    same_bits_for_every_thread_count("pile of 1000 (seed 1234)", pile_of_1000, 240, 500);
}

static void test_hub_with_overflow_contacts_same_bits_with_1_to_4_threads(void)
{
    same_bits_for_every_thread_count("hub ringed by 48 circles (overflow colour)", hub_and_ring, 60, 20);
}

static const kg_test_case all_tests[] = {
    KG_TEST(test_pyramid_24_hit_by_ball_same_bits_with_1_to_4_threads),
    KG_TEST(test_hub_with_overflow_contacts_same_bits_with_1_to_4_threads),
    KG_TEST(test_pyramid_40_hit_by_ball_same_bits_with_1_to_4_threads),
    KG_TEST(test_pile_of_1000_same_bits_with_1_to_4_threads),
};
enum { QUICK_TESTS = 2, ALL_TESTS = (int)(sizeof all_tests / sizeof all_tests[0]) };

int main(int argc, char** argv) { return kg_run_chosen_tests(all_tests, ALL_TESTS, QUICK_TESTS, argc, argv); }
