/* The collision stage: broadphase pairs of bodies, expanded into pairs of shapes where a
 * body has several, a manifold per pair (in parallel: pairs are independent), then the
 * touching pairs become this step's contacts, sorted by (a, b, shape_a, shape_b), with
 * last step's impulses carried over point by point through the feature ids. */
#include "collide/collide.h"
#include "backend/backend.h"
#include "core/parallel.h"
#include "collide/aabb.h"
#include "collide/broadphase.h"
#include "collide/manifold.h"
#include "collide/pair_contact.h"
#include "collide/recycle.h"
#include "collide/shape_index.h"
#include "collide/tilemap.h"
#include "kgyro/events.h"
#include "solve/coloring.h"
#include "core/alloc.h"
#include "core/error.h"
#include "core/joint.h"
#include "core/prefetch.h"
#include "core/snapshot_io.h"

#include <limits.h>
#include <stdatomic.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

/* The contact pool is sized from what the world needs, not from max_contacts: it starts at
 * this many slots per body of max_bodies (a body resting on another), at least
 * KG_MIN_CONTACT_SLOTS, never more than max_contacts, and grows when the pairs outgrow it
 * (docs/design.md, "Pools and handles"). */
#define KG_INITIAL_CONTACTS_PER_BODY 1
#define KG_MIN_CONTACT_SLOTS 64

/* How much larger than its bounds each body's box is in the broadphase search whose pairs
 * are kept (m; Box2D's aabbMargin): the search runs again only when a box leaves its
 * enlarged one or a body is added, removed or changed. large_pyramid, settling (steps
 * 21..40), searches twice in 20 steps; 0.05 m costs it 0.5 M instructions a step more
 * (searching more often), 0.2 m saves 0.2 M and costs a rain more. */
#define KG_PAIR_SLACK 0.1f

/* Where bodies fly (a rain, a wall smashed), some box leaves its enlarged one every step,
 * and a search with slack costs more than one without (larger boxes, more pairs, then the
 * check and the picking): after one that served no later step, the next 1, 2, 4, ... up
 * to this many steps search without it. */
#define KG_MAX_PLAIN_RUN 64

struct kg_collision {
    kg_broadphase* broadphase;
    kg_pair* found;         /* the last search's pairs, with the slack: a superset of the
                             * pairs while kg_broadphase_covers says so */
    int found_count;        /* -1 when found holds no search's pairs */
    int found_capacity;
    unsigned char* found_kept; /* per found pair: whether this step keeps it (threads only) */
    int* found_blocks;      /* per block of KG_PAIR_BLOCK found pairs: how many are kept, then
                             * where the block's kept ones go */
    int found_served;       /* whether the found pairs served a step after their search's */
    int plain_run;          /* steps to search without slack after a search with it served none */
    int plain_left;         /* of those, still to go */
    kg_pair* pairs;
    kg_shape_pair* shape_pairs; /* while a body has several shapes: the pairs' shape pairs */
    kg_shape_index* shape_index; /* the shapes of the bodies that have many (a chain's) */
    int shape_pair_capacity;
    int by_shapes;          /* whether the current list was made with a compound body: then
                             * one pair of bodies may have several contacts */
    int* block_touching;    /* one per block of KG_PAIR_BLOCK pairs: how many touch */
    kg_contact* contacts;
    kg_contact* previous;
    int* kept_colors;        /* per contact: the colour it keeps (solve/coloring.h, kg_kept_color) */
    int waiting_colors;      /* how many keep none */
    int kept_known;          /* whether kept_colors is this step's (0 in a zeroed or restored state) */
    kg_u32 kept_pool_writes; /* world->pool_writes when they were found: a write since may
                              * have changed a body's motion */
    int count;
    int previous_count;
    int body_count;          /* contacts [0, body_count) are body pairs, the rest tiles */
    int previous_body_count;
    kg_u32 shapes_version; /* the shape pool's version when the previous list was made, and
                            * whether it was made here at all */
    int shapes_known;
    int capacity;           /* of pairs and both contact arrays; world->def.max_contacts
                             * is kept equal to it (the solver and the OpenCL backend size from it) */
    int budget;             /* pairs the pool may grow to without a warning: max_contacts as
                             * given, or as raised by a growth past it */
};

static void kg_free_buffers(struct kg_collision* c)
{
    kg_free(c->found);
    kg_free(c->found_kept);
    kg_free(c->found_blocks);
    kg_free(c->pairs);
    kg_free(c->shape_pairs);
    kg_free(c->block_touching);
    kg_free(c->contacts);
    kg_free(c->previous);
    kg_free(c->kept_colors);
}

/* The narrowphase takes the pairs in blocks of this many: a block's contacts are written
 * one after another from the block's first index (as many as touch), then the blocks are
 * moved together (kg_gather_blocks). */
#define KG_PAIR_BLOCK 64

static size_t kg_block_count(size_t pairs) { return (pairs + KG_PAIR_BLOCK - 1) / KG_PAIR_BLOCK; }

/* Replaces *buffer by a zeroed one of size bytes holding its first keep bytes; on failure
 * *buffer is left as it was. */
static int kg_regrow(void** buffer, size_t keep, size_t size)
{
    void* grown = kg_alloc_zeroed(size);
    if (!grown) {
        return 0;
    }
    if (keep > 0) {
        memcpy(grown, *buffer, keep);
    }
    kg_free(*buffer);
    *buffer = grown;
    return 1;
}

/* Sizes the pair and contact buffers; contents of the pair and contact arrays are kept. One buffer
 * is replaced at a time, each old one freed as soon as its replacement is made, so that a
 * growth never holds two whole pools; a buffer larger than the capacity (left by a failure
 * part way) is harmless. */
static kg_result kg_reserve(kg_world* world, int capacity)
{
    struct kg_collision* c = world->collision;
    size_t n = (size_t)(capacity > 0 ? capacity : 1);
    size_t kept_pairs = (size_t)(c->capacity < capacity ? c->capacity : capacity);
    if (!kg_regrow((void**)&c->pairs, kept_pairs * sizeof *c->pairs, n * sizeof *c->pairs) ||
        !kg_regrow((void**)&c->block_touching, 0, kg_block_count(n) * sizeof *c->block_touching) ||
        !kg_regrow((void**)&c->contacts, (size_t)c->count * sizeof *c->contacts, n * sizeof *c->contacts) ||
        !kg_regrow((void**)&c->previous, (size_t)c->previous_count * sizeof *c->previous, n * sizeof *c->previous) ||
        !kg_regrow((void**)&c->kept_colors, 0, n * sizeof *c->kept_colors)) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate room for %d contacts", capacity);
    }
    c->capacity = capacity;
    c->kept_known = 0; /* the kept colours were not carried over */
    world->def.max_contacts = capacity;
    return KG_OK;
}

static int kg_min_int(int a, int b) { return a < b ? a : b; }
static int64_t kg_max_i64(int64_t a, int64_t b) { return a > b ? a : b; }
static int64_t kg_clamp_i64(int64_t v, int64_t lo, int64_t hi) { return v < lo ? lo : v > hi ? hi : v; }

kg_result kg_collision_create(kg_world* world)
{
    struct kg_collision* c = kg_alloc_zeroed(sizeof *c);
    if (!c) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the collision state");
    }
    world->collision = c;
    c->budget = world->def.max_contacts;
    int64_t initial = (int64_t)KG_INITIAL_CONTACTS_PER_BODY * world->def.max_bodies;
    initial = initial > KG_MIN_CONTACT_SLOTS ? initial : KG_MIN_CONTACT_SLOTS;
    kg_result r = kg_broadphase_create(world->def.max_bodies, &c->broadphase);
    c->shape_index = kg_shape_index_create();
    if (r == KG_OK && !c->shape_index) {
        r = kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the collision state");
    }
    c->found_count = -1;
    return r == KG_OK ? kg_reserve(world, (int)(initial < c->budget ? initial : c->budget)) : r;
}

/* Tile contacts cannot grow the pool in the middle of the stage (the tile pass is not run
 * twice: it remembers where bodies were, for one-way platforms), so while a tile map is
 * live the pool is kept at the budget, the room tile contacts always had. */
static kg_result kg_reserve_tile_room(kg_world* world)
{
    struct kg_collision* c = world->collision;
    if (c->capacity >= c->budget || kg_tilemaps_live_count(world) == 0) {
        return KG_OK;
    }
    return kg_reserve(world, c->budget);
}

void kg_collision_destroy(kg_world* world)
{
    struct kg_collision* c = world->collision;
    if (c) {
        kg_broadphase_destroy(c->broadphase);
        kg_shape_index_destroy(c->shape_index);
        kg_free_buffers(c);
        kg_free(c);
        world->collision = NULL;
    }
}

static int kg_grown_count(int n)
{
    int64_t want = (int64_t)n + n / 2;
    return want < INT_MAX ? (int)want : INT_MAX;
}

/* A search with the slack into c->found, grown to half again the pairs when they do not
 * fit (a pool finding its size); -1 when out of memory for it. */
static int kg_search_with_slack(kg_world* world)
{
    struct kg_collision* c = world->collision;
    float margin = world->def.speculative_distance + KG_PAIR_SLACK;
    int n = kg_broadphase_find_pairs(c->broadphase, &world->bodies, margin, c->found, c->found_capacity);
    if (n > c->found_capacity) {
        int grown = kg_grown_count(n);
        if (!kg_regrow((void**)&c->found, 0, (size_t)grown * sizeof *c->found) ||
            !kg_regrow((void**)&c->found_kept, 0, (size_t)grown) ||
            !kg_regrow((void**)&c->found_blocks, 0, kg_block_count((size_t)grown) * sizeof *c->found_blocks)) {
            c->found_capacity = 0; /* what was grown is kept, the capacity only for all three */
            return -1;
        }
        c->found_capacity = grown;
        n = kg_broadphase_find_pairs(c->broadphase, &world->bodies, margin, c->found, c->found_capacity);
    }
    return n;
}

typedef struct kg_cover_job {
    kg_broadphase* broadphase;
    const kg_body_pool* bodies;
    float margin;
    atomic_int covered;
} kg_cover_job;

static void kg_cover_range(void* context, int begin, int end)
{
    kg_cover_job* job = context;
    if (atomic_load_explicit(&job->covered, memory_order_relaxed) &&
        !kg_broadphase_covers_range(job->broadphase, job->bodies, job->margin, begin, end)) {
        atomic_store_explicit(&job->covered, 0, memory_order_relaxed);
    }
}

/* kg_broadphase_covers over the threads (serial, this check and the picking of the kept
 * pairs were a twentieth of large_pyramid's step on two, the other thread waiting). */
static int kg_covers(kg_world* world, float margin)
{
    kg_cover_job job = {world->collision->broadphase, &world->bodies, margin, 1};
    if (!kg_broadphase_same_slots(job.broadphase, job.bodies)) {
        return 0;
    }
    kg_parallel_for(world->threads, world->bodies.high_water, KG_BODY_GRAIN, kg_cover_range, &job);
    return atomic_load(&job.covered);
}

/* Whether c->found holds every pair of this step: last step's search still covers the
 * boxes, or a new one with the slack does (unless it is a step to search without). */
static int kg_found_serves(kg_world* world)
{
    struct kg_collision* c = world->collision;
    float margin = world->def.speculative_distance;
    if (c->found_count >= 0) {
        if (kg_covers(world, margin)) {
            c->found_served = 1;
            return 1;
        }
        c->plain_run = c->found_served ? 0 : kg_min_int(c->plain_run > 0 ? 2 * c->plain_run : 1, KG_MAX_PLAIN_RUN);
        c->plain_left = c->plain_run;
        c->found_count = -1;
    }
    if (c->plain_left > 0) {
        c->plain_left -= 1;
        return 0;
    }
    c->found_count = kg_search_with_slack(world);
    c->found_served = 0;
    return c->found_count >= 0 && kg_covers(world, margin);
}

typedef struct kg_keep_job {
    struct kg_collision* collision;
    int capacity;
} kg_keep_job;

static void kg_mark_kept_range(void* context, int begin, int end)
{
    const kg_keep_job* job = context;
    const struct kg_collision* c = job->collision;
    for (int block = begin; block < end; ++block) {
        int first = block * KG_PAIR_BLOCK;
        int last = first + KG_PAIR_BLOCK < c->found_count ? first + KG_PAIR_BLOCK : c->found_count;
        c->found_blocks[block] = kg_broadphase_mark_kept(c->broadphase, c->found, first, last, c->found_kept);
    }
}

static void kg_write_kept_range(void* context, int begin, int end)
{
    const kg_keep_job* job = context;
    const struct kg_collision* c = job->collision;
    for (int block = begin; block < end; ++block) {
        int at = c->found_blocks[block];
        int last = (block + 1) * KG_PAIR_BLOCK < c->found_count ? (block + 1) * KG_PAIR_BLOCK : c->found_count;
        for (int k = block * KG_PAIR_BLOCK; k < last && at < job->capacity; ++k) {
            if (c->found_kept[k]) { /* not written past its place: that is the next block's */
                c->pairs[at++] = c->found[k];
            }
        }
    }
}

/* kg_broadphase_keep_pairs over the threads: each block's kept pairs marked and counted,
 * the counts summed into places, the blocks written. One thread picks them in one pass. */
static int kg_keep_pairs(kg_world* world)
{
    struct kg_collision* c = world->collision;
    if (!world->threads) {
        return kg_broadphase_keep_pairs(c->broadphase, c->found, c->found_count, c->pairs, c->capacity);
    }
    kg_keep_job job = {c, c->capacity};
    int blocks = (int)kg_block_count((size_t)c->found_count);
    kg_parallel_for(world->threads, blocks, 1, kg_mark_kept_range, &job);
    int64_t total = 0;
    for (int block = 0; block < blocks; ++block) {
        int kept = c->found_blocks[block];
        c->found_blocks[block] = (int)(total < INT_MAX ? total : INT_MAX);
        total += kept;
    }
    kg_parallel_for(world->threads, blocks, 1, kg_write_kept_range, &job);
    return (int)(total < INT_MAX ? total : INT_MAX);
}

/* This step's pairs into c->pairs, as many as fit; returns how many there are. Picked
 * from the found pairs when they serve, the very list a search gives
 * (collide/broadphase.h); else searched without slack (also when they cannot serve: out
 * of memory for them, or boxes at the edge of the floats that the slack turns infinite). */
static int kg_pairs_now(kg_world* world, int found_serves)
{
    struct kg_collision* c = world->collision;
    if (found_serves) {
        return kg_keep_pairs(world);
    }
    c->found_count = -1; /* this search overwrites what the broadphase saw */
    return kg_broadphase_find_pairs(c->broadphase, &world->bodies, world->def.speculative_distance, c->pairs,
                                    c->capacity);
}

/* Pairs into c->pairs. A full buffer is the one case where a step allocates: it grows to
 * half again the pairs found, and the pairs are taken again, because dropping contacts
 * would let bodies fall through each other. Up to max_contacts this is the pool finding
 * its size, silently; past it, it warns (once). */
static kg_result kg_find_pairs(kg_world* world, int* pair_count)
{
    struct kg_collision* c = world->collision;
    int found_serves = kg_found_serves(world);
    int n = kg_pairs_now(world, found_serves);
    if (n > c->capacity) {
        int grown = kg_grown_count(n);
        if (n > c->budget) {
            kg_warn_once("contacts-grow", "more touching pairs (%d) than max_contacts (%d): growing the contact pool; "
                         "raise kg_world_def.max_contacts to avoid this", n, c->budget);
            c->budget = grown;
        } else {
            grown = kg_min_int(grown, c->budget);
        }
        kg_result r = kg_reserve(world, grown);
        if (r != KG_OK) {
            return r;
        }
        n = kg_pairs_now(world, found_serves);
    }
    *pair_count = n;
    return KG_OK;
}

/* Last step's contact of key (the same two shapes of the same two bodies, not others that
 * took over their slots), or NULL, searching from *old on: pairs come in key order, as
 * last step's contacts do, so a block of pairs walks them once. */
static const kg_contact* kg_previous_of(const kg_contact* previous, int count, int* old, kg_shape_pair key,
                                        const kg_body_pool* p)
{
    while (*old < count && kg_shape_pair_less(kg_contact_key(&previous[*old]), key)) {
        *old += 1;
    }
    return kg_is_contact_of(previous, count, *old, key, p->generation) ? &previous[*old] : NULL;
}

/* kg_previous_of where last step's list holds at most one contact per pair of bodies:
 * walked by the bodies alone (a, b), then checked for the bodies' generations and their
 * shapes (first_shape), which change when a one-shape body's shape is replaced: not
 * looked up (first_shape NULL) while no shape was added or removed since that list. */
KG_FN_INLINE const kg_contact* kg_previous_of_bodies(const kg_contact* previous, int count, int* old, kg_u32 a,
                                                     kg_u32 b, const kg_u32* generation, const kg_u32* first_shape)
{
    while (*old < count && kg_pair_less(previous[*old].a, previous[*old].b, a, b)) {
        *old += 1;
    }
    const kg_contact* c = &previous[*old];
    int same = *old < count && c->a == a && c->b == b && c->generation_a == generation[a] &&
               c->generation_b == generation[b] &&
               (!first_shape || (c->shape_a == first_shape[a] && c->shape_b == first_shape[b]));
    return same ? c : NULL;
}

/* ---- shape pairs ---------------------------------------------------------------------- */

kg_shape_arrays kg_world_shape_arrays(const kg_world* world)
{
    const kg_body_pool* p = &world->bodies;
    const kg_shape_pool* sp = &world->shapes;
    kg_shape_arrays s = {p->shape_count, p->first_shape, p->shape, sp->geometry, sp->next, sp->flags, sp->category,
                         sp->mask};
    return s;
}

const struct kg_shape_index* kg_collision_shape_index(const kg_world* world) { return world->collision->shape_index; }

/* The shape pairs of the body pairs, into c->shape_pairs, as many as fit; returns how
 * many there are. A body of many shapes is searched through the shape index. */
static int kg_expand_pairs(kg_world* world, int pair_count)
{
    struct kg_collision* c = world->collision;
    int n = 0;
    for (int k = 0; k < pair_count; ++k) {
        int room = n < c->shape_pair_capacity ? c->shape_pair_capacity - n : 0;
        n += kg_shape_index_expand(c->shape_index, world, c->pairs[k].a, c->pairs[k].b,
                                   c->shape_pairs + (room > 0 ? n : 0), room);
    }
    return n;
}

/* While a body has several shapes, the narrowphase's items are pairs of shapes, one
 * body pair giving several: into c->shape_pairs, and *count becomes their count. Their
 * buffer follows the contact pool's capacity, which grows (as for the pairs) when they
 * outgrow it. */
static kg_result kg_find_shape_pairs(kg_world* world, int* count)
{
    struct kg_collision* c = world->collision;
    KG_TRY(kg_shape_index_update(c->shape_index, world));
    for (;;) {
        if (c->shape_pair_capacity < c->capacity) {
            if (!kg_regrow((void**)&c->shape_pairs, 0, (size_t)c->capacity * sizeof *c->shape_pairs)) {
                return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate room for %d shape pairs", c->capacity);
            }
            c->shape_pair_capacity = c->capacity;
        }
        int n = kg_expand_pairs(world, *count);
        if (n <= c->capacity) {
            *count = n;
            return KG_OK;
        }
        if (n > c->budget) {
            kg_warn_once("contacts-grow", "more touching shape pairs (%d) than max_contacts (%d): growing the contact "
                         "pool; raise kg_world_def.max_contacts to avoid this", n, c->budget);
            c->budget = kg_grown_count(n);
        }
        KG_TRY(kg_reserve(world, kg_min_int(kg_grown_count(n), c->budget)));
    }
}

/* Between two static or sleeping bodies: last step's contact whole. Nothing has moved or
 * been solved since, so it is what computing it again and carrying the impulses gives,
 * bit for bit, and what the OpenCL backend, which does compute it, gets. No contact last
 * step, none now. */
static void kg_keep_contact(kg_contact* ct, const kg_contact* prev)
{
    if (prev) {
        *ct = *prev;
    } else {
        ct->manifold.point_count = 0;
    }
}

typedef struct kg_narrowphase_job {
    const kg_body_pool* bodies;
    const kg_shape_pool* shapes;
    const kg_pair* pairs;
    const kg_shape_pair* shape_pairs; /* the items when a body has several shapes, else NULL:
                                       * the items are the pairs, of one-shape bodies */
    int by_shapes;                    /* a body has several shapes, or had last step: one pair
                                       * of bodies may have several contacts, in either list */
    const kg_contact* previous;
    int previous_count; /* of body contacts, sorted by (a, b); tile contacts follow */
    kg_contact* contacts;
    int* kept_colors;
    int* block_touching;
    int pair_count;
    float speculative;
    float dt;
    int same_shapes; /* no shape added, removed or its material set since the previous list */
    atomic_int carried, missed; /* warm starts, summed over the ranges */
    atomic_int waiting;         /* contacts that keep no colour, summed over the ranges */
} kg_narrowphase_job;

/* The colour contacts[at] keeps (kg_kept_color, from its bodies' flags now), noted in
 * kept[at]; returns 1 when it keeps none. The colouring of the solve stage then has
 * nothing to do when every contact keeps its colour (a settled pile): it would otherwise
 * read every contact again (large_pyramid: 5% of the step). */
KG_FN_INLINE int kg_note_kept_color(int* kept, int at, kg_u32 word, kg_color_ends ends)
{
    kept[at] = kg_kept_color(word, ends);
    return kept[at] == KG_UNCOLORED;
}

/* The ends of a contact between bodies a and b: both are bodies (not the static world of
 * a tile contact), so there is no null slot to test. */
KG_FN_INLINE kg_color_ends kg_body_pair_ends(kg_u32 a, kg_u32 b, const kg_u32* flags)
{
    kg_color_ends e = {a, b, kg_flags_simulated(flags[a]), kg_flags_simulated(flags[b])};
    return e;
}

static int kg_rested(const kg_body_pool* p, kg_u32 i) { return (p->flags[i] & KG_FLAG_RESTED) != 0; }

/* The narrowphase's item k: a pair of shapes. */
static kg_shape_pair kg_item(const kg_narrowphase_job* job, int k)
{
    if (job->shape_pairs) {
        return job->shape_pairs[k];
    }
    kg_u32 a = job->pairs[k].a, b = job->pairs[k].b;
    return kg_shape_pair_make(a, b, job->bodies->first_shape[a], job->bodies->first_shape[b]);
}

/* A touching pair's contact, its manifold computed in place: its bodies, shapes and mixed
 * material (friction fa, fb, restitution ra, rb), and last step's (prev's) impulses and
 * colour carried over. */
static void kg_finish_contact(kg_contact* ct, kg_shape_pair key, float fa, float fb, float ra, float rb,
                              const kg_contact* prev, const kg_u32* generation, int* carried, int* missed)
{
    kg_contact_set_bodies(ct, key.a, key.b, key.shape_a, key.shape_b, generation, fa, fb, ra, rb);
    if (prev) {
        int matched = kg_contact_carry_impulses(&ct->manifold, &prev->manifold);
        *carried += matched;
        *missed += ct->manifold.point_count - matched;
        ct->color = prev->color;
    }
}

/* Last step's contact prev kept whole as ct, its points moved with the bodies
 * (kg_keep_manifold), when its shapes allow (the manifold says so: a shape slot is not
 * taken by another shape while a contact names it): what kg_pair_manifold and
 * kg_finish_contact make of a kept manifold, the same bits, without reading the shapes or
 * building the manifold aside and copying it in. Its material is the caller's to mix
 * again: a shape's may have been set since. */
KG_FN_INLINE int kg_recycle_contact(kg_contact* ct, const kg_contact* prev, const kg_body_pool* p,
                              float speculative_distance, float dt)
{
    if (!prev->manifold.keepable) {
        return 0;
    }
    kg_u32 a = prev->a, b = prev->b;
    if (!kg_pose_kept(&prev->base, p->xf[a], p->xf[b])) {
        return 0;
    }
    *ct = *prev;
    kg_place_base_points(&ct->manifold, &ct->base, p->xf[a], p->xf[b]);
    /* kg_keep_manifold's test, the pair's margin (a square root) computed only where a
     * point lies past the least it can be: the same answer */
    float farthest = kg_farthest_point(&ct->manifold);
    return farthest <= speculative_distance ||
           farthest <= kg_pair_speculative(speculative_distance, p->velocity[a], p->velocity[b], dt);
}

/* The contacts of the items [begin, end) that touch, each a manifold computed or kept
 * and last step's impulses carried over, written one after another from index begin in
 * place (not a manifold per pair copied into a contact after: that copy cost more than
 * moving the blocks together, which in a pile of touching bodies moves none). Returns how
 * many.
 *
 * While every body has one shape (now and last step: !job->by_shapes), the items are the
 * pairs of bodies, last step's contacts are found by the bodies, and a body's shape and
 * material are the body pool's (the same values); its shape is looked up only to name it
 * in a contact. Keying contacts by shapes then costs large_pyramid 0.3 M instructions a
 * step (34.1 M against 33.8 M, callgrind), 0.7 M without this path. */
KG_CPU_CLONES static int kg_narrowphase_block(kg_narrowphase_job* job, int begin, int end, int* carried_sum,
                                              int* missed_sum, int* waiting_sum)
{
    const kg_body_pool* p = job->bodies;
    const kg_shape_pool* sp = job->shapes;
    int by_shapes = job->by_shapes;
    const float* friction = by_shapes ? sp->friction : p->friction;
    const float* restitution = by_shapes ? sp->restitution : p->restitution;
    int n = begin, carried = 0, missed = 0, waiting = 0;
    int old = begin < end ? kg_first_not_before(job->previous, job->previous_count, kg_item(job, begin)) : 0;
    const kg_u32* first_shape = job->same_shapes ? NULL : p->first_shape; /* for the bodies' shapes' check */
    for (int k = begin; k < end; ++k) {
        /* by bodies: the shapes are named below, where a contact is made afresh */
        kg_shape_pair key = by_shapes ? kg_item(job, k) : kg_shape_pair_make(job->pairs[k].a, job->pairs[k].b, 0u, 0u);
        kg_u32 ga = by_shapes ? key.shape_a : key.a; /* the shapes' index in friction and restitution */
        kg_u32 gb = by_shapes ? key.shape_b : key.b;
        const kg_contact* prev = by_shapes ? kg_previous_of(job->previous, job->previous_count, &old, key, p)
                                           : kg_previous_of_bodies(job->previous, job->previous_count, &old, key.a,
                                                                   key.b, p->generation, first_shape);
        kg_contact* ct = &job->contacts[n]; /* a pair before it that did not touch left it free */
        if (old + KG_CONTACTS_AHEAD < job->previous_count) {
            kg_prefetch_bytes(&job->previous[old + KG_CONTACTS_AHEAD], sizeof(kg_contact), 0);
        }
        if (n + KG_CONTACTS_AHEAD < end) {
            kg_prefetch_bytes(&job->contacts[n + KG_CONTACTS_AHEAD], sizeof(kg_contact), 1);
        }
        if (kg_rested(p, key.a) && kg_rested(p, key.b)) {
            kg_keep_contact(ct, prev);
            carried += ct->manifold.point_count;
            if (ct->manifold.point_count > 0) {
                waiting += kg_note_kept_color(job->kept_colors, n++, ct->color,
                                              kg_body_pair_ends(ct->a, ct->b, p->flags));
            }
            continue;
        }
        if (prev && kg_recycle_contact(ct, prev, p, job->speculative, job->dt)) {
            if (!job->same_shapes) { /* else prev's, mixed from the same values */
                ct->friction = sqrtf(friction[ga] * friction[gb]);
                ct->restitution = kg_maxf(restitution[ga], restitution[gb]);
            }
            carried += kg_carry_kept_impulses(&ct->manifold, &prev->manifold);
            waiting +=
                kg_note_kept_color(job->kept_colors, n++, ct->color, kg_body_pair_ends(ct->a, ct->b, p->flags));
            continue;
        }
        key = by_shapes ? key : kg_item(job, k);
        const kg_shape* shape_a = by_shapes ? kg_shape_geometry(p, sp, key.shape_a) : &p->shape[key.a];
        const kg_shape* shape_b = by_shapes ? kg_shape_geometry(p, sp, key.shape_b) : &p->shape[key.b];
        /* computed afresh: prev, had it been kept, was kept above (the same test, the same
         * answer), so it is not offered again (in the tumbler that cost 1% of the step) */
        kg_pair_manifold(key.a, key.b, shape_a, shape_b, p->xf, p->velocity, job->speculative, job->dt, NULL,
                         &ct->manifold, &ct->base);
        if (ct->manifold.point_count == 0) {
            continue;
        }
        kg_finish_contact(ct, key, friction[ga], friction[gb], restitution[ga], restitution[gb], prev,
                          p->generation, &carried, &missed);
        waiting +=
            kg_note_kept_color(job->kept_colors, n++, ct->color, kg_body_pair_ends(ct->a, ct->b, p->flags));
    }
    *carried_sum += carried;
    *missed_sum += missed;
    *waiting_sum += waiting;
    return n - begin;
}

static void kg_narrowphase_range(void* context, int begin, int end)
{
    kg_narrowphase_job* job = context;
    int carried = 0, missed = 0, waiting = 0;
    for (int block = begin; block < end; ++block) {
        int first = block * KG_PAIR_BLOCK;
        int last = first + KG_PAIR_BLOCK < job->pair_count ? first + KG_PAIR_BLOCK : job->pair_count;
        job->block_touching[block] = kg_narrowphase_block(job, first, last, &carried, &missed, &waiting);
    }
    atomic_fetch_add(&job->carried, carried);
    atomic_fetch_add(&job->missed, missed);
    atomic_fetch_add(&job->waiting, waiting);
}

/* Moves each block's contacts to follow the last block's: the contacts of the touching
 * pairs in pair order, so sorted by (a, b). Returns how many. One by one rather than by
 * memmove, whose overlapping copy costs about four times the instructions. */
static int kg_gather_blocks(kg_contact* contacts, int* kept_colors, const int* block_touching, int pair_count)
{
    int count = 0;
    for (int block = 0; (size_t)block < kg_block_count((size_t)pair_count); ++block) {
        int first = block * KG_PAIR_BLOCK;
        for (int i = 0; count != first && i < block_touching[block]; ++i) {
            contacts[count + i] = contacts[first + i];
            kept_colors[count + i] = kept_colors[first + i];
        }
        count += block_touching[block];
    }
    return count;
}

void kg_collision_mark_rested(kg_world* world)
{
    kg_body_pool* p = &world->bodies;
    for (int i = 0; i < p->high_water; ++i) {
        if (kg_pool_alive(p, i) && (kg_pool_type(p, i) == KG_BODY_STATIC || kg_pool_asleep(p, i))) {
            p->flags[i] |= KG_FLAG_RESTED;
        }
    }
}

void kg_count_warm_starts(kg_world* world, int points, int carried)
{
    world->times.warm_starts_carried += carried;
    world->times.warm_starts_missed += points - carried;
}

kg_result kg_stage_collide(kg_world* world)
{
    struct kg_collision* c = world->collision;
    kg_contact* previous;
    int previous_count;
    kg_collision_begin_step(world, &previous, &previous_count);
    world->times.warm_starts_carried = 0;
    world->times.warm_starts_missed = 0;
    int pair_count = 0;
    kg_result r = kg_reserve_tile_room(world);
    if (r == KG_OK) {
        r = kg_find_pairs(world, &pair_count);
    }
    if (r == KG_OK) { /* bodies joined by a joint that does not collide_connected: no contact */
        pair_count = kg_joints_filter_pairs(world, c->pairs, pair_count);
    }
    int compound = world->shapes.compound_bodies > 0;
    if (r == KG_OK && compound) {
        r = kg_find_shape_pairs(world, &pair_count);
    }
    if (r != KG_OK) {
        return r;
    }
    kg_narrowphase_job job = {&world->bodies, &world->shapes, c->pairs, compound ? c->shape_pairs : NULL,
                              compound || c->by_shapes, c->previous, c->previous_body_count, c->contacts,
                              c->kept_colors, c->block_touching, pair_count, world->def.speculative_distance,
                              world->last_dt, c->shapes_known && c->shapes_version == world->shapes.version, 0, 0, 0};
    c->by_shapes = compound;
    c->shapes_version = world->shapes.version;
    c->shapes_known = 1;
    kg_parallel_for(world->threads, (int)kg_block_count((size_t)pair_count), 1, kg_narrowphase_range, &job);
    int carried = atomic_load(&job.carried);
    kg_count_warm_starts(world, carried + atomic_load(&job.missed), carried);
    c->count = kg_gather_blocks(c->contacts, c->kept_colors, c->block_touching, pair_count);
    c->body_count = c->count;
    int room = c->capacity - c->count;
    int tiles = kg_tilemap_collide(world, c->contacts + c->count, room, c->previous + c->previous_body_count,
                                   c->previous_count - c->previous_body_count);
    if (tiles > room) {
        kg_warn_once("tile-contacts-full", "more tile contacts (%d) than room left in max_contacts (%d): "
                     "the extra ones were dropped this step; raise kg_world_def.max_contacts", tiles, room);
    }
    c->count = (int)kg_contacts_with_tiles((kg_u32)c->count, (kg_u32)tiles, (kg_u32)c->capacity);
    int waiting = atomic_load(&job.waiting);
    for (int k = c->body_count; k < c->count; ++k) {
        kg_color_ends ends = kg_color_ends_of((kg_u32)k, c->contacts, world->bodies.flags);
        waiting += kg_note_kept_color(c->kept_colors, k, c->contacts[k].color, ends);
    }
    c->waiting_colors = waiting;
    c->kept_known = 1;
    c->kept_pool_writes = world->pool_writes;
    return KG_OK;
}

const int* kg_collision_kept_colors(const kg_world* world, int* waiting)
{
    const struct kg_collision* c = world->collision;
    *waiting = c->kept_known && c->kept_pool_writes == world->pool_writes ? c->waiting_colors : -1;
    return world->collision->kept_colors;
}

void kg_collision_forget_kept_colors(kg_world* world) { world->collision->kept_known = 0; }

kg_contact* kg_collision_contacts(kg_world* world, int* count)
{
    *count = world->collision->count;
    return world->collision->contacts;
}

/* The OpenCL backend may hold this step's contacts on the device. */
static void kg_sync_contacts(const kg_world* world)
{
    if (world->backend && world->backend->sync_contacts) {
        world->backend->sync_contacts((kg_world*)world);
    }
}

const kg_contact* kg_collision_synced_contacts(const kg_world* world, int* count)
{
    kg_sync_contacts(world);
    return kg_collision_contacts((kg_world*)world, count);
}

kg_contact* kg_collision_next_list(kg_world* world) { return world->collision->previous; }

kg_contact* kg_collision_previous(kg_world* world, int* count)
{
    *count = world->collision->previous_count;
    return world->collision->previous;
}

const kg_contact* kg_collision_synced_previous(const kg_world* world, int* count)
{
    if (world->backend && world->backend->sync_previous_contacts) {
        world->backend->sync_previous_contacts((kg_world*)world);
    }
    return kg_collision_previous((kg_world*)world, count);
}

int kg_world_contact_count(const kg_world* world)
{
    if (!world) {
        return 0;
    }
    kg_sync_contacts(world);
    return world->collision->count;
}

kg_contact* kg_collision_begin_step(kg_world* world, kg_contact** previous, int* previous_count)
{
    struct kg_collision* c = world->collision;
    kg_contact* swap = c->previous;
    c->previous = c->contacts;
    c->previous_count = c->count;
    c->previous_body_count = c->body_count;
    c->contacts = swap;
    c->count = 0;
    c->body_count = 0;
    c->kept_known = 0;
    *previous = c->previous;
    *previous_count = c->previous_count;
    return c->contacts;
}

int kg_collision_body_count(const kg_world* world) { return world->collision->body_count; }

void kg_collision_set_count(kg_world* world, int count, int body_count)
{
    world->collision->count = count;
    world->collision->body_count = body_count;
}

int kg_collision_capacity(kg_world* world)
{
    if (kg_reserve_tile_room(world) != KG_OK) {
        kg_warn_once("tile-room", "out of memory for the tile contacts' room: some may be dropped");
    }
    return world->collision->capacity;
}

int kg_collision_budget(const kg_world* world) { return world->collision->budget; }

kg_body kg_handle_of(kg_u32 slot, kg_u32 generation)
{
    kg_body h = KG_NULL_BODY_INIT;
    if (slot != KG_NULL_INDEX) {
        h.index = slot;
        h.generation = generation;
    }
    return h;
}

kg_shape_id kg_shape_handle_of(const kg_shape_pool* sp, kg_u32 slot, kg_u32 body)
{
    kg_shape_id h = KG_NULL_SHAPE_INIT;
    int alive = slot != KG_NULL_INDEX && (int)slot < sp->high_water && kg_shape_alive(sp, (int)slot);
    if (alive && sp->body[slot] == body) {
        h.index = slot;
        h.generation = sp->generation[slot];
    }
    return h;
}

kg_result kg_world_get_contact(const kg_world* world, int index, kg_contact_info* out)
{
    if (world) {
        kg_sync_contacts(world);
    }
    if (!world || !out || index < 0 || index >= world->collision->count) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "contact index %d out of range", index);
    }
    kg_contact_info_of(world, &world->collision->contacts[index], out);
    return KG_OK;
}

void kg_contact_info_of(const kg_world* world, const kg_contact* c, kg_contact_info* out)
{
    memset(out, 0, sizeof *out);
    out->a = kg_handle_of(c->a, c->generation_a);
    out->b = kg_handle_of(c->b, c->generation_b);
    out->shape_a = kg_shape_handle_of(&world->shapes, c->shape_a, c->a);
    out->shape_b = kg_shape_handle_of(&world->shapes, c->shape_b, c->b);
    out->normal = c->manifold.normal;
    out->point_count = c->manifold.point_count;
    for (int k = 0; k < c->manifold.point_count; ++k) {
        const kg_manifold_point* mp = &c->manifold.points[k];
        out->points[k] = mp->point;
        out->depths[k] = -mp->separation;
        out->normal_impulses[k] = mp->normal_impulse;
        out->tangent_impulses[k] = mp->tangent_impulse;
        out->total_normal_impulses[k] = mp->total_normal_impulse;
        out->feature_ids[k] = mp->id;
    }
}

/* A pass over the step's contacts: a body's are not listed apart (a body pair's contact is
 * found by its lower slot, which the list is sorted by, but b's by a search of it all). */
kg_result kg_body_get_contacts(const kg_world* world, kg_body body, kg_contact_info* out, int capacity, int* count)
{
    if (!count || capacity < 0 || (capacity > 0 && !out)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_body_get_contacts: bad arguments");
    }
    *count = 0;
    if (kg_world_resolve(world, body) < 0) {
        return kg_last_result();
    }
    int n = 0;
    const kg_contact* contacts = kg_collision_synced_contacts(world, &n);
    for (int k = 0; k < n; ++k) {
        const kg_contact* c = &contacts[k];
        int mine = (c->a == body.index && c->generation_a == body.generation) ||
                   (c->b == body.index && c->generation_b == body.generation);
        if (mine && *count < capacity) {
            KG_TRY(kg_world_get_contact(world, k, &out[*count]));
        }
        *count += mine;
    }
    return KG_OK;
}

/* ---- snapshots (core/snapshot.c) ---------------------------------------------------- */

/* The contact list's counts and flags, in the order a snapshot holds them. */
enum { KG_SNAP_COUNT, KG_SNAP_BODY_COUNT, KG_SNAP_BY_SHAPES, KG_SNAP_SHAPES_KNOWN, KG_SNAP_CAPACITY, KG_SNAP_BUDGET,
       KG_SNAP_WORDS };

void kg_collision_snapshot(const kg_world* world, kg_snap_out* out)
{
    const struct kg_collision* c = world->collision;
    int words[KG_SNAP_WORDS] = {c->count, c->body_count, c->by_shapes, c->shapes_known, c->capacity, c->budget};
    kg_snap_put(out, words, sizeof words);
    kg_snap_put_u32(out, c->shapes_version);
    kg_snap_put(out, c->contacts, (size_t)c->count * sizeof *c->contacts);
}

/* Whether contact c names bodies and shapes inside the pools' capacities and holds at most two points. */
static int kg_contact_sane(const kg_contact* c, kg_u32 bodies, kg_u32 shapes, int tile)
{
    int points = c->manifold.point_count >= 0 && c->manifold.point_count <= 2;
    if (tile) {
        return points && c->a < bodies && c->b == KG_NULL_INDEX;
    }
    return points && c->a < bodies && c->b < bodies && c->a < c->b && c->shape_a < shapes && c->shape_b < shapes;
}

void kg_collision_discard(struct kg_collision* staged)
{
    if (staged) {
        kg_free_buffers(staged);
        kg_free(staged);
    }
}

kg_result kg_collision_from_snapshot(const kg_world* world, kg_snap_in* in, int shape_capacity,
                                     struct kg_collision** out)
{
    *out = NULL;
    int w[KG_SNAP_WORDS] = {0};
    kg_snap_take_array(in, w, sizeof w[0], KG_SNAP_WORDS, "contact list");
    kg_u32 shapes_version = kg_snap_take_u32(in, "contact list");
    int count = w[KG_SNAP_COUNT], body_count = w[KG_SNAP_BODY_COUNT];
    if (!in->failed && (count < 0 || body_count < 0 || body_count > count ||
                        !kg_snap_has(in, sizeof(kg_contact), (uint64_t)count))) {
        kg_snap_reject(in, "contact counts");
    }
    if (in->failed) {
        return KG_ERROR_INVALID_ARGUMENT;
    }
    /* The pool's capacity and budget (which the buffer's bytes do not back) are held to
     * the world's own budget or 8 contacts a body, whichever is more: they only say how
     * far the pool grows before it grows again, not what a step computes. */
    int64_t most = kg_max_i64(kg_max_i64((int64_t)world->collision->budget, 8 * (int64_t)world->def.max_bodies + 64),
                              (int64_t)count);
    int capacity = (int)kg_clamp_i64(w[KG_SNAP_CAPACITY], kg_max_i64(count, 1), most);
    w[KG_SNAP_BUDGET] = (int)kg_clamp_i64(w[KG_SNAP_BUDGET], 1, most);
    struct kg_collision* c = kg_alloc_zeroed(sizeof *c);
    if (!c) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the collision state");
    }
    size_t n = (size_t)capacity;
    c->pairs = kg_alloc_zeroed(n * sizeof *c->pairs);
    c->block_touching = kg_alloc_zeroed(kg_block_count(n) * sizeof *c->block_touching);
    c->contacts = kg_alloc_zeroed(n * sizeof *c->contacts);
    c->previous = kg_alloc_zeroed(n * sizeof *c->previous);
    c->kept_colors = kg_alloc_zeroed(n * sizeof *c->kept_colors);
    if (!c->pairs || !c->block_touching || !c->contacts || !c->previous || !c->kept_colors) {
        kg_collision_discard(c);
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate room for %d contacts", capacity);
    }
    c->count = count;
    c->body_count = body_count;
    c->by_shapes = w[KG_SNAP_BY_SHAPES] != 0;
    c->shapes_known = w[KG_SNAP_SHAPES_KNOWN] != 0;
    c->capacity = capacity;
    c->budget = w[KG_SNAP_BUDGET];
    c->shapes_version = shapes_version;
    c->found_count = -1;
    kg_snap_take_array(in, c->contacts, sizeof *c->contacts, (size_t)c->count, "contacts");
    for (int k = 0; !in->failed && k < c->count; ++k) {
        if (!kg_contact_sane(&c->contacts[k], (kg_u32)world->def.max_bodies, (kg_u32)shape_capacity,
                             k >= c->body_count)) {
            kg_snap_reject(in, "a contact's bodies, shapes or points");
        }
    }
    if (in->failed) {
        kg_collision_discard(c);
        return KG_ERROR_INVALID_ARGUMENT;
    }
    *out = c;
    return KG_OK;
}

void kg_collision_adopt(kg_world* world, struct kg_collision* staged)
{
    struct kg_collision* old = world->collision;
    staged->broadphase = old->broadphase; /* its arrays are per body slot; what it saw is searched again */
    staged->shape_index = old->shape_index;
    old->broadphase = NULL;
    old->shape_index = NULL;
    kg_shape_index_forget(staged->shape_index);
    kg_collision_discard(old);
    world->collision = staged;
    world->def.max_contacts = staged->capacity;
}
