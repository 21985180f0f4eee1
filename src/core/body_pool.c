#include "core/body_pool.h"
#include "core/alloc.h"
#include "core/error.h"
#include "core/generation.h"
#include "collide/shape.h"
#include "core/snapshot_io.h"

#include <string.h>

#define KG_POOL_ARRAYS(X)                                                                          \
    X(center) X(rot) X(velocity) X(omega) X(force) X(torque) X(drag) X(sleep_time) X(island) X(xf) X(aabb) X(shape) X(first_shape) X(shape_count) X(local_center) \
    X(mass) X(inertia) X(inv_mass) X(inv_inertia) X(friction) X(restitution) X(linear_damping)      \
    X(angular_damping) X(category) X(mask) X(flags) X(generation) X(user_data)

kg_result kg_body_pool_init(kg_body_pool* pool, int capacity)
{
    memset(pool, 0, sizeof *pool);
    pool->capacity = capacity;
#define KG_ALLOC_ARRAY(name)                                                              \
    pool->name = kg_alloc_zeroed((size_t)capacity * sizeof *pool->name);                  \
    if (!pool->name) {                                                                    \
        kg_body_pool_free(pool);                                                          \
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate a pool of %d bodies", capacity); \
    }
    KG_POOL_ARRAYS(KG_ALLOC_ARRAY)
#undef KG_ALLOC_ARRAY
    return KG_OK;
}

void kg_body_pool_free(kg_body_pool* pool)
{
#define KG_FREE_ARRAY(name) kg_free(pool->name); pool->name = NULL;
    KG_POOL_ARRAYS(KG_FREE_ARRAY)
#undef KG_FREE_ARRAY
}

int kg_body_pool_acquire(kg_body_pool* pool)
{
    for (int i = pool->first_free; i < pool->high_water; ++i) {
        if (!kg_pool_alive(pool, i)) {
            pool->first_free = i + 1;
            pool->count += 1;
            return i;
        }
    }
    pool->first_free = pool->high_water + 1;
    if (pool->high_water == pool->capacity) {
        return -1;
    }
    pool->count += 1;
    return pool->high_water++;
}

void kg_body_pool_release(kg_body_pool* pool, int index)
{
    pool->flags[index] = 0;
    pool->generation[index] = kg_generation_next(pool->generation[index]);
    pool->count -= 1;
    if (index < pool->first_free) {
        pool->first_free = index;
    }
    while (pool->high_water > 0 && !kg_pool_alive(pool, pool->high_water - 1)) {
        pool->high_water -= 1;
    }
}

int kg_body_pool_resolve(const kg_body_pool* pool, kg_body handle)
{
    int i = (int)handle.index;
    if (handle.generation == 0 || handle.index >= (uint32_t)pool->capacity || !kg_pool_alive(pool, i) ||
        pool->generation[i] != handle.generation) {
        kg_fail(KG_ERROR_INVALID_HANDLE, "body handle {%u, %u} is stale, foreign or invalid (no live body of this world has it)",
                handle.index, handle.generation);
        return -1;
    }
    return i;
}

void kg_body_update_transform(kg_body_pool* pool, int i)
{
    kg_xf xf;
    xf.q = pool->rot[i];
    xf.p = kg_sub(pool->center[i], kg_rotate(xf.q, pool->local_center[i]));
    pool->xf[i] = xf;
    pool->aabb[i] = kg_shape_aabb(&pool->shape[i], xf);
}

/* ---- snapshots (core/snapshot.c) ---- */

uint64_t kg_body_pool_layout(uint64_t h)
{
    const kg_body_pool* none = NULL;
#define KG_FOLD_SIZE(name) h = kg_snap_fold(h, sizeof *none->name);
    KG_POOL_ARRAYS(KG_FOLD_SIZE)
#undef KG_FOLD_SIZE
    return h;
}

void kg_body_pool_snapshot(const kg_body_pool* pool, kg_snap_out* out)
{
    kg_snap_put_i32(out, pool->capacity);
    kg_snap_put_i32(out, pool->high_water);
    kg_snap_put_i32(out, pool->count);
    kg_snap_put_i32(out, pool->first_free);
    size_t n = (size_t)pool->high_water;
#define KG_PUT_ARRAY(name) kg_snap_put(out, pool->name, n * sizeof *pool->name);
    KG_POOL_ARRAYS(KG_PUT_ARRAY)
#undef KG_PUT_ARRAY
    /* a slot past high_water keeps the generation its last body left it */
    kg_snap_put(out, pool->generation + n, (size_t)(pool->capacity - pool->high_water) * sizeof *pool->generation);
}

/* Whether slot i's values can be stepped without reading out of bounds. */
static int kg_body_slot_sane(const kg_body_pool* p, int i)
{
    if (!kg_pool_alive(p, i)) {
        return 1;
    }
    kg_u32 type = kg_flags_type(p->flags[i]);
    int count = p->shape[i].count;
    int island = !kg_pool_asleep(p, i) || p->island[i] < (kg_u32)p->capacity; /* sleeping: names a slot's island */
    return type <= (kg_u32)KG_BODY_PARTICLE && count >= 0 && count <= KG_MAX_VERTS && island;
}

kg_result kg_body_pool_from_snapshot(kg_body_pool* pool, int capacity, kg_snap_in* in)
{
    int snap_capacity = kg_snap_take_i32(in, "body pool");
    int high_water = kg_snap_take_i32(in, "body pool");
    int count = kg_snap_take_i32(in, "body pool");
    int first_free = kg_snap_take_i32(in, "body pool");
    if (in->failed) {
        return KG_ERROR_INVALID_ARGUMENT;
    }
    if (snap_capacity != capacity) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "snapshot of a world of max_bodies %d cannot be restored into one "
                       "of max_bodies %d", snap_capacity, capacity);
    }
    if (high_water < 0 || high_water > capacity || count < 0 || count > high_water || first_free < 0 ||
        first_free > high_water + 1) {
        kg_snap_reject(in, "body pool counts");
        return KG_ERROR_INVALID_ARGUMENT;
    }
    KG_TRY(kg_body_pool_init(pool, capacity));
    pool->high_water = high_water;
    pool->count = count;
    pool->first_free = first_free;
    size_t n = (size_t)high_water;
#define KG_TAKE_ARRAY(name) kg_snap_take_array(in, pool->name, sizeof *pool->name, n, "body pool arrays");
    KG_POOL_ARRAYS(KG_TAKE_ARRAY)
#undef KG_TAKE_ARRAY
    kg_snap_take_array(in, pool->generation + n, sizeof *pool->generation, (size_t)(capacity - high_water),
                       "body pool generations");
    int alive = 0;
    for (int i = 0; !in->failed && i < high_water; ++i) {
        alive += kg_pool_alive(pool, i);
        if (!kg_body_slot_sane(pool, i)) {
            kg_snap_reject(in, "a body's type or shape");
        }
    }
    if (!in->failed && alive != count) {
        kg_snap_reject(in, "body count");
    }
    if (in->failed) {
        kg_body_pool_free(pool);
        return KG_ERROR_INVALID_ARGUMENT;
    }
    return KG_OK;
}
