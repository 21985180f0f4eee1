/* What the collision stage's kernels (kg_scan.cl, kg_broadphase.cl, kg_collide.cl, kg_color.cl) and their host code (cl_collide.c)
 * agree on: the slots of the small counters buffer, the broadphase proxy, the grid's
 * levels and the sizes of the scan blocks. KG_COLOR_COUNT comes from solve/coloring.h. */
#ifndef KG_COLLIDE_SHARED_H
#define KG_COLLIDE_SHARED_H

#include "core/kg_layout.h"
#include "solve/coloring.h"

/* The counters buffer: what the host reads back of a step. */
#define KG_CC_PAIRS 0        /* pairs the broadphase found, counted past the capacity */
#define KG_CC_OVERFLOW 1     /* non-zero when they did not all fit */
#define KG_CC_CONTACTS 2     /* this step's contacts: touching pairs, then tile contacts */
#define KG_CC_LEVELS 3       /* bit m set: some proxy is keyed at grid level m */
#define KG_CC_TILES 4        /* tile contacts found, counted past the room left */
#define KG_CC_BODY_CONTACTS 5 /* the touching pairs, the first contacts */
#define KG_CC_WAITING 6      /* contacts left uncoloured by a colouring round, 2 words */
#define KG_CC_WORDS 8

/* Grid levels: level m has cells of the base size times 2^m. A box is keyed at the
 * lowest level where it spans at most two cells per axis; the top level is one cell that
 * holds whatever is too large for every other. */
#define KG_BP_LEVELS 32
#define KG_BP_TOP_LEVEL (KG_BP_LEVELS - 1)

/* The plan of the level searches, words: boxes per level, then the largest footprint a
 * box of level u searches at level l (l * KG_BP_LEVELS + u), then per level u the bit
 * mask of the lower levels its boxes search down into. */
#define KG_BP_PLAN_COUNTS 0
#define KG_BP_PLAN_FOOTPRINTS KG_BP_LEVELS
#define KG_BP_PLAN_DOWN (KG_BP_PLAN_FOOTPRINTS + KG_BP_LEVELS * KG_BP_LEVELS)
#define KG_BP_PLAN_WORDS (KG_BP_PLAN_DOWN + KG_BP_LEVELS)

/* proxy flags */
#define KG_BP_CANDIDATE 0x1u /* alive, not frozen, finite bounds */
#define KG_BP_MOVES 0x2u     /* dynamic body or particle, not frozen, asleep or awake */

/* A body as the broadphase sees it, indexed by slot: its fattened box, the filter, and
 * where it is keyed in the hash grid. 48 bytes. */
typedef struct kg_bp_proxy {
    kg_aabb box;
    kg_u32 category;
    kg_u32 mask;
    kg_i32 cell_x;
    kg_i32 cell_y;
    kg_u32 level;
    kg_u32 flags;
    kg_u32 next; /* the next slot keyed in the same hash bucket, or KG_NULL_INDEX */
    kg_u32 pad;
} kg_bp_proxy;

KG_STATIC_ASSERT(sizeof(kg_bp_proxy) == 48, bp_proxy_size);

/* Box extents are binned by their float bits >> 20 (as collide/broadphase.c does), to
 * take the base cell size from their 90th percentile. */
#define KG_BP_EXTENT_SHIFT 20
#define KG_BP_EXTENT_BINS 2048

/* Prefix sums run in at most this many blocks, each summed serially by one work-item. */
#define KG_SCAN_MAX_BLOCKS 256
#define KG_SCAN_MIN_BLOCK 256

#endif
