/* The body API: validation at the door, then plain writes into the pool. A call that
 * fails changes nothing. */
#include "backend/backend.h"
#include "collide/events.h"
#include "collide/shape.h"
#include "core/body_shapes.h"
#include "core/error.h"
#include "core/joint.h"
#include "core/world.h"
#include "solve/sleep.h"

#include <math.h>
#include <string.h>

kg_body_def kg_default_body_def(void)
{
    kg_body_def def;
    memset(&def, 0, sizeof def);
    def.type = KG_BODY_DYNAMIC;
    def.density = 1.0f;
    def.friction = 0.6f;
    def.category = 1u;
    def.mask = 0xFFFFFFFFu;
    return def;
}

static int kg_finite2(kg_vec2 v) { return isfinite(v.x) && isfinite(v.y); }
static int kg_nonneg(float v) { return isfinite(v) && v >= 0.0f; }

const kg_body_pool* kg_world_read_pool(const kg_world* world)
{
    kg_world* w = (kg_world*)world;
    if (w->backend && w->backend->sync_to_host) {
        w->backend->sync_to_host(w);
    }
    return &w->bodies;
}

/* Write access for setters: sync first, then tell the backend to upload. */
kg_body_pool* kg_world_write_pool(kg_world* world)
{
    kg_world_read_pool(world);
    world->pool_writes += 1u;
    if (world->backend && world->backend->host_changed) {
        world->backend->host_changed(world);
    }
    return &world->bodies;
}

static kg_result kg_validate_body_def(const kg_body_def* d)
{
    if (d->type < KG_BODY_STATIC || d->type > KG_BODY_PARTICLE) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "unknown body type %d", (int)d->type);
    }
    if (!kg_finite2(d->position) || !isfinite(d->angle) || !kg_finite2(d->velocity) ||
        !isfinite(d->angular_velocity)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "body position, angle and velocities must be finite");
    }
    if (!kg_nonneg(d->density) || !kg_nonneg(d->mass)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "density and mass must be finite and >= 0 (got %g, %g)",
                       (double)d->density, (double)d->mass);
    }
    if (!kg_nonneg(d->friction)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "friction must be finite and >= 0 (got %g)", (double)d->friction);
    }
    if (!isfinite(d->restitution) || d->restitution < 0.0f || d->restitution > 1.0f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "restitution must be in [0, 1] (got %g)", (double)d->restitution);
    }
    if (!kg_nonneg(d->linear_damping) || !kg_nonneg(d->angular_damping)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "damping must be finite and >= 0");
    }
    if (d->shape.type == KG_SHAPE_NONE && d->type == KG_BODY_DYNAMIC) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "a dynamic body needs a shape (only particles, static and "
                                                  "kinematic bodies may have none)");
    }
    if (d->shape.type == KG_SHAPE_SEGMENT && (d->type == KG_BODY_DYNAMIC || d->type == KG_BODY_PARTICLE)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT,
                       "a segment has no area: only static and kinematic bodies may have one (use a thin capsule)");
    }
    if (d->bullet && d->type != KG_BODY_DYNAMIC) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "only a dynamic body can be a bullet");
    }
    return KG_OK;
}

/* A static or kinematic body made without a shape has none (a particle's is a point). */
static int kg_is_shapeless(const kg_body_def* d)
{
    return d->shape.type == KG_SHAPE_NONE && d->type != KG_BODY_PARTICLE;
}

/* Mass properties from the definition: an explicit mass scales the shape's distribution. */
static kg_result kg_body_mass_from_def(const kg_body_def* d, const kg_shape* shape, kg_mass_data* md)
{
    memset(md, 0, sizeof *md);
    if (d->type == KG_BODY_STATIC || d->type == KG_BODY_KINEMATIC) {
        md->center = shape->count >= 2 ? shape->centroid : shape->vertices[0];
        return KG_OK;
    }
    if (d->shape.type == KG_SHAPE_NONE) {
        if (!(d->mass > 0.0f)) {
            return kg_fail(KG_ERROR_INVALID_ARGUMENT, "a particle without a shape needs a mass > 0");
        }
        md->mass = d->mass;
        return KG_OK;
    }
    if (!(d->mass > 0.0f) && !(d->density > 0.0f)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "a moving body needs a density or a mass > 0");
    }
    *md = kg_shape_mass_of(shape, 1.0f);
    float scale = d->mass > 0.0f ? d->mass / md->mass : d->density;
    md->mass *= scale;
    md->inertia *= scale;
    if (!(md->mass > 0.0f) || !isfinite(md->mass) || !isfinite(md->inertia) || md->inertia < 0.0f ||
        !isfinite(1.0f / md->mass) || (md->inertia > 0.0f && !isfinite(1.0f / md->inertia))) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "body mass is not representable (%g)", (double)md->mass);
    }
    return KG_OK;
}

static void kg_body_write(kg_body_pool* p, int i, const kg_body_def* d, const kg_shape* shape, const kg_mass_data* md)
{
    int particle = d->type == KG_BODY_PARTICLE;
    int rotates = d->type == KG_BODY_DYNAMIC && !d->fixed_rotation && md->inertia > 0.0f;
    kg_rot q = particle ? kg_rot_identity() : (kg_rot){cosf(d->angle), sinf(d->angle)};
    p->shape[i] = *shape;
    p->local_center[i] = md->center;
    p->rot[i] = q;
    p->center[i] = kg_add(d->position, kg_rotate(q, md->center));
    p->velocity[i] = d->type == KG_BODY_STATIC ? kg_v2(0.0f, 0.0f) : d->velocity;
    p->omega[i] = (d->type == KG_BODY_STATIC || particle) ? 0.0f : d->angular_velocity;
    p->force[i] = kg_v2(0.0f, 0.0f);
    p->torque[i] = 0.0f;
    p->drag[i] = 0.0f;
    p->sleep_time[i] = 0.0f;
    p->island[i] = 0u;
    p->mass[i] = md->mass;
    p->inertia[i] = md->inertia;
    p->inv_mass[i] = md->mass > 0.0f ? 1.0f / md->mass : 0.0f;
    p->inv_inertia[i] = rotates ? 1.0f / md->inertia : 0.0f;
    p->friction[i] = d->friction;
    p->restitution[i] = d->restitution;
    p->linear_damping[i] = d->linear_damping;
    p->angular_damping[i] = d->angular_damping;
    p->category[i] = d->category;
    p->mask[i] = d->mask;
    p->user_data[i] = d->user_data;
    p->flags[i] = KG_FLAG_ALIVE | ((kg_u32)d->type << KG_TYPE_SHIFT) |
                  (d->fixed_rotation ? KG_FLAG_FIXED_ROTATION : 0u) | (d->mass > 0.0f ? KG_FLAG_MASS_SET : 0u) |
                  (d->bullet ? KG_FLAG_BULLET : 0u) | (d->enable_pre_solve ? KG_FLAG_PRE_SOLVE : 0u);
    p->first_shape[i] = KG_NULL_INDEX;
    p->shape_count[i] = 1u;
    if (p->generation[i] == 0) {
        p->generation[i] = 1;
    }
    kg_body_update_transform(p, i);
}

/* Everything kg_create_body checks about a definition, with the shape and mass it
 * would build. */
static kg_result kg_prepare_body(const kg_body_def* def, kg_shape* shape, kg_mass_data* md)
{
    kg_result r = kg_validate_body_def(def);
    if (r == KG_OK) {
        r = kg_shape_build(&def->shape, shape);
    }
    if (r == KG_OK) {
        r = kg_body_mass_from_def(def, shape, md);
    }
    return r;
}

kg_result kg_check_body_def(const kg_body_def* def)
{
    if (!def) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_check_body_def: NULL definition");
    }
    kg_shape shape;
    kg_mass_data md;
    return kg_prepare_body(def, &shape, &md);
}

/* Continuous collision keeps a list of the static bodies and a count of the bullets
 * (solve/solver.c), made again after any change to one of them. */
static void kg_note_static_edit(kg_world* world, const kg_body_pool* p, int i)
{
    if (kg_pool_type(p, i) == KG_BODY_STATIC || (p->flags[i] & KG_FLAG_BULLET) != 0u) {
        world->static_edits += 1u;
    }
}

kg_result kg_create_body(kg_world* world, const kg_body_def* def, kg_body* out_body)
{
    if (!world || !def || !out_body) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_create_body: NULL argument");
    }
    if (kg_world_refuses(world, "kg_create_body", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    kg_shape shape;
    kg_mass_data md;
    kg_result r = kg_prepare_body(def, &shape, &md);
    if (r != KG_OK) {
        return r;
    }
    kg_body_pool* p = kg_world_write_pool(world);
    int i = kg_body_pool_acquire(p);
    if (i < 0) {
        return kg_fail(KG_ERROR_POOL_FULL, "body pool full (max_bodies = %d)", p->capacity);
    }
    int shapeless = kg_is_shapeless(def);
    int s = shapeless ? 0 : kg_shape_pool_acquire(&world->shapes);
    if (s < 0) {
        kg_body_pool_release(p, i);
        return kg_last_result();
    }
    kg_body_write(p, i, def, &shape, &md);
    kg_note_static_edit(world, p, i);
    if (shapeless) { /* a static or kinematic body waiting for its shapes or chains */
        p->shape_count[i] = 0u;
        kg_body_material_changed(world, p, i); /* collides with nothing */
    } else {
        kg_body_shape_def first = kg_first_shape_def(def);
        kg_shape_attach(world, s, i, &first); /* its geometry is the body pool's shape */
        if (first.is_sensor) {
            kg_body_material_changed(world, p, i); /* a sensor alone collides with nothing */
        }
    }
    out_body->index = (uint32_t)i;
    out_body->generation = p->generation[i];
    return KG_OK;
}

kg_result kg_destroy_body(kg_world* world, kg_body body)
{
    if (kg_world_refuses(world, "kg_destroy_body", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    int i = kg_world_resolve(world, body);
    if (i < 0) {
        return kg_last_result();
    }
    kg_events_body_destroyed(world, (kg_u32)i);
    kg_joints_body_destroyed(world, (kg_u32)i, body); /* its joints go with it */
    kg_body_pool* p = kg_world_write_pool(world);
    kg_wake_touching(p, p->aabb[i], world->def.speculative_distance); /* what rested on it */
    kg_note_static_edit(world, p, i);
    kg_body_release_shapes(world, i);
    kg_body_pool_release(p, i);
    if (p->generation[i] == 0) {
        p->generation[i] = 1;
    }
    return KG_OK;
}

int kg_body_is_valid(const kg_world* world, kg_body body)
{
    return world && body.generation != 0 && body.index < (uint32_t)world->bodies.high_water &&
           kg_pool_alive(&world->bodies, (int)body.index) && world->bodies.generation[body.index] == body.generation;
}

/* Resolves a handle for reading; on failure returns NULL with the error set. */
static const kg_body_pool* kg_read_body(const kg_world* world, kg_body body, const void* out, int* index)
{
    if (!out) {
        kg_fail(KG_ERROR_INVALID_ARGUMENT, "NULL output pointer");
        return NULL;
    }
    *index = kg_world_resolve(world, body);
    return *index < 0 ? NULL : kg_world_read_pool(world);
}

/* The code of the failure a resolve or check just reported. */
static kg_result kg_read_error(void) { return kg_last_result(); }

static kg_body_state kg_state_of(const kg_body_pool* p, int i)
{
    kg_body_state s;
    s.position = p->xf[i].p;
    s.angle = atan2f(p->rot[i].s, p->rot[i].c);
    s.velocity = p->velocity[i];
    s.angular_velocity = p->omega[i];
    return s;
}

kg_result kg_body_get_state(const kg_world* world, kg_body body, kg_body_state* out)
{
    int i;
    const kg_body_pool* p = kg_read_body(world, body, out, &i);
    if (!p) {
        return kg_read_error();
    }
    *out = kg_state_of(p, i);
    return KG_OK;
}

kg_result kg_world_get_body_states(const kg_world* world, const kg_body* bodies, int count, kg_body_state* out)
{
    if (!world || count < 0 || (count > 0 && (!bodies || !out))) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_get_body_states: bad arguments");
    }
    for (int k = 0; k < count; ++k) {
        if (kg_world_resolve(world, bodies[k]) < 0) {
            return KG_ERROR_INVALID_HANDLE;
        }
    }
    const kg_body_pool* p = kg_world_read_pool(world);
    for (int k = 0; k < count; ++k) {
        out[k] = kg_state_of(p, (int)bodies[k].index);
    }
    return KG_OK;
}

#define KG_BODY_GETTER(fn_name, type, expr)                              \
    kg_result fn_name(const kg_world* world, kg_body body, type* out)    \
    {                                                                    \
        int i;                                                           \
        const kg_body_pool* p = kg_read_body(world, body, out, &i);      \
        if (!p) {                                                        \
            return kg_read_error();                                      \
        }                                                                \
        *out = (expr);                                                   \
        return KG_OK;                                                    \
    }

KG_BODY_GETTER(kg_body_get_position, kg_vec2, p->xf[i].p)
KG_BODY_GETTER(kg_body_get_angle, float, atan2f(p->rot[i].s, p->rot[i].c))
KG_BODY_GETTER(kg_body_get_velocity, kg_vec2, p->velocity[i])
KG_BODY_GETTER(kg_body_get_angular_velocity, float, p->omega[i])
KG_BODY_GETTER(kg_body_get_type, kg_body_type, kg_pool_type(p, i))
/* The first shape's geometry (a particle's point, or the bounds of a body left with no shape). */
static const kg_shape* kg_first_geometry(const kg_world* world, int i)
{
    kg_u32 first = world->bodies.first_shape[i];
    return first != KG_NULL_INDEX ? kg_shape_geometry(&world->bodies, &world->shapes, first) : &world->bodies.shape[i];
}

KG_BODY_GETTER(kg_body_get_shape, kg_shape_def, kg_shape_describe(kg_first_geometry(world, i)))
KG_BODY_GETTER(kg_body_get_aabb, kg_aabb, p->aabb[i])
KG_BODY_GETTER(kg_body_get_mass_data, kg_mass_data, ((kg_mass_data){p->mass[i], p->local_center[i], p->inertia[i]}))

kg_result kg_body_get_inverse_mass(const kg_world* world, kg_body body, float* inv_mass, float* inv_inertia)
{
    int i;
    const kg_body_pool* p = kg_read_body(world, body, inv_mass, &i);
    if (!p || !inv_inertia) {
        return p ? kg_fail(KG_ERROR_INVALID_ARGUMENT, "NULL output pointer") : kg_read_error();
    }
    *inv_mass = p->inv_mass[i];
    *inv_inertia = p->inv_inertia[i];
    return KG_OK;
}

void* kg_body_get_user_data(const kg_world* world, kg_body body)
{
    return kg_body_is_valid(world, body) ? world->bodies.user_data[body.index] : NULL;
}

/* The user's pointer is the host's alone: no pool is written, nothing woken or uploaded. */
kg_result kg_body_set_user_data(kg_world* world, kg_body body, void* user_data)
{
    int i = kg_world_resolve(world, body);
    if (i < 0) {
        return kg_read_error();
    }
    world->bodies.user_data[i] = user_data;
    return KG_OK;
}

static int kg_frozen(const kg_body_pool* p, int i) { return (p->flags[i] & KG_FLAG_FROZEN) != 0; }

/* Setting a finite pose or velocity is how a user brings a frozen body back. */
static void kg_unfreeze(kg_body_pool* p, int i) { p->flags[i] &= ~KG_FLAG_FROZEN; }

/* A force or impulse turns a body only if it can turn: 0 * infinity would be NaN. */
static float kg_turning(const kg_body_pool* p, int i, float moment) { return p->inv_inertia[i] > 0.0f ? moment : 0.0f; }

int kg_body_is_frozen(const kg_world* world, kg_body body)
{
    return kg_body_is_valid(world, body) && kg_frozen(kg_world_read_pool(world), (int)body.index);
}

/* Resolves a handle for writing after checking the new values; NULL on failure. */
static kg_body_pool* kg_write_body(kg_world* world, kg_body body, int values_ok, const char* what, int* index)
{
    *index = kg_world_resolve(world, body);
    if (*index < 0 || kg_world_refuses(world, "changing a body", KG_LOCK_ALL)) {
        return NULL;
    }
    if (!values_ok) {
        kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s", what);
        return NULL;
    }
    kg_body_pool* p = kg_world_write_pool(world);
    kg_wake_slot(p, *index); /* a body changed through the API is simulated again */
    kg_note_static_edit(world, p, *index);
    return p;
}

int kg_body_is_awake(const kg_world* world, kg_body body)
{
    return kg_body_is_valid(world, body) && !kg_pool_asleep(kg_world_read_pool(world), (int)body.index);
}

kg_result kg_body_wake(kg_world* world, kg_body body)
{
    int i;
    return kg_write_body(world, body, 1, "", &i) ? KG_OK : kg_read_error();
}

int kg_world_asleep_count(const kg_world* world)
{
    return world ? kg_pool_asleep_count(kg_world_read_pool(world)) : 0;
}

void kg_world_wake_region(kg_world* world, kg_aabb box)
{
    if (kg_pool_asleep_count(kg_world_read_pool(world)) > 0) {
        kg_wake_touching(kg_world_write_pool(world), box, world->def.speculative_distance);
    }
}

void kg_world_wake_all(kg_world* world)
{
    if (kg_pool_asleep_count(kg_world_read_pool(world)) == 0) {
        return;
    }
    kg_body_pool* p = kg_world_write_pool(world);
    for (int i = 0; i < p->high_water; ++i) {
        if (kg_pool_asleep(p, i)) {
            kg_wake_slot(p, i);
        }
    }
}

kg_result kg_body_set_transform(kg_world* world, kg_body body, kg_vec2 position, float angle)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, kg_finite2(position) && isfinite(angle),
                                    "position and angle must be finite", &i);
    if (!p) {
        return kg_read_error();
    }
    kg_rot q = kg_pool_type(p, i) == KG_BODY_PARTICLE ? kg_rot_identity() : (kg_rot){cosf(angle), sinf(angle)};
    kg_wake_touching(p, p->aabb[i], world->def.speculative_distance); /* what rested on it */
    p->rot[i] = q;
    p->center[i] = kg_add(position, kg_rotate(q, p->local_center[i]));
    kg_body_update_transform(p, i);
    kg_wake_touching(p, p->aabb[i], world->def.speculative_distance); /* what it lands in */
    kg_unfreeze(p, i);
    return KG_OK;
}

kg_result kg_body_set_velocity(kg_world* world, kg_body body, kg_vec2 velocity)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, kg_finite2(velocity), "velocity must be finite", &i);
    if (!p) {
        return kg_read_error();
    }
    if (kg_pool_type(p, i) != KG_BODY_STATIC) {
        p->velocity[i] = velocity;
        kg_unfreeze(p, i);
    }
    return KG_OK;
}

kg_result kg_body_set_angular_velocity(kg_world* world, kg_body body, float omega)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, isfinite(omega), "angular velocity must be finite", &i);
    if (!p) {
        return kg_read_error();
    }
    kg_body_type t = kg_pool_type(p, i);
    if (t == KG_BODY_DYNAMIC || t == KG_BODY_KINEMATIC) {
        p->omega[i] = omega;
    }
    return KG_OK;
}

kg_result kg_body_set_inverse_mass(kg_world* world, kg_body body, float inv_mass, float inv_inertia)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, kg_nonneg(inv_mass) && kg_nonneg(inv_inertia),
                                    "inverse mass and inertia must be finite and >= 0", &i);
    if (!p) {
        return kg_read_error();
    }
    kg_body_type t = kg_pool_type(p, i);
    if (t == KG_BODY_STATIC || t == KG_BODY_KINEMATIC) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "static and kinematic bodies have infinite mass");
    }
    p->inv_mass[i] = inv_mass;
    p->inv_inertia[i] = t == KG_BODY_PARTICLE ? 0.0f : inv_inertia;
    p->flags[i] |= KG_FLAG_MASS_SET;
    p->mass[i] = inv_mass > 0.0f ? 1.0f / inv_mass : 0.0f;
    p->inertia[i] = inv_inertia > 0.0f ? 1.0f / inv_inertia : 0.0f;
    return KG_OK;
}

kg_result kg_body_set_friction(kg_world* world, kg_body body, float friction)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, kg_nonneg(friction), "friction must be finite and >= 0", &i);
    if (!p) {
        return kg_read_error();
    }
    p->friction[i] = friction;
    for (kg_u32 s = p->first_shape[i]; s != KG_NULL_INDEX; s = world->shapes.next[s]) {
        world->shapes.friction[s] = friction;
    }
    world->shapes.version += 1u;
    return KG_OK;
}

kg_result kg_body_set_restitution(kg_world* world, kg_body body, float restitution)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, isfinite(restitution) && restitution >= 0.0f && restitution <= 1.0f,
                                    "restitution must be in [0, 1]", &i);
    if (!p) {
        return kg_read_error();
    }
    p->restitution[i] = restitution;
    for (kg_u32 s = p->first_shape[i]; s != KG_NULL_INDEX; s = world->shapes.next[s]) {
        world->shapes.restitution[s] = restitution;
    }
    world->shapes.version += 1u;
    return KG_OK;
}

kg_result kg_body_set_damping(kg_world* world, kg_body body, float linear, float angular)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, kg_nonneg(linear) && kg_nonneg(angular),
                                    "damping must be finite and >= 0", &i);
    if (!p) {
        return kg_read_error();
    }
    p->linear_damping[i] = linear;
    p->angular_damping[i] = angular;
    return KG_OK;
}

kg_result kg_body_set_filter(kg_world* world, kg_body body, uint32_t category, uint32_t mask)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, 1, "", &i);
    if (!p) {
        return kg_read_error();
    }
    kg_wake_touching(p, p->aabb[i], world->def.speculative_distance); /* contacts it may lose */
    for (kg_u32 s = p->first_shape[i]; s != KG_NULL_INDEX; s = world->shapes.next[s]) {
        world->shapes.category[s] = category;
        world->shapes.mask[s] = mask;
    }
    kg_body_material_changed(world, p, i); /* the body's filter, of its solid shapes */
    return KG_OK;
}

kg_result kg_body_set_bullet(kg_world* world, kg_body body, int bullet)
{
    int i = kg_world_resolve(world, body);
    int dynamic = i >= 0 && kg_pool_type(kg_world_read_pool(world), i) == KG_BODY_DYNAMIC;
    kg_body_pool* p = kg_write_body(world, body, !bullet || dynamic, "only a dynamic body can be a bullet", &i);
    if (!p) {
        return kg_read_error();
    }
    p->flags[i] = bullet ? (p->flags[i] | KG_FLAG_BULLET) : (p->flags[i] & ~KG_FLAG_BULLET);
    kg_note_static_edit(world, p, i);
    return KG_OK;
}

kg_result kg_body_set_pre_solve(kg_world* world, kg_body body, int enabled)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, 1, "", &i);
    if (!p) {
        return kg_read_error();
    }
    p->flags[i] = enabled ? (p->flags[i] | KG_FLAG_PRE_SOLVE) : (p->flags[i] & ~KG_FLAG_PRE_SOLVE);
    return KG_OK;
}

int kg_body_is_bullet(const kg_world* world, kg_body body)
{
    return kg_body_is_valid(world, body) && (world->bodies.flags[body.index] & KG_FLAG_BULLET) != 0u;
}

kg_result kg_body_apply_force(kg_world* world, kg_body body, kg_vec2 force, kg_vec2 world_point)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, kg_finite2(force) && kg_finite2(world_point),
                                    "force and point must be finite", &i);
    if (!p) {
        return kg_read_error();
    }
    if (!kg_frozen(p, i)) {
        p->force[i] = kg_add(p->force[i], force);
        p->torque[i] += kg_turning(p, i, kg_cross(kg_sub(world_point, p->center[i]), force));
    }
    return KG_OK;
}

kg_result kg_body_apply_force_to_center(kg_world* world, kg_body body, kg_vec2 force)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, kg_finite2(force), "force must be finite", &i);
    if (!p) {
        return kg_read_error();
    }
    if (!kg_frozen(p, i)) {
        p->force[i] = kg_add(p->force[i], force);
    }
    return KG_OK;
}

kg_result kg_body_apply_torque(kg_world* world, kg_body body, float torque)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, isfinite(torque), "torque must be finite", &i);
    if (!p) {
        return kg_read_error();
    }
    if (!kg_frozen(p, i)) {
        p->torque[i] += kg_turning(p, i, torque);
    }
    return KG_OK;
}

kg_result kg_body_apply_impulse(kg_world* world, kg_body body, kg_vec2 impulse, kg_vec2 world_point)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, kg_finite2(impulse) && kg_finite2(world_point),
                                    "impulse and point must be finite", &i);
    if (!p) {
        return kg_read_error();
    }
    if (!kg_frozen(p, i)) {
        p->velocity[i] = kg_mul_add(p->velocity[i], p->inv_mass[i], impulse);
        p->omega[i] += kg_turning(p, i, p->inv_inertia[i] * kg_cross(kg_sub(world_point, p->center[i]), impulse));
    }
    return KG_OK;
}

kg_result kg_body_apply_angular_impulse(kg_world* world, kg_body body, float impulse)
{
    int i;
    kg_body_pool* p = kg_write_body(world, body, isfinite(impulse), "impulse must be finite", &i);
    if (!p) {
        return kg_read_error();
    }
    if (!kg_frozen(p, i)) {
        p->omega[i] += kg_turning(p, i, p->inv_inertia[i] * impulse);
    }
    return KG_OK;
}
