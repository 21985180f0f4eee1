/* Snapshots of a world (include/kgyro/snapshot.h): a header, then each part of the state
 * written by the module that owns it (core/snapshot_io.h), in this order: the world's
 * counters and definition, the body pool, the shape pool, the applicators, the contacts,
 * the tile maps, the joints. Restoring reads every part into new storage first, checking it, and only
 * when all of it was read does the world take it (and free what it had): a bad snapshot
 * leaves the world untouched. docs/design.md, "Snapshots", tells what is kept and why. */
#include "kgyro/snapshot.h"
#include "backend/backend.h"
#include "collide/collide.h"
#include "collide/events.h"
#include "collide/query_index.h"
#include "collide/tilemap.h"
#include "core/alloc.h"
#include "core/error.h"
#include "core/joint.h"
#include "core/snapshot_io.h"
#include "core/world.h"
#include "solve/solver.h"

#include <stddef.h>
#include <string.h>

static const char kg_snapshot_magic[8] = {'K', 'G', 'Y', 'R', 'O', 'S', 'N', 'P'};

/* The layout a snapshot was written with: it is read only by a build that agrees on all. */
enum {
    KG_LAYOUT_BYTE_ORDER,
    KG_LAYOUT_FLOAT,
    KG_LAYOUT_POINTER,
    KG_LAYOUT_SHAPE,
    KG_LAYOUT_CONTACT,
    KG_LAYOUT_WORLD_DEF,
    KG_LAYOUT_APPLICATOR,
    KG_LAYOUT_COUNT
};

static const char* const kg_layout_names[KG_LAYOUT_COUNT] = {
    "byte order", "sizeof(float)", "pointer size", "sizeof(kg_shape)", "sizeof(kg_contact)", "sizeof(kg_world_def)",
    "sizeof(kg_applicator_slot)"};

typedef struct kg_snapshot_header {
    char magic[8];
    kg_u32 version;
    kg_u32 header_size;
    uint64_t total_size;
    uint64_t checksum; /* of the bytes after the header */
    kg_u32 layout[KG_LAYOUT_COUNT];
    kg_u32 pad;
    uint64_t pool_layout; /* every pooled array's element size, folded (kg_snap_fold) */
} kg_snapshot_header;

static void kg_layout_of(kg_snapshot_header* h)
{
    kg_u32 order = 0x01020304u;
    unsigned char first = 0;
    memcpy(&first, &order, 1);
    h->layout[KG_LAYOUT_BYTE_ORDER] = first;
    h->layout[KG_LAYOUT_FLOAT] = (kg_u32)sizeof(float);
    h->layout[KG_LAYOUT_POINTER] = (kg_u32)sizeof(void*);
    h->layout[KG_LAYOUT_SHAPE] = (kg_u32)sizeof(kg_shape);
    h->layout[KG_LAYOUT_CONTACT] = (kg_u32)sizeof(kg_contact);
    h->layout[KG_LAYOUT_WORLD_DEF] = (kg_u32)sizeof(kg_world_def);
    h->layout[KG_LAYOUT_APPLICATOR] = (kg_u32)sizeof(kg_applicator_slot);
    h->pool_layout = kg_joints_layout(kg_tilemaps_layout(kg_shape_pool_layout(kg_body_pool_layout(0x4B47u))));
}

/* A 64-bit checksum, eight lanes of 8 bytes at a time (a multiply's latency each, so the
 * lanes run side by side: 7.5 MB in about 0.2 ms): each lane step is a bijection of the
 * lane and of the word, so any one changed byte changes the result. */
#define KG_CHECKSUM_LANES 8
static uint64_t kg_checksum(const unsigned char* data, size_t size)
{
    const uint64_t prime = 0x9E3779B97F4A7C15ull;
    uint64_t lane[KG_CHECKSUM_LANES];
    for (int k = 0; k < KG_CHECKSUM_LANES; ++k) {
        lane[k] = (uint64_t)(k + 1);
    }
    size_t at = 0;
    for (; at + 8 * KG_CHECKSUM_LANES <= size; at += 8 * KG_CHECKSUM_LANES) {
        for (int k = 0; k < KG_CHECKSUM_LANES; ++k) {
            uint64_t word;
            memcpy(&word, data + at + 8 * (size_t)k, sizeof word);
            lane[k] = (lane[k] ^ word) * prime;
        }
    }
    uint64_t h = (uint64_t)size * prime;
    for (; at < size; ++at) {
        h = (h ^ data[at]) * 0x100000001B3ull;
    }
    for (int k = 0; k < KG_CHECKSUM_LANES; ++k) {
        h = (h ^ lane[k]) * prime;
        h ^= h >> 29;
    }
    return h;
}

/* ---- writing ---- */

static void kg_put_world(const kg_world* world, kg_snap_out* out)
{
    kg_snap_put_u64(out, world->step_index);
    kg_snap_put(out, &world->last_dt, sizeof world->last_dt);
    kg_snap_put_u32(out, world->static_edits);
    kg_snap_put_u32(out, world->pool_writes);
    kg_snap_put_i32(out, world->sensor_shapes_made);
    kg_snap_put(out, &world->def, sizeof world->def);
}

/* Every slot, the one past max_applicators included (its generation is seeded too); the
 * functions and user data are not written. */
static void kg_put_applicators(const kg_world* world, kg_snap_out* out)
{
    for (int i = 0; i <= world->def.max_applicators; ++i) {
        const kg_applicator_slot* a = &world->applicators[i];
        kg_applicator_slot plain = *a;
        plain.fn = NULL;
        plain.user_data = NULL;
        plain.bodies = NULL;
        kg_snap_put(out, &plain, sizeof plain);
        kg_snap_put(out, a->bodies, a->bodies ? (size_t)a->body_count * sizeof *a->bodies : 0u);
    }
}

static void kg_put_state(const kg_world* world, kg_snap_out* out)
{
    kg_put_world(world, out);
    kg_body_pool_snapshot(&world->bodies, out);
    kg_shape_pool_snapshot(&world->shapes, out);
    kg_put_applicators(world, out);
    kg_collision_snapshot(world, out);
    kg_tilemaps_snapshot(world, out);
    kg_joints_snapshot(world, out);
}

kg_result kg_world_snapshot_size(const kg_world* world, size_t* bytes)
{
    if (!world || !bytes) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_snapshot_size: NULL argument");
    }
    kg_snap_out counter = {NULL, sizeof(kg_snapshot_header)};
    kg_put_state(world, &counter);
    *bytes = counter.size;
    return KG_OK;
}

kg_result kg_world_snapshot(kg_world* world, void* buffer, size_t capacity, size_t* written)
{
    if (!world || !written || (!buffer && capacity > 0)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_snapshot: NULL argument");
    }
    if (kg_world_refuses(world, "kg_world_snapshot", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    if (world->backend->sync_for_snapshot) {
        world->backend->sync_for_snapshot(world);
    }
    KG_TRY(kg_world_snapshot_size(world, written));
    if (capacity < *written) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT,
                       "kg_world_snapshot: the buffer holds %zu bytes, the snapshot needs %zu", capacity, *written);
    }
    unsigned char* bytes = buffer;
    kg_snap_out out = {bytes + sizeof(kg_snapshot_header), sizeof(kg_snapshot_header)};
    kg_put_state(world, &out);
    kg_snapshot_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, kg_snapshot_magic, sizeof h.magic);
    h.version = KG_SNAPSHOT_VERSION;
    h.header_size = (kg_u32)sizeof h;
    h.total_size = out.size;
    kg_layout_of(&h);
    h.checksum = kg_checksum(bytes + sizeof h, out.size - sizeof h);
    memcpy(bytes, &h, sizeof h);
    return KG_OK;
}

void kg_snapshot_reseal(void* buffer, size_t size)
{
    kg_snapshot_header h;
    if (size < sizeof h) {
        return;
    }
    unsigned char* bytes = buffer;
    memcpy(&h, bytes, sizeof h);
    h.checksum = kg_checksum(bytes + sizeof h, size - sizeof h);
    memcpy(bytes, &h, sizeof h);
}

/* ---- reading ---- */

/* The header checked against this build and the buffer: KG_OK, or why not. */
static kg_result kg_check_header(const unsigned char* bytes, size_t size)
{
    kg_snapshot_header h, mine;
    if (size < sizeof h.magic || memcmp(bytes, kg_snapshot_magic, sizeof h.magic) != 0) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "not a KineticGyro snapshot (no \"KGYROSNP\" magic in its first "
                       "bytes; %zu bytes given)", size);
    }
    if (size < offsetof(kg_snapshot_header, header_size)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "snapshot truncated: %zu bytes, not even a header", size);
    }
    memcpy(&h.version, bytes + offsetof(kg_snapshot_header, version), sizeof h.version);
    if (h.version != KG_SNAPSHOT_VERSION) {
        return kg_fail(KG_ERROR_UNSUPPORTED, "snapshot format version %u: this build reads version %u only", h.version,
                       KG_SNAPSHOT_VERSION);
    }
    if (size < sizeof h) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "snapshot truncated: %zu bytes, less than its %zu-byte header", size,
                       sizeof h);
    }
    memcpy(&h, bytes, sizeof h);
    if (h.header_size != sizeof h || h.total_size != (uint64_t)size) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "snapshot truncated or padded: %zu bytes given, its header says %llu",
                       size, (unsigned long long)h.total_size);
    }
    kg_layout_of(&mine);
    for (int k = 0; k < KG_LAYOUT_COUNT; ++k) {
        if (h.layout[k] != mine.layout[k]) {
            return kg_fail(KG_ERROR_UNSUPPORTED, "snapshot from another build layout: its %s is %u, this build's %u",
                           kg_layout_names[k], h.layout[k], mine.layout[k]);
        }
    }
    if (h.pool_layout != mine.pool_layout) {
        return kg_fail(KG_ERROR_UNSUPPORTED, "snapshot from another build layout: the pooled structs differ in size");
    }
    if (kg_checksum(bytes + sizeof h, size - sizeof h) != h.checksum) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "snapshot corrupted: its checksum does not match its contents");
    }
    return KG_OK;
}

/* Everything read from a snapshot before the world takes it. */
typedef struct kg_staged {
    uint64_t step_index;
    float last_dt;
    kg_u32 static_edits, pool_writes;
    int sensor_shapes_made;
    kg_world_def def;
    kg_body_pool bodies;
    kg_shape_pool shapes;
    kg_applicator_slot* applicators;
    struct kg_collision* collision;
    struct kg_tilemaps* tilemaps;
    struct kg_joints* joints;
    int have_bodies, have_shapes;
} kg_staged;

static void kg_staged_free(kg_staged* s, int applicator_count)
{
    if (s->have_bodies) {
        kg_body_pool_free(&s->bodies);
    }
    if (s->have_shapes) {
        kg_shape_pool_free(&s->shapes);
    }
    for (int i = 0; s->applicators && i < applicator_count; ++i) {
        kg_free(s->applicators[i].bodies);
    }
    kg_free(s->applicators);
    kg_collision_discard(s->collision);
    kg_tilemaps_discard(s->tilemaps);
    kg_joints_discard(s->joints);
}

static int kg_take_world(const kg_world* world, kg_snap_in* in, kg_staged* s)
{
    s->step_index = kg_snap_take_u64(in, "world counters");
    kg_snap_take_array(in, &s->last_dt, sizeof s->last_dt, 1, "world counters");
    s->static_edits = kg_snap_take_u32(in, "world counters");
    s->pool_writes = kg_snap_take_u32(in, "world counters");
    s->sensor_shapes_made = kg_snap_take_i32(in, "world counters");
    kg_snap_take_array(in, &s->def, sizeof s->def, 1, "world definition");
    if (in->failed) {
        return 0;
    }
    if (s->def.max_bodies != world->def.max_bodies || s->def.max_applicators != world->def.max_applicators) {
        kg_fail(KG_ERROR_INVALID_ARGUMENT, "snapshot of a world of max_bodies %d, max_applicators %d cannot be "
                "restored into one of max_bodies %d, max_applicators %d", s->def.max_bodies, s->def.max_applicators,
                world->def.max_bodies, world->def.max_applicators);
        return 0;
    }
    s->def.backend = world->def.backend;
    s->def.device_index = world->def.device_index;
    s->def.threads = world->def.threads;
    s->def.max_contacts = world->def.max_contacts; /* the contact list's own capacity follows */
    return kg_world_def_check(&s->def) == KG_OK || kg_snap_reject(in, "world definition");
}

/* Whether live body i's shape list is what the step walks: shape_count live shapes of
 * its own, in slot order (the shape pool's check makes each next link go up), with
 * geometry of their own when they are several. */
static int kg_body_list_sane(const kg_body_pool* p, const kg_shape_pool* sp, int i)
{
    kg_u32 n = 0;
    for (kg_u32 s = p->first_shape[i]; s != KG_NULL_INDEX; s = sp->next[s]) {
        if (s >= (kg_u32)sp->high_water || !kg_shape_alive(sp, (int)s) || sp->body[s] != (kg_u32)i) {
            return 0;
        }
        if (p->shape_count[i] > 1u && (!sp->geometry || sp->geometry[s].count < 0 ||
                                       sp->geometry[s].count > KG_MAX_VERTS)) {
            return 0;
        }
        n += 1u;
    }
    return n == p->shape_count[i] && (n > 0u || p->shape[i].count >= 0);
}

/* Whether the bodies' shape lists and the shapes' owners agree, both ways. */
static int kg_body_shapes_sane(const kg_body_pool* p, const kg_shape_pool* sp)
{
    int compound = 0;
    for (int i = 0; i < p->high_water; ++i) {
        if (kg_pool_alive(p, i) && !kg_body_list_sane(p, sp, i)) {
            return 0;
        }
        compound += kg_pool_alive(p, i) && p->shape_count[i] > 1u;
    }
    for (int s = 0; s < sp->high_water; ++s) {
        kg_u32 b = sp->body[s];
        if (kg_shape_alive(sp, s) && (b >= (kg_u32)p->high_water || !kg_pool_alive(p, (int)b))) {
            return 0;
        }
    }
    return compound == sp->compound_bodies;
}

/* The applicators read: a slot holds a user applicator exactly where the world's does
 * (those keep the world's function and user data). */
static int kg_take_applicators(const kg_world* world, kg_snap_in* in, kg_staged* s)
{
    int n = world->def.max_applicators + 1;
    s->applicators = kg_alloc_zeroed((size_t)n * sizeof *s->applicators);
    if (!s->applicators) {
        return kg_snap_reject(in, "applicators (out of memory)");
    }
    for (int i = 0; i < n && !in->failed; ++i) {
        kg_applicator_slot* a = &s->applicators[i];
        kg_snap_take_array(in, a, sizeof *a, 1, "applicators");
        a->bodies = NULL;
        int listed = a->body_count > 0;
        int kind = (int)a->kind;
        if (!in->failed && (kind < (int)KG_APPLICATOR_FREE || kind > (int)KG_APPLICATOR_WIND || a->body_count < 0 ||
                            a->body_count > world->def.max_bodies ||
                            !kg_snap_has(in, sizeof *a->bodies, (uint64_t)a->body_count))) {
            return kg_snap_reject(in, "an applicator's kind or body count");
        }
        if (!in->failed && (a->kind == KG_APPLICATOR_USER) != (world->applicators[i].kind == KG_APPLICATOR_USER)) {
            kg_fail(KG_ERROR_INVALID_ARGUMENT, "snapshot applicator slot %d %s a user force applicator and the world's "
                    "does not: register the callbacks in the same order before restoring", i,
                    a->kind == KG_APPLICATOR_USER ? "holds" : "does not hold");
            return 0;
        }
        a->fn = a->kind == KG_APPLICATOR_USER ? world->applicators[i].fn : NULL;
        a->user_data = a->kind == KG_APPLICATOR_USER ? world->applicators[i].user_data : NULL;
        a->bodies = listed ? kg_alloc_zeroed((size_t)a->body_count * sizeof *a->bodies) : NULL;
        if (listed && !a->bodies) {
            return kg_snap_reject(in, "an applicator's bodies (out of memory)");
        }
        kg_snap_take_array(in, a->bodies, sizeof *a->bodies, (size_t)(listed ? a->body_count : 0), "applicators");
    }
    return !in->failed;
}

/* Reads the whole snapshot into s, checked; 0 with the error set when it cannot be. */
static int kg_take_state(const kg_world* world, kg_snap_in* in, kg_staged* s)
{
    if (!kg_take_world(world, in, s)) {
        return 0;
    }
    if (kg_body_pool_from_snapshot(&s->bodies, world->def.max_bodies, in) != KG_OK) {
        return 0;
    }
    s->have_bodies = 1;
    if (kg_shape_pool_from_snapshot(&s->shapes, world->def.max_bodies, in) != KG_OK) {
        return 0;
    }
    s->have_shapes = 1;
    if (!kg_body_shapes_sane(&s->bodies, &s->shapes)) {
        return kg_snap_reject(in, "a body's shapes");
    }
    if (!kg_take_applicators(world, in, s)) {
        return 0;
    }
    if (kg_collision_from_snapshot(world, in, s->shapes.capacity, &s->collision) != KG_OK) {
        return 0;
    }
    if (kg_tilemaps_from_snapshot(world, s->bodies.high_water, in, &s->tilemaps) != KG_OK) {
        return 0;
    }
    if (kg_joints_from_snapshot(&s->bodies, in, &s->joints) != KG_OK) {
        return 0;
    }
    return in->left == 0 || kg_snap_reject(in, "the end (bytes left over)");
}

/* The world takes the staged state; what it had is freed. */
static void kg_adopt(kg_world* world, kg_staged* s)
{
    world->step_index = s->step_index;
    world->last_dt = s->last_dt;
    world->static_edits = s->static_edits;
    world->pool_writes = s->pool_writes;
    world->sensor_shapes_made = s->sensor_shapes_made;
    world->def = s->def;
    kg_body_pool_free(&world->bodies);
    world->bodies = s->bodies;
    kg_shape_pool_free(&world->shapes);
    world->shapes = s->shapes;
    for (int i = 0; i < world->def.max_applicators; ++i) {
        kg_free(world->applicators[i].bodies);
    }
    kg_free(world->applicators);
    world->applicators = s->applicators;
    kg_collision_adopt(world, s->collision);
    kg_tilemaps_adopt(world, s->tilemaps);
    kg_joints_adopt(world, s->joints);
    memset(s, 0, sizeof *s);
}

/* What the world keeps only for speed or to report events is made again from the restored state. */
static void kg_forget_derived(kg_world* world)
{
    kg_solver_forget(world);
    kg_query_index_destroy(world->query_index);
    world->query_index = NULL;
    kg_events_destroy(world);
    kg_sensors_destroy(world);
    if (world->backend->restored) {
        world->backend->restored(world);
    }
}

kg_result kg_world_restore(kg_world* world, const void* buffer, size_t size)
{
    if (!world || (!buffer && size > 0)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_world_restore: NULL argument");
    }
    if (kg_world_refuses(world, "kg_world_restore", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    const unsigned char* bytes = buffer;
    KG_TRY(kg_check_header(bytes, size));
    kg_snap_in in = {bytes + sizeof(kg_snapshot_header), size - sizeof(kg_snapshot_header), NULL};
    kg_staged s;
    memset(&s, 0, sizeof s);
    kg_clear_error();
    int ok = kg_take_state(world, &in, &s);
    if (!ok) {
        kg_staged_free(&s, world->def.max_applicators + 1);
        if (in.failed) {
            return kg_fail(KG_ERROR_INVALID_ARGUMENT, "snapshot inconsistent: its %s cannot be read (checksum right: "
                           "written by another build, or forged)", in.failed);
        }
        return kg_last_result() != KG_OK ? kg_last_result()
                                         : kg_fail(KG_ERROR_INVALID_ARGUMENT, "snapshot cannot be restored");
    }
    kg_adopt(world, &s);
    kg_forget_derived(world);
    return KG_OK;
}
