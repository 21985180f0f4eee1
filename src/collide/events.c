/* Contact events, made when first asked for after a step, from the two contact lists the
 * collide stage keeps until the next step (this step's and the one before's): each list's
 * touching contacts as sorted keys, merged (begin where only the new list has a key, end
 * where only the old one has it), and hits read off the contacts the solver left. Nothing
 * is done for a step whose events nobody asks for; the lists grow with need, outside the
 * stages. */
#include "collide/events.h"
#include "collide/collide.h"
#include "collide/tilemap.h"
#include "core/alloc.h"
#include "core/error.h"
#include "kgyro/events.h"

#include <stdlib.h>
#include <string.h>

/* A touching contact of a step, as the next step recognises it. contact is its index in
 * that step's list (for begin events, which read its manifold). */
typedef struct kg_touch {
    kg_u32 a, b, shape_a, shape_b, tile, generation_a, generation_b, contact;
} kg_touch;

struct kg_events {
    kg_touch* touching[2]; /* the step before's and this step's touching contacts */
    int touching_count[2];
    int touching_capacity[2];
    kg_event_list begin, end, hit;
    uint64_t made_after; /* the step count the lists were made at; 0: none yet */
    kg_event_list destroyed_end; /* ends of destroyed bodies' contacts, */
    uint64_t* destroyed_at;      /* each with the step count when its body was destroyed */
    int destroyed_at_capacity;
};

kg_result kg_grow(void** items, int* capacity, int need, size_t size)
{
    if (need <= *capacity) {
        return KG_OK;
    }
    int grown = need > 2 * *capacity ? need : 2 * *capacity;
    void* bigger = kg_alloc_zeroed((size_t)grown * size);
    if (!bigger) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot grow the contact events to %d", grown);
    }
    if (*items) {
        memcpy(bigger, *items, (size_t)*capacity * size);
    }
    kg_free(*items);
    *items = bigger;
    *capacity = grown;
    return KG_OK;
}

kg_result kg_push(kg_event_list* list, const kg_contact_event* e)
{
    KG_TRY(kg_grow((void**)&list->items, &list->capacity, list->count + 1, sizeof *e));
    list->items[list->count++] = *e;
    return KG_OK;
}

/* Body pairs before tile contacts; then by slots, shapes or tile, and generations: the
 * contacts' own order, made total across steps (a slot reused is another body). */
static int kg_touch_compare(const kg_touch* p, const kg_touch* q)
{
    kg_u32 pk[8] = {p->b == KG_NULL_INDEX, p->a, p->b, p->tile, p->shape_a, p->shape_b, p->generation_a, p->generation_b};
    kg_u32 qk[8] = {q->b == KG_NULL_INDEX, q->a, q->b, q->tile, q->shape_a, q->shape_b, q->generation_a, q->generation_b};
    for (int i = 0; i < 8; ++i) {
        if (pk[i] != qk[i]) {
            return pk[i] < qk[i] ? -1 : 1;
        }
    }
    return 0;
}

static int kg_touch_sort(const void* p, const void* q) { return kg_touch_compare(p, q); }

static int kg_touches(const kg_contact* c, float slop)
{
    int touching = 0;
    for (int j = 0; j < c->manifold.point_count; ++j) {
        touching |= c->manifold.points[j].separation < slop;
    }
    return touching;
}

/* Contact k of a list as a touch record. */
static kg_touch kg_touch_of(const kg_contact* c, int k)
{
    kg_touch t = {c->a, c->b, c->shape_a, c->shape_b, c->tile, c->generation_a, c->generation_b, (kg_u32)k};
    return t;
}

/* An event's bodies, shapes, user data and tile, from a touch record. */
static kg_contact_event kg_event_of(const kg_world* world, kg_event_kind kind, const kg_touch* t)
{
    kg_contact_event e;
    memset(&e, 0, sizeof e);
    e.kind = kind;
    e.a = kg_handle_of(t->a, t->generation_a);
    e.b = kg_handle_of(t->b, t->generation_b);
    e.shape_a = kg_shape_handle_of(&world->shapes, t->shape_a, t->a);
    e.shape_b = kg_shape_handle_of(&world->shapes, t->shape_b, t->b);
    e.user_data_a = kg_body_get_user_data(world, e.a);
    e.user_data_b = kg_body_get_user_data(world, e.b);
    if (t->b == KG_NULL_INDEX) {
        kg_tile_key_cell(world, t->tile, &e.map, &e.layer, &e.x, &e.y);
    }
    return e;
}

static float kg_total_impulse(const kg_manifold* m)
{
    float total = 0.0f;
    for (int j = 0; j < m->point_count; ++j) {
        total += m->points[j].total_normal_impulse;
    }
    return total;
}

static kg_contact_event kg_begin_event(const kg_world* world, const kg_touch* t, const kg_contact* c)
{
    kg_contact_event e = kg_event_of(world, KG_EVENT_BEGIN, t);
    const kg_manifold* m = &c->manifold;
    e.normal = m->normal;
    e.point_count = m->point_count;
    int deepest = 0;
    for (int j = 0; j < m->point_count; ++j) {
        e.points[j] = m->points[j].point;
        e.depths[j] = -m->points[j].separation;
        deepest = e.depths[j] > e.depths[deepest] ? j : deepest;
    }
    e.point = e.points[deepest];
    e.normal_impulse = kg_total_impulse(m);
    return e;
}

/* Whether a touch record's bodies are still the ones it names. */
static int kg_touch_alive(const kg_world* world, const kg_touch* t)
{
    return kg_body_is_valid(world, kg_handle_of(t->a, t->generation_a)) &&
           (t->b == KG_NULL_INDEX || kg_body_is_valid(world, kg_handle_of(t->b, t->generation_b)));
}

/* A step's touching contacts, in order, into touching list `which`. */
static kg_result kg_list_touching(const kg_world* world, struct kg_events* ev, int which, const kg_contact* contacts,
                                  int count)
{
    KG_TRY(kg_grow((void**)&ev->touching[which], &ev->touching_capacity[which], count, sizeof(kg_touch)));
    kg_touch* out = ev->touching[which];
    int n = 0, tiles_from = -1;
    for (int k = 0; k < count; ++k) {
        const kg_contact* c = &contacts[k];
        if (!kg_touches(c, world->def.linear_slop)) {
            continue;
        }
        if (c->b == KG_NULL_INDEX && tiles_from < 0) {
            tiles_from = n;
        }
        out[n++] = kg_touch_of(c, k);
    }
    if (tiles_from >= 0) { /* tile contacts come by map and body: ordered here by body and tile */
        qsort(out + tiles_from, (size_t)(n - tiles_from), sizeof *out, kg_touch_sort);
    }
    ev->touching_count[which] = n;
    return KG_OK;
}

/* Begin and end events: the merge of the last step's touching list with this step's. */
static kg_result kg_compare_touching(const kg_world* world, struct kg_events* ev, const kg_contact* contacts)
{
    const kg_touch* old = ev->touching[0];
    const kg_touch* now = ev->touching[1];
    int old_count = ev->touching_count[0], now_count = ev->touching_count[1];
    int i = 0, j = 0;
    while (i < old_count || j < now_count) {
        int order = i == old_count ? 1 : j == now_count ? -1 : kg_touch_compare(&old[i], &now[j]);
        if (order > 0) {
            kg_contact_event e = kg_begin_event(world, &now[j], &contacts[now[j].contact]);
            KG_TRY(kg_push(&ev->begin, &e));
        } else if (order < 0 && kg_touch_alive(world, &old[i])) { /* else its end was noted on destroy */
            kg_contact_event e = kg_event_of(world, KG_EVENT_END, &old[i]);
            KG_TRY(kg_push(&ev->end, &e));
        }
        i += order <= 0;
        j += order >= 0;
    }
    return KG_OK;
}

/* Hit events: contacts with a point that pushed this step after closing faster than the
 * threshold; the fastest such point tells. */
static kg_result kg_find_hits(const kg_world* world, struct kg_events* ev, const kg_contact* contacts, int count)
{
    float threshold = world->def.hit_event_threshold;
    for (int k = 0; k < count; ++k) {
        const kg_manifold* m = &contacts[k].manifold;
        int fastest = -1;
        float speed = threshold;
        for (int j = 0; j < m->point_count; ++j) {
            float approach = -m->points[j].normal_velocity;
            if (m->points[j].total_normal_impulse > 0.0f && approach > speed) {
                fastest = j;
                speed = approach;
            }
        }
        if (fastest < 0) {
            continue;
        }
        const kg_contact* c = &contacts[k];
        kg_touch t = kg_touch_of(c, k);
        kg_contact_event e = kg_event_of(world, KG_EVENT_HIT, &t);
        e.normal = m->normal;
        e.point = m->points[fastest].point;
        e.approach_speed = speed;
        e.normal_impulse = kg_total_impulse(m);
        KG_TRY(kg_push(&ev->hit, &e));
    }
    return KG_OK;
}

static struct kg_events* kg_events_of(kg_world* world)
{
    if (!world->events) {
        world->events = kg_alloc_zeroed(sizeof *world->events);
        if (!world->events) {
            kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the contact events");
        }
    }
    return world->events;
}

/* The ends of contacts of bodies destroyed between the step before and this one first,
 * in the order of the calls; those destroyed since wait for the next step's. */
static kg_result kg_hand_out_destroyed(struct kg_events* ev, uint64_t step)
{
    int kept = 0;
    for (int i = 0; i < ev->destroyed_end.count; ++i) {
        uint64_t at = ev->destroyed_at[i];
        if (at + 1u == step) {
            KG_TRY(kg_push(&ev->end, &ev->destroyed_end.items[i]));
        } else if (at >= step) {
            ev->destroyed_at[kept] = at;
            ev->destroyed_end.items[kept++] = ev->destroyed_end.items[i];
        }
    }
    ev->destroyed_end.count = kept;
    return KG_OK;
}

/* The last step's events, made once. */
static kg_result kg_make_events(kg_world* world)
{
    struct kg_events* ev = kg_events_of(world);
    if (!ev) {
        return KG_ERROR_OUT_OF_MEMORY;
    }
    if (ev->made_after == world->step_index) {
        return KG_OK;
    }
    ev->begin.count = ev->end.count = ev->hit.count = 0;
    ev->made_after = world->step_index;
    int old_count = 0, count = 0;
    const kg_contact* old = kg_collision_synced_previous(world, &old_count);
    const kg_contact* contacts = kg_collision_synced_contacts(world, &count);
    KG_TRY(kg_hand_out_destroyed(ev, world->step_index));
    KG_TRY(kg_list_touching(world, ev, 0, old, old_count));
    KG_TRY(kg_list_touching(world, ev, 1, contacts, count));
    KG_TRY(kg_compare_touching(world, ev, contacts));
    return kg_find_hits(world, ev, contacts, count);
}

void kg_events_body_destroyed(kg_world* world, kg_u32 slot)
{
    struct kg_events* ev = world->step_index > 0 ? kg_events_of(world) : NULL;
    if (!ev) {
        return;
    }
    int count = 0;
    const kg_contact* contacts = kg_collision_synced_contacts(world, &count);
    for (int k = 0; k < count; ++k) {
        const kg_contact* c = &contacts[k];
        kg_touch t = kg_touch_of(c, k);
        if ((t.a != slot && t.b != slot) || !kg_touches(c, world->def.linear_slop) || !kg_touch_alive(world, &t)) {
            continue; /* not the body's, or ended already (the other body destroyed first) */
        }
        kg_contact_event e = kg_event_of(world, KG_EVENT_END, &t);
        kg_body none = KG_NULL_BODY_INIT;
        kg_shape_id no_shape = KG_NULL_SHAPE_INIT;
        if (t.a == slot) {
            e.a = none;
            e.shape_a = no_shape;
        } else {
            e.b = none;
            e.shape_b = no_shape;
        }
        int at = ev->destroyed_end.count; /* handed out with the next step's events */
        if (kg_grow((void**)&ev->destroyed_at, &ev->destroyed_at_capacity, at + 1, sizeof *ev->destroyed_at) != KG_OK ||
            kg_push(&ev->destroyed_end, &e) != KG_OK) {
            return; /* out of memory: the end is lost, the world is not */
        }
        ev->destroyed_at[at] = world->step_index;
    }
}

void kg_events_destroy(kg_world* world)
{
    struct kg_events* ev = world->events;
    if (!ev) {
        return;
    }
    for (int i = 0; i < 2; ++i) {
        kg_free(ev->touching[i]);
    }
    kg_free(ev->begin.items);
    kg_free(ev->end.items);
    kg_free(ev->hit.items);
    kg_free(ev->destroyed_end.items);
    kg_free(ev->destroyed_at);
    kg_free(ev);
    world->events = NULL;
}

kg_contact_events kg_world_get_contact_events(const kg_world* world)
{
    kg_contact_events out;
    memset(&out, 0, sizeof out);
    if (!world || world->step_index == 0 || kg_make_events((kg_world*)world) != KG_OK) {
        return out;
    }
    const struct kg_events* ev = world->events;
    {
        out.begin = ev->begin.items;
        out.begin_count = ev->begin.count;
        out.end = ev->end.items;
        out.end_count = ev->end.count;
        out.hit = ev->hit.items;
        out.hit_count = ev->hit.count;
    }
    return out;
}
