/* Abuse of the public API, and the numerical safety of the step (issue 9).
 *
 * test_random_call_sequences runs thousands of random sequences of public calls with
 * random and hostile arguments (NaN, infinities, 1e30, 1e-30, FLT_MAX, zero and negative
 * sizes, stale, foreign, null and garbage handles, NULL pointers) against a model of
 * the world that knows which bodies and applicators are alive. For every call the model
 * says what the answer must be: with no bad argument the call succeeds (or reports a
 * full pool) and its effect is visible through the getters; with exactly one bad
 * argument it fails with that argument's code; with several it fails with one of their
 * codes. A failing call leaves a message and changes nothing. After each sequence the
 * world must still step, and every body state must be finite.
 *
 * The other tests pin down single behaviours: the code for a NULL world, generation
 * wrap-around, frozen non-finite bodies that do not poison their neighbours, the speed
 * limits and extreme mass ratios. This test runs in the ASan+UBSan build too, where
 * "no crash" also means no sanitizer report. */
#include "kg_test.h"
#include "core/error.h"
#include "core/world.h"
#include "kgyro/kgyro.h"
#include "solve/integrate.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#define SEQUENCES 20000
#define CALLS_PER_SEQUENCE 80
#define MAX_MODEL_BODIES 48
#define MAX_MODEL_APPLICATORS 6
#define STALE_KEPT 16
#define REPORTS_SHOWN 25
#define DT (1.0f / 60.0f)

/* ---- random numbers and hostile values --------------------------------------------- */

typedef struct rng {
    uint64_t state;
} rng;

static uint32_t rng_next(rng* r)
{
    r->state = r->state * 6364136223846793005ull + 1442695040888963407ull;
    uint64_t x = r->state;
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdull;
    x ^= x >> 33;
    return (uint32_t)x;
}

static int rng_below(rng* r, int n) { return (int)(rng_next(r) % (uint32_t)n); }
static int rng_chance(rng* r, int percent) { return rng_below(r, 100) < percent; }
static float rng_range(rng* r, float lo, float hi) { return lo + (hi - lo) * (float)(rng_next(r) >> 8) / 16777216.0f; }

static const float kHostileFloats[] = {NAN,    INFINITY, -INFINITY, 1.0e30f, -1.0e30f, 1.0e-30f, -1.0e-30f,
                                       0.0f,   -0.0f,    FLT_MAX,   -FLT_MAX, 1.0e-45f, -1.0f};
#define HOSTILE_COUNT ((int)(sizeof kHostileFloats / sizeof kHostileFloats[0]))

/* A value in [lo, hi], or now and then one of the hostile values. */
static float any_float(rng* r, float lo, float hi)
{
    return rng_chance(r, 15) ? kHostileFloats[rng_below(r, HOSTILE_COUNT)] : rng_range(r, lo, hi);
}

static kg_vec2 any_vec(rng* r, float lo, float hi) { return (kg_vec2){any_float(r, lo, hi), any_float(r, lo, hi)}; }

static int finite2(kg_vec2 v) { return isfinite(v.x) && isfinite(v.y); }
static int non_negative(float v) { return isfinite(v) && v >= 0.0f; }

/* ---- expected answers -------------------------------------------------------------- */

/* A set of acceptable results, one bit per kg_result (KG_OK is bit 0). */
typedef unsigned result_set;
#define RESULT_BIT(code) (1u << (unsigned)(-(int)(code)))

/* The bad arguments of one call. With none the call must succeed; with one it must fail
 * with that code; with several, with one of theirs. uncertain adds results the model
 * cannot decide (a mass that underflows at some densities and not at others). */
typedef struct faults {
    int count;
    result_set codes;
    result_set uncertain;
} faults;

static void fault_if(faults* f, int bad, kg_result code)
{
    if (bad) {
        f->count++;
        f->codes |= RESULT_BIT(code);
    }
}

static result_set expected_results(faults f, kg_result success)
{
    return f.count > 0 ? f.codes : RESULT_BIT(success) | f.uncertain;
}

/* ---- the model --------------------------------------------------------------------- */

typedef struct model_body {
    kg_body handle;
    kg_body_type type;
    void* user_data;
} model_body;

typedef struct model_applicator {
    kg_applicator handle;
    int is_user;
} model_applicator;

typedef struct sequence {
    rng r;
    int seed;
    int call;
    kg_world* world;
    kg_world* other; /* a second world: its handles are foreign here */
    int max_bodies, max_applicators;
    model_body bodies[MAX_MODEL_BODIES];
    int body_count;
    kg_body stale[STALE_KEPT];
    int stale_count;
    kg_body other_bodies[4];
    int other_count;
    model_applicator applicators[MAX_MODEL_APPLICATORS];
    int applicator_count;
    kg_applicator stale_applicators[STALE_KEPT];
    int stale_applicator_count;
    int destroyed_since_step;
    long callbacks_seen, callbacks_expected;
} sequence;

static int g_reports;
static int g_chains_made; /* kg_create_chain calls that succeeded: the test must make some */
static char g_user_tags[MAX_MODEL_BODIES * 4];

/* Counts a disagreement with the model; prints the first few with their seed. */
static void report(const sequence* s, const char* call, const char* what)
{
    kg_test_failures++;
    if (g_reports++ < REPORTS_SHOWN) {
        fprintf(stderr, "seed %d call %d: %s: %s\n", s->seed, s->call, call, what);
    }
}

/* Checks a call's result against the expected set; a failure must leave a message. */
static int check_result(const sequence* s, const char* call, kg_result got, result_set expected)
{
    char what[256];
    int in_range = (int)got <= 0 && (int)got >= -9;
    if (!in_range || !(expected & RESULT_BIT(got))) {
        snprintf(what, sizeof what, "returned %d (%s: %s), which the model does not allow (allowed set 0x%x)",
                 (int)got, kg_result_string(got), kg_last_error(), expected);
        report(s, call, what);
        return 0;
    }
    if (got != KG_OK && kg_last_error()[0] == '\0') {
        snprintf(what, sizeof what, "returned %d without a message", (int)got);
        report(s, call, what);
    }
    return 1;
}

static void check_true(const sequence* s, const char* call, int ok, const char* what)
{
    if (!ok) {
        report(s, call, what);
    }
}

static int model_find(const sequence* s, kg_body h)
{
    for (int i = 0; i < s->body_count; ++i) {
        if (s->bodies[i].handle.index == h.index && s->bodies[i].handle.generation == h.generation) {
            return i;
        }
    }
    return -1;
}

static void remember_stale(sequence* s, kg_body h)
{
    s->stale[s->stale_count % STALE_KEPT] = h;
    s->stale_count++;
}

/* A handle of any kind; the model alone decides whether it names a live body. */
static kg_body pick_handle(sequence* s)
{
    int kind = rng_below(&s->r, 100);
    if (kind < 60 && s->body_count > 0) {
        return s->bodies[rng_below(&s->r, s->body_count)].handle;
    }
    if (kind < 75 && s->stale_count > 0) {
        int kept = s->stale_count < STALE_KEPT ? s->stale_count : STALE_KEPT;
        return s->stale[rng_below(&s->r, kept)];
    }
    if (kind < 85 && s->other_count > 0) {
        return s->other_bodies[rng_below(&s->r, s->other_count)];
    }
    if (kind < 92) {
        return (kg_body){0u, 0u};
    }
    return (kg_body){rng_next(&s->r) % 64u, rng_next(&s->r) % 4u};
}

/* The world most calls get: now and then NULL. */
static kg_world* pick_world(sequence* s) { return rng_chance(&s->r, 4) ? NULL : s->world; }

/* ---- snapshots: a failing call changes nothing -------------------------------------- */

typedef struct snapshot {
    int valid;
    int frozen; /* body.h: forces and impulses on a frozen body are ignored */
    kg_body_state state;
    float inv_mass, inv_inertia;
    int body_count;
} snapshot;

static snapshot take_snapshot(const sequence* s, kg_body h)
{
    snapshot snap;
    memset(&snap, 0, sizeof snap);
    snap.body_count = kg_world_body_count(s->world);
    snap.valid = model_find(s, h) >= 0;
    if (snap.valid) {
        kg_body_get_state(s->world, h, &snap.state);
        kg_body_get_inverse_mass(s->world, h, &snap.inv_mass, &snap.inv_inertia);
        snap.frozen = kg_body_is_frozen(s->world, h);
    }
    return snap;
}

static void check_unchanged(const sequence* s, const char* call, kg_body h, const snapshot* before)
{
    snapshot after = take_snapshot(s, h);
    int same = after.body_count == before->body_count && after.valid == before->valid &&
               memcmp(&after.state, &before->state, sizeof after.state) == 0 &&
               memcmp(&after.inv_mass, &before->inv_mass, sizeof after.inv_mass) == 0 &&
               memcmp(&after.inv_inertia, &before->inv_inertia, sizeof after.inv_inertia) == 0;
    check_true(s, call, same, "a failing call changed the world");
}

/* ---- body definitions ---------------------------------------------------------------- */

typedef enum shape_class {
    SHAPE_VALID,
    SHAPE_BAD_ARGUMENT,   /* NaN or infinite size, radius <= 0, unknown type */
    SHAPE_DEGENERATE,     /* no area, vertex count out of range */
    SHAPE_HUGE,           /* 1e30 m: its mass is not representable */
    SHAPE_TINY_CIRCLE,    /* radius 1e-30: its mass underflows at ordinary densities */
    SHAPE_POINT
} shape_class;

static kg_shape_def regular_polygon(int count, float radius)
{
    kg_vec2 v[KG_MAX_POLYGON_VERTICES];
    for (int i = 0; i < count; ++i) {
        float a = 6.2831853f * (float)i / (float)count;
        v[i] = (kg_vec2){radius * cosf(a), radius * sinf(a)};
    }
    return kg_polygon_shape(v, count);
}

static kg_shape_def random_shape(rng* r, shape_class* cls)
{
    static const float kBadSizes[] = {NAN, INFINITY, -INFINITY};
    static const int kBadCounts[] = {-1, 0, 1, 2, 9, 1000};
    float a = rng_range(r, 0.1f, 2.0f), b = rng_range(r, 0.1f, 2.0f);
    switch (rng_below(r, 14)) {
    case 0: *cls = SHAPE_BAD_ARGUMENT; return kg_box_shape(kBadSizes[rng_below(r, 3)], b);
    case 1: *cls = SHAPE_BAD_ARGUMENT; return kg_circle_shape(rng_chance(r, 50) ? -a : 0.0f);
    case 2: *cls = SHAPE_BAD_ARGUMENT; return kg_circle_shape(kBadSizes[rng_below(r, 3)]);
    case 3: {
        *cls = SHAPE_BAD_ARGUMENT;
        kg_shape_def bad = kg_box_shape(a, b);
        bad.type = (kg_shape_type)(rng_chance(r, 50) ? 7 : -1);
        return bad;
    }
    case 4: *cls = SHAPE_DEGENERATE; return kg_box_shape(0.0f, b);
    case 5: *cls = SHAPE_DEGENERATE; return kg_box_shape(1.0e-30f, 1.0e-30f);
    case 6: {
        *cls = SHAPE_DEGENERATE;
        kg_shape_def poly = regular_polygon(4, a);
        poly.count = kBadCounts[rng_below(r, 6)];
        return poly;
    }
    case 7: *cls = SHAPE_HUGE; return kg_box_shape(1.0e30f, 1.0e30f);
    case 8: *cls = SHAPE_TINY_CIRCLE; return kg_circle_shape(1.0e-30f);
    case 9: {
        *cls = SHAPE_POINT;
        kg_shape_def point;
        memset(&point, 0, sizeof point);
        point.type = KG_SHAPE_NONE;
        return point;
    }
    case 10: *cls = SHAPE_VALID; return regular_polygon(3 + rng_below(r, 6), a);
    case 11: *cls = SHAPE_VALID; return kg_circle_shape(a);
    case 12: { /* a box of negative width is refused, not taken as its mirror image */
        int negative = rng_chance(r, 20);
        *cls = negative ? SHAPE_DEGENERATE : SHAPE_VALID;
        return kg_box_shape(negative ? -a : a, b);
    }
    default: *cls = SHAPE_VALID; return kg_offset_box_shape(a, b, (kg_vec2){rng_range(r, -1, 1), 0.5f}, a);
    }
}

static const float kMassValues[] = {NAN, INFINITY, -INFINITY, -1.0f, 0.0f, 1.0e-30f, 1.0e30f};

static float random_mass_value(rng* r, float sane)
{
    return rng_chance(r, 25) ? kMassValues[rng_below(r, 7)] : sane;
}

static kg_body_def random_body_def(sequence* s, shape_class* cls)
{
    rng* r = &s->r;
    kg_body_def d = kg_default_body_def();
    d.type = rng_chance(r, 5) ? (kg_body_type)(rng_chance(r, 50) ? -1 : 4 + rng_below(r, 100))
                              : (kg_body_type)rng_below(r, 4);
    d.position = any_vec(r, -20.0f, 20.0f);
    d.angle = any_float(r, -4.0f, 4.0f);
    d.velocity = any_vec(r, -10.0f, 10.0f);
    d.angular_velocity = any_float(r, -10.0f, 10.0f);
    d.shape = random_shape(r, cls);
    d.density = random_mass_value(r, rng_range(r, 0.1f, 5.0f));
    d.mass = rng_chance(r, 30) ? random_mass_value(r, rng_range(r, 0.1f, 5.0f)) : 0.0f;
    d.friction = any_float(r, 0.0f, 1.0f);
    d.restitution = rng_chance(r, 10) ? rng_range(r, -1.0f, 2.0f) : any_float(r, 0.0f, 1.0f);
    d.linear_damping = any_float(r, 0.0f, 1.0f);
    d.angular_damping = any_float(r, 0.0f, 1.0f);
    d.category = rng_next(r);
    d.mask = rng_next(r);
    d.fixed_rotation = rng_chance(r, 20);
    d.user_data = &g_user_tags[rng_below(r, (int)sizeof g_user_tags)];
    return d;
}

static int moves(kg_body_type t) { return t == KG_BODY_DYNAMIC || t == KG_BODY_PARTICLE; }

static void shape_faults(faults* f, shape_class cls, kg_body_type type, int type_ok)
{
    result_set shape_codes = RESULT_BIT(KG_ERROR_INVALID_ARGUMENT) | RESULT_BIT(KG_ERROR_DEGENERATE_SHAPE);
    if (cls == SHAPE_BAD_ARGUMENT) {
        fault_if(f, 1, KG_ERROR_INVALID_ARGUMENT);
    } else if (cls == SHAPE_DEGENERATE) {
        fault_if(f, 1, KG_ERROR_DEGENERATE_SHAPE);
    } else if (cls == SHAPE_HUGE) {
        /* a moving body's mass cannot be represented; a static one's shape is unusable
         * in float, but whether it is refused is left to the hull builder */
        if (type_ok && moves(type)) {
            f->count++;
            f->codes |= shape_codes;
        } else {
            f->uncertain |= shape_codes;
        }
    } else if (cls == SHAPE_TINY_CIRCLE && type_ok && moves(type)) {
        f->uncertain |= RESULT_BIT(KG_ERROR_INVALID_ARGUMENT);
    } else if (cls == SHAPE_POINT) {
        fault_if(f, type_ok && type == KG_BODY_DYNAMIC, KG_ERROR_INVALID_ARGUMENT); /* static, kinematic: no shape */
    }
}

/* What kg_create_body must answer for d: the rules of body.h, one fault per field. */
static faults body_def_faults(const kg_body_def* d, shape_class cls)
{
    faults f = {0, 0, 0};
    int type_ok = d->type >= KG_BODY_STATIC && d->type <= KG_BODY_PARTICLE;
    fault_if(&f, !type_ok, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, !finite2(d->position) || !isfinite(d->angle), KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, !finite2(d->velocity) || !isfinite(d->angular_velocity), KG_ERROR_INVALID_ARGUMENT);
    int mass_values_ok = non_negative(d->density) && non_negative(d->mass);
    fault_if(&f, !mass_values_ok, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, !non_negative(d->friction), KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, !(d->restitution >= 0.0f && d->restitution <= 1.0f), KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, !non_negative(d->linear_damping) || !non_negative(d->angular_damping), KG_ERROR_INVALID_ARGUMENT);
    shape_faults(&f, cls, d->type, type_ok);
    if (type_ok && mass_values_ok && moves(d->type)) {
        int needs_mass = cls == SHAPE_POINT ? !(d->mass > 0.0f) : !(d->mass > 0.0f) && !(d->density > 0.0f);
        fault_if(&f, needs_mass, KG_ERROR_INVALID_ARGUMENT);
    }
    return f;
}

/* ---- checks of visible effects ------------------------------------------------------- */

static int near(float a, float b, float tol) { return fabsf(a - b) <= tol * (1.0f + fabsf(b)); }

static void check_pose(const sequence* s, const char* call, kg_body h, kg_vec2 position, float angle, kg_body_type t)
{
    kg_body_state st;
    kg_body_get_state(s->world, h, &st);
    check_true(s, call, near(st.position.x, position.x, 1e-4f) && near(st.position.y, position.y, 1e-4f),
               "the position read back is not the one set");
    float expected_angle = t == KG_BODY_PARTICLE ? 0.0f : angle;
    check_true(s, call,
               fabsf(cosf(st.angle) - cosf(expected_angle)) < 1e-4f &&
                   fabsf(sinf(st.angle) - sinf(expected_angle)) < 1e-4f,
               "the angle read back is not the one set");
}

static void check_created(sequence* s, const kg_body_def* d, kg_body h)
{
    const char* call = "kg_create_body";
    check_true(s, call, h.generation != 0 && kg_body_is_valid(s->world, h), "the new handle is not valid");
    kg_body_type type = KG_BODY_STATIC;
    kg_body_get_type(s->world, h, &type);
    check_true(s, call, type == d->type, "the type read back differs");
    check_true(s, call, kg_body_get_user_data(s->world, h) == d->user_data, "the user data read back differs");
    check_pose(s, call, h, d->position, d->angle, d->type);
    kg_body_state st;
    kg_body_get_state(s->world, h, &st);
    kg_vec2 v = d->type == KG_BODY_STATIC ? (kg_vec2){0.0f, 0.0f} : d->velocity;
    float w = (d->type == KG_BODY_STATIC || d->type == KG_BODY_PARTICLE) ? 0.0f : d->angular_velocity;
    check_true(s, call, st.velocity.x == v.x && st.velocity.y == v.y && st.angular_velocity == w,
               "the velocities read back differ");
}

/* ---- the calls ------------------------------------------------------------------------ */

static void call_create_body(sequence* s)
{
    shape_class cls;
    kg_body_def d = random_body_def(s, &cls);
    kg_world* w = pick_world(s);
    int def_null = rng_chance(&s->r, 3), out_null = rng_chance(&s->r, 3);
    faults f = def_null ? (faults){0, 0, 0} : body_def_faults(&d, cls);
    fault_if(&f, w == NULL, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, def_null, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, out_null, KG_ERROR_INVALID_ARGUMENT);
    int full = s->body_count >= s->max_bodies;
    int before = kg_world_body_count(s->world);
    kg_body h = KG_NULL_BODY_INIT;
    kg_result r = kg_create_body(w, def_null ? NULL : &d, out_null ? NULL : &h);
    check_result(s, "kg_create_body", r, expected_results(f, full ? KG_ERROR_POOL_FULL : KG_OK));
    if (r != KG_OK) {
        check_true(s, "kg_create_body", kg_world_body_count(s->world) == before, "a refused body was added");
        return;
    }
    s->bodies[s->body_count++] = (model_body){h, d.type, d.user_data};
    check_created(s, &d, h);
}

/* kg_create_chain: a zigzag of sane points, or one spoiled (too few, a non-finite or a
 * repeated point, a bad material), on any handle; only a static or kinematic body holds
 * one, and then it has a shape more a segment. */
static void call_create_chain(sequence* s)
{
    rng* r = &s->r;
    kg_vec2 points[40];
    kg_chain_def def = kg_default_chain_def();
    def.loop = rng_chance(r, 30);
    def.count = 1 + rng_below(r, 40);
    kg_vec2 at = {rng_range(r, -20.0f, 20.0f), rng_range(r, -20.0f, 20.0f)};
    for (int i = 0; i < def.count; ++i) {
        at.x += rng_range(r, 0.1f, 2.0f);
        at.y += rng_range(r, -1.0f, 1.0f);
        points[i] = at;
    }
    def.points = points;
    faults f = {0, 0, 0};
    fault_if(&f, def.count < (def.loop ? 3 : 2), KG_ERROR_INVALID_ARGUMENT);
    switch (rng_below(r, 8)) {
    case 0: points[rng_below(r, def.count)].y = kHostileFloats[rng_below(r, 3)]; fault_if(&f, 1, KG_ERROR_INVALID_ARGUMENT); break;
    case 1: def.friction = rng_chance(r, 50) ? -1.0f : NAN; fault_if(&f, 1, KG_ERROR_INVALID_ARGUMENT); break;
    case 2: def.restitution = 1.5f; fault_if(&f, 1, KG_ERROR_INVALID_ARGUMENT); break;
    case 3:
        if (def.count >= 2) {
            int i = 1 + rng_below(r, def.count - 1);
            points[i] = points[i - 1];
            fault_if(&f, 1, KG_ERROR_DEGENERATE_SHAPE);
        }
        break;
    default: break;
    }
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    int found = model_find(s, h), def_null = rng_chance(r, 3);
    fault_if(&f, w == NULL || def_null, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, found < 0, KG_ERROR_INVALID_HANDLE);
    if (found >= 0) {
        kg_body_type type = s->bodies[found].type;
        fault_if(&f, type != KG_BODY_STATIC && type != KG_BODY_KINEMATIC, KG_ERROR_INVALID_ARGUMENT);
    }
    int before = kg_body_shape_count(s->world, h);
    kg_result result = kg_create_chain(w, h, def_null ? NULL : &def, NULL);
    check_result(s, "kg_create_chain", result, expected_results(f, KG_OK));
    int segments = result == KG_OK ? (def.loop ? def.count : def.count - 1) : 0;
    g_chains_made += result == KG_OK;
    check_true(s, "kg_create_chain", kg_body_shape_count(s->world, h) == before + segments,
               "the body's shapes are not its old ones and the chain's segments");
}

static void call_destroy_body(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    int found = model_find(s, h);
    faults f = {0, 0, 0};
    fault_if(&f, w == NULL, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, found < 0, KG_ERROR_INVALID_HANDLE);
    kg_result r = kg_destroy_body(w, h);
    check_result(s, "kg_destroy_body", r, expected_results(f, KG_OK));
    if (r == KG_OK && found >= 0) {
        s->bodies[found] = s->bodies[--s->body_count];
        remember_stale(s, h);
        s->destroyed_since_step = 1;
        check_true(s, "kg_destroy_body", !kg_body_is_valid(s->world, h), "a destroyed handle is still valid");
    }
}

/* The faults every body setter shares: the world and the handle. */
static faults handle_faults(const sequence* s, const kg_world* w, kg_body h, int* found)
{
    faults f = {0, 0, 0};
    *found = model_find(s, h);
    fault_if(&f, w == NULL, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, *found < 0, KG_ERROR_INVALID_HANDLE);
    return f;
}

static void call_set_transform(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    kg_vec2 p = any_vec(&s->r, -30.0f, 30.0f);
    float a = any_float(&s->r, -10.0f, 10.0f);
    int found;
    faults f = handle_faults(s, w, h, &found);
    fault_if(&f, !finite2(p) || !isfinite(a), KG_ERROR_INVALID_ARGUMENT);
    snapshot before = take_snapshot(s, h);
    kg_result r = kg_body_set_transform(w, h, p, a);
    check_result(s, "kg_body_set_transform", r, expected_results(f, KG_OK));
    if (r == KG_OK) {
        check_pose(s, "kg_body_set_transform", h, p, a, s->bodies[found].type);
    } else {
        check_unchanged(s, "kg_body_set_transform", h, &before);
    }
}

static void call_set_velocity(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    kg_vec2 v = any_vec(&s->r, -20.0f, 20.0f);
    int found;
    faults f = handle_faults(s, w, h, &found);
    fault_if(&f, !finite2(v), KG_ERROR_INVALID_ARGUMENT);
    snapshot before = take_snapshot(s, h);
    kg_result r = kg_body_set_velocity(w, h, v);
    check_result(s, "kg_body_set_velocity", r, expected_results(f, KG_OK));
    if (r != KG_OK) {
        check_unchanged(s, "kg_body_set_velocity", h, &before);
        return;
    }
    kg_vec2 got;
    kg_body_get_velocity(s->world, h, &got);
    kg_vec2 want = s->bodies[found].type == KG_BODY_STATIC ? (kg_vec2){0.0f, 0.0f} : v;
    check_true(s, "kg_body_set_velocity", got.x == want.x && got.y == want.y, "the velocity read back differs");
}

static void call_set_angular_velocity(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    float omega = any_float(&s->r, -20.0f, 20.0f);
    int found;
    faults f = handle_faults(s, w, h, &found);
    fault_if(&f, !isfinite(omega), KG_ERROR_INVALID_ARGUMENT);
    snapshot before = take_snapshot(s, h);
    kg_result r = kg_body_set_angular_velocity(w, h, omega);
    check_result(s, "kg_body_set_angular_velocity", r, expected_results(f, KG_OK));
    if (r != KG_OK) {
        check_unchanged(s, "kg_body_set_angular_velocity", h, &before);
        return;
    }
    float got = NAN;
    kg_body_get_angular_velocity(s->world, h, &got);
    kg_body_type t = s->bodies[found].type;
    float want = (t == KG_BODY_DYNAMIC || t == KG_BODY_KINEMATIC) ? omega : 0.0f;
    check_true(s, "kg_body_set_angular_velocity", got == want, "the angular velocity read back differs");
}

static void call_set_inverse_mass(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    float inv_mass = any_float(&s->r, 0.0f, 2.0f), inv_inertia = any_float(&s->r, 0.0f, 2.0f);
    int found;
    faults f = handle_faults(s, w, h, &found);
    int values_ok = non_negative(inv_mass) && non_negative(inv_inertia);
    fault_if(&f, !values_ok, KG_ERROR_INVALID_ARGUMENT);
    kg_body_type t = found >= 0 ? s->bodies[found].type : KG_BODY_DYNAMIC;
    fault_if(&f, w && found >= 0 && values_ok && !moves(t), KG_ERROR_INVALID_ARGUMENT);
    snapshot before = take_snapshot(s, h);
    kg_result r = kg_body_set_inverse_mass(w, h, inv_mass, inv_inertia);
    check_result(s, "kg_body_set_inverse_mass", r, expected_results(f, KG_OK));
    if (r != KG_OK) {
        check_unchanged(s, "kg_body_set_inverse_mass", h, &before);
        return;
    }
    float got_mass = NAN, got_inertia = NAN;
    kg_body_get_inverse_mass(s->world, h, &got_mass, &got_inertia);
    float want_inertia = t == KG_BODY_PARTICLE ? 0.0f : inv_inertia;
    check_true(s, "kg_body_set_inverse_mass", got_mass == inv_mass && got_inertia == want_inertia,
               "the inverse mass read back differs");
}

/* Friction, restitution, damping and filter: no getters, so only the answers. */
static void call_set_material(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    int found;
    faults f = handle_faults(s, w, h, &found);
    float a = any_float(&s->r, 0.0f, 1.0f), b = any_float(&s->r, 0.0f, 1.0f);
    kg_result r;
    const char* call;
    snapshot before = take_snapshot(s, h);
    switch (rng_below(&s->r, 4)) {
    case 0:
        call = "kg_body_set_friction";
        fault_if(&f, !non_negative(a), KG_ERROR_INVALID_ARGUMENT);
        r = kg_body_set_friction(w, h, a);
        break;
    case 1:
        call = "kg_body_set_restitution";
        a = rng_chance(&s->r, 30) ? rng_range(&s->r, -1.0f, 2.0f) : a;
        fault_if(&f, !(a >= 0.0f && a <= 1.0f), KG_ERROR_INVALID_ARGUMENT);
        r = kg_body_set_restitution(w, h, a);
        break;
    case 2:
        call = "kg_body_set_damping";
        fault_if(&f, !non_negative(a) || !non_negative(b), KG_ERROR_INVALID_ARGUMENT);
        r = kg_body_set_damping(w, h, a, b);
        break;
    default:
        call = "kg_body_set_filter";
        r = kg_body_set_filter(w, h, rng_next(&s->r), rng_next(&s->r));
        break;
    }
    check_result(s, call, r, expected_results(f, KG_OK));
    if (r != KG_OK) {
        check_unchanged(s, call, h, &before);
    }
}

/* Forces and torques accumulate unseen until the step: only the answers. */
static void call_apply_force(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    int found;
    faults f = handle_faults(s, w, h, &found);
    kg_vec2 force = any_vec(&s->r, -100.0f, 100.0f), point = any_vec(&s->r, -20.0f, 20.0f);
    float torque = any_float(&s->r, -100.0f, 100.0f);
    kg_result r;
    const char* call;
    switch (rng_below(&s->r, 3)) {
    case 0:
        call = "kg_body_apply_force";
        fault_if(&f, !finite2(force) || !finite2(point), KG_ERROR_INVALID_ARGUMENT);
        r = kg_body_apply_force(w, h, force, point);
        break;
    case 1:
        call = "kg_body_apply_force_to_center";
        fault_if(&f, !finite2(force), KG_ERROR_INVALID_ARGUMENT);
        r = kg_body_apply_force_to_center(w, h, force);
        break;
    default:
        call = "kg_body_apply_torque";
        fault_if(&f, !isfinite(torque), KG_ERROR_INVALID_ARGUMENT);
        r = kg_body_apply_torque(w, h, torque);
        break;
    }
    check_result(s, call, r, expected_results(f, KG_OK));
}

/* Whether a finite impulse could make the velocity overflow, or the moment r x J
 * computed on the way (the lever arm is taken from the body origin, hence the margin
 * below FLT_MAX). */
static int impulse_may_overflow(const snapshot* before, kg_vec2 impulse, kg_vec2 point)
{
    double j = hypot(impulse.x, impulse.y);
    double r = hypot((double)point.x - before->state.position.x, (double)point.y - before->state.position.y);
    double linear = hypot(before->state.velocity.x, before->state.velocity.y) + before->inv_mass * j;
    double angular = fabs(before->state.angular_velocity) + before->inv_inertia * r * j;
    return !(linear < 1.0e37 && r * j < 1.0e37 && angular < 1.0e37);
}

static void call_apply_impulse(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    int found;
    faults f = handle_faults(s, w, h, &found);
    kg_vec2 impulse = any_vec(&s->r, -10.0f, 10.0f), point = any_vec(&s->r, -20.0f, 20.0f);
    fault_if(&f, !finite2(impulse) || !finite2(point), KG_ERROR_INVALID_ARGUMENT);
    snapshot before = take_snapshot(s, h);
    if (before.valid && impulse_may_overflow(&before, impulse, point)) {
        f.uncertain |= RESULT_BIT(KG_ERROR_INVALID_ARGUMENT); /* refusing it is fair too */
    }
    kg_result r = kg_body_apply_impulse(w, h, impulse, point);
    check_result(s, "kg_body_apply_impulse", r, expected_results(f, KG_OK));
    if (r != KG_OK) {
        check_unchanged(s, "kg_body_apply_impulse", h, &before);
        return;
    }
    kg_vec2 v;
    kg_body_get_velocity(s->world, h, &v);
    float want_x = before.frozen ? before.state.velocity.x : before.state.velocity.x + before.inv_mass * impulse.x;
    if (isfinite(want_x)) {
        check_true(s, "kg_body_apply_impulse", near(v.x, want_x, 1e-5f), "the impulse did not change the velocity");
    }
}

static void call_apply_angular_impulse(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    int found;
    faults f = handle_faults(s, w, h, &found);
    float impulse = any_float(&s->r, -10.0f, 10.0f);
    fault_if(&f, !isfinite(impulse), KG_ERROR_INVALID_ARGUMENT);
    snapshot before = take_snapshot(s, h);
    double spin = fabs(before.state.angular_velocity) + before.inv_inertia * fabs((double)impulse);
    if (before.valid && !(spin < 1.0e37)) {
        f.uncertain |= RESULT_BIT(KG_ERROR_INVALID_ARGUMENT); /* refusing an overflow is fair too */
    }
    kg_result r = kg_body_apply_angular_impulse(w, h, impulse);
    check_result(s, "kg_body_apply_angular_impulse", r, expected_results(f, KG_OK));
    if (r != KG_OK) {
        check_unchanged(s, "kg_body_apply_angular_impulse", h, &before);
        return;
    }
    float omega = NAN;
    kg_body_get_angular_velocity(s->world, h, &omega);
    float want = before.frozen ? before.state.angular_velocity : before.state.angular_velocity + before.inv_inertia * impulse;
    if (isfinite(want)) {
        check_true(s, "kg_body_apply_angular_impulse", near(omega, want, 1e-5f),
                   "the angular impulse did not change the angular velocity");
    }
}

/* Sleeping: a woken body is awake, and no more bodies sleep than live. */
static void call_wake(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    int found;
    faults f = handle_faults(s, w, h, &found);
    kg_result r = kg_body_wake(w, h);
    check_result(s, "kg_body_wake", r, expected_results(f, KG_OK));
    check_true(s, "kg_body_is_awake", kg_body_is_awake(w, h) == (r == KG_OK),
               "a body is awake after kg_body_wake exactly when the call succeeded");
    int asleep = kg_world_asleep_count(w);
    check_true(s, "kg_world_asleep_count", asleep >= 0 && asleep <= (w ? kg_world_body_count(w) : 0),
               "more bodies asleep than alive");
}

/* One of the per-body getters, maybe with a NULL output. */
static void call_getter(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body h = pick_handle(s);
    int found;
    faults f = handle_faults(s, w, h, &found);
    int out_null = rng_chance(&s->r, 10);
    fault_if(&f, out_null, KG_ERROR_INVALID_ARGUMENT);
    union {
        kg_body_state state;
        kg_vec2 v;
        float x;
        kg_body_type type;
        kg_shape_def shape;
        kg_mass_data mass;
        kg_aabb box;
    } out;
    void* o = out_null ? NULL : &out;
    float spare;
    int second_null = rng_chance(&s->r, 30);
    kg_result r;
    switch (rng_below(&s->r, 10)) {
    case 0: r = kg_body_get_state(w, h, o); break;
    case 1: r = kg_body_get_position(w, h, o); break;
    case 2: r = kg_body_get_angle(w, h, o); break;
    case 3: r = kg_body_get_velocity(w, h, o); break;
    case 4: r = kg_body_get_angular_velocity(w, h, o); break;
    case 5: r = kg_body_get_shape(w, h, o); break;
    case 6: r = kg_body_get_mass_data(w, h, o); break;
    case 7: r = kg_body_get_aabb(w, h, o); break;
    case 8:
        fault_if(&f, second_null, KG_ERROR_INVALID_ARGUMENT);
        r = kg_body_get_inverse_mass(w, h, o, second_null ? NULL : &spare);
        break;
    default:
        r = kg_body_get_type(w, h, o);
        if (r == KG_OK && found >= 0) {
            check_true(s, "kg_body_get_type", out.type == s->bodies[found].type, "the type differs from the model");
        }
        break;
    }
    check_result(s, "a body getter", r, expected_results(f, KG_OK));
    check_true(s, "kg_body_is_valid", kg_body_is_valid(w, h) == (w != NULL && found >= 0),
               "kg_body_is_valid disagrees with the model");
    void* ud = kg_body_get_user_data(w, h);
    check_true(s, "kg_body_get_user_data", ud == (w && found >= 0 ? s->bodies[found].user_data : NULL),
               "kg_body_get_user_data disagrees with the model");
}

static int handle_before(kg_body a, kg_body b) { return a.index < b.index; }

/* kg_world_get_bodies gives the live handles in slot order. */
static void call_get_bodies(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body out[MAX_MODEL_BODIES];
    int capacity = rng_chance(&s->r, 10) ? -1 - rng_below(&s->r, 3) : rng_below(&s->r, MAX_MODEL_BODIES + 1);
    int out_null = rng_chance(&s->r, 5), count_null = rng_chance(&s->r, 5);
    int count = -1;
    faults f = {0, 0, 0};
    fault_if(&f, w == NULL, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, capacity < 0, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, out_null && capacity > 0, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, count_null, KG_ERROR_INVALID_ARGUMENT);
    kg_result r = kg_world_get_bodies(w, out_null ? NULL : out, capacity, count_null ? NULL : &count);
    check_result(s, "kg_world_get_bodies", r, expected_results(f, KG_OK));
    check_true(s, "kg_world_body_count", kg_world_body_count(s->world) == s->body_count,
               "the body count differs from the model");
    if (r != KG_OK) {
        return;
    }
    int want = capacity < s->body_count ? capacity : s->body_count;
    check_true(s, "kg_world_get_bodies", count == want, "wrong number of handles");
    for (int i = 0; i < count; ++i) {
        check_true(s, "kg_world_get_bodies", model_find(s, out[i]) >= 0, "a handle that is not alive");
        check_true(s, "kg_world_get_bodies", i == 0 || handle_before(out[i - 1], out[i]), "not in slot order");
    }
}

static void call_get_body_states(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body handles[8];
    kg_body_state states[8];
    int count = rng_chance(&s->r, 10) ? -1 : rng_below(&s->r, 9);
    int any_dead = 0;
    for (int i = 0; i < 8; ++i) {
        handles[i] = pick_handle(s);
        any_dead |= i < count && model_find(s, handles[i]) < 0;
    }
    int handles_null = rng_chance(&s->r, 5), out_null = rng_chance(&s->r, 5);
    faults f = {0, 0, 0};
    fault_if(&f, w == NULL, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, count < 0, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, count > 0 && handles_null, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, count > 0 && out_null, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, any_dead && !handles_null, KG_ERROR_INVALID_HANDLE);
    kg_result r = kg_world_get_body_states(w, handles_null ? NULL : handles, count, out_null ? NULL : states);
    check_result(s, "kg_world_get_body_states", r, expected_results(f, KG_OK));
}

static void count_callback(kg_world* world, const kg_body* bodies, int count, void* user_data)
{
    sequence* s = user_data;
    s->callbacks_seen++;
    check_true(s, "applicator callback", world == s->world, "called with another world");
    for (int i = 0; i < count; ++i) {
        check_true(s, "applicator callback", model_find(s, bodies[i]) >= 0, "given a body that is not alive");
    }
    if (count > 0) {
        kg_vec2 push = {rng_range(&s->r, -5.0f, 5.0f), 1.0e30f};
        check_result(s, "kg_body_apply_force_to_center in a callback",
                     kg_body_apply_force_to_center(world, bodies[rng_below(&s->r, count)], push), RESULT_BIT(KG_OK));
    }
}

static int live_user_applicators(const sequence* s)
{
    int n = 0;
    for (int i = 0; i < s->applicator_count; ++i) {
        n += s->applicators[i].is_user;
    }
    return n;
}

static void call_add_applicator(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_body list[4];
    int count = rng_chance(&s->r, 40) ? 0 : (rng_chance(&s->r, 10) ? -1 : 1 + rng_below(&s->r, 4));
    for (int i = 0; i < 4; ++i) {
        list[i] = pick_handle(s); /* dead handles are allowed: they are skipped */
    }
    int list_null = count != 0 && rng_chance(&s->r, 10), out_null = rng_chance(&s->r, 4);
    faults f = {0, 0, 0};
    fault_if(&f, w == NULL, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, count < 0, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, count > 0 && list_null, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, w != NULL && count > s->max_bodies, KG_ERROR_INVALID_ARGUMENT); /* longer than the pool */
    fault_if(&f, out_null, KG_ERROR_INVALID_ARGUMENT);
    const kg_body* bodies = list_null || count == 0 ? NULL : list;
    kg_applicator a = {0u, 0u};
    kg_applicator* out = out_null ? NULL : &a;
    kg_result r;
    int kind = rng_below(&s->r, 3);
    if (kind == 0) {
        kg_vec2 g = any_vec(&s->r, -10.0f, 10.0f);
        fault_if(&f, !finite2(g), KG_ERROR_INVALID_ARGUMENT);
        r = kg_add_gravity_applicator(w, g, bodies, count, out);
    } else if (kind == 1) {
        kg_vec2 dir = rng_chance(&s->r, 15) ? (kg_vec2){0.0f, 0.0f} : any_vec(&s->r, -1.0f, 1.0f);
        float strength = any_float(&s->r, -5.0f, 5.0f), drag = any_float(&s->r, 0.0f, 1.0f);
        double length = hypot((double)dir.x, (double)dir.y);
        fault_if(&f, !finite2(dir) || (length == 0.0 && strength != 0.0f), KG_ERROR_INVALID_ARGUMENT);
        if (length > 0.0 && length < 1.0e-12 && strength != 0.0f) {
            f.uncertain |= RESULT_BIT(KG_ERROR_INVALID_ARGUMENT); /* too short to normalise in float */
        }
        fault_if(&f, !isfinite(strength), KG_ERROR_INVALID_ARGUMENT);
        fault_if(&f, !non_negative(drag), KG_ERROR_INVALID_ARGUMENT);
        r = kg_add_wind_applicator(w, dir, strength, drag, bodies, count, out);
    } else {
        int fn_null = rng_chance(&s->r, 10);
        fault_if(&f, fn_null, KG_ERROR_INVALID_ARGUMENT);
        r = kg_add_force_applicator(w, fn_null ? NULL : count_callback, bodies, count, s, out);
    }
    int full = s->applicator_count >= s->max_applicators;
    check_result(s, "kg_add_*_applicator", r, expected_results(f, full ? KG_ERROR_POOL_FULL : KG_OK));
    if (r == KG_OK && s->applicator_count < MAX_MODEL_APPLICATORS) {
        s->applicators[s->applicator_count++] = (model_applicator){a, kind == 2};
    }
}

static void call_remove_applicator(sequence* s)
{
    kg_world* w = pick_world(s);
    int pick = rng_below(&s->r, 10);
    kg_applicator a = {rng_next(&s->r) % 8u, rng_next(&s->r) % 3u};
    int live = -1;
    if (pick < 5 && s->applicator_count > 0) {
        live = rng_below(&s->r, s->applicator_count);
        a = s->applicators[live].handle;
    } else if (pick < 8 && s->stale_applicator_count > 0) {
        int kept = s->stale_applicator_count < STALE_KEPT ? s->stale_applicator_count : STALE_KEPT;
        a = s->stale_applicators[rng_below(&s->r, kept)];
    }
    for (int i = 0; i < s->applicator_count && live < 0; ++i) {
        live = memcmp(&s->applicators[i].handle, &a, sizeof a) == 0 ? i : -1;
    }
    faults f = {0, 0, 0};
    fault_if(&f, w == NULL, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, live < 0, KG_ERROR_INVALID_HANDLE);
    kg_result r = kg_remove_applicator(w, a);
    check_result(s, "kg_remove_applicator", r, expected_results(f, KG_OK));
    if (r == KG_OK && live >= 0) {
        s->stale_applicators[s->stale_applicator_count++ % STALE_KEPT] = a;
        s->applicators[live] = s->applicators[--s->applicator_count];
    }
}

static float random_dt(rng* r)
{
    static const float kBadDt[] = {NAN, INFINITY, -INFINITY, 0.0f, -0.0f, -DT};
    static const float kOddDt[] = {1.0e-30f, 1.0e-6f, 1.0f, 10.0f};
    int pick = rng_below(r, 100);
    return pick < 8 ? kBadDt[rng_below(r, 6)] : pick < 12 ? kOddDt[rng_below(r, 4)] : DT;
}

static void call_step(sequence* s)
{
    kg_world* w = pick_world(s);
    float dt = random_dt(&s->r);
    faults f = {0, 0, 0};
    fault_if(&f, w == NULL, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, !(isfinite(dt) && dt > 0.0f), KG_ERROR_INVALID_ARGUMENT);
    kg_result r = kg_world_step(w, dt);
    check_result(s, "kg_world_step", r, expected_results(f, KG_OK));
    if (r == KG_OK) {
        s->callbacks_expected += live_user_applicators(s);
        s->destroyed_since_step = 0;
    }
    check_true(s, "applicator callbacks", s->callbacks_seen == s->callbacks_expected,
               "user applicators were not called once per step each");
}

static void call_get_contact(sequence* s)
{
    kg_world* w = pick_world(s);
    int count = kg_world_contact_count(s->world);
    check_true(s, "kg_world_contact_count", kg_world_contact_count(NULL) == 0, "NULL world has contacts");
    int index = rng_below(&s->r, count + 4) - 2;
    int out_null = rng_chance(&s->r, 5);
    faults f = {0, 0, 0};
    fault_if(&f, w == NULL, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, index < 0 || index >= count, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, out_null, KG_ERROR_INVALID_ARGUMENT);
    kg_contact_info info;
    kg_result r = kg_world_get_contact(w, index, out_null ? NULL : &info);
    check_result(s, "kg_world_get_contact", r, expected_results(f, KG_OK));
    if (r == KG_OK && !s->destroyed_since_step) {
        int a = model_find(s, info.a), b = model_find(s, info.b);
        check_true(s, "kg_world_get_contact", a >= 0 && b >= 0 && a != b, "a contact names bodies that are not alive");
    }
}

static void call_world_settings(sequence* s)
{
    kg_world* w = pick_world(s);
    kg_vec2 g = any_vec(&s->r, -20.0f, 20.0f);
    faults f = {0, 0, 0};
    fault_if(&f, w == NULL, KG_ERROR_INVALID_ARGUMENT);
    fault_if(&f, !finite2(g), KG_ERROR_INVALID_ARGUMENT);
    kg_vec2 before = kg_world_get_gravity(s->world);
    kg_result r = kg_world_set_gravity(w, g);
    check_result(s, "kg_world_set_gravity", r, expected_results(f, KG_OK));
    kg_vec2 now = kg_world_get_gravity(s->world);
    kg_vec2 want = r == KG_OK ? g : before;
    check_true(s, "kg_world_get_gravity", now.x == want.x && now.y == want.y, "the gravity read back differs");
    check_true(s, "kg_world_get_def", kg_world_get_def(NULL) == NULL && kg_world_get_def(s->world) != NULL,
               "kg_world_get_def");
    kg_stage_times times;
    check_result(s, "kg_world_get_stage_times", kg_world_get_stage_times(w, rng_chance(&s->r, 10) ? NULL : &times),
                 RESULT_BIT(KG_OK) | RESULT_BIT(KG_ERROR_INVALID_ARGUMENT));
}

/* Bodies of the other world, whose handles are then foreign in this one. */
static void call_other_world(sequence* s)
{
    if (s->other_count < 4) {
        kg_body_def d = kg_default_body_def();
        d.shape = kg_circle_shape(0.5f);
        kg_body h;
        if (kg_create_body(s->other, &d, &h) == KG_OK) {
            s->other_bodies[s->other_count++] = h;
        }
    } else {
        kg_destroy_body(s->other, s->other_bodies[--s->other_count]);
    }
}

typedef void call_fn(sequence* s);

typedef struct weighted_call {
    call_fn* fn;
    int weight;
} weighted_call;

static const weighted_call kCalls[] = {
    {call_create_body, 20},    {call_destroy_body, 8},     {call_set_transform, 6},
    {call_set_velocity, 6},    {call_set_angular_velocity, 4}, {call_set_inverse_mass, 4},
    {call_set_material, 6},    {call_apply_force, 8},      {call_apply_impulse, 4},
    {call_apply_angular_impulse, 3}, {call_getter, 10},    {call_get_bodies, 3},
    {call_get_body_states, 3}, {call_add_applicator, 3},   {call_remove_applicator, 2},
    {call_step, 6},            {call_get_contact, 2},      {call_world_settings, 2},
    {call_other_world, 2},     {call_wake, 2},             {call_create_chain, 3},
};

static call_fn* pick_call(rng* r)
{
    int total = 0;
    for (size_t i = 0; i < sizeof kCalls / sizeof kCalls[0]; ++i) {
        total += kCalls[i].weight;
    }
    int x = rng_below(r, total);
    for (size_t i = 0;; ++i) {
        x -= kCalls[i].weight;
        if (x < 0) {
            return kCalls[i].fn;
        }
    }
}

/* ---- worlds ------------------------------------------------------------------------------ */

static kg_world_def sane_world_def(rng* r)
{
    kg_world_def d = kg_default_world_def();
    d.backend = KG_BACKEND_CPU;
    d.max_bodies = 1 + rng_below(r, MAX_MODEL_BODIES);
    d.max_applicators = rng_below(r, MAX_MODEL_APPLICATORS + 1);
    d.max_contacts = rng_chance(r, 50) ? 0 : 1 + rng_below(r, 100);
    d.substeps = 1 + rng_below(r, 8);
    d.threads = rng_below(r, 3);
    return d;
}

/* One world definition field made hostile, or none; returns the number of faults. */
static int spoil_world_def(rng* r, kg_world_def* d)
{
    float bad = kHostileFloats[rng_below(r, 3)];
    switch (rng_below(r, 18)) {
    case 0: d->gravity.x = bad; return 1;
    case 1: d->max_bodies = -rng_below(r, 3); return 1;
    case 2: d->max_contacts = -1; return 1;
    case 3: d->max_applicators = -1; return 1;
    case 4: d->substeps = -rng_below(r, 2); return 1;
    case 5: d->contact_hertz = rng_chance(r, 50) ? bad : -1.0f; return 1;
    case 6: d->contact_damping_ratio = rng_chance(r, 50) ? 0.0f : bad; return 1;
    case 7: d->max_push_out_speed = -1.0f; return 1;
    case 8: d->restitution_threshold = bad; return 1;
    case 9: d->linear_slop = -0.001f; return 1;
    case 10: d->speculative_distance = bad; return 1;
    case 11: d->max_linear_speed = rng_chance(r, 50) ? 0.0f : bad; return 1;
    case 12: d->backend = (kg_backend)(rng_chance(r, 50) ? -1 : 3 + rng_below(r, 50)); return 1;
    case 13: d->threads = -1; return 1;
    case 14: d->device_index = -1; return 1;
    case 15: d->sleep_speed = rng_chance(r, 50) ? -0.01f : bad; return 1;
    case 16: d->time_to_sleep = rng_chance(r, 50) ? 0.0f : bad; return 1;
    default: return 0;
    }
}

static kg_world* create_world(sequence* s)
{
    kg_world_def d = sane_world_def(&s->r);
    int spoiled = spoil_world_def(&s->r, &d);
    static char unset_marker;
    kg_world* w = (kg_world*)(void*)&unset_marker; /* not NULL, so that a refusal that leaves it shows */
    kg_result r = kg_create_world(&d, &w);
    check_result(s, "kg_create_world", r, RESULT_BIT(spoiled ? KG_ERROR_INVALID_ARGUMENT : KG_OK));
    if (r != KG_OK) {
        check_true(s, "kg_create_world", w == NULL, "a refused world left *out_world set");
        d = sane_world_def(&s->r);
        KG_CHECK_OK(kg_create_world(&d, &w));
    }
    kg_world* scratch = NULL;
    check_true(s, "kg_create_world", kg_create_world(NULL, &scratch) == KG_ERROR_INVALID_ARGUMENT &&
                                         kg_create_world(&d, NULL) == KG_ERROR_INVALID_ARGUMENT,
               "NULL arguments accepted");
    s->max_bodies = d.max_bodies;
    s->max_applicators = d.max_applicators;
    return w;
}

static int state_finite(const kg_body_state* st)
{
    return finite2(st->position) && isfinite(st->angle) && finite2(st->velocity) && isfinite(st->angular_velocity);
}

/* The end of every sequence: the world steps and every state is finite. */
static void check_world_survives(sequence* s)
{
    for (int i = 0; i < 5; ++i) {
        check_true(s, "kg_world_step", kg_world_step(s->world, DT) == KG_OK, "the world no longer steps");
    }
    kg_body handles[MAX_MODEL_BODIES];
    kg_body_state states[MAX_MODEL_BODIES];
    for (int i = 0; i < s->body_count; ++i) {
        handles[i] = s->bodies[i].handle;
    }
    check_true(s, "kg_world_get_body_states",
               kg_world_get_body_states(s->world, handles, s->body_count, states) == KG_OK, "a body was lost");
    for (int i = 0; i < s->body_count; ++i) {
        check_true(s, "after the sequence", state_finite(&states[i]), "a body state is not finite");
    }
    check_true(s, "kg_world_body_count", kg_world_body_count(s->world) == s->body_count, "the body count drifted");
}

static void run_sequence(int seed)
{
    sequence s;
    memset(&s, 0, sizeof s);
    s.seed = seed;
    s.r.state = (uint64_t)seed * 0x9E3779B97F4A7C15ull + 1u;
    s.world = create_world(&s);
    kg_world_def other = kg_default_world_def();
    other.max_bodies = 4;
    other.backend = KG_BACKEND_CPU;
    KG_CHECK_OK(kg_create_world(&other, &s.other));
    for (s.call = 0; s.call < CALLS_PER_SEQUENCE; ++s.call) {
        kg_clear_error(); /* so that a failure's message is its own, not a leftover */
        pick_call(&s.r)(&s);
    }
    check_world_survives(&s);
    kg_destroy_world(s.world);
    kg_destroy_world(s.other);
}

static void test_random_call_sequences(void)
{
    for (int seed = 1; seed <= SEQUENCES; ++seed) {
        run_sequence(seed);
    }
    if (g_reports > REPORTS_SHOWN) {
        fprintf(stderr, "... %d more disagreements with the model\n", g_reports - REPORTS_SHOWN);
    }
    printf("     %d sequences of %d calls, %d chains made\n", SEQUENCES, CALLS_PER_SEQUENCE, g_chains_made);
    KG_CHECK(g_chains_made > 100);
}

/* ---- single behaviours ------------------------------------------------------------------ */

static kg_world* make_world(kg_vec2 gravity, float max_linear_speed)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.max_bodies = 64;
    def.gravity = gravity;
    def.max_linear_speed = max_linear_speed;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

static kg_body add_box(kg_world* w, kg_body_type type, kg_vec2 position, float width, float height, float mass)
{
    kg_body_def d = kg_default_body_def();
    d.type = type;
    d.position = position;
    d.shape = kg_box_shape(width, height);
    d.mass = mass;
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &d, &b));
    return b;
}

static kg_body_state state_of(const kg_world* w, kg_body b)
{
    kg_body_state st;
    memset(&st, 0, sizeof st);
    KG_CHECK_OK(kg_body_get_state(w, b, &st));
    return st;
}

static float speed_of(kg_body_state st) { return hypotf(st.velocity.x, st.velocity.y); }

/* types.h: a NULL where a pointer is needed is KG_ERROR_INVALID_ARGUMENT, the world
 * included; KG_ERROR_INVALID_HANDLE is for handles. */
static void test_null_world_is_an_invalid_argument(void)
{
    kg_body b = {0u, 1u};
    kg_applicator a = {0u, 1u};
    kg_vec2 v = {0.0f, 0.0f};
    KG_CHECK(kg_destroy_body(NULL, b) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_remove_applicator(NULL, a) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_body_set_velocity(NULL, b, v) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_body_get_position(NULL, b, &v) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_step(NULL, DT) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_add_gravity_applicator(NULL, v, NULL, 0, &a) == KG_ERROR_INVALID_ARGUMENT);
}

/* A generation never comes back to 0, so a zeroed handle never names a body, however
 * often a slot is reused. The wrap is reached by moving a free slot's generation to
 * the end of its range rather than by four billion reuses. */
static void test_body_generation_wraps_past_zero(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, 0.0f}, 400.0f);
    kg_body first = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    KG_CHECK_OK(kg_destroy_body(w, first));
    w->bodies.generation[first.index] = UINT32_MAX;
    kg_body last = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    KG_CHECK(last.index == first.index && last.generation == UINT32_MAX);
    KG_CHECK_OK(kg_destroy_body(w, last));
    kg_body wrapped = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    KG_CHECK(wrapped.index == first.index && wrapped.generation != 0u);
    KG_CHECK(!kg_body_is_valid(w, last));
    kg_body zeroed = {first.index, 0u};
    KG_CHECK(!kg_body_is_valid(w, zeroed));
    KG_CHECK(kg_destroy_body(w, zeroed) == KG_ERROR_INVALID_HANDLE);
    kg_destroy_world(w);
}

/* The same for applicators: a zero-initialised kg_applicator must never remove one. */
static void test_applicator_generation_wraps_past_zero(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, 0.0f}, 400.0f);
    w->applicators[0].generation = UINT32_MAX;
    kg_applicator a = {0u, 0u};
    KG_CHECK_OK(kg_add_gravity_applicator(w, (kg_vec2){0.0f, 1.0f}, NULL, 0, &a));
    KG_CHECK(a.index == 0u && a.generation != 0u);
    kg_applicator zeroed = {0u, 0u};
    KG_CHECK(kg_remove_applicator(w, zeroed) == KG_ERROR_INVALID_HANDLE);
    kg_destroy_world(w);
}

/* A wind direction is normalised: any finite, non-zero vector is a direction, long
 * ones too (their squared length overflows a float). */
static void test_wind_accepts_any_finite_direction(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, 0.0f}, 400.0f);
    static const kg_vec2 kDirections[] = {{1.0f, 0.0f}, {3.0e19f, 0.0f}, {1.0e30f, -1.0e30f}, {FLT_MAX, FLT_MAX}};
    for (size_t i = 0; i < sizeof kDirections / sizeof kDirections[0]; ++i) {
        kg_applicator a;
        kg_result r = kg_add_wind_applicator(w, kDirections[i], 1.0f, 0.0f, NULL, 0, &a);
        if (r != KG_OK) {
            fprintf(stderr, "direction (%g, %g) refused: %s\n", (double)kDirections[i].x, (double)kDirections[i].y,
                    kg_last_error());
        }
        KG_CHECK(r == KG_OK && kg_remove_applicator(w, a) == KG_OK);
    }
    kg_destroy_world(w);
}

/* An impulse with a long lever arm on a body that cannot turn (static, kinematic,
 * particle): 0 * inf must not put a NaN in its angular velocity. */
static void test_impulse_on_body_that_cannot_turn_stays_finite(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, 0.0f}, 400.0f);
    kg_body_type types[] = {KG_BODY_STATIC, KG_BODY_KINEMATIC, KG_BODY_PARTICLE};
    for (int i = 0; i < 3; ++i) {
        kg_body b = add_box(w, types[i], (kg_vec2){5.0f * (float)i, 0.0f}, 1.0f, 1.0f, 0.0f);
        kg_result r = kg_body_apply_impulse(w, b, (kg_vec2){0.0f, 1.0e30f}, (kg_vec2){1.0e30f, 0.0f});
        kg_body_state st = state_of(w, b);
        KG_CHECK(r == KG_OK || r == KG_ERROR_INVALID_ARGUMENT);
        KG_CHECK(isfinite(st.angular_velocity) && isfinite(st.velocity.x) && isfinite(st.velocity.y));
    }
    kg_destroy_world(w);
}

/* Forces that overflow: the body's state goes non-finite in the step, and the step
 * freezes it at its last finite pose. */
static void make_non_finite(kg_world* w, kg_body b)
{
    KG_CHECK_OK(kg_body_apply_force_to_center(w, b, (kg_vec2){FLT_MAX, FLT_MAX}));
    KG_CHECK_OK(kg_body_apply_force_to_center(w, b, (kg_vec2){FLT_MAX, FLT_MAX}));
}

/* A frozen body stays where it was, finite, and a body far from it moves exactly as in
 * a world without the fault (nothing shared, such as the broadphase or the solver,
 * carries the NaN across). */
static void test_non_finite_body_is_frozen_and_isolated(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f}, 400.0f);
    kg_world* reference = make_world((kg_vec2){0.0f, -10.0f}, 400.0f);
    kg_body bad = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    kg_body good = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){10.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    add_box(reference, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    kg_body twin = add_box(reference, KG_BODY_DYNAMIC, (kg_vec2){10.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    make_non_finite(w, bad);
    for (int i = 0; i < 30; ++i) {
        KG_CHECK_OK(kg_world_step(w, DT));
        KG_CHECK_OK(kg_world_step(reference, DT));
    }
    KG_CHECK(kg_body_is_frozen(w, bad) && !kg_body_is_frozen(w, good));
    kg_body_state frozen = state_of(w, bad);
    KG_CHECK(frozen.position.x == 0.0f && frozen.position.y == 0.0f && frozen.angle == 0.0f);
    KG_CHECK(frozen.velocity.x == 0.0f && frozen.velocity.y == 0.0f && frozen.angular_velocity == 0.0f);
    kg_body_state a = state_of(w, good), b = state_of(reference, twin);
    KG_CHECK(memcmp(&a, &b, sizeof a) == 0);
    kg_destroy_world(w);
    kg_destroy_world(reference);
}

/* The same with a neighbour resting on the faulty body: it must stay finite and must
 * not be launched, neither in the step where the fault happens nor after. */
static void test_non_finite_body_does_not_poison_its_neighbour(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f}, 400.0f);
    add_box(w, KG_BODY_STATIC, (kg_vec2){0.0f, -0.5f}, 20.0f, 1.0f, 0.0f);
    kg_body bad = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.5f}, 1.0f, 1.0f, 0.0f);
    kg_body neighbour = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 1.5f}, 1.0f, 1.0f, 0.0f);
    for (int i = 0; i < 30; ++i) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    make_non_finite(w, bad);
    float fastest = 0.0f;
    int finite = 1;
    for (int i = 0; i < 60; ++i) {
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_body_state st = state_of(w, neighbour);
        finite &= state_finite(&st);
        fastest = fmaxf(fastest, speed_of(st));
    }
    kg_body_state st = state_of(w, neighbour);
    printf("     neighbour of a frozen body: fastest %.3g m/s, now at y = %.3g\n", (double)fastest,
           (double)st.position.y);
    KG_CHECK(finite);
    KG_CHECK(fastest < 1.0f);
    KG_CHECK(st.position.y > 1.0f && st.position.y < 2.0f);
    kg_destroy_world(w);
}

/* A body frozen by the step must not take a non-finite state back from the API. */
static void test_frozen_body_stays_finite(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f}, 400.0f);
    kg_body b = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    make_non_finite(w, b);
    KG_CHECK_OK(kg_world_step(w, DT));
    kg_body_apply_impulse(w, b, (kg_vec2){FLT_MAX, 0.0f}, (kg_vec2){1.0e30f, 0.0f});
    kg_body_apply_impulse(w, b, (kg_vec2){FLT_MAX, 0.0f}, (kg_vec2){1.0e30f, 0.0f});
    KG_CHECK_OK(kg_world_step(w, DT));
    kg_body_state st = state_of(w, b);
    KG_CHECK(state_finite(&st));
    kg_destroy_world(w);
}

/* The component of v along dir, in double so that a dir near FLT_MAX has a length. */
static double component_along(kg_vec2 v, kg_vec2 dir)
{
    double length = hypot((double)dir.x, (double)dir.y);
    return ((double)v.x * dir.x + (double)v.y * dir.y) / length;
}

/* body.h: setting a frozen body's transform and velocity brings it back, and it moves
 * under gravity again. */
static void test_frozen_body_comes_back(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f}, 400.0f);
    kg_body b = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    make_non_finite(w, b);
    KG_CHECK_OK(kg_world_step(w, DT));
    KG_CHECK(kg_body_is_frozen(w, b));
    KG_CHECK_OK(kg_body_set_transform(w, b, (kg_vec2){0.0f, 5.0f}, 0.0f));
    KG_CHECK_OK(kg_body_set_velocity(w, b, (kg_vec2){0.0f, 0.0f}));
    KG_CHECK(!kg_body_is_frozen(w, b));
    for (int i = 0; i < 10; ++i) {
        KG_CHECK_OK(kg_world_step(w, DT));
    }
    kg_body_state st = state_of(w, b);
    KG_CHECK(!kg_body_is_frozen(w, b) && st.position.y < 5.0f && st.velocity.y < 0.0f);
    kg_destroy_world(w);
}

/* world.h: velocities are clamped to max_linear_speed; the direction is kept. Speeds
 * whose square overflows a float are clamped too, not zeroed. */
static void test_linear_speed_is_clamped(void)
{
    const float limit = 100.0f;
    kg_world* w = make_world((kg_vec2){0.0f, 0.0f}, limit);
    static const kg_vec2 kVelocities[] = {{1000.0f, 0.0f}, {0.0f, -5000.0f}, {1.0e20f, 0.0f}, {FLT_MAX, FLT_MAX}};
    static const kg_body_type kTypes[] = {KG_BODY_DYNAMIC, KG_BODY_PARTICLE, KG_BODY_DYNAMIC, KG_BODY_DYNAMIC};
    kg_body bodies[4];
    for (int i = 0; i < 4; ++i) {
        bodies[i] = add_box(w, kTypes[i], (kg_vec2){20.0f * (float)i, 0.0f}, 1.0f, 1.0f, 0.0f);
        KG_CHECK_OK(kg_body_set_velocity(w, bodies[i], kVelocities[i]));
    }
    KG_CHECK_OK(kg_world_step(w, DT));
    for (int i = 0; i < 4; ++i) {
        kg_body_state st = state_of(w, bodies[i]);
        double along = component_along(st.velocity, kVelocities[i]);
        if (fabsf(speed_of(st) - limit) > 1e-3f * limit) {
            fprintf(stderr, "velocity (%g, %g) became (%g, %g), not %g m/s\n", (double)kVelocities[i].x,
                    (double)kVelocities[i].y, (double)st.velocity.x, (double)st.velocity.y, (double)limit);
        }
        KG_CHECK_NEAR(speed_of(st), limit, 1e-3 * limit);
        KG_CHECK_NEAR(along, limit, 1e-3 * limit);
        KG_CHECK(hypotf(st.position.x - 20.0f * (float)i, st.position.y) <= limit * DT * 1.001f);
    }
    kg_destroy_world(w);
}

/* The rotation per sub-step is limited (integrate.h): the angular rate is clamped to
 * KG_MAX_ROTATION_PER_SUBSTEP / h, keeping its sign, however large it was. */
static void test_angular_rate_is_clamped(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, 0.0f}, 400.0f);
    const float h = DT / (float)kg_world_get_def(w)->substeps;
    const float limit = KG_MAX_ROTATION_PER_SUBSTEP / h;
    static const float kRates[] = {1.0e6f, -1.0e30f, FLT_MAX};
    for (int i = 0; i < 3; ++i) {
        kg_body b = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){5.0f * (float)i, 0.0f}, 1.0f, 1.0f, 0.0f);
        KG_CHECK_OK(kg_body_set_angular_velocity(w, b, kRates[i]));
        KG_CHECK_OK(kg_world_step(w, DT));
        kg_body_state st = state_of(w, b);
        KG_CHECK(state_finite(&st));
        KG_CHECK_NEAR(st.angular_velocity, copysignf(limit, kRates[i]), 1e-5 * limit);
    }
    kg_destroy_world(w);
}

/* How far a soft contact of the world's defaults sinks under load newtons when its
 * effective mass is mass: a spring of stiffness mass (2 pi hertz)^2 (docs/design.md).
 * Contacts with a static body are twice as stiff, up to a quarter of the sub-step rate. */
static double soft_contact_sag(double load, double mass, int against_static)
{
    kg_world_def def = kg_default_world_def();
    double quarter_rate = 0.25 * (double)def.substeps / (double)DT;
    double hertz = fmin((against_static ? 2.0 : 1.0) * (double)def.contact_hertz, quarter_rate);
    double omega = 2.0 * 3.14159265358979 * hertz;
    return load / (mass * omega * omega);
}

/* Two boxes of masses in ratio 1:1000 stacked on the ground, the heavy one on top and
 * the other way round: for three seconds nobody moves faster than 1 m/s (the speed of
 * a 5 cm fall; an exploding stack is far faster), and at the end the stack stands
 * upright where it was, each contact pressed in as far as a spring of its stiffness
 * under its load (within 20% and 5 mm): a light box under a heavy one sinks by
 * centimetres, as soft contacts do. */
static void check_stack_of_ratio(float lower_mass, float upper_mass)
{
    kg_world* w = make_world((kg_vec2){0.0f, -10.0f}, 400.0f);
    add_box(w, KG_BODY_STATIC, (kg_vec2){0.0f, -0.5f}, 20.0f, 1.0f, 0.0f);
    kg_body lower = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.5f}, 1.0f, 1.0f, lower_mass);
    kg_body upper = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 1.5f}, 1.0f, 1.0f, upper_mass);
    float fastest = 0.0f;
    for (int i = 0; i < 180; ++i) {
        KG_CHECK_OK(kg_world_step(w, DT));
        fastest = fmaxf(fastest, fmaxf(speed_of(state_of(w, lower)), speed_of(state_of(w, upper))));
    }
    kg_body_state lo = state_of(w, lower), up = state_of(w, upper);
    printf("     masses %g below %g: fastest %.3g m/s, lower at y = %.4g, upper at y = %.4g, angles %.3g %.3g\n",
           (double)lower_mass, (double)upper_mass, (double)fastest, (double)lo.position.y, (double)up.position.y,
           (double)lo.angle, (double)up.angle);
    KG_CHECK(state_finite(&lo) && state_finite(&up));
    KG_CHECK(fastest < 1.0f);
    double m_low = lower_mass, m_up = upper_mass, g = 10.0;
    double ground_sag = soft_contact_sag((m_low + m_up) * g, m_low, 1);
    double between_sag = soft_contact_sag(m_up * g, m_low * m_up / (m_low + m_up), 0);
    printf("     expected sag: ground contact %.4g m, between the boxes %.4g m\n", ground_sag, between_sag);
    KG_CHECK_NEAR(lo.position.y, 0.5 - ground_sag, 0.2 * ground_sag + 0.005);
    KG_CHECK_NEAR(up.position.y, 1.5 - ground_sag - between_sag, 0.2 * (ground_sag + between_sag) + 0.005);
    KG_CHECK_NEAR(lo.position.x, 0.0f, 0.05f);
    KG_CHECK_NEAR(up.position.x, 0.0f, 0.05f);
    KG_CHECK(fabsf(lo.angle) < 0.05f && fabsf(up.angle) < 0.05f);
    kg_destroy_world(w);
}

static void test_extreme_mass_ratio_heavy_on_light(void) { check_stack_of_ratio(1.0f, 1000.0f); }

static void test_extreme_mass_ratio_light_on_heavy(void) { check_stack_of_ratio(1000.0f, 1.0f); }

/* force.h: an applicator's list is copied, and handles in it that die are skipped.
 * Nothing forbids a body listed twice; a list longer than the world's body capacity
 * must be refused or must not overrun the buffer the step collects the live targets in. */
static void test_applicator_list_longer_than_the_pool(void)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    def.max_bodies = 1;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    kg_body b = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    kg_body list[8] = {b, b, b, b, b, b, b, b};
    kg_applicator a;
    kg_result r = kg_add_gravity_applicator(w, (kg_vec2){0.0f, 1.0f}, list, 8, &a);
    KG_CHECK(r == KG_OK || r == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK_OK(kg_world_step(w, DT));
    kg_destroy_world(w);
}

/* A contact reported after one of its bodies died must not name the body that took
 * the dead one's slot. */
static void test_contact_never_names_a_newcomer(void)
{
    kg_world* w = make_world((kg_vec2){0.0f, 0.0f}, 400.0f);
    kg_body a = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    kg_body b = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){0.9f, 0.0f}, 1.0f, 1.0f, 0.0f);
    KG_CHECK_OK(kg_world_step(w, DT));
    KG_CHECK(kg_world_contact_count(w) >= 1);
    KG_CHECK_OK(kg_destroy_body(w, b));
    kg_body newcomer = add_box(w, KG_BODY_DYNAMIC, (kg_vec2){50.0f, 0.0f}, 1.0f, 1.0f, 0.0f);
    KG_CHECK(newcomer.index == b.index);
    for (int i = 0; i < kg_world_contact_count(w); ++i) {
        kg_contact_info info;
        KG_CHECK_OK(kg_world_get_contact(w, i, &info));
        int names_newcomer = (info.a.index == newcomer.index && info.a.generation == newcomer.generation) ||
                             (info.b.index == newcomer.index && info.b.generation == newcomer.generation);
        KG_CHECK(!names_newcomer);
    }
    (void)a;
    kg_destroy_world(w);
}

/* Line-buffered, so that when a test crashes (a sanitizer report aborts), the results
 * of those before it are not lost in stdout's buffer. */
__attribute__((constructor)) static void flush_every_line(void) { setvbuf(stdout, NULL, _IOLBF, 0); }

/* The random sequences last: a crash there must not hide the single behaviours. */
KG_TEST_MAIN(KG_TEST(test_null_world_is_an_invalid_argument), KG_TEST(test_body_generation_wraps_past_zero),
             KG_TEST(test_applicator_generation_wraps_past_zero), KG_TEST(test_wind_accepts_any_finite_direction),
             KG_TEST(test_impulse_on_body_that_cannot_turn_stays_finite),
             KG_TEST(test_non_finite_body_is_frozen_and_isolated),
             KG_TEST(test_non_finite_body_does_not_poison_its_neighbour), KG_TEST(test_frozen_body_stays_finite),
             KG_TEST(test_frozen_body_comes_back),
             KG_TEST(test_linear_speed_is_clamped), KG_TEST(test_angular_rate_is_clamped),
             KG_TEST(test_extreme_mass_ratio_heavy_on_light), KG_TEST(test_extreme_mass_ratio_light_on_heavy),
             KG_TEST(test_contact_never_names_a_newcomer), KG_TEST(test_applicator_list_longer_than_the_pool),
             KG_TEST(test_random_call_sequences))
