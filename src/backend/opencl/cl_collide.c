/* The collision stage on the device, and the colouring that opens the solve stage
 * (kernels in kernels/kg_scan.cl, kg_broadphase.cl, kg_collide.cl and kg_color.cl): the
 * contacts collide/collide.c gives, in the same order, coloured as solve/coloring.h
 * colours. The kernels in order, and what is read
 * back, are in docs/design.md, "The OpenCL pipeline". */
#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_backend.h"
#include "backend/opencl/cl_sort.h"
#include "collide/collide.h"
#include "collide/tilemap.h"
#include "core/alloc.h"
#include "core/error.h"
#include "solve/solver.h"

/* ---- broadphase --------------------------------------------------------------------- */

/* collide/broadphase.c's search on the device: the proxies and their extents, the grid,
 * the boxes sorted by cell (small) and by lower x (large), then each small and each large
 * entry's pairs counted, summed (the total to counts[KG_CC_PAIRS]) and written, within
 * capacity. */
static kg_result kg_find_pairs(kg_world* world, kg_cl_backend* b, int capacity)
{
    kg_cl_collide_buffers* c = &b->collide;
    const char* label = "kg_broadphase";
    int slots = world->bodies.high_water;
    KG_LAUNCH(b, BP_CLEAR, KG_BP_EXTENT_BINS, label, KG_MEM(c->histogram), KG_MEM(c->counts), KG_MEM(c->bp_words));
    KG_LAUNCH(b, BP_PROXIES, slots, label, KG_INT(slots), KG_FLOAT(world->def.speculative_distance), KG_MEM(KG_A(FLAGS)),
              KG_MEM(KG_A(AABB)), KG_MEM(KG_A(CATEGORY)), KG_MEM(KG_A(MASK)), KG_MEM(c->proxies),
              KG_MEM(c->histogram), KG_MEM(c->run), KG_MEM(c->run_fill),
              KG_MEM(b->wake_marks));
    KG_LAUNCH(b, BP_CELLS, 1, label, KG_MEM(c->histogram), KG_MEM(c->grid));
    KG_LAUNCH(b, BP_BOUNDS, slots, label, KG_INT(slots), KG_MEM(c->proxies), KG_MEM(c->grid), KG_MEM(c->bp_words));
    KG_LAUNCH(b, BP_BUILD_GRID, 1, label, KG_MEM(c->grid), KG_MEM(c->bp_words));
    KG_LAUNCH(b, BP_KEYS, slots, label, KG_INT(slots), KG_MEM(c->grid), KG_MEM(c->proxies), KG_MEM(c->keys),
              KG_MEM(c->items), KG_MEM(c->large_keys), KG_MEM(c->large_items));
    KG_TRY(kg_cl_sort(b, c->keys, c->items, c->key_scratch, c->item_scratch, slots, 32, label));
    KG_TRY(kg_cl_sort(b, c->large_keys, c->large_items, c->key_scratch, c->item_scratch, slots, 32, label));
    KG_LAUNCH(b, BP_GATHER, slots, label, KG_INT(slots), KG_MEM(c->keys), KG_MEM(c->items), KG_MEM(c->large_keys),
              KG_MEM(c->proxies), KG_MEM(c->sorted), KG_MEM(c->bp_words));
    KG_LAUNCH(b, BP_COUNT_PAIRS, 2 * slots, label, KG_INT(slots), KG_MEM(c->grid), KG_MEM(c->keys), KG_MEM(c->sorted),
              KG_MEM(c->large_items), KG_MEM(c->proxies), KG_MEM(c->bp_words), KG_MEM(c->found));
    KG_TRY(kg_cl_scan(b, c->found, c->found, 2 * slots, KG_CC_PAIRS, label));
    KG_LAUNCH(b, BP_WRITE_PAIRS, 2 * slots, label, KG_INT(slots), KG_INT(capacity), KG_MEM(c->grid), KG_MEM(c->keys),
              KG_MEM(c->sorted), KG_MEM(c->large_items), KG_MEM(c->proxies), KG_MEM(c->bp_words), KG_MEM(c->found),
              KG_MEM(c->raw_pairs));
    return KG_OK;
}

/* The pairs found, in (a, b) order: each lower slot's run placed by the prefix sum of the
 * run lengths, then sorted by the upper slot. */
static kg_result kg_order_pairs(kg_world* world, kg_cl_backend* b, int pairs)
{
    kg_cl_collide_buffers* c = &b->collide;
    const char* label = "kg_broadphase";
    int slots = world->bodies.high_water;
    KG_LAUNCH(b, BP_COUNT_RUNS, pairs, label, KG_INT(pairs), KG_MEM(c->raw_pairs), KG_MEM(c->run));
    KG_TRY(kg_cl_scan(b, c->run, c->run, slots, -1, label));
    KG_LAUNCH(b, BP_SCATTER, pairs, label, KG_INT(pairs), KG_MEM(c->raw_pairs), KG_MEM(c->run), KG_MEM(c->run_fill),
              KG_MEM(c->pairs));
    KG_LAUNCH(b, BP_SORT_RUNS, slots, label, KG_INT(slots), KG_MEM(c->run), KG_MEM(c->pairs));
    return KG_OK;
}

/* ---- narrowphase and persistence ------------------------------------------------------ */

static kg_result kg_build_contacts(kg_world* world, kg_cl_backend* b, int pairs)
{
    kg_cl_collide_buffers* c = &b->collide;
    const char* label = "kg_narrowphase";
    cl_mem previous = b->contacts[b->current], next = b->contacts[b->current ^ 1];
    KG_LAUNCH(b, NARROWPHASE, pairs, label, KG_INT(pairs), KG_FLOAT(world->def.speculative_distance),
              KG_FLOAT(world->last_dt), KG_MEM(c->pairs), KG_MEM(KG_A(SHAPE)), KG_MEM(KG_A(XF)), KG_MEM(KG_A(VELOCITY)),
              KG_MEM(previous), KG_INT(b->body_contact_count), KG_MEM(KG_A(GENERATION)), KG_MEM(KG_A(FIRST_SHAPE)),
              KG_MEM(c->manifolds), KG_MEM(c->bases), KG_MEM(c->touching));
    KG_TRY(kg_cl_drop_joined(world, b, c->pairs, pairs, 0, c->touching)); /* joined bodies: no contact */
    KG_TRY(kg_cl_scan(b, c->touching, c->touching, pairs, KG_CC_CONTACTS, label));
    KG_LAUNCH(b, BUILD_CONTACTS, pairs, label, KG_INT(pairs), KG_MEM(c->pairs), KG_MEM(c->manifolds),
              KG_MEM(c->bases), KG_MEM(c->touching), KG_MEM(previous), KG_INT(b->body_contact_count),
              KG_MEM(KG_A(GENERATION)), KG_MEM(KG_A(FIRST_SHAPE)), KG_MEM(KG_A(FRICTION)), KG_MEM(KG_A(RESTITUTION)),
              KG_MEM(next));
    return KG_OK;
}

/* While a body has several shapes: the pairs of bodies expanded into pairs of shapes
 * (collide/pair_contact.h's kg_expand_pair, as on the host), their count read back into
 * *items; written only when they fit in capacity. */
static kg_result kg_expand_pairs(kg_world* world, kg_cl_backend* b, int pairs, int capacity, int* items)
{
    kg_cl_collide_buffers* c = &b->collide;
    const char* label = "kg_narrowphase";
    float speculative = world->def.speculative_distance, dt = world->last_dt;
    KG_LAUNCH(b, COUNT_SHAPE_PAIRS, pairs, label, KG_INT(pairs), KG_MEM(c->pairs), KG_SHAPE_ARGS(b),
              KG_MEM(KG_A(XF)), KG_MEM(KG_A(VELOCITY)), KG_MEM(KG_A(AABB)), KG_FLOAT(speculative), KG_FLOAT(dt),
              KG_MEM(c->shape_run));
    KG_TRY(kg_cl_scan(b, c->shape_run, c->shape_run, pairs, KG_CC_SHAPE_PAIRS, label));
    cl_uint total = 0u;
    KG_TRY(kg_cl_read(b, c->counts, KG_CC_SHAPE_PAIRS * sizeof total, sizeof total, &total));
    *items = (int)total;
    if (*items > capacity) {
        return KG_OK;
    }
    KG_LAUNCH(b, WRITE_SHAPE_PAIRS, pairs, label, KG_INT(pairs), KG_MEM(c->pairs), KG_SHAPE_ARGS(b),
              KG_MEM(KG_A(XF)), KG_MEM(KG_A(VELOCITY)), KG_MEM(KG_A(AABB)), KG_FLOAT(speculative), KG_FLOAT(dt),
              KG_MEM(c->shape_run), KG_MEM(c->shape_items), KG_MEM(c->item_pairs));
    return KG_OK;
}

/* kg_build_contacts over the pairs of shapes. */
static kg_result kg_build_shape_contacts(kg_world* world, kg_cl_backend* b, int items)
{
    kg_cl_collide_buffers* c = &b->collide;
    const char* label = "kg_narrowphase";
    cl_mem previous = b->contacts[b->current], next = b->contacts[b->current ^ 1];
    KG_LAUNCH(b, NARROWPHASE_SHAPES, items, label, KG_INT(items), KG_FLOAT(world->def.speculative_distance),
              KG_FLOAT(world->last_dt), KG_MEM(c->shape_items), KG_SHAPE_ARGS(b), KG_MEM(KG_A(XF)),
              KG_MEM(KG_A(VELOCITY)), KG_MEM(previous), KG_INT(b->body_contact_count), KG_MEM(KG_A(GENERATION)),
              KG_MEM(c->manifolds), KG_MEM(c->bases), KG_MEM(c->touching));
    KG_TRY(kg_cl_drop_joined(world, b, c->shape_items, items, 1, c->touching)); /* joined bodies: no contact */
    KG_TRY(kg_cl_scan(b, c->touching, c->touching, items, KG_CC_CONTACTS, label));
    KG_LAUNCH(b, BUILD_SHAPE_CONTACTS, items, label, KG_INT(items), KG_MEM(c->shape_items), KG_MEM(c->manifolds),
              KG_MEM(c->bases), KG_MEM(c->touching), KG_MEM(previous), KG_INT(b->body_contact_count),
              KG_MEM(KG_A(GENERATION)), KG_MEM(b->shape_friction), KG_MEM(b->shape_restitution), KG_MEM(next));
    return KG_OK;
}

/* ---- tile maps -------------------------------------------------------------------------- */

/* Map m's cells, from the host's arrays to the device's, at the same place. */
static kg_result kg_write_map_cells(kg_cl_backend* b, const kg_tilemap_arrays* a, const kg_tile_map_info* m)
{
    size_t first = m->cell_offset, count = (size_t)m->width * (size_t)m->height * (size_t)m->layer_count;
    /* blocking: kg_tilemap_set_tile may change the host's cells as soon as the step ends */
    return kg_cl_write(b, b->collide.tile_cells, first * sizeof(kg_u32), count * sizeof(kg_u32), a->cells + first, 1);
}

/* The host's tile arrays (collide/tilemap.h) into new buffers of their size. */
static kg_result kg_build_tile_buffers(kg_world* world, kg_cl_backend* b, int maps)
{
    kg_cl_collide_buffers* c = &b->collide;
    kg_cl_release(b, &c->tile_maps);
    kg_cl_release(b, &c->tile_cells);
    kg_cl_release(b, &c->tile_protos);
    c->tiles_built = 0;
    kg_tilemap_arrays a;
    kg_tilemaps_arrays(world, &a);
    for (int i = 0; i < maps; ++i) {
        kg_tilemaps_take_dirty(world, i);
    }
    size_t info_size = (size_t)maps * sizeof *a.maps, proto_size = a.proto_count * sizeof *a.protos;
    KG_TRY(kg_cl_buffer(b, info_size, &c->tile_maps));
    KG_TRY(kg_cl_buffer(b, a.cell_count * sizeof *a.cells, &c->tile_cells));
    KG_TRY(kg_cl_buffer(b, proto_size, &c->tile_protos));
    KG_TRY(kg_cl_write(b, c->tile_maps, 0, info_size, a.maps, 1));
    KG_TRY(kg_cl_write(b, c->tile_protos, 0, proto_size, a.protos, 1));
    /* blocking: kg_tilemap_set_tile may change the host's cells as soon as the step ends */
    KG_TRY(kg_cl_write(b, c->tile_cells, 0, a.cell_count * sizeof *a.cells, a.cells, 1));
    c->tiles_built = 1;
    c->tile_map_count = maps;
    c->tile_layout = kg_tilemaps_layout_version(world);
    return KG_OK;
}

/* The maps on the device: built again when a map was created or destroyed, else the
 * cells of the maps whose tiles changed written again. */
static kg_result kg_sync_tiles(kg_world* world, kg_cl_backend* b, int maps)
{
    kg_cl_collide_buffers* c = &b->collide;
    if (!c->tiles_built || c->tile_layout != kg_tilemaps_layout_version(world) || c->tile_map_count != maps) {
        return kg_build_tile_buffers(world, b, maps);
    }
    kg_tilemap_arrays a;
    kg_tilemaps_arrays(world, &a);
    for (int i = 0; i < maps; ++i) {
        if (kg_tilemaps_take_dirty(world, i)) {
            kg_result r = kg_write_map_cells(b, &a, &a.maps[i]);
            if (r != KG_OK) {
                c->tiles_built = 0; /* written again in whole next time */
                return r;
            }
        }
    }
    return KG_OK;
}

kg_result kg_cl_sync_tiles(kg_world* world, kg_cl_backend* b)
{
    int maps = kg_tilemaps_live_count(world);
    return maps > 0 ? kg_sync_tiles(world, b, maps) : KG_OK;
}

kg_result kg_cl_sync_statics(kg_world* world, kg_cl_backend* b, kg_static_list* list)
{
    kg_cl_collide_buffers* c = &b->collide;
    *list = kg_continuous_statics(world);
    if (c->statics_sent && c->statics_edits == list->edits) {
        return KG_OK;
    }
    c->statics_sent = 0;
    if (list->count > 0) {
        size_t size = (size_t)list->count * sizeof *list->entries;
        KG_TRY(kg_cl_write(b, c->statics, 0, size, list->entries, 1));
    }
    c->statics_edits = list->edits;
    c->statics_sent = 1;
    return KG_OK;
}

/* The host's one-way state to both device copies (slots the steps never write keep it). */
static kg_result kg_tile_state_to_device(kg_world* world, kg_cl_backend* b)
{
    if (b->tile_state_on_device) {
        return KG_OK;
    }
    kg_cl_collide_buffers* c = &b->collide;
    size_t n = (size_t)world->bodies.capacity;
    for (int k = 0; k < 2; ++k) {
        KG_TRY(kg_cl_write(b, c->last_origin[k], 0, n * sizeof(kg_vec2), kg_tilemaps_last_origin(world), 1));
        KG_TRY(kg_cl_write(b, c->last_generation[k], 0, n * sizeof(kg_u32), kg_tilemaps_last_generation(world), 1));
    }
    b->tile_state_on_device = 1;
    return KG_OK;
}

kg_result kg_cl_tile_state_to_host(kg_world* world, kg_cl_backend* b)
{
    if (!b->tile_state_on_device || !world->tilemaps) {
        return KG_OK;
    }
    kg_cl_collide_buffers* c = &b->collide;
    size_t n = (size_t)world->bodies.high_water;
    KG_TRY(kg_cl_read(b, c->last_origin[c->tile_state], 0, n * sizeof(kg_vec2), kg_tilemaps_last_origin(world)));
    KG_TRY(kg_cl_read(b, c->last_generation[c->tile_state], 0, n * sizeof(kg_u32),
                      kg_tilemaps_last_generation(world)));
    b->tile_state_on_device = 0;
    return KG_OK;
}

void kg_cl_commit_tile_state(kg_cl_backend* b)
{
    if (b->tiles_ran) {
        b->collide.tile_state ^= 1;
        b->tiles_ran = 0;
    }
}

/* kg_tilemap_collide of collide/tilemap.c: after the body contacts, counted per body,
 * summed, then written; counts[KG_CC_CONTACTS] becomes the total within capacity. */
static kg_result kg_collide_tiles(kg_world* world, kg_cl_backend* b, int capacity)
{
    kg_cl_collide_buffers* c = &b->collide;
    const char* label = "kg_narrowphase";
    int maps = kg_tilemaps_live_count(world);
    b->tiles_ran = 0;
    if (maps == 0) {
        return KG_OK; /* as on the host: no contacts, the one-way state left as it is */
    }
    KG_TRY(kg_sync_tiles(world, b, maps));
    KG_TRY(kg_tile_state_to_device(world, b));
    int slots = world->bodies.high_water, previous_count = 0;
    kg_collision_contacts(world, &previous_count);
    cl_mem previous = b->contacts[b->current], next = b->contacts[b->current ^ 1];
    int in = c->tile_state, out = c->tile_state ^ 1;
    kg_tile_pass_params prm = {maps, world->def.speculative_distance, world->def.linear_slop, b->body_contact_count,
                               previous_count, (kg_u32)capacity, 0};
    for (prm.write = 0; prm.write < 2; ++prm.write) {
        if (prm.write) {
            KG_TRY(kg_cl_scan(b, c->tile_run, c->tile_run, slots, KG_CC_TILES, label));
            KG_LAUNCH(b, TILE_TOTAL, 1, label, KG_INT(capacity), KG_MEM(c->counts));
        }
        KG_LAUNCH(b, TILE_COLLIDE_BODIES, slots, label, KG_INT(slots), KG_VALUE(prm), KG_MEM(c->tile_maps),
                  KG_MEM(c->tile_cells), KG_MEM(c->tile_protos), KG_MEM(KG_A(FLAGS)), KG_MEM(KG_A(AABB)),
                  KG_MEM(KG_A(XF)), KG_MEM(KG_A(SHAPE)), KG_MEM(KG_A(CENTER)), KG_MEM(KG_A(CATEGORY)),
                  KG_MEM(KG_A(MASK)), KG_MEM(KG_A(GENERATION)), KG_MEM(KG_A(FRICTION)), KG_MEM(KG_A(RESTITUTION)),
                  KG_MEM(previous), KG_MEM(c->last_origin[in]), KG_MEM(c->last_generation[in]),
                  KG_MEM(c->last_origin[out]), KG_MEM(c->last_generation[out]), KG_MEM(KG_A(FIRST_SHAPE)),
                  KG_MEM(KG_A(SHAPE_COUNT)), KG_MEM(b->shape_next), KG_MEM(b->shape_flags),
                  KG_MEM(b->shape_geometry), KG_MEM(b->shape_category), KG_MEM(b->shape_mask),
                  KG_MEM(b->shape_friction), KG_MEM(b->shape_restitution), KG_MEM(c->tile_run),
                  KG_MEM(c->counts), KG_MEM(next));
    }
    b->tiles_ran = 1;
    return KG_OK;
}

/* ---- colouring ------------------------------------------------------------------------ */

/* The rounds of solve/coloring.h until no contact waits. Every round colours at least
 * the contact of least priority still waiting, so count rounds always end them. */
static kg_result kg_color_in_rounds(kg_cl_backend* b, cl_mem contacts, int count)
{
    kg_cl_collide_buffers* c = &b->collide;
    int bits = (int)kg_bits_for((kg_u32)count);
    for (int round = 0; round <= count;) {
        for (int end = round + KG_CL_ROUNDS_PER_LOOK; round < end; ++round) {
            cl_mem bids = c->color_bids[round & 1], next_bids = c->color_bids[(round + 1) & 1];
            KG_LAUNCH(b, BID_COLORS, count, "kg_color", KG_INT(count), KG_INT(bits), KG_MEM(contacts),
                      KG_MEM(KG_A(FLAGS)), KG_MEM(c->colors), KG_MEM(bids));
            KG_LAUNCH(b, TAKE_COLORS, count, "kg_color", KG_INT(count), KG_INT(bits), KG_INT(round),
                      KG_MEM(contacts), KG_MEM(KG_A(FLAGS)), KG_MEM(c->colors), KG_MEM(bids), KG_MEM(next_bids),
                      KG_MEM(c->colors_used), KG_MEM(c->counts));
        }
        cl_uint waiting = 0u;
        KG_TRY(kg_cl_rounds_left(b, KG_CC_WAITING, round, &waiting));
        if (waiting == 0u) {
            return KG_OK;
        }
    }
    return kg_fail(KG_ERROR_BACKEND, "the device's colouring did not end in %d rounds", count);
}

/* Colours count contacts (kept colours first): serially when they are few
 * (b->color_serial_max), else in rounds and then sorted by colour (stable: contact order
 * within a colour). */
static kg_result kg_color(kg_cl_backend* b, cl_mem contacts, int count)
{
    kg_cl_collide_buffers* c = &b->collide;
    KG_LAUNCH(b, RESET_COLORS, count, "kg_color", KG_INT(count), KG_MEM(contacts), KG_MEM(KG_A(FLAGS)),
              KG_MEM(c->colors), KG_MEM(c->colors_used), KG_MEM(c->color_bids[0]), KG_MEM(c->color_items),
              KG_MEM(c->counts));
    if (count <= b->color_serial_max) {
        KG_LAUNCH(b, COLOR_CONTACTS, 1, "kg_color", KG_INT(count), KG_MEM(contacts), KG_MEM(KG_A(FLAGS)),
                  KG_MEM(c->colors_used), KG_MEM(c->colors), KG_MEM(b->order), KG_MEM(b->color_start));
        return KG_OK;
    }
    KG_LAUNCH(b, KEEP_COLORS, count, "kg_color", KG_INT(count), KG_MEM(contacts), KG_MEM(KG_A(FLAGS)),
              KG_MEM(c->colors), KG_MEM(c->colors_used));
    KG_TRY(kg_color_in_rounds(b, contacts, count));
    KG_TRY(kg_cl_sort_pass(b, c->colors, c->color_items, c->sorted_colors, b->order, count, 0,
                           (int)kg_bits_for(KG_COLOR_COUNT + 1), "kg_color"));
    KG_LAUNCH(b, COLOR_RANGES, KG_COLOR_COUNT + 2, "kg_color", KG_INT(count), KG_MEM(c->sorted_colors),
              KG_MEM(b->color_start));
    return KG_OK;
}

/* ---- the stage -------------------------------------------------------------------------- */

/* The contacts the device lists hold this step: the world's pool, within the buffers. */
static int kg_device_contact_capacity(kg_world* world, const kg_cl_backend* b)
{
    int capacity = kg_collision_capacity(world);
    return capacity < b->contact_capacity ? capacity : b->contact_capacity;
}

static kg_result kg_read_counters(kg_cl_backend* b, int words)
{
    return kg_cl_read(b, b->collide.counts, 0, (size_t)words * sizeof(cl_uint), b->counters);
}

/* The colour ranges the solver's launches need, read back. */
static kg_result kg_take_color_ranges(kg_cl_backend* b)
{
    kg_graph_coloring* g = &b->coloring;
    KG_TRY(kg_cl_read(b, b->color_start, 0, sizeof g->color_start, g->color_start));
    g->color_count = kg_colors_in_use(g->color_start);
    return KG_OK;
}

kg_result kg_cl_collide_on_device(kg_world* world, kg_cl_backend* b, int* fits)
{
    int capacity = kg_device_contact_capacity(world, b);
    KG_TRY(kg_cl_sync_shapes(b, world));
    KG_TRY(kg_find_pairs(world, b, capacity));
    KG_TRY(kg_read_counters(b, KG_CC_PAIRS + 1)); /* the pair count */
    *fits = b->counters[KG_CC_PAIRS] <= (cl_uint)capacity;
    if (!*fits) {
        return KG_OK;
    }
    b->step_pairs = (int)b->counters[KG_CC_PAIRS];
    b->step_pair_list = b->collide.pairs;
    KG_TRY(kg_order_pairs(world, b, b->step_pairs));
    if (world->shapes.compound_bodies == 0) {
        KG_TRY(kg_build_contacts(world, b, b->step_pairs));
        return kg_collide_tiles(world, b, capacity);
    }
    int items = 0;
    KG_TRY(kg_expand_pairs(world, b, b->step_pairs, capacity, &items));
    *fits = items <= capacity;
    if (!*fits) {
        return KG_OK;
    }
    b->step_pairs = items;
    b->step_pair_list = b->collide.item_pairs;
    KG_TRY(kg_build_shape_contacts(world, b, items));
    return kg_collide_tiles(world, b, capacity);
}

kg_result kg_cl_count_contacts(kg_world* world, kg_cl_backend* b, int* count, int* body_count)
{
    KG_TRY(kg_read_counters(b, KG_CC_WORDS));
    *count = (int)b->counters[KG_CC_CONTACTS];
    *body_count = *count;
    if (b->tiles_ran) {
        int capacity = kg_device_contact_capacity(world, b);
        int bodies = (int)b->counters[KG_CC_BODY_CONTACTS], tiles = (int)b->counters[KG_CC_TILES];
        *body_count = bodies;
        if (tiles > capacity - bodies) {
            kg_warn_once("tile-contacts-full", "more tile contacts (%d) than room left in max_contacts (%d): "
                         "the extra ones were dropped this step; raise kg_world_def.max_contacts", tiles,
                         capacity - bodies);
        }
    }
    return KG_OK;
}

kg_result kg_cl_color_on_device(kg_world* world, kg_cl_backend* b, int* count, int* body_count)
{
    KG_TRY(kg_cl_count_contacts(world, b, count, body_count));
    KG_TRY(kg_color(b, b->contacts[b->current ^ 1], *count));
    return kg_take_color_ranges(b);
}

kg_result kg_cl_read_previous_contacts(kg_world* world, kg_cl_backend* b)
{
    if (!b->previous_contacts_stale) {
        return KG_OK;
    }
    int count = 0;
    kg_contact* host = kg_collision_previous(world, &count);
    KG_TRY(kg_cl_read(b, b->contacts[b->current ^ 1], 0, (size_t)count * sizeof *host, host));
    b->previous_contacts_stale = 0;
    return KG_OK;
}

kg_result kg_cl_read_contacts(kg_world* world, kg_cl_backend* b)
{
    if (!b->contacts_stale) {
        return KG_OK;
    }
    int count = 0;
    kg_contact* host = kg_collision_contacts(world, &count);
    KG_TRY(kg_cl_read(b, b->contacts[b->current], 0, (size_t)count * sizeof *host, host));
    b->contacts_stale = 0;
    return KG_OK;
}
#endif
