/* Sensors: after each step of a world that has any, every sensor shape's visitors (the
 * shapes of other bodies and the tiles it overlaps) are found through the query index
 * (collide/query.c), sorted, and compared with the last step's by a merge walk: begin
 * where only the new list has a visit, end where only the old one has it. The sensor
 * shapes are listed again only when the shape pool changed. */
#include "collide/events.h"
#include "collide/query_index.h"
#include "core/alloc.h"
#include "core/error.h"

#include <stdlib.h>
#include <string.h>

/* A sensor shape overlapping a visitor: a shape of a body, or a tile (map >= 0). The user
 * data are kept so that an end event can give them after the body is gone. */
typedef struct kg_visit {
    kg_u32 sensor, sensor_generation; /* the sensor's shape slot and generation */
    kg_u32 is_tile;
    kg_u32 body, body_generation, shape, shape_generation;
    kg_u32 map, map_generation, layer, y, x;
    kg_u32 sensor_body, sensor_body_generation;
    void* sensor_user_data;
    void* user_data;
} kg_visit;

struct kg_sensors {
    kg_visit* visits[2]; /* [current]: the last step's; the other, this step's as it is found */
    int visit_count[2];
    int visit_capacity[2];
    int current;
    kg_u32* slots; /* the sensor shapes, listed at shapes_version */
    int slot_count, slot_capacity;
    kg_u32 shapes_version;
    int listed;
    kg_event_list begin, end;
    kg_result failure; /* of a visit that could not be stored, in the middle of a query */
};

static kg_result kg_list_sensors(kg_world* world, struct kg_sensors* s)
{
    const kg_shape_pool* sp = &world->shapes;
    if (s->listed && s->shapes_version == sp->version) {
        return KG_OK;
    }
    s->slot_count = 0;
    for (int k = 0; k < sp->high_water; ++k) {
        if (kg_shape_alive(sp, k) && kg_shape_is_sensor(sp, (kg_u32)k)) {
            KG_TRY(kg_grow((void**)&s->slots, &s->slot_capacity, s->slot_count + 1, sizeof *s->slots));
            s->slots[s->slot_count++] = (kg_u32)k;
        }
    }
    s->shapes_version = sp->version;
    s->listed = 1;
    return KG_OK;
}

static int kg_visit_compare(const void* p, const void* q)
{
    const kg_visit* a = p;
    const kg_visit* b = q;
    kg_u32 ak[11] = {a->sensor, a->sensor_generation, a->is_tile, a->body, a->body_generation, a->shape,
                     a->shape_generation, a->map, a->layer, a->y, a->x};
    kg_u32 bk[11] = {b->sensor, b->sensor_generation, b->is_tile, b->body, b->body_generation, b->shape,
                     b->shape_generation, b->map, b->layer, b->y, b->x};
    for (int i = 0; i < 11; ++i) {
        if (ak[i] != bk[i]) {
            return ak[i] < bk[i] ? -1 : 1;
        }
    }
    return 0;
}

typedef struct kg_sensor_scan {
    struct kg_sensors* s;
    kg_visit sensor; /* the sensor's fields, the visitor's to fill */
} kg_sensor_scan;

static int kg_note_visit(const kg_overlap_result* found, void* ctx)
{
    kg_sensor_scan* scan = ctx;
    struct kg_sensors* s = scan->s;
    int next = s->current ^ 1;
    kg_visit v = scan->sensor;
    v.is_tile = found->body.generation == 0u;
    v.body = found->body.index;
    v.body_generation = found->body.generation;
    v.shape = found->shape.index;
    v.shape_generation = found->shape.generation;
    v.map = v.is_tile ? found->map.index : 0u;
    v.map_generation = v.is_tile ? found->map.generation : 0u;
    v.layer = (kg_u32)found->layer;
    v.y = (kg_u32)found->y;
    v.x = (kg_u32)found->x;
    v.user_data = found->user_data;
    s->failure = kg_grow((void**)&s->visits[next], &s->visit_capacity[next], s->visit_count[next] + 1, sizeof v);
    if (s->failure != KG_OK) {
        return 0;
    }
    s->visits[next][s->visit_count[next]++] = v;
    return 1;
}

/* This step's visits of every sensor, sorted, into the list that is not current. */
static kg_result kg_find_visits(kg_world* world, struct kg_sensors* s)
{
    const kg_body_pool* p = kg_world_read_pool(world);
    const kg_shape_pool* sp = &world->shapes;
    s->visit_count[s->current ^ 1] = 0;
    for (int k = 0; k < s->slot_count; ++k) {
        kg_u32 slot = s->slots[k], i = sp->body[slot];
        kg_sensor_scan scan;
        memset(&scan, 0, sizeof scan);
        scan.s = s;
        scan.sensor.sensor = slot;
        scan.sensor.sensor_generation = sp->generation[slot];
        scan.sensor.sensor_body = i;
        scan.sensor.sensor_body_generation = p->generation[i];
        scan.sensor.sensor_user_data = p->user_data[i];
        kg_query_filter filter = kg_default_query_filter();
        filter.category = sp->category[slot];
        filter.mask = sp->mask[slot];
        filter.flags = KG_QUERY_SKIP_SENSORS;
        s->failure = KG_OK;
        KG_TRY(kg_overlap_of_shape(world, slot, filter, kg_note_visit, &scan));
        KG_TRY(s->failure);
    }
    int next = s->current ^ 1;
    if (s->visit_count[next] > 1) {
        qsort(s->visits[next], (size_t)s->visit_count[next], sizeof(kg_visit), kg_visit_compare);
    }
    return KG_OK;
}

/* A visit as an event; a body no longer alive is named by the null handle. */
static kg_contact_event kg_sensor_event(const kg_world* world, kg_event_kind kind, const kg_visit* v)
{
    kg_contact_event e;
    memset(&e, 0, sizeof e);
    e.kind = kind;
    kg_body sensor_body = {v->sensor_body, v->sensor_body_generation};
    kg_body visitor = {v->body, v->body_generation};
    if (kg_body_is_valid(world, sensor_body)) {
        e.a = sensor_body;
        e.shape_a.index = v->sensor;
        e.shape_a.generation = v->sensor_generation;
    }
    if (!v->is_tile && kg_body_is_valid(world, visitor)) {
        e.b = visitor;
        e.shape_b.index = v->shape;
        e.shape_b.generation = v->shape_generation;
    }
    e.user_data_a = v->sensor_user_data;
    e.user_data_b = v->user_data;
    if (v->is_tile) {
        e.map.index = v->map;
        e.map.generation = v->map_generation;
        e.layer = (int)v->layer;
        e.x = (int)v->x;
        e.y = (int)v->y;
    }
    return e;
}

static kg_result kg_compare_visits(kg_world* world, struct kg_sensors* s)
{
    const kg_visit* old = s->visits[s->current];
    const kg_visit* now = s->visits[s->current ^ 1];
    int old_count = s->visit_count[s->current], now_count = s->visit_count[s->current ^ 1];
    int i = 0, j = 0;
    while (i < old_count || j < now_count) {
        int order = i == old_count ? 1 : j == now_count ? -1 : kg_visit_compare(&old[i], &now[j]);
        if (order != 0) {
            kg_contact_event e = order > 0 ? kg_sensor_event(world, KG_EVENT_SENSOR_BEGIN, &now[j])
                                           : kg_sensor_event(world, KG_EVENT_SENSOR_END, &old[i]);
            KG_TRY(kg_push(order > 0 ? &s->begin : &s->end, &e));
        }
        i += order <= 0;
        j += order >= 0;
    }
    return KG_OK;
}

kg_result kg_sensors_after_step(kg_world* world)
{
    struct kg_sensors* s = world->sensors;
    if (!s) {
        s = world->sensors = kg_alloc_zeroed(sizeof *s);
        if (!s) {
            return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the sensors");
        }
    }
    s->begin.count = s->end.count = 0;
    KG_TRY(kg_list_sensors(world, s));
    KG_TRY(kg_find_visits(world, s));
    KG_TRY(kg_compare_visits(world, s));
    s->current ^= 1;
    return KG_OK;
}

void kg_sensors_destroy(kg_world* world)
{
    struct kg_sensors* s = world->sensors;
    if (!s) {
        return;
    }
    kg_free(s->visits[0]);
    kg_free(s->visits[1]);
    kg_free(s->slots);
    kg_free(s->begin.items);
    kg_free(s->end.items);
    kg_free(s);
    world->sensors = NULL;
}

kg_sensor_events kg_world_get_sensor_events(const kg_world* world)
{
    kg_sensor_events out;
    memset(&out, 0, sizeof out);
    const struct kg_sensors* s = world ? world->sensors : NULL;
    if (s) {
        out.begin = s->begin.items;
        out.begin_count = s->begin.count;
        out.end = s->end.items;
        out.end_count = s->end.count;
    }
    return out;
}
