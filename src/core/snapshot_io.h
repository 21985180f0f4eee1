/* The cursors a snapshot (include/kgyro/snapshot.h) is written and read with: each part
 * of the world (pools, contacts, tile maps) writes its own state with kg_snap_put and
 * reads it back with kg_snap_take, so no module knows another's layout. Arrays are copied
 * by their element size and count, whatever their structs hold.
 *
 * A writer without a buffer only counts (kg_world_snapshot_size). A reader never reads
 * past its end: a take that does not fit fails the reader (and returns NULL), and every
 * later take fails too, so a part may read on and check once. */
#ifndef KG_SNAPSHOT_IO_H
#define KG_SNAPSHOT_IO_H

#include "core/kg_shared.h"
#include "kgyro/types.h"

#include <stdint.h>
#include <string.h>

typedef struct kg_snap_out {
    unsigned char* at; /* NULL: counting only */
    size_t size;       /* bytes written (or counted) so far */
} kg_snap_out;

typedef struct kg_snap_in {
    const unsigned char* at;
    size_t left;
    const char* failed; /* what could not be read, or NULL */
} kg_snap_in;

static inline void kg_snap_put(kg_snap_out* out, const void* data, size_t size)
{
    if (out->at && size > 0) {
        memcpy(out->at, data, size);
        out->at += size;
    }
    out->size += size;
}

static inline void kg_snap_put_u32(kg_snap_out* out, kg_u32 v) { kg_snap_put(out, &v, sizeof v); }
static inline void kg_snap_put_i32(kg_snap_out* out, int v) { kg_snap_put(out, &v, sizeof v); }
static inline void kg_snap_put_u64(kg_snap_out* out, uint64_t v) { kg_snap_put(out, &v, sizeof v); }

/* The next size bytes, or NULL (the reader failed, naming what) when fewer are left. */
static inline const void* kg_snap_take(kg_snap_in* in, size_t size, const char* what)
{
    if (in->failed || size > in->left) {
        in->failed = in->failed ? in->failed : what;
        return NULL;
    }
    const void* p = in->at;
    in->at += size;
    in->left -= size;
    return p;
}

/* Copies count elements of size bytes into to (left as it was when they are not there). */
static inline int kg_snap_take_array(kg_snap_in* in, void* to, size_t size, size_t count, const char* what)
{
    if (count > 0 && size > SIZE_MAX / count) {
        in->failed = in->failed ? in->failed : what;
        return 0;
    }
    const void* p = kg_snap_take(in, size * count, what);
    if (p && size * count > 0) {
        memcpy(to, p, size * count);
    }
    return p != NULL;
}

static inline kg_u32 kg_snap_take_u32(kg_snap_in* in, const char* what)
{
    kg_u32 v = 0;
    kg_snap_take_array(in, &v, sizeof v, 1, what);
    return v;
}

static inline int kg_snap_take_i32(kg_snap_in* in, const char* what)
{
    int v = 0;
    kg_snap_take_array(in, &v, sizeof v, 1, what);
    return v;
}

static inline uint64_t kg_snap_take_u64(kg_snap_in* in, const char* what)
{
    uint64_t v = 0;
    kg_snap_take_array(in, &v, sizeof v, 1, what);
    return v;
}

/* Whether count elements of size bytes are left to read: checked before allocating for
 * them, so that a forged count cannot make a reader allocate more than the buffer holds. */
static inline int kg_snap_has(const kg_snap_in* in, size_t size, uint64_t count)
{
    return !in->failed && size > 0 && count <= (uint64_t)(in->left / size);
}

/* Marks the reader failed for a value out of range (what says which); returns 0. */
static inline int kg_snap_reject(kg_snap_in* in, const char* what)
{
    in->failed = in->failed ? in->failed : what;
    return 0;
}

/* A 64-bit fold of the element sizes of a layout, for the snapshot's fingerprint. */
static inline uint64_t kg_snap_fold(uint64_t h, size_t size)
{
    h ^= (uint64_t)size + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    return h * 0x100000001B3ull;
}

/* For the tests and the fuzz target: the checksum of a snapshot of size bytes written again
 * over its header (nothing when shorter than one), so that forged contents reach the
 * checks behind it. */
void kg_snapshot_reseal(void* buffer, size_t size);

#endif
