/* What the collision stage's kernels (kg_scan.cl, kg_broadphase.cl, kg_collide.cl,
 * kg_color.cl) and their host code (cl_collide.c) agree on: the slots of the small
 * counters buffer and the sizes of the scan blocks (the broadphase's structs are
 * collide/broadphase_grid.h's). KG_COLOR_COUNT comes from solve/coloring.h. */
#ifndef KG_COLLIDE_SHARED_H
#define KG_COLLIDE_SHARED_H

#include "collide/broadphase_grid.h"
#include "core/kg_layout.h"
#include "solve/coloring.h"

/* The counters buffer: what the host reads back of a step. */
#define KG_CC_PAIRS 0         /* pairs the broadphase found, counted past the capacity */
#define KG_CC_CONTACTS 1      /* this step's contacts: touching pairs, then tile contacts */
#define KG_CC_TILES 2         /* tile contacts found, counted past the room left */
#define KG_CC_BODY_CONTACTS 3 /* the touching pairs, the first contacts */
#define KG_CC_WAITING 4       /* contacts left uncoloured by a colouring round, 2 words */
#define KG_CC_HOOKED 6        /* islands hooked by a round of the sleep stage, 2 words */
#define KG_CC_SHAPE_PAIRS 8   /* while a body has several shapes: the pairs of shapes */
#define KG_CC_WORDS 9

/* The broadphase's words on the device: the grid's bounds (collide/broadphase_grid.h),
 * then how many boxes are small and how many large (where their sorted keys end). */
#define KG_BP_BOUNDS 0
#define KG_BP_SMALL 4
#define KG_BP_LARGE 5
#define KG_BP_WORDS 6

/* Word i of them before a search: the bounds empty (min x, min y, max x, max y), the
 * counts 0. */
KG_FN kg_u32 kg_bp_word_cleared(int i)
{
    int bound = i - KG_BP_BOUNDS;
    return bound < 0 || bound >= 4 ? 0u : bound < 2 ? KG_BP_BOUNDS_EMPTY_MIN : KG_BP_BOUNDS_EMPTY_MAX;
}

/* Prefix sums run in at most this many blocks, each summed serially by one work-item. */
#define KG_SCAN_MAX_BLOCKS 256
#define KG_SCAN_MIN_BLOCK 256

#endif
