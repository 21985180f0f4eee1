/* Chipmunk 7 adapter: one cpBody per scene body, with its shape (none for a point
 * particle), or a compound body's shapes.
 *
 * Chipmunk's conventions differ from kgyro's in ways that matter here:
 *  - a body's position is its centre of gravity; shapes are given in body-local
 *    coordinates around the body origin, so the centre of gravity is set explicitly
 *    (cpBodySetCenterOfGravity) and the origin placed after it;
 *  - mass and moment are the caller's to give: cpAreaFor*, cpCentroidForPoly and
 *    cpMomentFor* compute them from the same shape and density kgyro uses;
 *  - materials combine by product, where kgyro and Box2D take sqrt(fa * fb) for friction:
 *    each shape gets sqrt(f), so the product is kgyro's mix. Elasticity is passed the
 *    same way (kgyro takes the larger restitution; the benchmark scenes use 0);
 *  - its defaults are tuned for pixels: the collision slop (allowed overlap) is 0.1
 *    units, 10 cm here, so it gets the scene's linear slop instead;
 *  - damping is per space: per-body damping goes through a velocity update function.
 * Sleeping is off (its default). The spatial index is its default bounding-box tree.
 * With threads > 1 it runs cpHastySpace, whose solver uses at most 2 threads. */
#include "peer_adapter.h"

#include <chipmunk/chipmunk.h>
#include <chipmunk/cpHastySpace.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

enum { KG_CP_ITERATIONS = 10, KG_CP_MAX_THREADS = 2 };

typedef struct kg_cp_shape {
    cpShape* shape;
    kg_shape_type type;
} kg_cp_shape;

typedef struct kg_cp_item {
    cpBody* body;
    cpShape* shape; /* NULL for a point particle */
    kg_shape_type shape_type;
    kg_cp_shape* more; /* a compound body's shapes after the first */
    int more_count;
    cpFloat linear_damping, angular_damping;
} kg_cp_item;

typedef struct kg_cp_world {
    cpSpace* space;
    int hasty;
    int count;
    kg_cp_item* items; /* scene order; never reallocated, bodies point into it */
    cpConstraint** constraints; /* the joints' (several a joint), freed with the world */
    int constraint_count, constraint_capacity;
} kg_cp_world;

static int kg_cp_threads(int threads) { return threads > KG_CP_MAX_THREADS ? KG_CP_MAX_THREADS : threads; }

static const char* kg_cp_describe(int threads)
{
    static char text[256];
    snprintf(text, sizeof text,
             "Chipmunk %s: %d iterations, slop = the scene's linear slop, bounding-box tree, sleeping off, %d thread%s",
             cpVersionString, KG_CP_ITERATIONS, threads > 1 ? kg_cp_threads(threads) : 1,
             threads > 1 ? "s (cpHastySpace; it uses at most 2)" : "");
    return text;
}

static void* kg_cp_create(const kg_peer_setup* setup)
{
    kg_cp_world* w = calloc(1, sizeof *w);
    if (!w) {
        return NULL;
    }
    w->items = calloc((size_t)setup->body_count + 1, sizeof *w->items);
    if (!w->items) {
        free(w);
        return NULL;
    }
    w->hasty = setup->threads > 1;
    w->space = w->hasty ? cpHastySpaceNew() : cpSpaceNew();
    if (w->hasty) {
        cpHastySpaceSetThreads(w->space, (unsigned long)kg_cp_threads(setup->threads));
    }
    cpSpaceSetGravity(w->space, cpv(setup->gravity.x, setup->gravity.y));
    cpSpaceSetIterations(w->space, KG_CP_ITERATIONS);
    cpSpaceSetCollisionSlop(w->space, setup->linear_slop);
    return w;
}

/* Chipmunk frees neither bodies, shapes nor constraints with the space. */
static void kg_cp_destroy(void* world)
{
    kg_cp_world* w = world;
    if (w->hasty) {
        cpHastySpaceFree(w->space);
    } else {
        cpSpaceFree(w->space);
    }
    for (int i = 0; i < w->constraint_count; ++i) {
        cpConstraintFree(w->constraints[i]);
    }
    free(w->constraints);
    for (int i = 0; i < w->count; ++i) {
        cpShapeFree(w->items[i].shape);
        for (int k = 0; k < w->items[i].more_count; ++k) {
            cpShapeFree(w->items[i].more[k].shape);
        }
        free(w->items[i].more);
        cpBodyFree(w->items[i].body);
    }
    free(w->items);
    free(w);
}

typedef struct kg_cp_mass_props {
    cpFloat mass, moment;
    cpVect cog; /* body-local */
} kg_cp_mass_props;

static int kg_cp_polygon_vertices(const kg_shape_def* shape, cpVect* out)
{
    for (int i = 0; i < shape->count; ++i) {
        out[i] = cpv(shape->vertices[i].x, shape->vertices[i].y);
    }
    return shape->count;
}

/* Mass about the centre of gravity; fixed rotation is an infinite moment. */
static kg_cp_mass_props kg_cp_mass_of(const kg_peer_body* pb)
{
    const kg_body_def* def = pb->def;
    const kg_shape_def* shape = &def->shape;
    kg_cp_mass_props m = {def->mass, INFINITY, cpvzero};
    if (pb->shapes) { /* a compound body: kgyro's mass data of its shapes */
        m.mass = pb->mass.mass;
        m.cog = cpv(pb->mass.center.x, pb->mass.center.y);
        m.moment = pb->mass.inertia;
    } else if (shape->type == KG_SHAPE_POLYGON) {
        cpVect verts[KG_MAX_POLYGON_VERTICES];
        int n = kg_cp_polygon_vertices(shape, verts);
        m.mass = pb->density * cpAreaForPoly(n, verts, 0.0);
        m.cog = cpCentroidForPoly(n, verts);
        m.moment = cpMomentForPoly(m.mass, n, verts, cpvneg(m.cog), 0.0);
    } else if (shape->type == KG_SHAPE_CIRCLE) {
        m.mass = pb->density * cpAreaForCircle(0.0, shape->radius);
        m.cog = cpv(shape->center.x, shape->center.y);
        m.moment = cpMomentForCircle(m.mass, 0.0, shape->radius, cpvzero);
    } else if (shape->type == KG_SHAPE_CAPSULE) { /* Chipmunk's segment moment is a box's: kgyro's */
        kg_mass_data data = {0.0f, {0.0f, 0.0f}, 0.0f};
        kg_shape_mass(shape, pb->density, &data);
        m.mass = data.mass;
        m.cog = cpv(data.center.x, data.center.y);
        m.moment = data.inertia;
    }
    if (def->fixed_rotation || def->type == KG_BODY_PARTICLE) {
        m.moment = INFINITY;
    }
    return m;
}

static void kg_cp_damped_velocity(cpBody* body, cpVect gravity, cpFloat damping, cpFloat dt)
{
    const kg_cp_item* item = cpBodyGetUserData(body);
    cpBodyUpdateVelocity(body, gravity, damping, dt);
    cpBodySetVelocity(body, cpvmult(cpBodyGetVelocity(body), 1.0 / (1.0 + dt * item->linear_damping)));
    cpBodySetAngularVelocity(body, cpBodyGetAngularVelocity(body) / (1.0 + dt * item->angular_damping));
}

static cpBody* kg_cp_new_dynamic(kg_cp_item* item, const kg_peer_body* pb)
{
    const kg_body_def* def = pb->def;
    kg_cp_mass_props m = kg_cp_mass_of(pb);
    cpBody* body = cpBodyNew(m.mass, m.moment);
    cpBodySetCenterOfGravity(body, m.cog);
    if (def->linear_damping > 0.0f || def->angular_damping > 0.0f) {
        item->linear_damping = def->linear_damping;
        item->angular_damping = def->angular_damping;
        cpBodySetUserData(body, item);
        cpBodySetVelocityUpdateFunc(body, kg_cp_damped_velocity);
    }
    return body;
}

/* The angle first: placing the origin goes through the rotated centre of gravity. */
static cpBody* kg_cp_new_body(kg_cp_item* item, const kg_peer_body* pb)
{
    const kg_body_def* def = pb->def;
    cpBody* body;
    if (def->type == KG_BODY_STATIC) {
        body = cpBodyNewStatic();
    } else if (def->type == KG_BODY_KINEMATIC) {
        body = cpBodyNewKinematic();
    } else {
        body = kg_cp_new_dynamic(item, pb);
    }
    cpBodySetAngle(body, def->angle);
    cpBodySetPosition(body, cpv(def->position.x, def->position.y));
    if (def->type != KG_BODY_STATIC) {
        cpBodySetVelocity(body, cpv(def->velocity.x, def->velocity.y));
        cpBodySetAngularVelocity(body, def->angular_velocity);
    }
    return body;
}

static cpShape* kg_cp_new_shape(cpBody* body, const kg_body_shape_def* def)
{
    const kg_shape_def* shape = &def->geometry;
    cpShape* s;
    if (shape->type == KG_SHAPE_POLYGON) {
        cpVect verts[KG_MAX_POLYGON_VERTICES];
        int n = kg_cp_polygon_vertices(shape, verts);
        s = cpPolyShapeNew(body, n, verts, cpTransformIdentity, 0.0);
    } else if (shape->type == KG_SHAPE_CAPSULE || shape->type == KG_SHAPE_SEGMENT) { /* a segment's radius is 0 */
        s = cpSegmentShapeNew(body, cpv(shape->vertices[0].x, shape->vertices[0].y),
                              cpv(shape->vertices[1].x, shape->vertices[1].y), shape->radius);
    } else {
        s = cpCircleShapeNew(body, shape->radius, cpv(shape->center.x, shape->center.y));
    }
    cpShapeSetFriction(s, sqrt(def->friction));
    cpShapeSetElasticity(s, sqrt(def->restitution));
    cpShapeSetFilter(s, cpShapeFilterNew(CP_NO_GROUP, def->category, def->mask));
    cpShapeSetSensor(s, def->is_sensor ? cpTrue : cpFalse);
    return s;
}

/* A compound body's shapes after its first, into item->more. */
static const char* kg_cp_add_more_shapes(kg_cp_world* w, kg_cp_item* item, const kg_peer_body* pb)
{
    item->more = calloc((size_t)pb->shape_count, sizeof *item->more);
    if (!item->more) {
        return "out of memory";
    }
    for (int k = 1; k < pb->shape_count; ++k) {
        kg_cp_shape* more = &item->more[item->more_count++];
        more->shape = cpSpaceAddShape(w->space, kg_cp_new_shape(item->body, &pb->shapes[k]));
        more->type = pb->shapes[k].geometry.type;
    }
    return NULL;
}

static const char* kg_cp_add_body(void* world, const kg_peer_body* pb)
{
    kg_cp_world* w = world;
    if (pb->def->shape.type == KG_SHAPE_POLYGON && pb->def->shape.count < 3) {
        return "a polygon needs at least 3 vertices";
    }
    const kg_body_def* def = pb->def;
    kg_cp_item* item = &w->items[w->count++];
    item->body = cpSpaceAddBody(w->space, kg_cp_new_body(item, pb));
    item->shape_type = def->shape.type;
    kg_body_shape_def first = {def->shape, pb->density, def->friction, def->restitution, def->category, def->mask,
                               0, NULL};
    if (item->shape_type != KG_SHAPE_NONE) {
        item->shape = cpSpaceAddShape(w->space, kg_cp_new_shape(item->body, pb->shapes ? &pb->shapes[0] : &first));
    }
    return pb->shapes ? kg_cp_add_more_shapes(w, item, pb) : NULL;
}

/* ---- joints ---- */

/* A joint's body: the scene's, or for -1 the space's static body (the world). */
static cpBody* kg_cp_joint_body(kg_cp_world* w, int index)
{
    return index >= 0 ? w->items[index].body : cpSpaceGetStaticBody(w->space);
}

/* Adds c to the space, colliding its bodies as the joint says, and keeps it to free. */
static const char* kg_cp_add_constraint(kg_cp_world* w, cpConstraint* c, int collide_connected)
{
    if (w->constraint_count == w->constraint_capacity) {
        int capacity = w->constraint_capacity ? 2 * w->constraint_capacity : 64;
        cpConstraint** grown = realloc(w->constraints, (size_t)capacity * sizeof *grown);
        if (!grown) {
            cpConstraintFree(c);
            return "out of memory";
        }
        w->constraints = grown;
        w->constraint_capacity = capacity;
    }
    cpConstraintSetCollideBodies(c, collide_connected ? cpTrue : cpFalse);
    w->constraints[w->constraint_count++] = cpSpaceAddConstraint(w->space, c);
    return NULL;
}

/* A pivot, and a rotary limit, a motor and a rotary spring as the joint has them.
 * Chipmunk's angles are b's minus a's, kgyro's joint angle that minus reference_angle;
 * its simple motor drives a's spin minus b's to its rate. */
static const char* kg_cp_add_revolute(kg_cp_world* w, cpBody* a, cpBody* b, const kg_scene_joint* j)
{
    const kg_revolute_joint_def* d = &j->revolute;
    int collide = d->base.collide_connected;
    const char* why = kg_cp_add_constraint(w, cpPivotJointNew(a, b, cpv(j->anchor_a.x, j->anchor_a.y)), collide);
    if (!why && d->enable_limit) {
        why = kg_cp_add_constraint(
            w, cpRotaryLimitJointNew(a, b, d->lower_angle + d->reference_angle, d->upper_angle + d->reference_angle),
            collide);
    }
    if (!why && d->enable_motor) {
        cpConstraint* motor = cpSimpleMotorNew(a, b, -d->motor_speed);
        cpConstraintSetMaxForce(motor, d->max_motor_torque);
        why = kg_cp_add_constraint(w, motor, collide);
    }
    if (!why && d->enable_spring && d->hertz > 0.0f) {
        return "kgyro's rotary spring (hertz) is not mapped to Chipmunk's (stiffness)";
    }
    return why;
}

/* A rod (pin), a rope (slide joint from 0) or limits; springs are not mapped. */
static const char* kg_cp_add_distance(kg_cp_world* w, cpBody* a, cpBody* b, const kg_scene_joint* j)
{
    const kg_distance_joint_def* d = &j->distance;
    if (d->enable_spring && d->hertz > 0.0f) {
        return "kgyro's distance spring (hertz) is not mapped to Chipmunk's (stiffness)";
    }
    cpVect la = cpBodyWorldToLocal(a, cpv(j->anchor_a.x, j->anchor_a.y));
    cpVect lb = cpBodyWorldToLocal(b, cpv(j->anchor_b.x, j->anchor_b.y));
    int free_length = d->enable_spring || d->enable_limit;
    cpFloat min = d->enable_limit ? d->min_length : (free_length ? 0.0 : d->length);
    cpFloat max = d->enable_limit ? d->max_length : (free_length ? INFINITY : d->length);
    return kg_cp_add_constraint(w, cpSlideJointNew(a, b, la, lb, min, max), d->base.collide_connected);
}

static const char* kg_cp_add_joint(void* world, const kg_scene_joint* j)
{
    kg_cp_world* w = world;
    cpBody* a = kg_cp_joint_body(w, j->body_a);
    cpBody* b = kg_cp_joint_body(w, j->body_b);
    switch (j->type) {
    case KG_JOINT_REVOLUTE: return kg_cp_add_revolute(w, a, b, j);
    case KG_JOINT_DISTANCE: return kg_cp_add_distance(w, a, b, j);
    default: return "this kind of joint is not mapped to Chipmunk";
    }
}

static void kg_cp_step(void* world, float dt)
{
    kg_cp_world* w = world;
    if (w->hasty) {
        cpHastySpaceStep(w->space, dt);
    } else {
        cpSpaceStep(w->space, dt);
    }
}

static cpBody* kg_cp_body(const void* world, int index) { return ((const kg_cp_world*)world)->items[index].body; }

static kg_vec2 kg_cp_vec(cpVect v) { return (kg_vec2){(float)v.x, (float)v.y}; }

static void kg_cp_get_state(const void* world, int index, kg_body_state* out)
{
    const cpBody* body = kg_cp_body(world, index);
    out->position = kg_cp_vec(cpBodyGetPosition(body));
    out->angle = (float)cpBodyGetAngle(body);
    out->velocity = kg_cp_vec(cpBodyGetVelocity(body));
    out->angular_velocity = (float)cpBodyGetAngularVelocity(body);
}

static kg_vec2 kg_cp_rotation_center(const void* world, int index)
{
    const cpBody* body = kg_cp_body(world, index);
    return kg_cp_vec(cpBodyLocalToWorld(body, cpBodyGetCenterOfGravity(body)));
}

static void kg_cp_set_velocity(void* world, int index, kg_vec2 velocity)
{
    cpBodySetVelocity(kg_cp_body(world, index), cpv(velocity.x, velocity.y));
}

static double kg_cp_mass(const void* world, int index)
{
    cpBody* body = kg_cp_body(world, index);
    return cpBodyGetType(body) == CP_BODY_TYPE_DYNAMIC ? cpBodyGetMass(body) : 0.0;
}

static void kg_cp_include(kg_aabb* box, cpVect p, cpFloat radius)
{
    box->lower.x = fminf(box->lower.x, (float)(p.x - radius));
    box->lower.y = fminf(box->lower.y, (float)(p.y - radius));
    box->upper.x = fmaxf(box->upper.x, (float)(p.x + radius));
    box->upper.y = fmaxf(box->upper.y, (float)(p.y + radius));
}

/* From the shape's vertices: the shape's cached box is only refreshed when it is stepped. */
/* A shape of body (a polygon or a circle) into box. */
static void kg_cp_include_shape(kg_aabb* box, const cpBody* body, const cpShape* shape, kg_shape_type type)
{
    if (type == KG_SHAPE_POLYGON) {
        for (int i = 0; i < cpPolyShapeGetCount(shape); ++i) {
            kg_cp_include(box, cpBodyLocalToWorld(body, cpPolyShapeGetVert(shape, i)), 0.0);
        }
    } else if (type == KG_SHAPE_CAPSULE || type == KG_SHAPE_SEGMENT) {
        kg_cp_include(box, cpBodyLocalToWorld(body, cpSegmentShapeGetA(shape)), cpSegmentShapeGetRadius(shape));
        kg_cp_include(box, cpBodyLocalToWorld(body, cpSegmentShapeGetB(shape)), cpSegmentShapeGetRadius(shape));
    } else {
        kg_cp_include(box, cpBodyLocalToWorld(body, cpCircleShapeGetOffset(shape)), cpCircleShapeGetRadius(shape));
    }
}

static kg_aabb kg_cp_bounds(const void* world, int index)
{
    const kg_cp_item* item = &((const kg_cp_world*)world)->items[index];
    const cpBody* body = item->body;
    kg_aabb box = {{INFINITY, INFINITY}, {-INFINITY, -INFINITY}};
    if (item->shape_type == KG_SHAPE_NONE) {
        kg_cp_include(&box, cpBodyGetPosition(body), 0.0);
        return box;
    }
    kg_cp_include_shape(&box, body, item->shape, item->shape_type);
    for (int k = 0; k < item->more_count; ++k) {
        kg_cp_include_shape(&box, body, item->more[k].shape, item->more[k].type);
    }
    return box;
}

const kg_peer_adapter kg_chipmunk_adapter = {
    "chipmunk", kg_cp_describe, kg_cp_create, kg_cp_destroy, kg_cp_add_body, kg_cp_add_joint, kg_cp_step, kg_cp_get_state,
    kg_cp_rotation_center, kg_cp_set_velocity, kg_cp_mass, kg_cp_bounds,
};
