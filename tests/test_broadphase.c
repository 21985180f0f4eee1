/* The broadphase against a brute-force all-pairs check: same pairs, sorted, no duplicates,
 * on random mixed scenes, moving scenes, the shapes of the standard benchmark scenes,
 * degenerate inputs and output overflow; and the pairs of a search kept for later steps. */
#include "collide/aabb.h"
#include "collide/broadphase.h"
#include "core/body_pool.h"
#include "kg_test.h"

#include <string.h>

#define ALL_BITS 0xFFFFFFFFu

/* ---- deterministic random numbers ---- */

static kg_u32 rng_state = 12345u;

static kg_u32 rng_next(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return rng_state;
}

static float rng_range(float lo, float hi) { return lo + (hi - lo) * (float)(rng_next() >> 8) * (1.0f / 16777216.0f); }
/* Two draws in a fixed order (the order of a call's arguments is unspecified in C). */
static kg_vec2 rng_vec(float lo, float hi)
{
    float x = rng_range(lo, hi);
    float y = rng_range(lo, hi);
    return kg_v2(x, y);
}

static int rng_percent(int percent) { return (int)(rng_next() % 100u) < percent; }

/* ---- scene building ---- */

static kg_aabb box_at(float x, float y, float w, float h)
{
    kg_aabb b;
    b.lower = kg_v2(x, y);
    b.upper = kg_v2(x + w, y + h);
    return b;
}

static int add_body(kg_body_pool* pool, kg_body_type type, kg_aabb box)
{
    int i = kg_body_pool_acquire(pool);
    if (i < 0) {
        return -1;
    }
    pool->flags[i] = KG_FLAG_ALIVE | ((kg_u32)type << KG_TYPE_SHIFT);
    pool->aabb[i] = box;
    pool->category[i] = 1u;
    pool->mask[i] = ALL_BITS;
    return i;
}

static kg_body_type random_type(void)
{
    kg_u32 r = rng_next() % 100u;
    if (r < 10) {
        return KG_BODY_STATIC;
    }
    if (r < 15) {
        return KG_BODY_KINEMATIC;
    }
    if (r < 22) {
        return KG_BODY_PARTICLE;
    }
    return KG_BODY_DYNAMIC;
}

/* Mostly small boxes, some medium, a few large and a rare huge one; particles are points
 * or specks. Positions span side x side metres. */
static kg_aabb random_box(kg_body_type type, float side)
{
    kg_vec2 at = rng_vec(0.0f, side);
    if (type == KG_BODY_PARTICLE) {
        float s = rng_percent(50) ? 0.0f : rng_range(0.0f, 0.05f);
        return box_at(at.x, at.y, s, s);
    }
    kg_u32 r = rng_next() % 1000u;
    float lo = 0.05f, hi = 1.0f;
    if (r < 3) {
        lo = 50.0f;
        hi = 300.0f;
    } else if (r < 30) {
        lo = 4.0f;
        hi = 30.0f;
    } else if (r < 150) {
        lo = 1.0f;
        hi = 4.0f;
    }
    kg_vec2 size = rng_vec(lo, hi);
    return box_at(at.x, at.y, size.x, size.y);
}

/* Random category/mask on some bodies, so filtering removes some overlapping pairs. */
static void random_filter(kg_body_pool* pool, int i)
{
    if (rng_percent(15)) {
        pool->category[i] = 1u << (rng_next() % 4u);
        pool->mask[i] = rng_next() & 0xFu;
    }
}

static void fill_random_scene(kg_body_pool* pool, int count, float side)
{
    for (int k = 0; k < count; ++k) {
        kg_body_type type = random_type();
        int i = add_body(pool, type, random_box(type, side));
        random_filter(pool, i);
    }
    /* a few dead and frozen slots among the live ones */
    for (int i = 7; i < pool->high_water; i += 97) {
        kg_body_pool_release(pool, i);
    }
    for (int i = 13; i < pool->high_water; i += 151) {
        if (kg_pool_alive(pool, i)) {
            pool->flags[i] |= KG_FLAG_FROZEN;
        }
    }
}

/* Moves most bodies a little, teleports a few, kills some and creates others, like the
 * bodies of a world between two steps. */
static void move_random_scene(kg_body_pool* pool, float side)
{
    for (int i = 0; i < pool->high_water; ++i) {
        if (!kg_pool_alive(pool, i) || kg_pool_type(pool, i) == KG_BODY_STATIC) {
            continue;
        }
        kg_vec2 d = rng_vec(-0.3f, 0.3f);
        if (rng_percent(1)) {
            d = rng_vec(-0.5f * side, 0.5f * side);
        }
        pool->aabb[i].lower = kg_add(pool->aabb[i].lower, d);
        pool->aabb[i].upper = kg_add(pool->aabb[i].upper, d);
    }
    for (int i = (int)(rng_next() % 50u); i < pool->high_water; i += 211) {
        if (kg_pool_alive(pool, i)) {
            kg_body_pool_release(pool, i);
        }
    }
    for (int k = 0; k < 30; ++k) {
        kg_body_type type = random_type();
        int i = add_body(pool, type, random_box(type, side));
        if (i >= 0) {
            random_filter(pool, i);
        }
    }
}

/* ---- brute force ---- */

typedef struct candidate {
    kg_aabb box; /* fattened */
    kg_u32 slot, category, mask;
    int moves;
} candidate;

/* The bodies that may pair: alive, with finite fattened bounds. A frozen body stays, as
 * solid as a static one: it pairs only with moving bodies. */
static int gather_candidates(const kg_body_pool* pool, float margin, candidate* out)
{
    int n = 0;
    for (int i = 0; i < pool->high_water; ++i) {
        kg_aabb box = kg_aabb_fatten(pool->aabb[i], margin);
        if (!(pool->flags[i] & KG_FLAG_ALIVE) || !kg_vec_is_finite(box.lower) || !kg_vec_is_finite(box.upper)) {
            continue;
        }
        kg_body_type t = kg_pool_type(pool, i);
        candidate* c = &out[n++];
        c->box = box;
        c->slot = (kg_u32)i;
        c->category = pool->category[i];
        c->mask = pool->mask[i];
        c->moves = !(pool->flags[i] & KG_FLAG_FROZEN) && (t == KG_BODY_DYNAMIC || t == KG_BODY_PARTICLE);
    }
    return n;
}

/* Every pair by the definition, in (a, b) order; returns the count (out holds up to capacity). */
static int brute_force_pairs(const kg_body_pool* pool, float margin, kg_pair* out, int capacity)
{
    candidate* cands = malloc((size_t)(pool->high_water + 1) * sizeof *cands);
    int n = gather_candidates(pool, margin, cands);
    int count = 0;
    for (int i = 0; i < n; ++i) {
        const candidate* p = &cands[i];
        for (int j = i + 1; j < n; ++j) {
            const candidate* q = &cands[j];
            /* the x half of kg_aabb_overlap first, only to be quick without optimisation */
            if (q->box.lower.x > p->box.upper.x || p->box.lower.x > q->box.upper.x) {
                continue;
            }
            if (!(p->moves || q->moves) || !(p->category & q->mask) || !(q->category & p->mask) ||
                !kg_aabb_overlap(p->box, q->box)) {
                continue;
            }
            if (count < capacity) {
                out[count].a = p->slot;
                out[count].b = q->slot;
            }
            count += 1;
        }
    }
    free(cands);
    return count;
}

/* ---- comparison ---- */

typedef struct pair_buffers {
    kg_pair* found;
    kg_pair* expected;
    int capacity;
} pair_buffers;

static pair_buffers make_buffers(int capacity)
{
    pair_buffers p;
    p.capacity = capacity;
    p.found = malloc((size_t)capacity * sizeof *p.found);
    p.expected = malloc((size_t)capacity * sizeof *p.expected);
    return p;
}

static void free_buffers(pair_buffers* p)
{
    free(p->found);
    free(p->expected);
}

/* Prints the first difference, so a failure says which pair went missing or appeared. */
static int same_pairs(const kg_pair* found, const kg_pair* expected, int count, const char* what)
{
    for (int i = 0; i < count; ++i) {
        if (found[i].a != expected[i].a || found[i].b != expected[i].b) {
            fprintf(stderr, "%s: pair %d is (%u, %u), expected (%u, %u)\n", what, i, found[i].a, found[i].b,
                    expected[i].a, expected[i].b);
            return 0;
        }
    }
    return 1;
}

/* Runs the broadphase and the brute force on the pool and checks they agree exactly.
 * Returns the pair count. */
static int check_against_brute_force(kg_broadphase* bp, const kg_body_pool* pool, float margin,
                                     pair_buffers* buf, const char* what)
{
    int expected = brute_force_pairs(pool, margin, buf->expected, buf->capacity);
    int found = kg_broadphase_find_pairs(bp, pool, margin, buf->found, buf->capacity);
    if (found != expected) {
        fprintf(stderr, "%s: %d pairs, brute force finds %d\n", what, found, expected);
    }
    KG_CHECK(found == expected);
    KG_CHECK(expected <= buf->capacity);
    if (found == expected && expected <= buf->capacity) {
        KG_CHECK(same_pairs(buf->found, buf->expected, expected, what));
    }
    return expected;
}

static kg_broadphase* make_broadphase(int capacity)
{
    kg_broadphase* bp = NULL;
    KG_CHECK_OK(kg_broadphase_create(capacity, &bp));
    return bp;
}

/* ---- tests ---- */

static void test_empty_and_single(void)
{
    kg_body_pool pool;
    KG_CHECK_OK(kg_body_pool_init(&pool, 8));
    kg_broadphase* bp = make_broadphase(8);
    kg_pair pairs[4];
    KG_CHECK(kg_broadphase_find_pairs(bp, &pool, 0.1f, pairs, 4) == 0);
    KG_CHECK(kg_broadphase_find_pairs(bp, &pool, 0.1f, NULL, 0) == 0);

    add_body(&pool, KG_BODY_DYNAMIC, box_at(0.0f, 0.0f, 1.0f, 1.0f));
    KG_CHECK(kg_broadphase_find_pairs(bp, &pool, 0.1f, pairs, 4) == 0);

    /* touching boxes overlap; one a hair apart does not */
    add_body(&pool, KG_BODY_STATIC, box_at(1.0f, 0.0f, 1.0f, 1.0f));
    KG_CHECK(kg_broadphase_find_pairs(bp, &pool, 0.0f, pairs, 4) == 1);
    KG_CHECK(pairs[0].a == 0 && pairs[0].b == 1);
    pool.aabb[1] = box_at(1.001f, 0.0f, 1.0f, 1.0f);
    KG_CHECK(kg_broadphase_find_pairs(bp, &pool, 0.0f, pairs, 4) == 0);
    KG_CHECK(kg_broadphase_find_pairs(bp, &pool, 0.01f, pairs, 4) == 1);

    /* all slots dead again */
    kg_body_pool_release(&pool, 1);
    kg_body_pool_release(&pool, 0);
    KG_CHECK(kg_broadphase_find_pairs(bp, &pool, 0.1f, pairs, 4) == 0);

    kg_broadphase_destroy(bp);
    kg_body_pool_free(&pool);

    kg_broadphase* none = make_broadphase(0);
    KG_CHECK_OK(kg_body_pool_init(&pool, 0));
    KG_CHECK(kg_broadphase_find_pairs(none, &pool, 0.0f, NULL, 0) == 0);
    kg_broadphase_destroy(none);
    kg_body_pool_free(&pool);
}

/* Static and kinematic bodies never pair with each other; filters and frozen bodies count. */
static void test_pair_rules(void)
{
    kg_body_pool pool;
    KG_CHECK_OK(kg_body_pool_init(&pool, 16));
    kg_broadphase* bp = make_broadphase(16);
    kg_body_type types[4] = {KG_BODY_STATIC, KG_BODY_KINEMATIC, KG_BODY_DYNAMIC, KG_BODY_PARTICLE};
    for (int k = 0; k < 8; ++k) {
        add_body(&pool, types[k % 4], box_at(0.1f * (float)k, 0.0f, 1.0f, 1.0f));
    }
    pair_buffers buf = make_buffers(64);
    int all = check_against_brute_force(bp, &pool, 0.0f, &buf, "rules");
    /* 28 couples among 8 bodies, minus the 6 among the 4 static or kinematic ones */
    KG_CHECK(all == 22);

    pool.category[2] = 2u;
    pool.mask[3] = ~2u;
    pool.flags[4] |= KG_FLAG_FROZEN;
    int filtered = check_against_brute_force(bp, &pool, 0.0f, &buf, "rules filtered");
    KG_CHECK(filtered < all);

    pool.aabb[5].lower.x = NAN;
    check_against_brute_force(bp, &pool, 0.0f, &buf, "rules nan");

    free_buffers(&buf);
    kg_broadphase_destroy(bp);
    kg_body_pool_free(&pool);
}

/* 10,000 mixed bodies moving over several steps, with dead, frozen and filtered ones:
 * crowded (about 12 pairs a body, more than the broadphase keeps, so it searches twice)
 * and spread out (about 4 a body, which it keeps). */
static void check_random_moving_scene(float side, kg_u32 seed)
{
    const int body_count = 10000;
    kg_body_pool pool;
    KG_CHECK_OK(kg_body_pool_init(&pool, body_count + 100));
    kg_broadphase* bp = make_broadphase(body_count + 100);
    pair_buffers buf = make_buffers(400000);
    rng_state = seed;
    fill_random_scene(&pool, body_count, side);
    float margins[5] = {0.0f, 0.1f, 0.02f, 0.5f, 0.1f};
    for (int step = 0; step < 5; ++step) {
        int pairs = check_against_brute_force(bp, &pool, margins[step], &buf, "random scene");
        kg_broadphase_stats stats = kg_broadphase_get_stats(bp);
        KG_CHECK(pairs > body_count / 2);
        KG_CHECK(stats.large_count > 0 && stats.small_count > stats.large_count);
        move_random_scene(&pool, side);
    }
    free_buffers(&buf);
    kg_broadphase_destroy(bp);
    kg_body_pool_free(&pool);
}

static void test_random_moving_scenes(void)
{
    check_random_moving_scene(100.0f, 2024u);
    check_random_moving_scene(300.0f, 4048u);
}

/* Same input, same output, from the same broadphase called again and from a new one. */
static void test_deterministic(void)
{
    kg_body_pool pool;
    KG_CHECK_OK(kg_body_pool_init(&pool, 3000));
    rng_state = 77u;
    fill_random_scene(&pool, 3000, 50.0f);
    kg_broadphase* first = make_broadphase(3000);
    kg_broadphase* second = make_broadphase(3000);
    pair_buffers buf = make_buffers(100000);
    int n1 = kg_broadphase_find_pairs(first, &pool, 0.05f, buf.found, buf.capacity);
    int n2 = kg_broadphase_find_pairs(second, &pool, 0.05f, buf.expected, buf.capacity);
    KG_CHECK(n1 == n2 && n1 > 0 && n1 <= buf.capacity);
    KG_CHECK(memcmp(buf.found, buf.expected, (size_t)n1 * sizeof *buf.found) == 0);
    int n3 = kg_broadphase_find_pairs(first, &pool, 0.05f, buf.expected, buf.capacity);
    KG_CHECK(n3 == n1 && memcmp(buf.found, buf.expected, (size_t)n1 * sizeof *buf.found) == 0);
    free_buffers(&buf);
    kg_broadphase_destroy(first);
    kg_broadphase_destroy(second);
    kg_body_pool_free(&pool);
}

/* A small capacity: the count is still the true one and the written prefix is the true
 * prefix, including a cut through the middle of one slot's long run (the ground's). */
static void test_overflow(void)
{
    kg_body_pool pool;
    KG_CHECK_OK(kg_body_pool_init(&pool, 2100));
    add_body(&pool, KG_BODY_STATIC, box_at(-5.0f, -1.0f, 60.0f, 1.0f));
    rng_state = 99u;
    fill_random_scene(&pool, 2000, 50.0f);
    for (int i = 1; i < pool.high_water; i += 3) {
        if (kg_pool_alive(&pool, i)) {
            pool.flags[i] = KG_FLAG_ALIVE | ((kg_u32)KG_BODY_DYNAMIC << KG_TYPE_SHIFT);
            pool.aabb[i] = box_at(rng_range(-5.0f, 55.0f), -0.1f, 0.5f, 0.5f);
            pool.category[i] = 1u;
            pool.mask[i] = ALL_BITS;
        }
    }
    kg_broadphase* bp = make_broadphase(2100);
    const int room = 200000;
    kg_pair* expected = malloc((size_t)room * sizeof *expected);
    kg_pair* found = malloc((size_t)room * sizeof *found);
    int total = brute_force_pairs(&pool, 0.05f, expected, room);
    KG_CHECK(total > 1000 && total < room - 8);
    int ground_run = 0;
    while (ground_run < total && expected[ground_run].a == 0) {
        ground_run += 1;
    }
    KG_CHECK(ground_run > 100);

    int capacities[] = {0, 1, 7, ground_run / 2, ground_run, ground_run + 3, total / 3, total - 1, total, total + 5};
    for (int k = 0; k < (int)(sizeof capacities / sizeof capacities[0]); ++k) {
        int cap = capacities[k];
        memset(found, 0xFF, (size_t)room * sizeof *found);
        int n = kg_broadphase_find_pairs(bp, &pool, 0.05f, cap > 0 ? found : NULL, cap);
        KG_CHECK(n == total);
        int written = cap < total ? cap : total;
        KG_CHECK(same_pairs(found, expected, written, "overflow prefix"));
        /* nothing written past the capacity */
        KG_CHECK(found[cap].a == ALL_BITS && found[cap].b == ALL_BITS);
    }
    free(found);
    free(expected);
    kg_broadphase_destroy(bp);
    kg_body_pool_free(&pool);
}

/* Rows of unit boxes, each row offset by half a box, standing on a ground box. */
static void add_pyramid(kg_body_pool* pool, float x, float y, int base)
{
    for (int row = 0; row < base; ++row) {
        for (int k = 0; k < base - row; ++k) {
            add_body(pool, KG_BODY_DYNAMIC, box_at(x + 0.5f * (float)row + (float)k, y + (float)row, 1.0f, 1.0f));
        }
    }
}

/* The shapes of the standard scenes: a large pyramid on a 200 m ground, many small
 * pyramids on one ground, a dense grid of touching boxes. */
static void test_standard_scene_shapes(void)
{
    kg_body_pool pool;
    KG_CHECK_OK(kg_body_pool_init(&pool, 12000));
    kg_broadphase* bp = make_broadphase(12000);
    pair_buffers buf = make_buffers(200000);

    add_body(&pool, KG_BODY_STATIC, box_at(-100.0f, -1.0f, 200.0f, 1.0f));
    add_pyramid(&pool, -20.0f, 0.0f, 40);
    check_against_brute_force(bp, &pool, 0.1f, &buf, "pyramid");
    KG_CHECK(kg_broadphase_get_stats(bp).large_count >= 1);
    kg_body_pool_free(&pool);

    KG_CHECK_OK(kg_body_pool_init(&pool, 12000));
    add_body(&pool, KG_BODY_STATIC, box_at(-300.0f, -1.0f, 600.0f, 1.0f));
    for (int p = 0; p < 40; ++p) {
        add_pyramid(&pool, -280.0f + 14.0f * (float)p, 0.0f, 10);
    }
    check_against_brute_force(bp, &pool, 0.02f, &buf, "many pyramids");
    kg_body_pool_free(&pool);

    KG_CHECK_OK(kg_body_pool_init(&pool, 12000));
    for (int row = 0; row < 80; ++row) {
        for (int col = 0; col < 120; ++col) {
            add_body(&pool, KG_BODY_DYNAMIC, box_at(0.5f * (float)col, 0.5f * (float)row, 0.5f, 0.5f));
        }
    }
    int grid_pairs = check_against_brute_force(bp, &pool, 0.0f, &buf, "grid");
    /* touching neighbours: 119*80 + 120*79 sides and 2*119*79 corners */
    KG_CHECK(grid_pairs == 119 * 80 + 120 * 79 + 2 * 119 * 79);

    free_buffers(&buf);
    kg_broadphase_destroy(bp);
    kg_body_pool_free(&pool);
}

/* Small shapes in a container whose four walls are huge static boxes: the walls are
 * handled apart and still pair with exactly the shapes that touch them. */
static void test_container_with_huge_walls(void)
{
    const int count = 8000;
    kg_body_pool pool;
    KG_CHECK_OK(kg_body_pool_init(&pool, count + 4));
    kg_broadphase* bp = make_broadphase(count + 4);
    pair_buffers buf = make_buffers(200000);
    rng_state = 5u;
    for (int k = 0; k < count; ++k) {
        float s = rng_range(0.1f, 0.4f);
        kg_vec2 at = rng_vec(0.0f, 40.0f);
        kg_aabb box = box_at(at.x, at.y, s, s);
        add_body(&pool, k % 3 ? KG_BODY_DYNAMIC : KG_BODY_PARTICLE, box);
    }
    add_body(&pool, KG_BODY_STATIC, box_at(-1000.0f, -1000.0f, 1000.1f, 2040.0f));
    add_body(&pool, KG_BODY_STATIC, box_at(39.9f, -1000.0f, 1000.0f, 2040.0f));
    add_body(&pool, KG_BODY_STATIC, box_at(-1000.0f, -1000.0f, 2040.0f, 1000.1f));
    add_body(&pool, KG_BODY_STATIC, box_at(-1000.0f, 39.9f, 2040.0f, 1000.0f));
    check_against_brute_force(bp, &pool, 0.05f, &buf, "container");
    kg_broadphase_stats stats = kg_broadphase_get_stats(bp);
    KG_CHECK(stats.large_count >= 4 && stats.large_count < count / 10);
    free_buffers(&buf);
    kg_broadphase_destroy(bp);
    kg_body_pool_free(&pool);
}

/* Degenerate inputs: far outliers that stretch the grid, a pile of points on one spot,
 * boxes of no size without a margin, coordinates near the float range. */
static void test_degenerate_scenes(void)
{
    kg_body_pool pool;
    KG_CHECK_OK(kg_body_pool_init(&pool, 3000));
    kg_broadphase* bp = make_broadphase(3000);
    pair_buffers buf = make_buffers(300000);
    rng_state = 31u;
    fill_random_scene(&pool, 2000, 30.0f);
    add_body(&pool, KG_BODY_DYNAMIC, box_at(1.0e7f, 3.0f, 0.5f, 0.5f));
    add_body(&pool, KG_BODY_DYNAMIC, box_at(-1.0e7f, -2.0e7f, 0.5f, 0.5f));
    add_body(&pool, KG_BODY_DYNAMIC, box_at(3.0e38f, 3.0e38f, 1.0e37f, 1.0e37f));
    add_body(&pool, KG_BODY_STATIC, box_at(-3.0e38f, -3.0e38f, 1.0e38f, 1.0e38f));
    check_against_brute_force(bp, &pool, 0.05f, &buf, "outliers");
    /* small boxes at both ends of the float range: their span overflows a float */
    add_body(&pool, KG_BODY_DYNAMIC, box_at(-3.3e38f, -3.3e38f, 0.5f, 0.5f));
    add_body(&pool, KG_BODY_DYNAMIC, box_at(3.3e38f, 3.3e38f, 0.5f, 0.5f));
    check_against_brute_force(bp, &pool, 0.05f, &buf, "float range");
    /* boxes as wide as the float range */
    for (int k = 0; k < 3; ++k) {
        int i = add_body(&pool, KG_BODY_KINEMATIC, box_at(0.0f, 0.0f, 1.0f, 1.0f));
        pool.aabb[i].lower = kg_v2(-KG_FLT_MAX, -KG_FLT_MAX);
        pool.aabb[i].upper = kg_v2(KG_FLT_MAX, KG_FLT_MAX);
    }
    check_against_brute_force(bp, &pool, 0.05f, &buf, "infinitely wide");
    kg_body_pool_free(&pool);

    KG_CHECK_OK(kg_body_pool_init(&pool, 3000));
    for (int k = 0; k < 4; ++k) {
        int i = add_body(&pool, KG_BODY_DYNAMIC, box_at(0.0f, 0.0f, 1.0f, 1.0f));
        pool.aabb[i].lower = kg_v2(-KG_FLT_MAX, -KG_FLT_MAX);
        pool.aabb[i].upper = kg_v2(KG_FLT_MAX, KG_FLT_MAX);
    }
    KG_CHECK(check_against_brute_force(bp, &pool, 0.0f, &buf, "only infinitely wide") == 6);
    kg_body_pool_free(&pool);

    KG_CHECK_OK(kg_body_pool_init(&pool, 3000));
    for (int k = 0; k < 500; ++k) {
        add_body(&pool, KG_BODY_PARTICLE, box_at(2.0f, 2.0f, 0.0f, 0.0f));
    }
    for (int k = 0; k < 500; ++k) {
        kg_vec2 at = rng_vec(0.0f, 4.0f);
        add_body(&pool, KG_BODY_PARTICLE, box_at(at.x, at.y, 0.0f, 0.0f));
    }
    int pile = check_against_brute_force(bp, &pool, 0.0f, &buf, "pile of points");
    KG_CHECK(pile >= 500 * 499 / 2);
    check_against_brute_force(bp, &pool, 0.01f, &buf, "pile of specks");

    free_buffers(&buf);
    kg_broadphase_destroy(bp);
    kg_body_pool_free(&pool);
}

/* Nudges every non-static body by up to reach on each axis. */
static void nudge_scene(kg_body_pool* pool, float reach)
{
    for (int i = 0; i < pool->high_water; ++i) {
        if (kg_pool_alive(pool, i) && kg_pool_type(pool, i) != KG_BODY_STATIC) {
            kg_vec2 d = rng_vec(-reach, reach);
            pool->aabb[i].lower = kg_add(pool->aabb[i].lower, d);
            pool->aabb[i].upper = kg_add(pool->aabb[i].upper, d);
        }
    }
}

/* Whether the pairs of a search with margin + slack, kept, are exactly a search's now. */
static int kept_pairs_exact(kg_broadphase* bp, const kg_body_pool* pool, float margin, const kg_pair* kept,
                            int kept_count, pair_buffers* buf)
{
    int expected = brute_force_pairs(pool, margin, buf->expected, buf->capacity);
    int n = kg_broadphase_keep_pairs(bp, kept, kept_count, buf->found, buf->capacity);
    return n == expected && same_pairs(buf->found, buf->expected, n, "kept pairs");
}

/* A search with slack serves later steps while the boxes stay within the slack and
 * nothing else changes; any change that may add a pair makes it stop. */
static void test_kept_pairs(void)
{
    const float margin = 0.05f, slack = 0.1f;
    kg_body_pool pool;
    KG_CHECK_OK(kg_body_pool_init(&pool, 4000));
    kg_broadphase* bp = make_broadphase(4000);
    pair_buffers buf = make_buffers(200000);
    kg_pair* kept = malloc(200000 * sizeof *kept);
    rng_state = 777u;
    fill_random_scene(&pool, 3000, 100.0f);
    int count = kg_broadphase_find_pairs(bp, &pool, margin + slack, kept, 200000);
    for (int step = 0; step < 4; ++step) {
        nudge_scene(&pool, 0.02f);
        KG_CHECK(kg_broadphase_covers(bp, &pool, margin));
        KG_CHECK(kept_pairs_exact(bp, &pool, margin, kept, count, &buf));
    }
    KG_CHECK(!kg_broadphase_covers(bp, &pool, margin + 2.0f * slack)); /* boxes grown past it */

    int body = 0;
    while (!kg_pool_alive(&pool, body) || kg_pool_type(&pool, body) != KG_BODY_DYNAMIC ||
           (pool.flags[body] & KG_FLAG_FROZEN)) {
        body += 1;
    }
    kg_aabb box = pool.aabb[body];
    kg_u32 category = pool.category[body], mask = pool.mask[body], flags = pool.flags[body];
    pool.aabb[body].upper.x += 0.2f; /* out of its enlarged box */
    KG_CHECK(!kg_broadphase_covers(bp, &pool, margin));
    pool.aabb[body] = box;
    pool.category[body] = category ^ 2u;
    KG_CHECK(!kg_broadphase_covers(bp, &pool, margin));
    pool.category[body] = category;
    pool.mask[body] = mask ^ 2u;
    KG_CHECK(!kg_broadphase_covers(bp, &pool, margin));
    pool.mask[body] = mask;
    pool.flags[body] |= KG_FLAG_FROZEN; /* no longer moves */
    KG_CHECK(!kg_broadphase_covers(bp, &pool, margin));
    pool.flags[body] = flags;
    pool.aabb[body].lower.x = NAN;
    KG_CHECK(!kg_broadphase_covers(bp, &pool, margin));
    pool.aabb[body] = box;
    kg_body_pool_release(&pool, body);
    KG_CHECK(!kg_broadphase_covers(bp, &pool, margin));
    /* a body born in its slot, the same to the search as the one that died */
    KG_CHECK(add_body(&pool, KG_BODY_DYNAMIC, box) == body);
    KG_CHECK(kg_broadphase_covers(bp, &pool, margin) == (category == 1u && mask == ALL_BITS));
    add_body(&pool, KG_BODY_DYNAMIC, box); /* in a slot dead at the search */
    KG_CHECK(!kg_broadphase_covers(bp, &pool, margin));

    free(kept);
    free_buffers(&buf);
    kg_broadphase_destroy(bp);
    kg_body_pool_free(&pool);
}

KG_TEST_MAIN(KG_TEST(test_empty_and_single), KG_TEST(test_pair_rules), KG_TEST(test_random_moving_scenes),
             KG_TEST(test_deterministic), KG_TEST(test_overflow), KG_TEST(test_standard_scene_shapes),
             KG_TEST(test_container_with_huge_walls), KG_TEST(test_degenerate_scenes), KG_TEST(test_kept_pairs))
