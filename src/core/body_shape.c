/* The shapes of a body (kgyro/shape.h): a shape pool beside the body pool, each body's
 * shapes a list in slot order, and what the body derives from them. Validation at the
 * door, as in core/body.c: a call that fails changes nothing. */
#include "backend/backend.h"
#include "collide/shape.h"
#include "core/body_shapes.h"
#include "core/error.h"
#include "solve/sleep.h"

#include <math.h>
#include <string.h>

kg_body_shape_def kg_default_body_shape_def(void)
{
    kg_body_shape_def def;
    memset(&def, 0, sizeof def);
    def.density = 1.0f;
    def.friction = 0.6f;
    def.category = 1u;
    def.mask = 0xFFFFFFFFu;
    return def;
}

kg_body_shape_def kg_first_shape_def(const kg_body_def* d)
{
    kg_body_shape_def def = kg_default_body_shape_def();
    def.geometry = d->shape;
    def.density = d->density;
    def.friction = d->friction;
    def.restitution = d->restitution;
    def.category = d->category;
    def.mask = d->mask;
    def.is_sensor = d->is_sensor;
    return def;
}

/* kg_shape_attach, inserting into body i's list from link on (a place in it below s). */
static void kg_shape_attach_at(kg_world* world, int s, int i, const kg_body_shape_def* def, kg_u32* link)
{
    kg_shape_pool* sp = &world->shapes;
    sp->body[s] = (kg_u32)i;
    sp->density[s] = def->density;
    sp->friction[s] = def->friction;
    sp->restitution[s] = def->restitution;
    sp->category[s] = def->category;
    sp->mask[s] = def->mask;
    sp->flags[s] = KG_SHAPE_ALIVE | (def->is_sensor ? KG_SHAPE_SENSOR : 0u);
    world->sensor_shapes_made += def->is_sensor != 0;
    sp->user_data[s] = def->user_data;
    if (sp->generation[s] == 0) {
        sp->generation[s] = 1;
    }
    kg_shape_list_insert(sp, link, (kg_u32)s);
    sp->version += 1u;
}

void kg_shape_attach(kg_world* world, int s, int i, const kg_body_shape_def* def)
{
    kg_shape_attach_at(world, s, i, def, &world->bodies.first_shape[i]);
}

/* A box in the body frame around every shape of the list from first: the bounds of a
 * compound body. */
static kg_shape kg_bounds_of_shapes(const kg_shape_pool* sp, kg_u32 first)
{
    kg_xf identity = {kg_v2(0.0f, 0.0f), kg_rot_identity()};
    kg_aabb box = kg_shape_aabb(&sp->geometry[first], identity);
    for (kg_u32 s = sp->next[first]; s != KG_NULL_INDEX; s = sp->next[s]) {
        kg_aabb more = kg_shape_aabb(&sp->geometry[s], identity);
        box.lower = kg_vmin(box.lower, more.lower);
        box.upper = kg_vmax(box.upper, more.upper);
    }
    kg_vec2 corners[4] = {box.lower, {box.upper.x, box.lower.y}, box.upper, {box.lower.x, box.upper.y}};
    kg_shape_def def = kg_polygon_shape(corners, 4);
    kg_shape bounds;
    if (kg_shape_build(&def, &bounds) != KG_OK) { /* shapes too small for a box: a circle around them */
        memset(&bounds, 0, sizeof bounds);
        bounds.count = 1;
        bounds.vertices[0] = kg_scale(0.5f, kg_add(box.lower, box.upper));
        bounds.radius = 0.5f * kg_length(kg_sub(box.upper, box.lower));
    }
    return bounds;
}

/* Mass data of the shapes from first at their densities: masses summed, the centre of mass
 * their weighted mean, the inertia each shape's about that centre (parallel axis).
 * Returns 0 when they have no mass. */
static int kg_mass_of_shapes(const kg_shape_pool* sp, kg_u32 first, kg_mass_data* out)
{
    if (sp->next[first] == KG_NULL_INDEX) { /* as kg_create_body computes it, to the bit */
        *out = kg_shape_mass_of(&sp->geometry[first], 1.0f);
        out->mass *= sp->density[first];
        out->inertia *= sp->density[first];
        return out->mass > 0.0f && isfinite(out->mass) && isfinite(out->inertia);
    }
    float mass = 0.0f;
    kg_vec2 moment = kg_v2(0.0f, 0.0f);
    for (kg_u32 s = first; s != KG_NULL_INDEX; s = sp->next[s]) {
        kg_mass_data md = kg_shape_mass_of(&sp->geometry[s], 1.0f);
        float m = md.mass * sp->density[s];
        mass += m;
        moment = kg_mul_add(moment, m, md.center);
    }
    if (!(mass > 0.0f) || !isfinite(mass)) {
        return 0;
    }
    kg_vec2 center = kg_scale(1.0f / mass, moment);
    float inertia = 0.0f;
    for (kg_u32 s = first; s != KG_NULL_INDEX; s = sp->next[s]) {
        kg_mass_data md = kg_shape_mass_of(&sp->geometry[s], 1.0f);
        float m = md.mass * sp->density[s];
        inertia += md.inertia * sp->density[s] + m * kg_length_sq(kg_sub(md.center, center));
    }
    out->mass = mass;
    out->center = center;
    out->inertia = inertia;
    return isfinite(inertia);
}

/* New mass data for moving body i: its origin stays where it is, its centre of mass moves,
 * and the velocity of the centre follows the rotation about the old one. */
static void kg_body_set_mass_data(kg_body_pool* p, int i, const kg_mass_data* md)
{
    int rotates =
        kg_pool_type(p, i) == KG_BODY_DYNAMIC && !(p->flags[i] & KG_FLAG_FIXED_ROTATION) && md->inertia > 0.0f;
    kg_vec2 old_center = p->center[i];
    p->local_center[i] = md->center;
    p->center[i] = kg_xf_point(p->xf[i], md->center);
    p->velocity[i] = kg_add(p->velocity[i], kg_cross_sv(p->omega[i], kg_sub(p->center[i], old_center)));
    p->mass[i] = md->mass;
    p->inertia[i] = md->inertia;
    p->inv_mass[i] = 1.0f / md->mass;
    p->inv_inertia[i] = rotates ? 1.0f / md->inertia : 0.0f;
}

static int kg_body_moves_by_mass(const kg_body_pool* p, int i)
{
    kg_body_type t = kg_pool_type(p, i);
    return (t == KG_BODY_DYNAMIC || t == KG_BODY_PARTICLE) && !(p->flags[i] & KG_FLAG_MASS_SET);
}

void kg_body_material_changed(kg_world* world, kg_body_pool* p, int i)
{
    const kg_shape_pool* sp = &world->shapes;
    kg_u32 first = p->first_shape[i], category = 0u, mask = 0u;
    for (kg_u32 s = first; s != KG_NULL_INDEX; s = sp->next[s]) {
        if (!kg_shape_is_sensor(sp, s)) {
            category |= sp->category[s];
            mask |= sp->mask[s];
        }
    }
    p->category[i] = category;
    p->mask[i] = mask;
    world->shapes.version += 1u;
    if (first != KG_NULL_INDEX) {
        p->friction[i] = sp->friction[first];
        p->restitution[i] = sp->restitution[first];
    }
}

void kg_body_shapes_changed(kg_world* world, kg_body_pool* p, int i, int shape_count_before)
{
    kg_shape_pool* sp = &world->shapes;
    kg_u32 first = p->first_shape[i], count = 0u;
    for (kg_u32 s = first; s != KG_NULL_INDEX; s = sp->next[s]) {
        count += 1u;
    }
    sp->compound_bodies += (count > 1u) - (shape_count_before > 1);
    p->shape_count[i] = count;
    if (count == 1u) {
        p->shape[i] = sp->geometry[first];
    } else if (count > 1u) {
        p->shape[i] = kg_bounds_of_shapes(sp, first);
    }
    kg_body_material_changed(world, p, i);
    kg_mass_data md;
    if (kg_body_moves_by_mass(p, i) && first != KG_NULL_INDEX && kg_mass_of_shapes(sp, first, &md)) {
        kg_body_set_mass_data(p, i, &md);
    }
    kg_body_update_transform(p, i);
}

void kg_body_release_shapes(kg_world* world, int i)
{
    kg_shape_pool* sp = &world->shapes;
    kg_body_pool* p = &world->bodies;
    sp->compound_bodies -= p->shape_count[i] > 1u;
    for (kg_u32 s = p->first_shape[i]; s != KG_NULL_INDEX;) {
        kg_u32 next = sp->next[s];
        kg_shape_pool_release(sp, (int)s);
        s = next;
    }
    p->first_shape[i] = KG_NULL_INDEX;
    p->shape_count[i] = 0u;
}

/* ---- the API -------------------------------------------------------------------------- */

static int kg_finite_vec2(kg_vec2 v) { return isfinite(v.x) && isfinite(v.y); }

kg_shape_def kg_shape_moved(kg_shape_def def, kg_vec2 center, float angle)
{
    kg_xf xf = {center, {cosf(angle), sinf(angle)}};
    def.center = kg_xf_point(xf, def.center);
    for (int k = 0; k < def.count && k < KG_MAX_POLYGON_VERTICES; ++k) {
        def.vertices[k] = kg_xf_point(xf, def.vertices[k]);
    }
    return def;
}

static kg_result kg_check_material(float density, float friction, float restitution)
{
    if (!isfinite(density) || density < 0.0f || !isfinite(friction) || friction < 0.0f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "shape density and friction must be finite and >= 0 (got %g, %g)",
                       (double)density, (double)friction);
    }
    if (!isfinite(restitution) || restitution < 0.0f || restitution > 1.0f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "shape restitution must be in [0, 1] (got %g)", (double)restitution);
    }
    return KG_OK;
}

/* Everything kg_create_shape checks of def, with the geometry it would build. */
static kg_result kg_prepare_shape(const kg_body_shape_def* def, kg_shape* geometry)
{
    KG_TRY(kg_check_material(def->density, def->friction, def->restitution));
    if (def->geometry.type == KG_SHAPE_NONE) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "a shape needs a geometry (only a particle's first shape is a point)");
    }
    KG_TRY(kg_shape_build(&def->geometry, geometry));
    kg_mass_data md = kg_shape_mass_of(geometry, def->density);
    if (!isfinite(md.mass) || !isfinite(md.inertia) || !kg_finite_vec2(md.center)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "shape mass at density %g is not representable", (double)def->density);
    }
    return KG_OK;
}

/* The pool for writing (the backend syncs and uploads) with body i woken, and whatever
 * touched its bounds, which may lose what it rests on. */
static kg_body_pool* kg_edit_body(kg_world* world, int i)
{
    kg_body_pool* p = kg_world_write_pool(world);
    kg_wake_slot(p, i);
    kg_wake_touching(p, p->aabb[i], world->def.speculative_distance);
    return p;
}

/* After body i gained a shape: the sleeping bodies it now reaches, when it cannot wake
 * them itself. A moving body, awake now, wakes the islands its new contacts reach in the
 * wake stage; a static or kinematic one does not, and would hold them asleep in its new
 * shape. (Asking every body, as for a removal, made building a world of compound bodies
 * quadratic: 4,000 of them spent 0.4 G instructions waking nothing.) */
static void kg_wake_reached(kg_world* world, kg_body_pool* p, int i)
{
    kg_wake_slot(p, i);
    if (!kg_pool_collides(p, i)) {
        kg_wake_touching(p, p->aabb[i], world->def.speculative_distance);
    }
}

/* Body i about to gain shapes: a body of one shape kept its geometry in the body pool
 * alone, and the shape pool takes it now that the body becomes compound. Returns how
 * many shapes it had. */
static int kg_prepare_to_add_shapes(kg_world* world, const kg_body_pool* p, int i)
{
    int before = (int)p->shape_count[i];
    if (before == 1) {
        world->shapes.geometry[p->first_shape[i]] = p->shape[i];
    }
    return before;
}

kg_result kg_create_shape(kg_world* world, kg_body body, const kg_body_shape_def* def, kg_shape_id* out)
{
    if (!world || !def || !out) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_create_shape: NULL argument");
    }
    if (kg_world_refuses(world, "kg_create_shape", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    int i = kg_world_resolve(world, body);
    if (i < 0) {
        return kg_last_result();
    }
    kg_shape geometry;
    KG_TRY(kg_prepare_shape(def, &geometry));
    KG_TRY(kg_shape_pool_reserve_geometry(&world->shapes));
    int s = kg_shape_pool_acquire(&world->shapes);
    if (s < 0) {
        return kg_last_result();
    }
    kg_body_pool* p = kg_world_write_pool(world);
    int before = kg_prepare_to_add_shapes(world, p, i);
    world->shapes.geometry[s] = geometry;
    kg_shape_attach(world, s, i, def);
    kg_body_shapes_changed(world, p, i, before);
    kg_wake_reached(world, p, i);
    out->index = (uint32_t)s;
    out->generation = world->shapes.generation[s];
    return KG_OK;
}

/* The slot of a live shape handle of world, or -1 with the error set. */
static int kg_resolve_shape(const kg_world* world, kg_shape_id shape)
{
    if (!world) {
        kg_fail(KG_ERROR_INVALID_ARGUMENT, "NULL world");
        return -1;
    }
    return kg_shape_pool_resolve(&world->shapes, shape);
}

kg_result kg_destroy_shape(kg_world* world, kg_shape_id shape)
{
    if (kg_world_refuses(world, "kg_destroy_shape", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    int s = kg_resolve_shape(world, shape);
    if (s < 0) {
        return kg_last_result();
    }
    int i = (int)world->shapes.body[s];
    kg_body_pool* p = kg_edit_body(world, i);
    int before = (int)p->shape_count[i];
    kg_shape_list_remove(&world->shapes, &p->first_shape[i], (kg_u32)s);
    kg_shape_pool_release(&world->shapes, s);
    kg_body_shapes_changed(world, p, i, before);
    return KG_OK;
}

int kg_shape_is_valid(const kg_world* world, kg_shape_id shape)
{
    return world && shape.generation != 0 && shape.index < (uint32_t)world->shapes.high_water &&
           kg_shape_alive(&world->shapes, (int)shape.index) && world->shapes.generation[shape.index] == shape.generation;
}

int kg_body_shape_count(const kg_world* world, kg_body body)
{
    return kg_body_is_valid(world, body) ? (int)world->bodies.shape_count[body.index] : 0;
}

kg_result kg_body_get_shapes(const kg_world* world, kg_body body, kg_shape_id* out, int capacity, int* count)
{
    if (!count || capacity < 0 || (capacity > 0 && !out)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_body_get_shapes: bad arguments");
    }
    int i = kg_world_resolve(world, body);
    if (i < 0) {
        return kg_last_result();
    }
    const kg_shape_pool* sp = &world->shapes;
    int n = 0;
    for (kg_u32 s = world->bodies.first_shape[i]; s != KG_NULL_INDEX; s = sp->next[s], ++n) {
        if (n < capacity) {
            out[n].index = s;
            out[n].generation = sp->generation[s];
        }
    }
    *count = n;
    return KG_OK;
}

kg_result kg_shape_get_body(const kg_world* world, kg_shape_id shape, kg_body* out)
{
    int s = out ? kg_resolve_shape(world, shape) : -1;
    if (s < 0) {
        return out ? kg_last_result() : kg_fail(KG_ERROR_INVALID_ARGUMENT, "NULL output pointer");
    }
    kg_u32 i = world->shapes.body[s];
    out->index = i;
    out->generation = world->bodies.generation[i];
    return KG_OK;
}

kg_result kg_shape_get_def(const kg_world* world, kg_shape_id shape, kg_body_shape_def* out)
{
    int s = out ? kg_resolve_shape(world, shape) : -1;
    if (s < 0) {
        return out ? kg_last_result() : kg_fail(KG_ERROR_INVALID_ARGUMENT, "NULL output pointer");
    }
    const kg_shape_pool* sp = &world->shapes;
    out->geometry = kg_shape_describe(kg_shape_geometry(&world->bodies, sp, (kg_u32)s));
    out->density = sp->density[s];
    out->friction = sp->friction[s];
    out->restitution = sp->restitution[s];
    out->category = sp->category[s];
    out->mask = sp->mask[s];
    out->is_sensor = kg_shape_is_sensor(sp, (kg_u32)s);
    out->user_data = sp->user_data[s];
    return KG_OK;
}

/* Resolves a shape for a change of material or filter, after checking the new values:
 * its slot, with its body woken and the body pool ready for writing, or -1. Refused
 * from a pre-solve callback, as a body's changes are (it would wake a body between the
 * collide and solve stages). */
static int kg_write_shape(kg_world* world, kg_shape_id shape, kg_result values)
{
    if (kg_world_refuses(world, "changing a shape", KG_LOCK_ALL)) {
        return -1;
    }
    int s = kg_resolve_shape(world, shape);
    if (s < 0 || values != KG_OK) {
        return -1;
    }
    kg_edit_body(world, (int)world->shapes.body[s]);
    return s;
}

kg_result kg_shape_set_friction(kg_world* world, kg_shape_id shape, float friction)
{
    int s = kg_write_shape(world, shape, kg_check_material(0.0f, friction, 0.0f));
    if (s < 0) {
        return kg_last_result();
    }
    world->shapes.friction[s] = friction;
    kg_body_material_changed(world, &world->bodies, (int)world->shapes.body[s]);
    return KG_OK;
}

kg_result kg_shape_set_restitution(kg_world* world, kg_shape_id shape, float restitution)
{
    int s = kg_write_shape(world, shape, kg_check_material(0.0f, 0.0f, restitution));
    if (s < 0) {
        return kg_last_result();
    }
    world->shapes.restitution[s] = restitution;
    kg_body_material_changed(world, &world->bodies, (int)world->shapes.body[s]);
    return KG_OK;
}

kg_result kg_shape_set_filter(kg_world* world, kg_shape_id shape, uint32_t category, uint32_t mask)
{
    int s = kg_write_shape(world, shape, KG_OK);
    if (s < 0) {
        return kg_last_result();
    }
    world->shapes.category[s] = category;
    world->shapes.mask[s] = mask;
    kg_body_material_changed(world, &world->bodies, (int)world->shapes.body[s]);
    return KG_OK;
}

/* ---- chains --------------------------------------------------------------------------- */

kg_chain_def kg_default_chain_def(void)
{
    kg_chain_def def;
    memset(&def, 0, sizeof def);
    def.friction = 0.6f;
    def.category = 1u;
    def.mask = 0xFFFFFFFFu;
    return def;
}

/* Everything kg_create_chain checks before it changes anything: body slot i may hold it. */
static kg_result kg_check_chain(const kg_world* world, int i, const kg_chain_def* def)
{
    kg_body_type type = kg_pool_type(&world->bodies, i);
    if (type != KG_BODY_STATIC && type != KG_BODY_KINEMATIC) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT,
                       "a chain has no mass: only static and kinematic bodies may hold one (use capsules or polygons)");
    }
    KG_TRY(kg_check_material(0.0f, def->friction, def->restitution));
    return kg_check_chain_points(def->points, def->count, def->loop);
}

kg_result kg_create_chain(kg_world* world, kg_body body, const kg_chain_def* def, kg_shape_id* out_segments)
{
    if (!world || !def) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_create_chain: NULL argument");
    }
    if (kg_world_refuses(world, "kg_create_chain", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    int i = kg_world_resolve(world, body);
    if (i < 0) {
        return kg_last_result();
    }
    KG_TRY(kg_check_chain(world, i, def));
    int segments = def->loop ? def->count : def->count - 1;
    kg_shape_pool* sp = &world->shapes;
    KG_TRY(kg_shape_pool_reserve_geometry(sp));
    KG_TRY(kg_shape_pool_reserve(sp, segments)); /* from here on nothing fails */
    kg_body_pool* p = kg_world_write_pool(world);
    int before = kg_prepare_to_add_shapes(world, p, i);
    kg_body_shape_def material = kg_default_body_shape_def();
    material.density = 0.0f;
    material.friction = def->friction;
    material.restitution = def->restitution;
    material.category = def->category;
    material.mask = def->mask;
    material.user_data = def->user_data;
    kg_u32 last = KG_NULL_INDEX;
    for (int k = 0; k < segments; ++k) {
        int s = kg_shape_pool_acquire(sp);
        sp->geometry[s] = kg_chain_segment_build(def->points, def->count, def->loop, k);
        /* slots mostly come in ascending order: go on from the last segment's place in the
         * list rather than walk it from the start for each (a long chain was quadratic) */
        kg_u32* from = (last != KG_NULL_INDEX && last < (kg_u32)s) ? &sp->next[last] : &p->first_shape[i];
        kg_shape_attach_at(world, s, i, &material, from);
        last = (kg_u32)s;
        if (out_segments) {
            out_segments[k].index = (uint32_t)s;
            out_segments[k].generation = sp->generation[s];
        }
    }
    kg_body_shapes_changed(world, p, i, before);
    kg_wake_reached(world, p, i);
    return KG_OK;
}
