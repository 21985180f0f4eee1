// Box2D 2.4 adapter: one b2Body with at most one fixture per scene body.
//
// Box2D 2.4 solves with velocity and position iterations and has no sub-steps (those came
// with v3), so the "4 sub-steps" of the benchmark scenes cannot be matched; it gets the
// iteration counts its own samples use. Sleeping is off. Continuous collision is off
// too: neither kgyro nor Chipmunk has a time-of-impact pass, and Box2D 2.4's costs it a
// sub-solve per impact (on particles_10000 it made the mean step 2.3 times longer), so
// leaving it on would compare different work. Box2D 2.4 runs on one thread.
//
// Box2D 2.4 rounds every polygon by b2_polygonRadius (1 cm): a 1 m box collides as a
// 1.02 m one, and the 100 rows of large_pyramid would stand 1 m taller than in the other
// engines. Polygons are therefore inset by that radius, so that the rounded shape's faces
// are the scene's faces, and the body gets the mass, centre and inertia of the scene's
// shape (Box2D would compute them from the inset core).
#include "peer_adapter.h"

#include <box2d/box2d.h>

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

namespace {

const int32 kVelocityIterations = 8;
const int32 kPositionIterations = 3;

struct Box2DWorld {
    b2World* world;
    b2Body** bodies;
    int count;
    b2Body* ground; // what joints to the world hold on to, made with the first
    float restitution_threshold;
};

b2Vec2 ToB2(kg_vec2 v) { return b2Vec2(v.x, v.y); }

kg_vec2 FromB2(const b2Vec2& v)
{
    kg_vec2 out = {v.x, v.y};
    return out;
}

b2BodyType BodyType(kg_body_type type)
{
    switch (type) {
    case KG_BODY_STATIC:
        return b2_staticBody;
    case KG_BODY_KINEMATIC:
        return b2_kinematicBody;
    default:
        return b2_dynamicBody;
    }
}

// Debian's 2.4.1 library still says 2.4.0 in b2_version: prefer the package's version.
const char* Version()
{
#ifdef KG_PEER_BOX2D_VERSION
    return KG_PEER_BOX2D_VERSION;
#else
    static char text[32];
    snprintf(text, sizeof text, "%d.%d.%d", b2_version.major, b2_version.minor, b2_version.revision);
    return text;
#endif
}

const char* Describe(int threads)
{
    static char text[320];
    snprintf(text, sizeof text,
             "Box2D %s: %d velocity + %d position iterations, no sub-steps (2.4 has none), polygons inset by "
             "its %.0f mm skin, continuous off, sleeping off, 1 thread%s",
             Version(), kVelocityIterations, kPositionIterations, 1000.0 * b2_polygonRadius,
             threads > 1 ? " (2.4 is single-threaded)" : "");
    return text;
}

void* Create(const kg_peer_setup* setup)
{
    Box2DWorld* w = static_cast<Box2DWorld*>(calloc(1, sizeof(Box2DWorld)));
    if (!w) {
        return NULL;
    }
    w->bodies = static_cast<b2Body**>(calloc(static_cast<size_t>(setup->body_count) + 1, sizeof(b2Body*)));
    if (!w->bodies) {
        free(w);
        return NULL;
    }
    w->world = new b2World(ToB2(setup->gravity));
    w->world->SetAllowSleeping(false);
    w->world->SetContinuousPhysics(false);
    w->restitution_threshold = setup->restitution_threshold;
    return w;
}

void Destroy(void* world)
{
    Box2DWorld* w = static_cast<Box2DWorld*>(world);
    delete w->world;
    free(w->bodies);
    free(w);
}

b2BodyDef MakeBodyDef(const kg_body_def* def)
{
    b2BodyDef bd;
    bd.type = BodyType(def->type);
    bd.position = ToB2(def->position);
    bd.angle = def->angle;
    bd.linearVelocity = ToB2(def->velocity);
    bd.angularVelocity = def->angular_velocity;
    bd.linearDamping = def->linear_damping;
    bd.angularDamping = def->angular_damping;
    bd.allowSleep = false;
    bd.fixedRotation = def->fixed_rotation != 0 || def->type == KG_BODY_PARTICLE;
    return bd;
}

// Box2D 2.4 filters on 16 bits; kgyro's all-ones default maps to Box2D's.
bool FitsFilter(uint32_t bits) { return bits <= 0xFFFFu || bits == 0xFFFFFFFFu; }

float SignedArea(const b2Vec2* v, int count)
{
    float twice = 0.0f;
    for (int i = 0; i < count; ++i) {
        twice += b2Cross(v[i], v[(i + 1) % count]);
    }
    return 0.5f * twice;
}

b2Vec2 OutwardNormal(const b2Vec2& from, const b2Vec2& to, float winding)
{
    b2Vec2 edge = to - from;
    edge.Normalize();
    return winding * b2Vec2(edge.y, -edge.x);
}

// Moves every edge of the convex polygon inwards by radius: each vertex moves along
// the sum of its two edge normals, scaled so that both edges move by exactly radius.
// Keeps the polygon as it is when it is too small to be inset.
void InsetPolygon(const kg_shape_def* shape, float radius, b2Vec2* out, int count)
{
    b2Vec2 v[b2_maxPolygonVertices];
    for (int i = 0; i < count; ++i) {
        v[i] = ToB2(shape->vertices[i]);
    }
    float area = SignedArea(v, count);
    float winding = area > 0.0f ? 1.0f : -1.0f;
    for (int i = 0; i < count; ++i) {
        b2Vec2 before = OutwardNormal(v[(i + count - 1) % count], v[i], winding);
        b2Vec2 after = OutwardNormal(v[i], v[(i + 1) % count], winding);
        out[i] = v[i] - (radius / (1.0f + b2Dot(before, after))) * (before + after);
    }
    float inset_area = SignedArea(out, count);
    if (!(inset_area * winding > 0.25f * area * winding)) {
        for (int i = 0; i < count; ++i) {
            out[i] = v[i];
        }
    }
}

// The scene shape's exact mass properties; b2MassData wants inertia about the origin.
void SetSceneMass(b2Body* body, const kg_body_def* def, float density)
{
    kg_mass_data m;
    if (kg_shape_mass(&def->shape, density, &m) != KG_OK) {
        return;
    }
    b2MassData data;
    data.mass = m.mass;
    data.center = ToB2(m.center);
    data.I = m.inertia + m.mass * b2Dot(data.center, data.center);
    body->SetMassData(&data);
}

// A fixture of the shape with its density, material and filter.
const char* AddShape(Box2DWorld* w, b2Body* body, const kg_body_shape_def* shape)
{
    if (!FitsFilter(shape->category)) {
        return "collision categories above bit 15 do not fit Box2D 2.4's 16-bit filter";
    }
    b2FixtureDef fd;
    fd.density = shape->density;
    fd.friction = shape->friction;
    fd.restitution = shape->restitution;
    fd.restitutionThreshold = w->restitution_threshold;
    fd.isSensor = shape->is_sensor != 0;
    fd.filter.categoryBits = static_cast<uint16>(shape->category & 0xFFFFu);
    fd.filter.maskBits = static_cast<uint16>(shape->mask & 0xFFFFu);
    b2PolygonShape polygon;
    b2CircleShape circle;
    b2EdgeShape edge;
    const kg_shape_def* geometry = &shape->geometry;
    if (geometry->type == KG_SHAPE_CAPSULE) {
        return "Box2D 2.4 has no capsule shape";
    }
    if (geometry->type == KG_SHAPE_SEGMENT) {
        edge.SetTwoSided(ToB2(geometry->vertices[0]), ToB2(geometry->vertices[1]));
        fd.shape = &edge;
    } else if (geometry->type == KG_SHAPE_POLYGON) {
        b2Vec2 points[b2_maxPolygonVertices];
        int count = geometry->count < b2_maxPolygonVertices ? geometry->count : b2_maxPolygonVertices;
        InsetPolygon(geometry, b2_polygonRadius, points, count);
        polygon.Set(points, count);
        fd.shape = &polygon;
    } else {
        circle.m_p = ToB2(geometry->center);
        circle.m_radius = geometry->radius;
        fd.shape = &circle;
    }
    body->CreateFixture(&fd);
    return NULL;
}

// A body of one shape: the def's, at the resolved density.
const char* AddFixture(Box2DWorld* w, b2Body* body, const kg_peer_body* pb)
{
    const kg_body_def* def = pb->def;
    kg_body_shape_def shape = {def->shape, pb->density, def->friction, def->restitution, def->category, def->mask,
                               0, NULL};
    const char* why = AddShape(w, body, &shape);
    if (!why && body->GetType() == b2_dynamicBody) {
        SetSceneMass(body, def, pb->density);
    }
    return why;
}

// A compound body: a fixture per shape, the mass data of them all (kgyro's).
const char* AddFixtures(Box2DWorld* w, b2Body* body, const kg_peer_body* pb)
{
    for (int k = 0; k < pb->shape_count; ++k) {
        const char* why = AddShape(w, body, &pb->shapes[k]);
        if (why) {
            return why;
        }
    }
    if (body->GetType() == b2_dynamicBody) {
        b2MassData data;
        data.mass = pb->mass.mass;
        data.center = ToB2(pb->mass.center);
        data.I = pb->mass.inertia + pb->mass.mass * b2Dot(data.center, data.center);
        body->SetMassData(&data);
    }
    return NULL;
}

// A point particle has no fixture to derive a mass from: give it the mass directly.
void SetPointMass(b2Body* body, float mass)
{
    b2MassData data;
    data.mass = mass;
    data.center.SetZero();
    data.I = 0.0f;
    body->SetMassData(&data);
}

const char* AddBody(void* world, const kg_peer_body* pb)
{
    Box2DWorld* w = static_cast<Box2DWorld*>(world);
    const kg_body_def* def = pb->def;
    b2BodyDef bd = MakeBodyDef(def);
    b2Body* body = w->world->CreateBody(&bd);
    w->bodies[w->count++] = body;
    if (pb->shapes) {
        return AddFixtures(w, body, pb);
    }
    if (def->shape.type != KG_SHAPE_NONE) {
        return AddFixture(w, body, pb);
    }
    if (bd.type == b2_dynamicBody) {
        SetPointMass(body, def->mass);
    }
    return NULL;
}

// A joint's body: the scene's, or for -1 the world (a static body at the origin).
b2Body* JointBody(Box2DWorld* w, int index)
{
    if (index >= 0) {
        return w->bodies[index];
    }
    if (!w->ground) {
        b2BodyDef bd;
        w->ground = w->world->CreateBody(&bd);
    }
    return w->ground;
}

const char* AddRevolute(Box2DWorld* w, b2Body* a, b2Body* b, const kg_scene_joint* j)
{
    const kg_revolute_joint_def& d = j->revolute;
    if (d.enable_spring) {
        return "Box2D 2.4's revolute joint has no spring";
    }
    b2RevoluteJointDef jd;
    jd.Initialize(a, b, ToB2(j->anchor_a));
    jd.referenceAngle = d.reference_angle;
    jd.enableLimit = d.enable_limit != 0;
    jd.lowerAngle = d.lower_angle;
    jd.upperAngle = d.upper_angle;
    jd.enableMotor = d.enable_motor != 0;
    jd.motorSpeed = d.motor_speed;
    jd.maxMotorTorque = d.max_motor_torque;
    jd.collideConnected = d.base.collide_connected != 0;
    w->world->CreateJoint(&jd);
    return NULL;
}

// Rigid (min = max = length), a spring about its length, or a rope (limits, no spring),
// as Box2D 2.4.1's distance joint tells them apart.
const char* AddDistance(Box2DWorld* w, b2Body* a, b2Body* b, const kg_scene_joint* j)
{
    const kg_distance_joint_def& d = j->distance;
    b2DistanceJointDef jd;
    jd.Initialize(a, b, ToB2(j->anchor_a), ToB2(j->anchor_b));
    jd.length = d.length;
    bool free_length = d.enable_spring || d.enable_limit;
    jd.minLength = d.enable_limit ? d.min_length : (free_length ? 0.0f : d.length);
    jd.maxLength = d.enable_limit ? d.max_length : (free_length ? FLT_MAX : d.length);
    if (d.enable_spring && d.hertz > 0.0f) {
        b2LinearStiffness(jd.stiffness, jd.damping, d.hertz, d.damping_ratio, a, b);
    }
    jd.collideConnected = d.base.collide_connected != 0;
    w->world->CreateJoint(&jd);
    return NULL;
}

const char* AddWeld(Box2DWorld* w, b2Body* a, b2Body* b, const kg_scene_joint* j)
{
    const kg_weld_joint_def& d = j->weld;
    if (d.linear_hertz > 0.0f) {
        return "Box2D 2.4's weld joint has no linear softness";
    }
    b2WeldJointDef jd;
    jd.Initialize(a, b, ToB2(j->anchor_a));
    jd.referenceAngle = d.reference_angle;
    if (d.angular_hertz > 0.0f) {
        b2AngularStiffness(jd.stiffness, jd.damping, d.angular_hertz, d.angular_damping_ratio, a, b);
    }
    jd.collideConnected = d.base.collide_connected != 0;
    w->world->CreateJoint(&jd);
    return NULL;
}

const char* AddJoint(void* world, const kg_scene_joint* j)
{
    Box2DWorld* w = static_cast<Box2DWorld*>(world);
    b2Body* a = JointBody(w, j->body_a);
    b2Body* b = JointBody(w, j->body_b);
    switch (j->type) {
    case KG_JOINT_REVOLUTE:
        return AddRevolute(w, a, b, j);
    case KG_JOINT_DISTANCE:
        return AddDistance(w, a, b, j);
    case KG_JOINT_WELD:
        return AddWeld(w, a, b, j);
    default:
        return "this kind of joint is not mapped to Box2D 2.4";
    }
}

void Step(void* world, float dt)
{
    static_cast<Box2DWorld*>(world)->world->Step(dt, kVelocityIterations, kPositionIterations);
}

const b2Body* BodyAt(const void* world, int index) { return static_cast<const Box2DWorld*>(world)->bodies[index]; }

void GetState(const void* world, int index, kg_body_state* out)
{
    const b2Body* body = BodyAt(world, index);
    out->position = FromB2(body->GetPosition());
    out->angle = body->GetAngle();
    out->velocity = FromB2(body->GetLinearVelocity());
    out->angular_velocity = body->GetAngularVelocity();
}

kg_vec2 RotationCenter(const void* world, int index) { return FromB2(BodyAt(world, index)->GetWorldCenter()); }

void SetVelocity(void* world, int index, kg_vec2 velocity)
{
    static_cast<Box2DWorld*>(world)->bodies[index]->SetLinearVelocity(ToB2(velocity));
}

double Mass(const void* world, int index)
{
    const b2Body* body = BodyAt(world, index);
    return body->GetType() == b2_dynamicBody ? body->GetMass() : 0.0;
}

void Include(kg_aabb* box, const b2Vec2& p, float radius)
{
    box->lower.x = fminf(box->lower.x, p.x - radius);
    box->lower.y = fminf(box->lower.y, p.y - radius);
    box->upper.x = fmaxf(box->upper.x, p.x + radius);
    box->upper.y = fmaxf(box->upper.y, p.y + radius);
}

// From the shape itself, skin included: the fixture's AABB also carries the broad-phase
// margin, which would make the engines look different when they are not.
kg_aabb Bounds(const void* world, int index)
{
    const b2Body* body = BodyAt(world, index);
    const b2Transform& xf = body->GetTransform();
    kg_aabb box = {{INFINITY, INFINITY}, {-INFINITY, -INFINITY}};
    const b2Fixture* fixture = body->GetFixtureList();
    if (!fixture) {
        Include(&box, xf.p, 0.0f);
        return box;
    }
    for (; fixture; fixture = fixture->GetNext()) {
        const b2Shape* shape = fixture->GetShape();
        if (shape->GetType() == b2Shape::e_circle) {
            const b2CircleShape* circle = static_cast<const b2CircleShape*>(shape);
            Include(&box, b2Mul(xf, circle->m_p), circle->m_radius);
            continue;
        }
        if (shape->GetType() == b2Shape::e_edge) {
            const b2EdgeShape* edge = static_cast<const b2EdgeShape*>(shape);
            Include(&box, b2Mul(xf, edge->m_vertex1), 0.0f);
            Include(&box, b2Mul(xf, edge->m_vertex2), 0.0f);
            continue;
        }
        const b2PolygonShape* polygon = static_cast<const b2PolygonShape*>(shape);
        for (int32 i = 0; i < polygon->m_count; ++i) {
            Include(&box, b2Mul(xf, polygon->m_vertices[i]), polygon->m_radius);
        }
    }
    return box;
}

} // namespace

extern "C" const kg_peer_adapter kg_box2d_adapter = {
    "box2d", Describe, Create, Destroy, AddBody, AddJoint, Step, GetState, RotationCenter, SetVelocity, Mass, Bounds,
};
