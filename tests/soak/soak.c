/* kg_soak: steps random scenes for a long time with bodies and applicators added and
 * removed all the time, and fails when anything drifts (issue 9, `make soak`).
 *
 *   kg_soak [--seconds N] [--seed N] [--first-round N] [--no-memory-check]
 *
 * Rounds follow each other until the time is up. A round is a world from a fixed cycle
 * of configurations (capacities, sub-steps, threads), a container on a wide ground, and
 * a few thousand steps during which bodies of every type and shape rain in, are kicked,
 * teleported and destroyed, applicators come and go, and now and then the pool is
 * filled until it reports KG_ERROR_POOL_FULL. Checked:
 *  - every state read back is finite, and no body is ever frozen (inputs are sane, so
 *    a frozen body means the step produced a NaN or an infinity);
 *  - no energy blow-up: the mechanical energy of the scene (kinetic and potential)
 *    stays within what the scene was given (a fall from the ceiling under the strongest
 *    gravity, a spawn speed, a kick, the wind and the contact push-out per kilogram);
 *    no body runs away faster than SOAK_RUNAWAY_SPEED; no body falls through the ground;
 *  - handles: a full pool answers KG_ERROR_POOL_FULL and the world goes on; slot
 *    generations are moved close to their end so that they wrap during the run; a
 *    handle never has generation 0 and a destroyed body's handle never works again;
 *  - memory: the resident set size, sampled every second, stays after the first cycle
 *    of configurations within the peak of that cycle (plus a small margin); left out
 *    with --no-memory-check (under AddressSanitizer, whose quarantine grows the RSS on
 *    its own). Leaks are checked by running this program under LeakSanitizer
 *    (scripts/soak.sh).
 * Every round depends only on the seed and its number, so a failure, reported as
 * "seed S round R step N", is replayed by kg_soak --seed S --first-round R.
 * Prints a summary; exit status 1 on any failure. */
#include "core/body_pool.h"
#include "core/world.h"
#include "kgyro/kgyro.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define SOAK_GRAVITY 10.0f
#define SOAK_EXTRA_GRAVITY 1.0f /* the most one gravity applicator adds, downwards */
#define SOAK_MAX_APPLICATORS 8
#define SOAK_ARENA_HEIGHT 30.0f /* bodies spawn and are teleported below this */
#define SOAK_CEILING 100.0f     /* bodies above (a wind with an upward part lifts light ones) are recycled */
#define SOAK_SPAWN_SPEED 5.0f
#define SOAK_PLATFORM_LOWEST 14.0f /* kinematic bodies move above the walls (12 m high) */
#define SOAK_KICK_SPEED 8.0f
#define SOAK_WIND_TERMINAL 4.0f /* strength / drag of every wind */
#define SOAK_PUSH_OUT_SPEED 3.0f /* kg_world_def.max_push_out_speed, the default */
/* Energy per kg a body can be given: a fall from the ceiling under gravity and every
 * applicator, the fastest spawn, kick, wind and push-out. Contacts move energy between
 * bodies but must not add to the total. */
#define SOAK_ENERGY_PER_KG                                                                           \
    ((SOAK_GRAVITY + SOAK_MAX_APPLICATORS * SOAK_EXTRA_GRAVITY) * SOAK_CEILING +                     \
     0.5f * (SOAK_SPAWN_SPEED * SOAK_SPAWN_SPEED + SOAK_KICK_SPEED * SOAK_KICK_SPEED +              \
             SOAK_WIND_TERMINAL * SOAK_WIND_TERMINAL + SOAK_PUSH_OUT_SPEED * SOAK_PUSH_OUT_SPEED))
/* Far beyond what a light body can get from a heavy one in a pile, far below the
 * max_linear_speed clamp (400 m/s) that would hide a real explosion. */
#define SOAK_RUNAWAY_SPEED 150.0f
#define SOAK_ARENA_BODIES 3
#define SOAK_STEPS_PER_ROUND 3000
#define SOAK_STALE_KEPT 256
#define SOAK_RSS_MARGIN_KB (8 * 1024)
#define SOAK_ROUNDS_LISTED 16
#define DT (1.0f / 60.0f)

typedef struct soak_config {
    int max_bodies;
    int max_applicators;
    int substeps;
    int threads;
} soak_config;

/* The cycle of configurations: the first pass through it sets the memory baseline. */
static const soak_config kConfigs[] = {
    {64, 4, 4, 1}, {512, SOAK_MAX_APPLICATORS, 4, 2}, {200, 2, 8, 1}, {1024, SOAK_MAX_APPLICATORS, 2, 2},
    {32, 1, 1, 1}, {300, 6, 6, 2},
};
#define CONFIG_COUNT ((int)(sizeof kConfigs / sizeof kConfigs[0]))

typedef struct soak_stats {
    long seed, first_round;
    long rounds, steps, created, destroyed, pool_full, wraps, kicks, applicators_added, wandered_off;
    long failures;
    long failed_rounds[SOAK_ROUNDS_LISTED]; /* the first rounds that failed, to replay */
    int failed_round_count;
    float fastest;
    long rss_baseline_kb, rss_peak_kb;
} soak_stats;

typedef struct soak_rng {
    uint64_t state;
} soak_rng;

typedef struct soak {
    soak_rng r;
    kg_world* world;
    const soak_config* config;
    int step; /* in the round */
    kg_body* live; /* the live dynamic, kinematic and particle bodies (statics apart) */
    int live_count;
    kg_body stale[SOAK_STALE_KEPT];
    int stale_count;
    kg_applicator* applicators;
    int applicator_count;
    uint32_t* last_generation; /* per slot, to count wraps */
    kg_vec2 platform_velocity; /* of every kinematic body of the round */
    soak_stats* stats;
} soak;

static uint32_t soak_next(soak_rng* r)
{
    r->state = r->state * 6364136223846793005ull + 1442695040888963407ull;
    uint64_t x = r->state ^ (r->state >> 33);
    x *= 0xff51afd7ed558ccdull;
    return (uint32_t)(x ^ (x >> 33));
}

static int soak_below(soak* s, int n) { return (int)(soak_next(&s->r) % (uint32_t)n); }
static int soak_chance(soak* s, int per_mille) { return soak_below(s, 1000) < per_mille; }
static float soak_range(soak* s, float lo, float hi)
{
    return lo + (hi - lo) * (float)(soak_next(&s->r) >> 8) / 16777216.0f;
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static long rss_kb(void)
{
    FILE* f = fopen("/proc/self/statm", "r");
    long pages = 0, resident = 0;
    if (f) {
        if (fscanf(f, "%ld %ld", &pages, &resident) != 2) {
            resident = 0;
        }
        fclose(f);
    }
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

static void note_failed_round(soak_stats* st)
{
    int n = st->failed_round_count;
    if (n < SOAK_ROUNDS_LISTED && (n == 0 || st->failed_rounds[n - 1] != st->rounds)) {
        st->failed_rounds[st->failed_round_count++] = st->rounds;
    }
}

static void fail(soak* s, const char* what)
{
    note_failed_round(s->stats);
    if (s->stats->failures++ < 20) {
        fprintf(stderr, "kg_soak: seed %ld round %ld step %d: %s\n", s->stats->seed, s->stats->rounds, s->step, what);
    }
}

/* ---- building ---------------------------------------------------------------------- */

static void add_static_box(soak* s, kg_vec2 position, float width, float height)
{
    kg_body_def d = kg_default_body_def();
    d.type = KG_BODY_STATIC;
    d.position = position;
    d.shape = kg_box_shape(width, height);
    kg_body b;
    if (kg_create_body(s->world, &d, &b) != KG_OK) {
        fail(s, "a static box of the arena was refused");
    }
}

/* A container 24 m wide on a 400 m ground, so that what spills over lands on ground. */
static void build_arena(soak* s)
{
    add_static_box(s, (kg_vec2){0.0f, -1.0f}, 400.0f, 2.0f);
    add_static_box(s, (kg_vec2){-12.5f, 6.0f}, 1.0f, 12.0f);
    add_static_box(s, (kg_vec2){12.5f, 6.0f}, 1.0f, 12.0f);
}

static kg_shape_def random_shape(soak* s)
{
    float size = soak_range(s, 0.2f, 0.8f);
    switch (soak_below(s, 4)) {
    case 0: return kg_circle_shape(0.5f * size);
    case 1: return kg_box_shape(size, soak_range(s, 0.2f, 0.8f));
    case 2: {
        kg_vec2 v[KG_MAX_POLYGON_VERTICES];
        int n = 3 + soak_below(s, 6);
        for (int i = 0; i < n; ++i) {
            float a = 6.2831853f * ((float)i + soak_range(s, 0.0f, 0.5f)) / (float)n;
            v[i] = (kg_vec2){0.5f * size * cosf(a), 0.5f * size * sinf(a)};
        }
        return kg_polygon_shape(v, n);
    }
    default: return kg_offset_box_shape(size, 0.3f, (kg_vec2){0.1f, 0.0f}, soak_range(s, -1.0f, 1.0f));
    }
}

static kg_body_def random_body(soak* s)
{
    kg_body_def d = kg_default_body_def();
    int kind = soak_below(s, 100);
    d.type = kind < 80 ? KG_BODY_DYNAMIC : kind < 95 ? KG_BODY_PARTICLE : KG_BODY_KINEMATIC;
    d.shape = random_shape(s);
    d.position = (kg_vec2){soak_range(s, -11.0f, 11.0f), soak_range(s, 12.0f, SOAK_ARENA_HEIGHT - 2.0f)};
    d.angle = d.type == KG_BODY_PARTICLE ? 0.0f : soak_range(s, -3.0f, 3.0f);
    float speed = SOAK_SPAWN_SPEED / 1.5f;
    d.velocity = (kg_vec2){soak_range(s, -speed, speed), soak_range(s, -speed, speed)};
    d.angular_velocity = d.type == KG_BODY_PARTICLE ? 0.0f : soak_range(s, -2.0f, 2.0f);
    d.density = soak_range(s, 0.5f, 5.0f); /* with the sizes: masses up to 200x apart */
    d.friction = soak_range(s, 0.0f, 1.0f);
    d.restitution = soak_chance(s, 200) ? soak_range(s, 0.0f, 0.8f) : 0.0f;
    d.linear_damping = soak_chance(s, 300) ? soak_range(s, 0.0f, 0.5f) : 0.0f;
    d.fixed_rotation = soak_chance(s, 50);
    if (d.type == KG_BODY_KINEMATIC) {
        /* A moving platform above the walls, all of a round's platforms at the same
         * velocity, not turning: an infinite mass driven into the ground, a wall or
         * another platform rightly crushes what lies between, which no solver can
         * resolve (the soak found bodies pushed through the ground and ejected at 150 m/s). */
        d.position.y = soak_range(s, SOAK_PLATFORM_LOWEST, SOAK_ARENA_HEIGHT - 2.0f);
        d.velocity = s->platform_velocity;
        d.angular_velocity = 0.0f;
    }
    return d;
}

/* ---- handles ----------------------------------------------------------------------- */

/* Handles of a slot kept in the stale ring are forgotten when the slot is aged: aging
 * stands for four billion reuses, after which a generation may legitimately repeat. */
static void forget_stale_of_slot(soak* s, uint32_t slot)
{
    for (int i = 0; i < SOAK_STALE_KEPT; ++i) {
        if (s->stale[i].index == slot) {
            s->stale[i] = (kg_body)KG_NULL_BODY_INIT;
        }
    }
}

/* Moves the generation of a free slot near its end, so that slot churn wraps it. */
static void age_free_slots(soak* s)
{
    kg_body_pool* p = &s->world->bodies;
    for (int i = 0; i < p->high_water; ++i) {
        if (!kg_pool_alive(p, i) && soak_chance(s, 100)) {
            p->generation[i] = UINT32_MAX - (uint32_t)soak_below(s, 4);
            forget_stale_of_slot(s, (uint32_t)i);
        }
    }
}

static void note_generation(soak* s, kg_body h)
{
    if (h.generation == 0u) {
        fail(s, "a new handle has generation 0");
    }
    if (h.generation < s->last_generation[h.index]) {
        s->stats->wraps++;
    }
    s->last_generation[h.index] = h.generation;
}

static int spawn(soak* s)
{
    kg_body_def d = random_body(s);
    kg_body h;
    kg_result r = kg_create_body(s->world, &d, &h);
    if (r == KG_ERROR_POOL_FULL) {
        s->stats->pool_full++;
        return 0;
    }
    if (r != KG_OK) {
        fail(s, kg_last_error());
        return 0;
    }
    note_generation(s, h);
    s->live[s->live_count++] = h;
    s->stats->created++;
    return 1;
}

static void destroy_at(soak* s, int k)
{
    kg_body h = s->live[k];
    if (kg_destroy_body(s->world, h) != KG_OK) {
        fail(s, "a live body could not be destroyed");
    }
    s->live[k] = s->live[--s->live_count];
    s->stale[s->stale_count++ % SOAK_STALE_KEPT] = h;
    s->stats->destroyed++;
}

/* Fills the pool: the call after the last free slot must answer POOL_FULL. */
static void fill_pool(soak* s)
{
    while (spawn(s)) {
    }
    if (kg_world_body_count(s->world) != s->config->max_bodies + SOAK_ARENA_BODIES) {
        fail(s, "the pool reported full before max_bodies");
    }
}

static void check_stale_handles(soak* s)
{
    int kept = s->stale_count < SOAK_STALE_KEPT ? s->stale_count : SOAK_STALE_KEPT;
    for (int i = 0; i < kept; ++i) {
        kg_vec2 p;
        if (kg_body_is_valid(s->world, s->stale[i]) ||
            kg_body_get_position(s->world, s->stale[i], &p) != KG_ERROR_INVALID_HANDLE) {
            fail(s, "a destroyed body's handle works again");
        }
    }
}

/* ---- applicators ------------------------------------------------------------------- */

/* A user applicator: a small random sideways acceleration on every seventh body (a
 * force in proportion to the mass, so light bodies do not gain more energy). */
static void nudge(kg_world* world, const kg_body* bodies, int count, void* user_data)
{
    soak* s = user_data;
    for (int i = 0; i < count; i += 7) {
        kg_mass_data md;
        if (kg_body_get_mass_data(world, bodies[i], &md) == KG_OK) {
            kg_body_apply_force_to_center(world, bodies[i], (kg_vec2){md.mass * soak_range(s, -0.5f, 0.5f), 0.0f});
        }
    }
}

static void add_applicator(soak* s)
{
    kg_applicator a;
    kg_body some[3];
    int count = s->live_count >= 3 && soak_chance(s, 500) ? 3 : 0;
    for (int i = 0; i < count; ++i) {
        some[i] = s->live[soak_below(s, s->live_count)];
    }
    kg_result r;
    switch (soak_below(s, 3)) {
    case 0:
        r = kg_add_gravity_applicator(s->world, (kg_vec2){0.0f, -soak_range(s, 0.0f, SOAK_EXTRA_GRAVITY)}, some, count,
                                      &a);
        break;
    case 1: {
        float strength = soak_range(s, 0.5f, 2.0f);
        r = kg_add_wind_applicator(s->world, (kg_vec2){soak_range(s, -1.0f, 1.0f), 0.2f}, strength,
                                   strength / SOAK_WIND_TERMINAL, some, count, &a);
        break;
    }
    default: r = kg_add_force_applicator(s->world, nudge, some, count, s, &a); break;
    }
    if (r == KG_OK) {
        s->applicators[s->applicator_count++] = a;
        s->stats->applicators_added++;
    } else if (r != KG_ERROR_POOL_FULL || s->applicator_count < s->config->max_applicators) {
        fail(s, "an applicator was refused with room left");
    }
}

static void remove_applicator(soak* s)
{
    int k = soak_below(s, s->applicator_count);
    if (kg_remove_applicator(s->world, s->applicators[k]) != KG_OK) {
        fail(s, "a live applicator could not be removed");
    }
    kg_applicator gone = s->applicators[k];
    s->applicators[k] = s->applicators[--s->applicator_count];
    if (kg_remove_applicator(s->world, gone) != KG_ERROR_INVALID_HANDLE) {
        fail(s, "a removed applicator's handle works again");
    }
}

/* ---- churn ------------------------------------------------------------------------- */

static void kick(soak* s)
{
    kg_body h = s->live[soak_below(s, s->live_count)];
    kg_body_type type;
    kg_mass_data md;
    kg_vec2 origin;
    if (kg_body_get_type(s->world, h, &type) != KG_OK || kg_body_get_mass_data(s->world, h, &md) != KG_OK ||
        kg_body_get_position(s->world, h, &origin) != KG_OK) {
        fail(s, "a live body cannot be read");
        return;
    }
    if (type == KG_BODY_DYNAMIC || type == KG_BODY_PARTICLE) {
        /* at the body origin, close to its centre of mass: a kick, not a spin */
        float dv = SOAK_KICK_SPEED / 1.5f;
        kg_vec2 impulse = {md.mass * soak_range(s, -dv, dv), md.mass * soak_range(s, 0.0f, dv)};
        kg_body_set_velocity(s->world, h, (kg_vec2){0.0f, 0.0f});
        kg_body_set_angular_velocity(s->world, h, 0.0f);
        kg_body_apply_impulse(s->world, h, impulse, origin);
        s->stats->kicks++;
    }
}

static void churn(soak* s)
{
    if (s->live_count > 0 && soak_chance(s, 150)) {
        destroy_at(s, soak_below(s, s->live_count));
    }
    if (soak_chance(s, 160)) {
        spawn(s);
    }
    if (s->live_count > 0 && soak_chance(s, 20)) {
        kick(s);
    }
    if (s->live_count > 0 && soak_chance(s, 5)) {
        kg_body h = s->live[soak_below(s, s->live_count)];
        kg_body_type type = KG_BODY_DYNAMIC;
        kg_body_get_type(s->world, h, &type);
        kg_body_set_transform(s->world, h, (kg_vec2){soak_range(s, -10.0f, 10.0f), 25.0f}, 0.0f);
        kg_body_set_velocity(s->world, h, type == KG_BODY_KINEMATIC ? s->platform_velocity : (kg_vec2){0.0f, 0.0f});
    }
    if (soak_chance(s, 4)) {
        if (s->applicator_count > 0 && soak_chance(s, 500)) {
            remove_applicator(s);
        } else {
            add_applicator(s);
        }
    }
    if (soak_chance(s, 1)) {
        fill_pool(s);
    }
    if (s->live_count > 0 && soak_chance(s, 2)) {
        while (s->live_count > s->config->max_bodies / 4) {
            destroy_at(s, soak_below(s, s->live_count));
        }
        age_free_slots(s);
    }
}

/* ---- checks ------------------------------------------------------------------------ */

static int state_finite(const kg_body_state* st)
{
    return isfinite(st->position.x) && isfinite(st->position.y) && isfinite(st->angle) && isfinite(st->velocity.x) &&
           isfinite(st->velocity.y) && isfinite(st->angular_velocity);
}

/* Fell through the ground (bodies that wander off sideways are recycled before). */
static int fell_through(const kg_body_state* st) { return st->position.y < -3.0f; }

static void check_bodies(soak* s)
{
    double energy = 0.0, budget = 0.0;
    for (int k = 0; k < s->live_count; ++k) {
        kg_body_state st;
        kg_mass_data md;
        kg_body_type type;
        if (kg_body_get_state(s->world, s->live[k], &st) != KG_OK ||
            kg_body_get_mass_data(s->world, s->live[k], &md) != KG_OK ||
            kg_body_get_type(s->world, s->live[k], &type) != KG_OK) {
            fail(s, "a live body cannot be read");
            continue;
        }
        if (!state_finite(&st)) {
            fail(s, "a body state is not finite");
            continue;
        }
        if (type == KG_BODY_KINEMATIC) {
            continue; /* it moves at its own constant velocity, through everything */
        }
        float speed = hypotf(st.velocity.x, st.velocity.y);
        s->stats->fastest = fmaxf(s->stats->fastest, speed);
        if (speed > SOAK_RUNAWAY_SPEED) {
            fail(s, "a body runs away");
        }
        if (fell_through(&st)) {
            fail(s, "a body fell through the ground");
        }
        energy += 0.5 * md.mass * (double)speed * speed + 0.5 * md.inertia * (double)st.angular_velocity * st.angular_velocity +
                  md.mass * (double)SOAK_GRAVITY * st.position.y;
        budget += md.mass * (double)SOAK_ENERGY_PER_KG;
    }
    if (energy > budget) {
        fail(s, "the energy of the scene exceeds the energy it was given");
    }
}

/* With sane inputs no body may ever be frozen (body.h): a frozen body means the step
 * produced a NaN or an infinity. */
static void check_none_frozen(soak* s)
{
    for (int k = 0; k < s->live_count; ++k) {
        if (kg_body_is_frozen(s->world, s->live[k])) {
            fail(s, "a body was frozen: the step produced a non-finite state");
            return;
        }
    }
}

/* Bodies that wander far from the container (kinematic movers, bodies spilled and
 * blown along the ground) are replaced before they reach the ground's end. */
static void recycle_wanderers(soak* s)
{
    for (int k = s->live_count - 1; k >= 0; --k) {
        kg_vec2 p;
        if (kg_body_get_position(s->world, s->live[k], &p) == KG_OK && (fabsf(p.x) > 100.0f || p.y > SOAK_CEILING)) {
            destroy_at(s, k);
            s->stats->wandered_off++;
        }
    }
}

/* ---- rounds ------------------------------------------------------------------------ */

static void sample_memory(soak* s, int in_baseline_cycle)
{
    long kb = rss_kb();
    if (in_baseline_cycle) {
        s->stats->rss_baseline_kb = kb > s->stats->rss_baseline_kb ? kb : s->stats->rss_baseline_kb;
    } else {
        s->stats->rss_peak_kb = kb > s->stats->rss_peak_kb ? kb : s->stats->rss_peak_kb;
    }
}

static kg_world* create_world(const soak_config* c)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.gravity = (kg_vec2){0.0f, -SOAK_GRAVITY};
    def.max_bodies = c->max_bodies + SOAK_ARENA_BODIES;
    def.max_applicators = c->max_applicators;
    def.substeps = c->substeps;
    def.threads = c->threads;
    kg_world* w = NULL;
    return kg_create_world(&def, &w) == KG_OK ? w : NULL;
}

static void run_round(soak_stats* stats, double deadline, double* next_sample)
{
    soak s;
    memset(&s, 0, sizeof s);
    s.r.state = (uint64_t)stats->seed * 0x9E3779B97F4A7C15ull + (uint64_t)stats->rounds;
    s.stats = stats;
    s.config = &kConfigs[stats->rounds % CONFIG_COUNT];
    s.platform_velocity = (kg_vec2){soak_range(&s, -1.0f, 1.0f), 0.0f};
    s.world = create_world(s.config);
    s.live = calloc((size_t)s.config->max_bodies + SOAK_ARENA_BODIES, sizeof *s.live);
    s.applicators = calloc((size_t)s.config->max_applicators + 1, sizeof *s.applicators);
    s.last_generation = calloc((size_t)s.config->max_bodies + SOAK_ARENA_BODIES, sizeof *s.last_generation);
    if (!s.world || !s.live || !s.applicators || !s.last_generation) {
        fail(&s, "cannot create the round's world");
    } else {
        build_arena(&s);
        for (s.step = 0; s.step < SOAK_STEPS_PER_ROUND && now_seconds() < deadline; ++s.step) {
            churn(&s);
            if (kg_world_step(s.world, DT) != KG_OK) {
                fail(&s, "kg_world_step failed");
            }
            stats->steps++;
            check_bodies(&s);
            check_none_frozen(&s);
            recycle_wanderers(&s);
            if (s.step % 97 == 0) {
                check_stale_handles(&s);
            }
            if (now_seconds() >= *next_sample) {
                sample_memory(&s, stats->rounds < stats->first_round + CONFIG_COUNT);
                *next_sample += 1.0;
            }
        }
    }
    kg_destroy_world(s.world);
    free(s.live);
    free(s.applicators);
    free(s.last_generation);
    stats->rounds++;
}

static void print_summary(const soak_stats* st, double seconds)
{
    printf("kg_soak: %.0f s, %ld rounds, %ld steps, %ld bodies created, %ld destroyed (%ld wandered off),\n"
           "         %ld pool-full answers, %ld generation wraps, %ld kicks, %ld applicators added,\n"
           "         fastest body %.1f m/s (runaway above %.0f), RSS %ld kB after the first cycle, %ld kB at most\n"
           "         later, %ld failures\n",
           seconds, st->rounds - st->first_round, st->steps, st->created, st->destroyed, st->wandered_off, st->pool_full, st->wraps,
           st->kicks, st->applicators_added, (double)st->fastest, (double)SOAK_RUNAWAY_SPEED, st->rss_baseline_kb,
           st->rss_peak_kb, st->failures);
    for (int i = 0; i < st->failed_round_count; ++i) {
        printf("%s%ld", i == 0 ? "kg_soak: failing rounds (kg_soak --seed N --first-round R): " : ", ",
               st->failed_rounds[i]);
    }
    if (st->failed_round_count > 0) {
        printf("\n");
    }
}

int main(int argc, char** argv)
{
    double seconds = 60.0;
    long seed = 1, first_round = 0;
    int check_memory = 1;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) {
            seconds = atof(argv[++i]);
        } else if (strcmp(argv[i], "--seed") == 0 && i + 1 < argc) {
            seed = atol(argv[++i]);
        } else if (strcmp(argv[i], "--first-round") == 0 && i + 1 < argc) {
            first_round = atol(argv[++i]);
        } else if (strcmp(argv[i], "--no-memory-check") == 0) {
            check_memory = 0;
        } else {
            fprintf(stderr, "usage: kg_soak [--seconds N] [--seed N] [--first-round N] [--no-memory-check]\n");
            return 2;
        }
    }
    soak_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.seed = seed;
    stats.first_round = first_round;
    stats.rounds = first_round;
    double start = now_seconds(), deadline = start + seconds, next_sample = start;
    while (now_seconds() < deadline) {
        run_round(&stats, deadline, &next_sample);
    }
    int memory_grew = check_memory && stats.rounds > first_round + CONFIG_COUNT &&
                      stats.rss_peak_kb > stats.rss_baseline_kb + SOAK_RSS_MARGIN_KB;
    if (memory_grew) {
        fprintf(stderr, "kg_soak: the resident set grew from %ld kB to %ld kB\n", stats.rss_baseline_kb,
                stats.rss_peak_kb);
    }
    print_summary(&stats, now_seconds() - start);
    return stats.failures == 0 && !memory_grew ? 0 : 1;
}
