/* A kg_debug_draw whose callbacks record every call, positions in world metres, for the
 * debug draw tests (test_debug_draw.c, test_opencl_draw.c). */
#ifndef KG_DEBUG_DRAW_RECORDER_H
#define KG_DEBUG_DRAW_RECORDER_H

#include "kgyro/kgyro.h"

#include <math.h>
#include <string.h>

typedef enum kg_call_kind {
    KG_CALL_POLYGON,
    KG_CALL_SOLID_POLYGON,
    KG_CALL_CIRCLE,
    KG_CALL_SOLID_CIRCLE,
    KG_CALL_CAPSULE,
    KG_CALL_SEGMENT,
    KG_CALL_TRANSFORM,
    KG_CALL_POINT,
    KG_CALL_KINDS
} kg_call_kind;

/* points: a polygon's vertices, a circle's centre, a capsule's or segment's ends, a
 * point; radius also holds a point's size. */
typedef struct kg_call {
    kg_call_kind kind;
    kg_color color;
    int count;
    kg_vec2 points[KG_MAX_POLYGON_VERTICES];
    float radius;
    kg_transform transform;
} kg_call;

#define KG_MAX_CALLS 4096

typedef struct kg_recorder {
    kg_call calls[KG_MAX_CALLS];
    int count;    /* recorded, at most KG_MAX_CALLS */
    int overflow; /* calls past KG_MAX_CALLS */
    int per_kind[KG_CALL_KINDS];
} kg_recorder;

static kg_vec2 kg_apply(kg_transform xf, kg_vec2 p)
{
    return (kg_vec2){xf.position.x + xf.c * p.x - xf.s * p.y, xf.position.y + xf.s * p.x + xf.c * p.y};
}

static kg_call* kg_record(void* context, kg_call_kind kind, kg_color color)
{
    kg_recorder* r = context;
    r->per_kind[kind]++;
    if (r->count == KG_MAX_CALLS) {
        r->overflow++;
        return NULL;
    }
    kg_call* call = &r->calls[r->count++];
    memset(call, 0, sizeof *call);
    call->kind = kind;
    call->color = color;
    return call;
}

static void kg_rec_polygon(const kg_vec2* vertices, int count, kg_color color, void* context)
{
    kg_call* c = kg_record(context, KG_CALL_POLYGON, color);
    for (int i = 0; c && i < count && i < KG_MAX_POLYGON_VERTICES; ++i) {
        c->points[c->count++] = vertices[i];
    }
}

static void kg_rec_solid_polygon(kg_transform xf, const kg_vec2* vertices, int count, float radius, kg_color color,
                                 void* context)
{
    kg_call* c = kg_record(context, KG_CALL_SOLID_POLYGON, color);
    for (int i = 0; c && i < count && i < KG_MAX_POLYGON_VERTICES; ++i) {
        c->points[c->count++] = kg_apply(xf, vertices[i]);
    }
    if (c) {
        c->radius = radius;
        c->transform = xf;
    }
}

static void kg_rec_circle(kg_vec2 center, float radius, kg_color color, void* context)
{
    kg_call* c = kg_record(context, KG_CALL_CIRCLE, color);
    if (c) {
        c->points[0] = center;
        c->count = 1;
        c->radius = radius;
    }
}

static void kg_rec_solid_circle(kg_transform xf, float radius, kg_color color, void* context)
{
    kg_call* c = kg_record(context, KG_CALL_SOLID_CIRCLE, color);
    if (c) {
        c->points[0] = xf.position;
        c->count = 1;
        c->radius = radius;
        c->transform = xf;
    }
}

static void kg_rec_capsule(kg_vec2 p1, kg_vec2 p2, float radius, kg_color color, void* context)
{
    kg_call* c = kg_record(context, KG_CALL_CAPSULE, color);
    if (c) {
        c->points[0] = p1;
        c->points[1] = p2;
        c->count = 2;
        c->radius = radius;
    }
}

static void kg_rec_segment(kg_vec2 p1, kg_vec2 p2, kg_color color, void* context)
{
    kg_call* c = kg_record(context, KG_CALL_SEGMENT, color);
    if (c) {
        c->points[0] = p1;
        c->points[1] = p2;
        c->count = 2;
    }
}

static void kg_rec_transform(kg_transform xf, void* context)
{
    kg_call* c = kg_record(context, KG_CALL_TRANSFORM, 0u);
    if (c) {
        c->points[0] = xf.position;
        c->count = 1;
        c->transform = xf;
    }
}

static void kg_rec_point(kg_vec2 point, float size, kg_color color, void* context)
{
    kg_call* c = kg_record(context, KG_CALL_POINT, color);
    if (c) {
        c->points[0] = point;
        c->count = 1;
        c->radius = size;
    }
}

/* Every callback set, recording into r, with the given flags. */
static kg_debug_draw kg_recording_draw(kg_recorder* r, unsigned flags)
{
    memset(r, 0, sizeof *r);
    kg_debug_draw d = kg_default_debug_draw();
    d.draw_polygon = kg_rec_polygon;
    d.draw_solid_polygon = kg_rec_solid_polygon;
    d.draw_circle = kg_rec_circle;
    d.draw_solid_circle = kg_rec_solid_circle;
    d.draw_capsule = kg_rec_capsule;
    d.draw_segment = kg_rec_segment;
    d.draw_transform = kg_rec_transform;
    d.draw_point = kg_rec_point;
    d.flags = flags;
    d.context = r;
    return d;
}

#endif
