/* The joint pool and its API (include/kgyro/joint.h, docs/joints.md). */
#include "core/joint.h"
#include "collide/broadphase_grid.h"
#include "core/alloc.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/generation.h"
#include "core/snapshot_io.h"
#include "solve/contact_wide.h"
#include "solve/joint_row.h"
#include "solve/sleep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* What the host keeps of a joint beside its row. */
typedef struct kg_joint_info {
    kg_u32 generation; /* the slot's: bumped when the joint is destroyed */
    kg_i32 alive;
    kg_i32 collide_connected;
    kg_u32 generation_a, generation_b; /* of the bodies, for handing their handles out */
    float break_force, break_torque;   /* 0: never breaks */
    void* user_data;
} kg_joint_info;

typedef struct kg_joint_event_list {
    kg_joint_event* items;
    int count, capacity;
} kg_joint_event_list;

struct kg_joints {
    kg_joint_row* rows;
    kg_joint_info* info;
    int capacity;
    int high_water; /* slots [0, high_water) have been used */
    int count;
    kg_u32 tag;
    int derived_stale; /* the pairs and links below are made again when asked for */
    kg_u32 version;    /* moves when they change (the OpenCL backend uploads them again) */
    kg_u32* apart;     /* the pairs of bodies that must not collide (two slots each, the lower
                        * first), sorted, unique */
    int apart_count;
    kg_u32* links;     /* two slots a link */
    int link_count;
    /* the joints' colours: order lists the live joints colour by colour (slot order within
     * one), colour c's at [color_start[c], color_start[c + 1]), the overflow's last */
    kg_i32* order;
    int color_start[KG_JOINT_COLORS + 2];
    kg_u32* body_colors; /* scratch of the colouring: per body slot, the colours its joints took */
    int body_color_capacity;
    kg_joint_event_list pending; /* destroyed since the last step began */
    kg_joint_event_list events;  /* handed out: destroyed before the last step, broken by it */
    int breakable;               /* joints ever given a break threshold: the step looks at them */
    int iterations;              /* of each solve and relax pass (kg_world_set_joint_iterations) */
    /* this step's active revolute joints `lanes->width` at a time (kg_joints_prepare;
     * lanes NULL: every joint one at a time): colour c's blocks at [block_start[c],
     * block_start[c + 1]), lane l of block k the joint lane_joint[k width + l] (-1: a
     * padding lane); its other active joints at others[other_start[c], other_start[c + 1]) */
    const kg_contact_rows* lanes;
    void* blocks;
    kg_i32* lane_joint;
    kg_i32* others;
    int lane_capacity; /* blocks' lanes, lane_joint's entries */
    int other_capacity;
    int block_start[KG_JOINT_COLORS + 1];
    int other_start[KG_JOINT_COLORS + 1];
};

#define KG_JOINTS_FIRST_CAPACITY 16

void kg_joints_destroy(kg_world* world)
{
    struct kg_joints* j = world->joints;
    if (!j) {
        return;
    }
    kg_free(j->rows);
    kg_free(j->info);
    kg_free(j->apart);
    kg_free(j->links);
    kg_free(j->order);
    kg_free(j->body_colors);
    kg_free(j->blocks);
    kg_free(j->lane_joint);
    kg_free(j->others);
    kg_free(j->pending.items);
    kg_free(j->events.items);
    kg_free(j);
    world->joints = NULL;
}

int kg_joints_live(const kg_world* world) { return world && world->joints ? world->joints->count : 0; }

int kg_world_joint_count(const kg_world* world) { return kg_joints_live(world); }

static struct kg_joints* kg_joints_of(kg_world* world);

kg_result kg_world_set_joint_iterations(kg_world* world, int iterations)
{
    if (!world || iterations < 1 || iterations > 64) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT,
                       "kg_world_set_joint_iterations: iterations must be in [1, 64] (got %d)", iterations);
    }
    if (kg_world_refuses(world, "kg_world_set_joint_iterations", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    struct kg_joints* j = kg_joints_of(world);
    if (!j) {
        return kg_last_result();
    }
    j->iterations = iterations;
    return KG_OK;
}

int kg_world_get_joint_iterations(const kg_world* world)
{
    return world && world->joints ? world->joints->iterations : KG_JOINT_ITERATIONS;
}

int kg_joints_slots(const kg_world* world) { return world && world->joints ? world->joints->high_water : 0; }

kg_joint kg_joint_of_slot(const kg_world* world, uint32_t i)
{
    kg_joint j = KG_NULL_JOINT_INIT;
    const struct kg_joints* p = world ? world->joints : NULL;
    if (p && i < (uint32_t)p->high_water && p->info[i].alive) {
        j.index = i;
        j.generation = p->info[i].generation;
    }
    return j;
}

/* The pool, made with the first joint; NULL (error set) when out of memory. */
static struct kg_joints* kg_joints_of(kg_world* world)
{
    if (!world->joints) {
        struct kg_joints* j = kg_alloc_zeroed(sizeof *j);
        if (!j) {
            kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the joint pool");
            return NULL;
        }
        j->tag = world->shapes.tag;
        j->iterations = KG_JOINT_ITERATIONS;
        world->joints = j;
    }
    return world->joints;
}

static int kg_joints_grow(struct kg_joints* j)
{
    int capacity = j->capacity > 0 ? 2 * j->capacity : KG_JOINTS_FIRST_CAPACITY;
    kg_joint_row* rows = kg_alloc_zeroed((size_t)capacity * sizeof *rows);
    kg_joint_info* info = kg_alloc_zeroed((size_t)capacity * sizeof *info);
    kg_u32* links = kg_alloc_zeroed((size_t)capacity * 2 * sizeof *links);
    kg_u32* apart = kg_alloc_zeroed((size_t)capacity * 2 * sizeof *apart);
    kg_i32* order = kg_alloc_zeroed((size_t)capacity * sizeof *order);
    if (!rows || !info || !links || !apart || !order) {
        kg_free(rows);
        kg_free(info);
        kg_free(links);
        kg_free(apart);
        kg_free(order);
        kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot grow the joint pool to %d joints", capacity);
        return 0;
    }
    if (j->capacity > 0) {
        memcpy(rows, j->rows, (size_t)j->capacity * sizeof *rows);
        memcpy(info, j->info, (size_t)j->capacity * sizeof *info);
    }
    for (int i = j->capacity; i < capacity; ++i) {
        info[i].generation = kg_generation_first(j->tag);
    }
    kg_free(j->rows);
    kg_free(j->info);
    kg_free(j->links);
    kg_free(j->apart);
    kg_free(j->order);
    j->order = order;
    j->rows = rows;
    j->info = info;
    j->links = links;
    j->apart = apart;
    j->capacity = capacity;
    j->derived_stale = 1;
    j->version += 1;
    return 1;
}

/* The slot of a live joint handle, or -1 with the error set. */
static int kg_joint_resolve(const kg_world* world, kg_joint joint)
{
    if (!world) {
        kg_fail(KG_ERROR_INVALID_ARGUMENT, "NULL world");
        return -1;
    }
    const struct kg_joints* j = world->joints;
    if (!j || joint.generation == 0u || joint.index >= (uint32_t)j->high_water || !j->info[joint.index].alive ||
        j->info[joint.index].generation != joint.generation) {
        kg_fail(KG_ERROR_INVALID_HANDLE, "invalid joint handle {%u, %u} (stale, destroyed or another world's)",
                joint.index, joint.generation);
        return -1;
    }
    return (int)joint.index;
}

int kg_joint_is_valid(const kg_world* world, kg_joint joint)
{
    const struct kg_joints* j = world ? world->joints : NULL;
    return j && joint.generation != 0u && joint.index < (uint32_t)j->high_water && j->info[joint.index].alive &&
           j->info[joint.index].generation == joint.generation;
}

static int kg_finite2(kg_vec2 v) { return isfinite(v.x) && isfinite(v.y); }
static int kg_nonneg(float v) { return isfinite(v) && v >= 0.0f; }
static int kg_is_null_body(kg_body b) { return b.index == 0u && b.generation == 0u; }

static kg_body kg_body_handle(const kg_world* world, kg_u32 slot)
{
    kg_body b = KG_NULL_BODY_INIT;
    if (slot != KG_NULL_INDEX) {
        b.index = slot;
        b.generation = world->bodies.generation[slot];
    }
    return b;
}

static void kg_wake_joint_bodies(kg_world* world, const kg_joint_row* r)
{
    kg_body_pool* p = kg_world_write_pool(world);
    if (r->a != KG_NULL_INDEX) {
        kg_wake_slot(p, (int)r->a);
    }
    if (r->b != KG_NULL_INDEX) {
        kg_wake_slot(p, (int)r->b);
    }
}

static kg_joint_base_def kg_default_base(void)
{
    kg_joint_base_def d;
    memset(&d, 0, sizeof d);
    d.constraint_hertz = 0.0f; /* as stiff as the sub-step allows: KG_JOINT_HERTZ_CAP of its rate */
    d.constraint_damping_ratio = 5.0f;
    return d;
}

kg_revolute_joint_def kg_default_revolute_joint_def(void)
{
    kg_revolute_joint_def d;
    memset(&d, 0, sizeof d);
    d.base = kg_default_base();
    d.lower_angle = -0.5f * KG_JOINT_PI;
    d.upper_angle = 0.5f * KG_JOINT_PI;
    d.damping_ratio = 0.0f;
    return d;
}

kg_distance_joint_def kg_default_distance_joint_def(void)
{
    kg_distance_joint_def d;
    memset(&d, 0, sizeof d);
    d.base = kg_default_base();
    d.length = 1.0f;
    d.max_length = 1e6f;
    return d;
}

kg_weld_joint_def kg_default_weld_joint_def(void)
{
    kg_weld_joint_def d;
    memset(&d, 0, sizeof d);
    d.base = kg_default_base();
    return d;
}

kg_mouse_joint_def kg_default_mouse_joint_def(void)
{
    kg_mouse_joint_def d;
    memset(&d, 0, sizeof d);
    d.base = kg_default_base();
    d.hertz = 5.0f;
    d.damping_ratio = 0.7f;
    d.max_force = 1000.0f;
    return d;
}

kg_prismatic_joint_def kg_default_prismatic_joint_def(void)
{
    kg_prismatic_joint_def d;
    memset(&d, 0, sizeof d);
    d.base = kg_default_base();
    d.local_axis_a = kg_v2(1.0f, 0.0f);
    d.lower_translation = -1.0f;
    d.upper_translation = 1.0f;
    return d;
}

kg_wheel_joint_def kg_default_wheel_joint_def(void)
{
    kg_wheel_joint_def d;
    memset(&d, 0, sizeof d);
    d.base = kg_default_base();
    d.local_axis_a = kg_v2(0.0f, 1.0f);
    d.lower_translation = -0.25f;
    d.upper_translation = 0.25f;
    d.enable_spring = 1;
    d.hertz = 1.0f;
    d.damping_ratio = 0.7f;
    return d;
}

kg_motor_joint_def kg_default_motor_joint_def(void)
{
    kg_motor_joint_def d;
    memset(&d, 0, sizeof d);
    d.base = kg_default_base();
    d.max_force = 1.0f;
    d.max_torque = 1.0f;
    d.correction_factor = 0.3f;
    return d;
}

kg_result kg_check_base_values(const kg_joint_base_def* base, const char* call)
{
    if (!kg_nonneg(base->constraint_hertz) || !kg_nonneg(base->constraint_damping_ratio)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: constraint_hertz and constraint_damping_ratio must be finite "
                       "and >= 0", call);
    }
    if (!kg_nonneg(base->break_force) || !kg_nonneg(base->break_torque)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: break_force and break_torque must be finite and >= 0", call);
    }
    return KG_OK;
}

/* The checks every kind shares: the world takes joints now, body_b lives, body_a is the
 * world or another live body, the constraint's softness is sane. Fills the row's slots
 * and the bodies' generations. */
static kg_result kg_check_base(kg_world* world, const kg_joint_base_def* base, const char* call, int a_is_world,
                               kg_joint_row* row, kg_joint_info* info)
{
    if (!world || !base) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: NULL argument", call);
    }
    if (kg_world_refuses(world, call, KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    int b = kg_world_resolve(world, base->body_b);
    if (b < 0) {
        return kg_fail(KG_ERROR_INVALID_HANDLE, "%s: body_b is not a live body of this world", call);
    }
    int a = -1;
    if (!a_is_world && !kg_is_null_body(base->body_a)) {
        a = kg_world_resolve(world, base->body_a);
        if (a < 0) {
            return kg_fail(KG_ERROR_INVALID_HANDLE, "%s: body_a is not a live body of this world", call);
        }
        if (a == b) {
            return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: a joint between a body and itself", call);
        }
    }
    kg_result values = kg_check_base_values(base, call);
    if (values != KG_OK) {
        return values;
    }
    memset(row, 0, sizeof *row);
    memset(info, 0, sizeof *info);
    row->a = a < 0 ? KG_NULL_INDEX : (kg_u32)a;
    row->b = (kg_u32)b;
    row->constraint_hertz = base->constraint_hertz;
    row->constraint_damping_ratio = base->constraint_damping_ratio;
    info->collide_connected = base->collide_connected != 0;
    info->break_force = base->break_force;
    info->break_torque = base->break_torque;
    info->user_data = base->user_data;
    info->generation_a = a < 0 ? 0u : world->bodies.generation[a];
    info->generation_b = world->bodies.generation[b];
    return KG_OK;
}

/* A new joint of row and info in the lowest free slot, its bodies woken. */
static kg_result kg_add_joint(kg_world* world, const kg_joint_row* row, const kg_joint_info* info, kg_joint* out)
{
    struct kg_joints* j = kg_joints_of(world);
    if (!j) {
        return kg_last_result();
    }
    int slot = 0;
    while (slot < j->high_water && j->info[slot].alive) {
        ++slot;
    }
    if (slot >= j->capacity && !kg_joints_grow(j)) {
        return kg_last_result();
    }
    kg_u32 generation = j->info[slot].generation;
    j->rows[slot] = *row;
    j->info[slot] = *info;
    j->info[slot].generation = generation;
    j->info[slot].alive = 1;
    j->breakable |= info->break_force > 0.0f || info->break_torque > 0.0f;
    j->high_water = slot + 1 > j->high_water ? slot + 1 : j->high_water;
    j->count += 1;
    j->derived_stale = 1;
    j->version += 1;
    kg_wake_joint_bodies(world, row);
    if (out) {
        out->index = (uint32_t)slot;
        out->generation = generation;
    }
    return KG_OK;
}

static kg_result kg_check_spring(float hertz, float damping_ratio, const char* call)
{
    if (!kg_nonneg(hertz) || !kg_nonneg(damping_ratio)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: hertz and damping ratio must be finite and >= 0", call);
    }
    return KG_OK;
}

static kg_result kg_check_angles(int enable, float lower, float upper, const char* call)
{
    (void)enable;
    if (!isfinite(lower) || !isfinite(upper) || lower > upper || lower < -KG_JOINT_PI - 1e-3f ||
        upper > KG_JOINT_PI + 1e-3f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: angle limits must be finite, lower <= upper, within [-pi, pi]",
                       call);
    }
    return KG_OK;
}

static kg_result kg_check_motor(float speed, float max_torque, const char* call)
{
    if (!isfinite(speed) || !kg_nonneg(max_torque)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: motor speed must be finite and its maximum torque >= 0", call);
    }
    return KG_OK;
}

static kg_result kg_check_lengths(float min_length, float max_length, const char* call)
{
    if (!kg_nonneg(min_length) || !kg_nonneg(max_length) || min_length > max_length) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: lengths must be finite, 0 <= min_length <= max_length", call);
    }
    return KG_OK;
}

static kg_u32 kg_option(int enabled, kg_u32 bit) { return enabled ? bit : 0u; }

kg_result kg_check_revolute_values(const kg_revolute_joint_def* def, const char* call)
{
    kg_result r;
    if (!kg_finite2(def->local_anchor_a) || !kg_finite2(def->local_anchor_b) || !isfinite(def->reference_angle)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: anchors and reference angle must be finite", call);
    }
    if ((r = kg_check_angles(def->enable_limit, def->lower_angle, def->upper_angle, call)) != KG_OK ||
        (r = kg_check_motor(def->motor_speed, def->max_motor_torque, call)) != KG_OK) {
        return r;
    }
    return kg_check_spring(def->hertz, def->damping_ratio, call);
}

kg_result kg_create_revolute_joint(kg_world* world, const kg_revolute_joint_def* def, kg_joint* out)
{
    const char* call = "kg_create_revolute_joint";
    kg_joint_row row;
    kg_joint_info info;
    kg_result r = kg_check_base(world, def ? &def->base : NULL, call, 0, &row, &info);
    if (r != KG_OK) {
        return r;
    }
    if ((r = kg_check_revolute_values(def, call)) != KG_OK) {
        return r;
    }
    row.type = KG_JOINT_ROW_REVOLUTE;
    row.options = kg_option(def->enable_limit, KG_JOINT_OPT_LIMIT) | kg_option(def->enable_motor, KG_JOINT_OPT_MOTOR) |
                  kg_option(def->enable_spring, KG_JOINT_OPT_SPRING);
    row.local_a = def->local_anchor_a;
    row.local_b = def->local_anchor_b;
    row.reference_angle = def->reference_angle;
    row.lower = def->lower_angle;
    row.upper = def->upper_angle;
    row.motor_speed = def->motor_speed;
    row.max_motor_torque = def->max_motor_torque;
    row.hertz = def->hertz;
    row.damping_ratio = def->damping_ratio;
    return kg_add_joint(world, &row, &info, out);
}

kg_result kg_check_distance_values(const kg_distance_joint_def* def, const char* call)
{
    kg_result r;
    if (!kg_finite2(def->local_anchor_a) || !kg_finite2(def->local_anchor_b)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: anchors must be finite", call);
    }
    if (!isfinite(def->length) || def->length <= 0.0f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: length must be finite and > 0", call);
    }
    if ((r = kg_check_lengths(def->min_length, def->max_length, call)) != KG_OK) {
        return r;
    }
    return kg_check_spring(def->hertz, def->damping_ratio, call);
}

kg_result kg_create_distance_joint(kg_world* world, const kg_distance_joint_def* def, kg_joint* out)
{
    const char* call = "kg_create_distance_joint";
    kg_joint_row row;
    kg_joint_info info;
    kg_result r = kg_check_base(world, def ? &def->base : NULL, call, 0, &row, &info);
    if (r != KG_OK) {
        return r;
    }
    if ((r = kg_check_distance_values(def, call)) != KG_OK) {
        return r;
    }
    row.type = KG_JOINT_ROW_DISTANCE;
    row.options = kg_option(def->enable_limit, KG_JOINT_OPT_LIMIT) | kg_option(def->enable_spring, KG_JOINT_OPT_SPRING);
    row.local_a = def->local_anchor_a;
    row.local_b = def->local_anchor_b;
    row.length = def->length;
    row.lower = def->min_length;
    row.upper = def->max_length;
    row.hertz = def->hertz;
    row.damping_ratio = def->damping_ratio;
    return kg_add_joint(world, &row, &info, out);
}

kg_result kg_check_weld_values(const kg_weld_joint_def* def, const char* call)
{
    kg_result r;
    if (!kg_finite2(def->local_anchor_a) || !kg_finite2(def->local_anchor_b) || !isfinite(def->reference_angle)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: anchors and reference angle must be finite", call);
    }
    if ((r = kg_check_spring(def->linear_hertz, def->linear_damping_ratio, call)) != KG_OK) {
        return r;
    }
    return kg_check_spring(def->angular_hertz, def->angular_damping_ratio, call);
}

kg_result kg_create_weld_joint(kg_world* world, const kg_weld_joint_def* def, kg_joint* out)
{
    const char* call = "kg_create_weld_joint";
    kg_joint_row row;
    kg_joint_info info;
    kg_result r = kg_check_base(world, def ? &def->base : NULL, call, 0, &row, &info);
    if (r != KG_OK) {
        return r;
    }
    if ((r = kg_check_weld_values(def, call)) != KG_OK) {
        return r;
    }
    row.type = KG_JOINT_ROW_WELD;
    row.local_a = def->local_anchor_a;
    row.local_b = def->local_anchor_b;
    row.reference_angle = def->reference_angle;
    row.hertz = def->linear_hertz;
    row.damping_ratio = def->linear_damping_ratio;
    row.hertz2 = def->angular_hertz;
    row.damping_ratio2 = def->angular_damping_ratio;
    return kg_add_joint(world, &row, &info, out);
}

kg_result kg_check_mouse_values(const kg_mouse_joint_def* def, const char* call)
{
    if (!kg_finite2(def->target) || !kg_finite2(def->local_anchor_b)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: target and anchor must be finite", call);
    }
    if (!isfinite(def->hertz) || def->hertz <= 0.0f || !kg_nonneg(def->damping_ratio) || !kg_nonneg(def->max_force)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: hertz must be > 0, damping ratio and max_force >= 0", call);
    }
    return KG_OK;
}

kg_result kg_create_mouse_joint(kg_world* world, const kg_mouse_joint_def* def, kg_joint* out)
{
    const char* call = "kg_create_mouse_joint";
    kg_joint_row row;
    kg_joint_info info;
    kg_result r = kg_check_base(world, def ? &def->base : NULL, call, 1, &row, &info);
    if (r != KG_OK) {
        return r;
    }
    if ((r = kg_check_mouse_values(def, call)) != KG_OK) {
        return r;
    }
    row.type = KG_JOINT_ROW_MOUSE;
    row.local_a = def->target;
    row.local_b = def->local_anchor_b;
    row.hertz = def->hertz;
    row.damping_ratio = def->damping_ratio;
    row.max_force = def->max_force;
    return kg_add_joint(world, &row, &info, out);
}

static kg_result kg_check_translations(float lower, float upper, const char* call)
{
    if (!isfinite(lower) || !isfinite(upper) || lower > upper) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: translation limits must be finite, lower <= upper", call);
    }
    return KG_OK;
}

/* axis normalized into *out, or an error for a zero or non-finite one. */
static kg_result kg_check_axis(kg_vec2 axis, const char* call, kg_vec2* out)
{
    float length = sqrtf(axis.x * axis.x + axis.y * axis.y);
    if (!kg_finite2(axis) || !(length > 1e-6f) || !isfinite(length)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: the axis must be finite and not zero", call);
    }
    *out = kg_v2(axis.x / length, axis.y / length);
    return KG_OK;
}

kg_result kg_check_prismatic_values(const kg_prismatic_joint_def* def, const char* call)
{
    kg_result r;
    kg_vec2 axis;
    if (!kg_finite2(def->local_anchor_a) || !kg_finite2(def->local_anchor_b) || !isfinite(def->reference_angle)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: anchors and reference angle must be finite", call);
    }
    if ((r = kg_check_axis(def->local_axis_a, call, &axis)) != KG_OK ||
        (r = kg_check_translations(def->lower_translation, def->upper_translation, call)) != KG_OK ||
        (r = kg_check_motor(def->motor_speed, def->max_motor_force, call)) != KG_OK) {
        return r;
    }
    return kg_check_spring(def->hertz, def->damping_ratio, call);
}

kg_result kg_create_prismatic_joint(kg_world* world, const kg_prismatic_joint_def* def, kg_joint* out)
{
    const char* call = "kg_create_prismatic_joint";
    kg_joint_row row;
    kg_joint_info info;
    kg_result r = kg_check_base(world, def ? &def->base : NULL, call, 0, &row, &info);
    if (r != KG_OK) {
        return r;
    }
    if ((r = kg_check_prismatic_values(def, call)) != KG_OK ||
        (r = kg_check_axis(def->local_axis_a, call, &row.local_axis)) != KG_OK) {
        return r;
    }
    row.type = KG_JOINT_ROW_PRISMATIC;
    row.options = kg_option(def->enable_limit, KG_JOINT_OPT_LIMIT) | kg_option(def->enable_motor, KG_JOINT_OPT_MOTOR) |
                  kg_option(def->enable_spring, KG_JOINT_OPT_SPRING);
    row.local_a = def->local_anchor_a;
    row.local_b = def->local_anchor_b;
    row.reference_angle = def->reference_angle;
    row.lower = def->lower_translation;
    row.upper = def->upper_translation;
    row.motor_speed = def->motor_speed;
    row.max_motor_torque = def->max_motor_force;
    row.hertz = def->hertz;
    row.damping_ratio = def->damping_ratio;
    return kg_add_joint(world, &row, &info, out);
}

kg_result kg_check_wheel_values(const kg_wheel_joint_def* def, const char* call)
{
    kg_result r;
    kg_vec2 axis;
    if (!kg_finite2(def->local_anchor_a) || !kg_finite2(def->local_anchor_b)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: anchors must be finite", call);
    }
    if ((r = kg_check_axis(def->local_axis_a, call, &axis)) != KG_OK ||
        (r = kg_check_translations(def->lower_translation, def->upper_translation, call)) != KG_OK ||
        (r = kg_check_motor(def->motor_speed, def->max_motor_torque, call)) != KG_OK) {
        return r;
    }
    return kg_check_spring(def->hertz, def->damping_ratio, call);
}

kg_result kg_create_wheel_joint(kg_world* world, const kg_wheel_joint_def* def, kg_joint* out)
{
    const char* call = "kg_create_wheel_joint";
    kg_joint_row row;
    kg_joint_info info;
    kg_result r = kg_check_base(world, def ? &def->base : NULL, call, 0, &row, &info);
    if (r != KG_OK) {
        return r;
    }
    if ((r = kg_check_wheel_values(def, call)) != KG_OK ||
        (r = kg_check_axis(def->local_axis_a, call, &row.local_axis)) != KG_OK) {
        return r;
    }
    row.type = KG_JOINT_ROW_WHEEL;
    row.options = kg_option(def->enable_limit, KG_JOINT_OPT_LIMIT) | kg_option(def->enable_motor, KG_JOINT_OPT_MOTOR) |
                  kg_option(def->enable_spring, KG_JOINT_OPT_SPRING);
    row.local_a = def->local_anchor_a;
    row.local_b = def->local_anchor_b;
    row.lower = def->lower_translation;
    row.upper = def->upper_translation;
    row.motor_speed = def->motor_speed;
    row.max_motor_torque = def->max_motor_torque;
    row.hertz = def->hertz;
    row.damping_ratio = def->damping_ratio;
    return kg_add_joint(world, &row, &info, out);
}

kg_result kg_check_motor_values(const kg_motor_joint_def* def, const char* call)
{
    if (!kg_finite2(def->linear_offset) || !isfinite(def->angular_offset) || !kg_nonneg(def->max_force) ||
        !kg_nonneg(def->max_torque) || !kg_nonneg(def->correction_factor) || def->correction_factor > 1.0f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: offsets must be finite, max_force and max_torque >= 0, "
                       "correction_factor in [0, 1]", call);
    }
    return KG_OK;
}

kg_result kg_create_motor_joint(kg_world* world, const kg_motor_joint_def* def, kg_joint* out)
{
    const char* call = "kg_create_motor_joint";
    kg_joint_row row;
    kg_joint_info info;
    kg_result r = kg_check_base(world, def ? &def->base : NULL, call, 0, &row, &info);
    if (r != KG_OK) {
        return r;
    }
    if ((r = kg_check_motor_values(def, call)) != KG_OK) {
        return r;
    }
    row.type = KG_JOINT_ROW_MOTOR;
    row.local_a = def->linear_offset;
    row.local_b = kg_v2(0.0f, 0.0f);
    row.reference_angle = def->angular_offset;
    row.max_force = def->max_force;
    row.max_motor_torque = def->max_torque;
    row.length = def->correction_factor;
    return kg_add_joint(world, &row, &info, out);
}

/* Frees slot i (its generation moves on). */
static void kg_release_joint(struct kg_joints* j, int i)
{
    j->info[i].alive = 0;
    j->info[i].generation = kg_generation_next(j->info[i].generation);
    if (j->info[i].generation == 0u) {
        j->info[i].generation = kg_generation_first(j->tag);
    }
    memset(&j->rows[i], 0, sizeof j->rows[i]);
    j->rows[i].a = j->rows[i].b = KG_NULL_INDEX; /* no bodies: never active (the device runs every slot) */
    j->count -= 1;
    j->derived_stale = 1;
    j->version += 1;
    while (j->high_water > 0 && !j->info[j->high_water - 1].alive) {
        j->high_water -= 1;
    }
}

kg_result kg_destroy_joint(kg_world* world, kg_joint joint)
{
    if (kg_world_refuses(world, "kg_destroy_joint", KG_LOCK_STEP)) {
        return KG_ERROR_LOCKED;
    }
    int i = kg_joint_resolve(world, joint);
    if (i < 0) {
        return kg_last_result();
    }
    kg_wake_joint_bodies(world, &world->joints->rows[i]);
    kg_release_joint(world->joints, i);
    return KG_OK;
}

static kg_result kg_push_event(kg_joint_event_list* list, const kg_joint_event* e)
{
    if (list->count == list->capacity) {
        int capacity = list->capacity > 0 ? 2 * list->capacity : 8;
        kg_joint_event* items = kg_alloc_zeroed((size_t)capacity * sizeof *items);
        if (!items) {
            return KG_ERROR_OUT_OF_MEMORY;
        }
        if (list->count > 0) {
            memcpy(items, list->items, (size_t)list->count * sizeof *items);
        }
        kg_free(list->items);
        list->items = items;
        list->capacity = capacity;
    }
    list->items[list->count++] = *e;
    return KG_OK;
}

void kg_joints_body_destroyed(kg_world* world, kg_u32 slot, kg_body body)
{
    struct kg_joints* j = world->joints;
    if (!j || j->count == 0) {
        return;
    }
    for (int i = 0; i < j->high_water; ++i) {
        if (!j->info[i].alive || (j->rows[i].a != slot && j->rows[i].b != slot)) {
            continue;
        }
        kg_joint_event e;
        memset(&e, 0, sizeof e);
        e.joint.index = (uint32_t)i;
        e.joint.generation = j->info[i].generation;
        e.kind = KG_JOINT_EVENT_BODY_DESTROYED;
        e.body = body;
        e.user_data = j->info[i].user_data;
        if (kg_push_event(&j->pending, &e) != KG_OK) {
            kg_warn_once("joint-events", "out of memory for joint events: an event was lost");
        }
        kg_wake_joint_bodies(world, &j->rows[i]);
        kg_release_joint(j, i);
    }
}

/* The reaction of row r over the last step's sub-step (zero before any step). */
static void kg_reaction_of(const kg_world* world, const kg_joint_row* r, kg_vec2* force, float* torque)
{
    float inv_h = world->last_dt > 0.0f ? (float)world->def.substeps / world->last_dt : 0.0f;
    kg_joint_reaction(r, inv_h, force, torque);
}

void kg_joints_after_step(kg_world* world)
{
    struct kg_joints* j = world->joints;
    if (!j || j->breakable == 0) {
        return;
    }
    for (int i = 0; i < j->high_water; ++i) {
        const kg_joint_info* info = &j->info[i];
        if (!info->alive || (info->break_force == 0.0f && info->break_torque == 0.0f)) {
            continue;
        }
        kg_vec2 force;
        float torque;
        kg_reaction_of(world, &j->rows[i], &force, &torque);
        int broken = (info->break_force > 0.0f && kg_length(force) > info->break_force) ||
                     (info->break_torque > 0.0f && fabsf(torque) > info->break_torque);
        if (!broken) {
            continue;
        }
        kg_joint_event e;
        memset(&e, 0, sizeof e);
        e.joint.index = (uint32_t)i;
        e.joint.generation = info->generation;
        e.kind = KG_JOINT_EVENT_BROKEN;
        e.user_data = info->user_data;
        e.force = force;
        e.torque = torque;
        if (kg_push_event(&j->events, &e) != KG_OK) {
            kg_warn_once("joint-events", "out of memory for joint events: an event was lost");
        }
        kg_wake_joint_bodies(world, &j->rows[i]);
        kg_release_joint(j, i);
    }
}

void kg_joints_begin_step(kg_world* world)
{
    struct kg_joints* j = world->joints;
    if (!j) {
        return;
    }
    kg_joint_event_list t = j->events;
    j->events = j->pending;
    j->pending = t;
    j->pending.count = 0;
}

kg_joint_events kg_world_get_joint_events(const kg_world* world)
{
    kg_joint_events out = {NULL, 0};
    if (world && world->joints) {
        out.events = world->joints->events.items;
        out.count = world->joints->events.count;
    }
    return out;
}

/* ---- what the other stages ask ------------------------------------------------------ */

/* Two pairs of slots (two kg_u32 each) in (a, b) order. */
static int kg_compare_pairs(const void* pa, const void* pb)
{
    const kg_u32* a = pa;
    const kg_u32* b = pb;
    if (a[0] != b[0]) {
        return a[0] < b[0] ? -1 : 1;
    }
    return a[1] < b[1] ? -1 : (a[1] > b[1] ? 1 : 0);
}

/* The joints' colours (greedy, in slot order): each takes the lowest colour that no joint
 * before it on either of its bodies took, static bodies counted too (so that a body made
 * dynamic later needs no new colouring); past KG_JOINT_COLORS, the overflow. Then the
 * order, colour by colour. Without memory for the scratch every joint is the overflow's. */
static void kg_joints_color(struct kg_joints* j, int max_bodies)
{
    if (j->body_color_capacity < max_bodies) {
        kg_free(j->body_colors);
        j->body_colors = kg_alloc_zeroed((size_t)max_bodies * sizeof *j->body_colors);
        j->body_color_capacity = j->body_colors ? max_bodies : 0;
    }
    int counts[KG_JOINT_COLORS + 1] = {0};
    kg_u32* used = j->body_colors;
    for (int i = 0; used && i < j->high_water; ++i) {
        const kg_joint_row* r = &j->rows[i];
        if (r->a != KG_NULL_INDEX) {
            used[r->a] = 0u;
        }
        if (r->b != KG_NULL_INDEX) {
            used[r->b] = 0u;
        }
    }
    for (int i = 0; i < j->high_water; ++i) {
        if (!j->info[i].alive) {
            continue;
        }
        const kg_joint_row* r = &j->rows[i];
        kg_u32 taken = used ? (r->a != KG_NULL_INDEX ? used[r->a] : 0u) | (r->b != KG_NULL_INDEX ? used[r->b] : 0u)
                            : ~0u;
        int c = 0;
        while (c < KG_JOINT_COLORS && (taken & (1u << c))) {
            ++c;
        }
        if (c < KG_JOINT_COLORS) {
            if (r->a != KG_NULL_INDEX) {
                used[r->a] |= 1u << c;
            }
            if (r->b != KG_NULL_INDEX) {
                used[r->b] |= 1u << c;
            }
        }
        j->order[i] = c; /* the colour for now: the order is made below */
        counts[c] += 1;
    }
    int next[KG_JOINT_COLORS + 1];
    j->color_start[0] = 0;
    for (int c = 0; c <= KG_JOINT_COLORS; ++c) {
        next[c] = j->color_start[c];
        j->color_start[c + 1] = j->color_start[c] + counts[c];
    }
    /* the colours copied out, then the joints placed colour by colour in slot order */
    kg_i32* colors = kg_alloc_zeroed((size_t)(j->high_water > 0 ? j->high_water : 1) * sizeof *colors);
    if (!colors) { /* no scratch: every joint serially, in slot order */
        int n = 0;
        for (int i = 0; i < j->high_water; ++i) {
            if (j->info[i].alive) {
                j->order[n++] = i;
            }
        }
        for (int c = 0; c <= KG_JOINT_COLORS; ++c) {
            j->color_start[c] = 0;
        }
        j->color_start[KG_JOINT_COLORS + 1] = n;
        return;
    }
    memcpy(colors, j->order, (size_t)j->high_water * sizeof *colors);
    for (int i = 0; i < j->high_water; ++i) {
        if (j->info[i].alive) {
            j->order[next[colors[i]]++] = i;
        }
    }
    kg_free(colors);
}

/* The pairs kept apart, the islands' links and the colours, made again after a joint
 * changed. */
static void kg_joints_derive(struct kg_joints* j, int max_bodies)
{
    if (!j->derived_stale) {
        return;
    }
    kg_joints_color(j, max_bodies);
    int apart = 0, links = 0;
    for (int i = 0; i < j->high_water; ++i) {
        const kg_joint_row* r = &j->rows[i];
        if (!j->info[i].alive || r->a == KG_NULL_INDEX || r->b == KG_NULL_INDEX) {
            continue;
        }
        j->links[2 * links] = r->a;
        j->links[2 * links + 1] = r->b;
        links += 1;
        if (!j->info[i].collide_connected) {
            j->apart[2 * apart] = r->a < r->b ? r->a : r->b;
            j->apart[2 * apart + 1] = r->a < r->b ? r->b : r->a;
            apart += 1;
        }
    }
    qsort(j->apart, (size_t)apart, 2 * sizeof *j->apart, kg_compare_pairs);
    int unique = 0;
    for (int k = 0; k < apart; ++k) {
        if (unique == 0 || kg_compare_pairs(&j->apart[2 * (unique - 1)], &j->apart[2 * k]) != 0) {
            j->apart[2 * unique] = j->apart[2 * k];
            j->apart[2 * unique + 1] = j->apart[2 * k + 1];
            unique += 1;
        }
    }
    j->apart_count = unique;
    j->link_count = links;
    j->derived_stale = 0;
}

int kg_joints_filter_pairs(kg_world* world, kg_pair* pairs, int count)
{
    struct kg_joints* j = world->joints;
    if (!j || j->count == 0) {
        return count;
    }
    kg_joints_derive(j, world->def.max_bodies);
    if (j->apart_count == 0) {
        return count;
    }
    int kept = 0;
    for (int k = 0; k < count; ++k) {
        kg_pair p = pairs[k];
        if (!kg_pair_is_joined(j->apart, j->apart_count, p.a, p.b)) {
            pairs[kept++] = p;
        }
    }
    return kept;
}

const kg_u32* kg_joints_apart(kg_world* world, int* count)
{
    struct kg_joints* j = world->joints;
    *count = 0;
    if (!j || j->count == 0) {
        return NULL;
    }
    kg_joints_derive(j, world->def.max_bodies);
    *count = j->apart_count;
    return j->apart;
}

kg_joint_row* kg_joints_rows(kg_world* world, int* slots)
{
    struct kg_joints* j = world->joints;
    *slots = j && j->count > 0 ? j->high_water : 0;
    return j ? j->rows : NULL;
}

kg_u32 kg_joints_version(const kg_world* world) { return world->joints ? world->joints->version : 0u; }

const kg_u32* kg_joints_links(kg_world* world, int* count)
{
    struct kg_joints* j = world->joints;
    *count = 0;
    if (!j || j->count == 0) {
        return NULL;
    }
    kg_joints_derive(j, world->def.max_bodies);
    *count = j->link_count;
    return j->links;
}

/* Room for the lanes of every colour's revolute joints (each colour's last block padded)
 * and for the other joints; 0 without the memory. */
static int kg_joints_reserve_lanes(struct kg_joints* j, int width)
{
    int lanes = j->high_water + KG_JOINT_COLORS * (width - 1);
    if (j->lane_capacity < lanes) {
        kg_free(j->blocks);
        kg_free(j->lane_joint);
        j->blocks = kg_alloc_zeroed((size_t)lanes * sizeof(kg_revolute_lanes));
        j->lane_joint = kg_alloc_zeroed((size_t)lanes * sizeof *j->lane_joint);
        j->lane_capacity = j->blocks && j->lane_joint ? lanes : 0;
    }
    if (j->other_capacity < j->high_water) {
        kg_free(j->others);
        j->others = kg_alloc_zeroed((size_t)j->high_water * sizeof *j->others);
        j->other_capacity = j->others ? j->high_water : 0;
    }
    return j->lane_capacity >= lanes && j->other_capacity >= j->high_water;
}

/* Lane `lane` of block `block` from l (a padding lane: zeros, the still body twice):
 * data movement only, a 4-byte field at a time. */
static void kg_revolute_to_lane(struct kg_joints* j, int block, int lane, const kg_revolute_lanes* l)
{
    for (size_t f = 0; f < sizeof *l; f += 4) {
        memcpy(kg_revolute_lane_field(j->blocks, j->lanes->width, block, lane, f), (const unsigned char*)l + f, 4);
    }
}

static kg_revolute_lanes kg_revolute_of_lane(struct kg_joints* j, int block, int lane)
{
    kg_revolute_lanes l;
    for (size_t f = 0; f < sizeof l; f += 4) {
        memcpy((unsigned char*)&l + f, kg_revolute_lane_field(j->blocks, j->lanes->width, block, lane, f), 4);
    }
    return l;
}

/* Each colour's active joints: its revolute ones into blocks of lanes (the world's slot
 * the still body), the others listed. */
static void kg_joints_plan_lanes(struct kg_joints* j, kg_u32 still)
{
    int width = j->lanes->width, block = 0, other = 0;
    kg_revolute_lanes padding;
    memset(&padding, 0, sizeof padding);
    padding.a = still;
    padding.b = still;
    for (int c = 0; c < KG_JOINT_COLORS; ++c) {
        j->block_start[c] = block;
        j->other_start[c] = other;
        int lane = 0;
        for (int k = j->color_start[c]; k < j->color_start[c + 1]; ++k) {
            const kg_joint_row* r = &j->rows[j->order[k]];
            if (!r->active) {
                continue;
            }
            if (r->type != KG_JOINT_ROW_REVOLUTE) {
                j->others[other++] = j->order[k];
                continue;
            }
            kg_revolute_lanes l = kg_revolute_lanes_of(r);
            l.a = l.a != KG_NULL_INDEX ? l.a : still;
            l.b = l.b != KG_NULL_INDEX ? l.b : still;
            kg_revolute_to_lane(j, block, lane, &l);
            j->lane_joint[block * width + lane] = j->order[k];
            if (++lane == width) {
                lane = 0;
                block += 1;
            }
        }
        for (; lane > 0 && lane < width; ++lane) {
            kg_revolute_to_lane(j, block, lane, &padding);
            j->lane_joint[block * width + lane] = -1;
        }
        block += lane > 0 ? 1 : 0;
    }
    j->block_start[KG_JOINT_COLORS] = block;
    j->other_start[KG_JOINT_COLORS] = other;
}

void kg_joints_prepare(kg_world* world, const kg_solver_body* bodies, kg_solver_params prm,
                       const kg_contact_rows* lanes, kg_u32 still)
{
    struct kg_joints* j = world->joints;
    if (!j || j->count == 0) {
        return;
    }
    kg_joints_derive(j, world->def.max_bodies);
    const kg_body_pool* p = &world->bodies;
    for (int i = 0; i < j->high_water; ++i) {
        if (j->info[i].alive) {
            kg_joint_prepare(j->rows, i, bodies, p->inv_mass, p->inv_inertia, p->center, p->rot, p->local_center, prm);
        }
    }
    j->lanes = kg_joints_reserve_lanes(j, lanes->width) ? lanes : NULL;
    if (!j->lanes) {
        kg_warn_once("joint-lanes", "out of memory for the joints' lanes: joints solved one at a time");
        return;
    }
    kg_joints_plan_lanes(j, still);
}

void kg_joints_finish(kg_world* world)
{
    struct kg_joints* j = world->joints;
    if (!j || j->count == 0 || !j->lanes) {
        return;
    }
    int width = j->lanes->width;
    for (int k = 0; k < j->block_start[KG_JOINT_COLORS] * width; ++k) {
        if (j->lane_joint[k] >= 0) {
            kg_revolute_lanes l = kg_revolute_of_lane(j, k / width, k % width);
            kg_revolute_keep(&j->rows[j->lane_joint[k]], &l);
        }
    }
}

/* Joints of a colour, or of the overflow: order[begin, end) of them. They share no body
 * (but the overflow's, run serially), so any split of them across threads computes the
 * same bits. */
typedef struct kg_joint_job {
    const kg_i32* order;
    kg_joint_row* rows;
    kg_solver_body* bodies;
    kg_solver_params prm;
    int pass;
    int last_iteration;
    const kg_contact_rows* lanes; /* blocks [begin, end) of revolute joints in `blocks` */
    void* blocks;
} kg_joint_job;

static void kg_joint_range(void* context, int begin, int end)
{
    const kg_joint_job* job = context;
    kg_joint_share(0, 1, job->order, begin, end, 0, job->rows, job->bodies, job->prm, job->pass,
                   job->last_iteration);
}

static void kg_revolute_range(void* context, int begin, int end)
{
    const kg_joint_job* job = context;
    job->lanes->run_revolute(job->blocks, begin, end, job->bodies, job->prm, job->pass, job->last_iteration);
}

/* Joints a thread takes at a time within a colour. */
#define KG_JOINT_GRAIN 32

/* Colour c's joints through one pass: its revolute joints' blocks, then its others; or,
 * without lanes, all of them one at a time. */
static void kg_joints_color_pass(kg_world* world, struct kg_joints* j, int c, kg_joint_job job)
{
    const kg_i32* singles = j->order; /* the joints solved one at a time */
    const int* single_start = j->color_start;
    if (j->lanes) {
        int width = j->lanes->width, first = j->block_start[c], blocks = j->block_start[c + 1] - first;
        if (blocks > 0) {
            job.blocks = (unsigned char*)j->blocks + (size_t)first * width * sizeof(kg_revolute_lanes);
            kg_parallel_for(world->threads, blocks, (KG_JOINT_GRAIN + width - 1) / width, kg_revolute_range, &job);
        }
        singles = j->others;
        single_start = j->other_start;
    }
    job.order = singles + single_start[c];
    int n = single_start[c + 1] - single_start[c];
    if (n > 0) {
        kg_parallel_for(world->threads, n, KG_JOINT_GRAIN, kg_joint_range, &job);
    }
}

void kg_joints_pass(kg_world* world, kg_solver_body* bodies, kg_solver_params prm, int pass)
{
    struct kg_joints* j = world->joints;
    if (!j || j->count == 0) {
        return;
    }
    int iterations = pass == KG_PASS_WARM_START ? 1 : j->iterations;
    for (int it = 0; it < iterations; ++it) {
        int last = it == iterations - 1;
        kg_joint_job job = {j->order, j->rows, bodies, prm, pass, last, j->lanes, NULL};
        for (int c = 0; c < KG_JOINT_COLORS; ++c) {
            kg_joints_color_pass(world, j, c, job);
        }
        /* the overflow, serially, in order */
        kg_joint_range(&job, j->color_start[KG_JOINT_COLORS], j->color_start[KG_JOINT_COLORS + 1]);
    }
}

const kg_i32* kg_joints_order(kg_world* world, int color_start[KG_JOINT_COLORS + 2])
{
    struct kg_joints* j = world->joints;
    memset(color_start, 0, (KG_JOINT_COLORS + 2) * sizeof *color_start);
    if (!j || j->count == 0) {
        return NULL;
    }
    kg_joints_derive(j, world->def.max_bodies);
    memcpy(color_start, j->color_start, sizeof j->color_start);
    return j->order;
}

/* ---- getters and setters ------------------------------------------------------------ */

/* The row of a live joint for reading, or NULL with the error set. */
static const kg_joint_row* kg_read_joint(const kg_world* world, kg_joint joint, const void* out)
{
    if (!out) {
        kg_fail(KG_ERROR_INVALID_ARGUMENT, "NULL output pointer");
        return NULL;
    }
    int i = kg_joint_resolve(world, joint);
    return i < 0 ? NULL : &world->joints->rows[i];
}

/* The row of a live joint of type for changing (its bodies woken), or NULL. */
static kg_joint_row* kg_write_joint(kg_world* world, kg_joint joint, kg_i32 type, const char* call)
{
    if (kg_world_refuses(world, call, KG_LOCK_ALL)) {
        return NULL;
    }
    int i = kg_joint_resolve(world, joint);
    if (i < 0) {
        return NULL;
    }
    kg_joint_row* r = &world->joints->rows[i];
    if (type >= 0 && r->type != type) {
        kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: the joint is of another type", call);
        return NULL;
    }
    kg_wake_joint_bodies(world, r);
    return r;
}

kg_result kg_joint_local_point(const kg_world* world, kg_body body, kg_vec2 world_point, kg_vec2* out)
{
    if (!out || !kg_finite2(world_point)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_joint_local_point: NULL output or non-finite point");
    }
    if (kg_is_null_body(body)) {
        *out = world_point;
        return KG_OK;
    }
    int i = kg_world_resolve(world, body);
    if (i < 0) {
        return kg_last_result();
    }
    *out = kg_xf_inv_point(kg_world_read_pool(world)->xf[i], world_point);
    return KG_OK;
}

kg_result kg_joint_get_type(const kg_world* world, kg_joint joint, kg_joint_type* out)
{
    const kg_joint_row* r = kg_read_joint(world, joint, out);
    if (!r) {
        return kg_last_result();
    }
    *out = (kg_joint_type)r->type;
    return KG_OK;
}

kg_result kg_joint_get_bodies(const kg_world* world, kg_joint joint, kg_body* body_a, kg_body* body_b)
{
    const kg_joint_row* r = kg_read_joint(world, joint, body_a && body_b ? body_a : NULL);
    if (!r) {
        return kg_last_result();
    }
    *body_a = kg_body_handle(world, r->a);
    *body_b = kg_body_handle(world, r->b);
    return KG_OK;
}

kg_result kg_joint_get_world_anchors(const kg_world* world, kg_joint joint, kg_vec2* anchor_a, kg_vec2* anchor_b)
{
    const kg_joint_row* r = kg_read_joint(world, joint, anchor_a && anchor_b ? anchor_a : NULL);
    if (!r) {
        return kg_last_result();
    }
    const kg_body_pool* p = kg_world_read_pool(world);
    *anchor_a = r->a == KG_NULL_INDEX ? r->local_a : kg_xf_point(p->xf[r->a], r->local_a);
    *anchor_b = kg_xf_point(p->xf[r->b], r->local_b);
    return KG_OK;
}

kg_result kg_joint_get_reaction(const kg_world* world, kg_joint joint, kg_vec2* force, float* torque)
{
    const kg_joint_row* r = kg_read_joint(world, joint, force && torque ? force : NULL);
    if (!r) {
        return kg_last_result();
    }
    kg_reaction_of(world, r, force, torque);
    return KG_OK;
}

void* kg_joint_get_user_data(const kg_world* world, kg_joint joint)
{
    int i = kg_joint_resolve(world, joint);
    return i < 0 ? NULL : world->joints->info[i].user_data;
}

kg_result kg_joint_set_user_data(kg_world* world, kg_joint joint, void* user_data)
{
    int i = kg_joint_resolve(world, joint);
    if (i < 0) {
        return kg_last_result();
    }
    world->joints->info[i].user_data = user_data;
    return KG_OK;
}

kg_result kg_joint_set_collide_connected(kg_world* world, kg_joint joint, int collide)
{
    if (!kg_write_joint(world, joint, -1, "kg_joint_set_collide_connected")) {
        return kg_last_result();
    }
    world->joints->info[joint.index].collide_connected = collide != 0;
    world->joints->derived_stale = 1;
    world->joints->version += 1;
    return KG_OK;
}

kg_result kg_joint_set_break_thresholds(kg_world* world, kg_joint joint, float break_force, float break_torque)
{
    const char* call = "kg_joint_set_break_thresholds";
    if (!kg_nonneg(break_force) || !kg_nonneg(break_torque)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: thresholds must be finite and >= 0", call);
    }
    if (!kg_write_joint(world, joint, -1, call)) {
        return kg_last_result();
    }
    kg_joint_info* info = &world->joints->info[joint.index];
    info->break_force = break_force;
    info->break_torque = break_torque;
    world->joints->breakable |= break_force > 0.0f || break_torque > 0.0f;
    return KG_OK;
}

kg_result kg_joint_wake(kg_world* world, kg_joint joint)
{
    return kg_write_joint(world, joint, -1, "kg_joint_wake") ? KG_OK : kg_last_result();
}

kg_result kg_revolute_joint_set_limits(kg_world* world, kg_joint joint, int enable, float lower, float upper)
{
    const char* call = "kg_revolute_joint_set_limits";
    kg_result res = kg_check_angles(enable, lower, upper, call);
    kg_joint_row* r = res == KG_OK ? kg_write_joint(world, joint, KG_JOINT_ROW_REVOLUTE, call) : NULL;
    if (!r) {
        return kg_last_result();
    }
    r->options = (r->options & ~KG_JOINT_OPT_LIMIT) | kg_option(enable, KG_JOINT_OPT_LIMIT);
    r->lower = lower;
    r->upper = upper;
    if (!enable) {
        r->lower_impulse = r->upper_impulse = 0.0f;
    }
    return KG_OK;
}

kg_result kg_revolute_joint_set_motor(kg_world* world, kg_joint joint, int enable, float speed, float max_torque)
{
    const char* call = "kg_revolute_joint_set_motor";
    kg_result res = kg_check_motor(speed, max_torque, call);
    kg_joint_row* r = res == KG_OK ? kg_write_joint(world, joint, KG_JOINT_ROW_REVOLUTE, call) : NULL;
    if (!r) {
        return kg_last_result();
    }
    r->options = (r->options & ~KG_JOINT_OPT_MOTOR) | kg_option(enable, KG_JOINT_OPT_MOTOR);
    r->motor_speed = speed;
    r->max_motor_torque = max_torque;
    if (!enable) {
        r->motor_impulse = 0.0f;
    }
    return KG_OK;
}

kg_result kg_revolute_joint_set_spring(kg_world* world, kg_joint joint, int enable, float hertz, float damping_ratio)
{
    const char* call = "kg_revolute_joint_set_spring";
    kg_result res = kg_check_spring(hertz, damping_ratio, call);
    kg_joint_row* r = res == KG_OK ? kg_write_joint(world, joint, KG_JOINT_ROW_REVOLUTE, call) : NULL;
    if (!r) {
        return kg_last_result();
    }
    r->options = (r->options & ~KG_JOINT_OPT_SPRING) | kg_option(enable, KG_JOINT_OPT_SPRING);
    r->hertz = hertz;
    r->damping_ratio = damping_ratio;
    if (!enable) {
        r->spring_impulse = 0.0f;
    }
    return KG_OK;
}

kg_result kg_revolute_joint_get_angle(const kg_world* world, kg_joint joint, float* out)
{
    const kg_joint_row* r = kg_read_joint(world, joint, out);
    if (!r) {
        return kg_last_result();
    }
    if (r->type != KG_JOINT_ROW_REVOLUTE) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_revolute_joint_get_angle: not a revolute joint");
    }
    const kg_body_pool* p = kg_world_read_pool(world);
    kg_rot qa = r->a == KG_NULL_INDEX ? kg_rot_identity() : p->rot[r->a];
    *out = kg_unwind_angle(kg_relative_angle(p->rot[r->b], qa) - r->reference_angle);
    return KG_OK;
}

kg_result kg_distance_joint_set_length(kg_world* world, kg_joint joint, float length)
{
    const char* call = "kg_distance_joint_set_length";
    if (!isfinite(length) || length <= 0.0f) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: length must be finite and > 0", call);
    }
    kg_joint_row* r = kg_write_joint(world, joint, KG_JOINT_ROW_DISTANCE, call);
    if (!r) {
        return kg_last_result();
    }
    r->length = length;
    return KG_OK;
}

kg_result kg_distance_joint_set_limits(kg_world* world, kg_joint joint, int enable, float min_length,
                                       float max_length)
{
    const char* call = "kg_distance_joint_set_limits";
    kg_result res = kg_check_lengths(min_length, max_length, call);
    kg_joint_row* r = res == KG_OK ? kg_write_joint(world, joint, KG_JOINT_ROW_DISTANCE, call) : NULL;
    if (!r) {
        return kg_last_result();
    }
    r->options = (r->options & ~KG_JOINT_OPT_LIMIT) | kg_option(enable, KG_JOINT_OPT_LIMIT);
    r->lower = min_length;
    r->upper = max_length;
    return KG_OK;
}

kg_result kg_distance_joint_set_spring(kg_world* world, kg_joint joint, int enable, float hertz, float damping_ratio)
{
    const char* call = "kg_distance_joint_set_spring";
    kg_result res = kg_check_spring(hertz, damping_ratio, call);
    kg_joint_row* r = res == KG_OK ? kg_write_joint(world, joint, KG_JOINT_ROW_DISTANCE, call) : NULL;
    if (!r) {
        return kg_last_result();
    }
    r->options = (r->options & ~KG_JOINT_OPT_SPRING) | kg_option(enable, KG_JOINT_OPT_SPRING);
    r->hertz = hertz;
    r->damping_ratio = damping_ratio;
    return KG_OK;
}

kg_result kg_weld_joint_set_stiffness(kg_world* world, kg_joint joint, float linear_hertz, float linear_damping_ratio,
                                      float angular_hertz, float angular_damping_ratio)
{
    const char* call = "kg_weld_joint_set_stiffness";
    kg_result res = kg_check_spring(linear_hertz, linear_damping_ratio, call);
    if (res == KG_OK) {
        res = kg_check_spring(angular_hertz, angular_damping_ratio, call);
    }
    kg_joint_row* r = res == KG_OK ? kg_write_joint(world, joint, KG_JOINT_ROW_WELD, call) : NULL;
    if (!r) {
        return kg_last_result();
    }
    r->hertz = linear_hertz;
    r->damping_ratio = linear_damping_ratio;
    r->hertz2 = angular_hertz;
    r->damping_ratio2 = angular_damping_ratio;
    return KG_OK;
}

/* The shared setters of the kinds along an axis. */
static kg_result kg_axis_set_limits(kg_world* world, kg_joint joint, kg_i32 type, const char* call, int enable,
                                    float lower, float upper)
{
    kg_result res = kg_check_translations(lower, upper, call);
    kg_joint_row* r = res == KG_OK ? kg_write_joint(world, joint, type, call) : NULL;
    if (!r) {
        return kg_last_result();
    }
    r->options = (r->options & ~KG_JOINT_OPT_LIMIT) | kg_option(enable, KG_JOINT_OPT_LIMIT);
    r->lower = lower;
    r->upper = upper;
    if (!enable) {
        r->lower_impulse = r->upper_impulse = 0.0f;
    }
    return KG_OK;
}

static kg_result kg_axis_set_motor(kg_world* world, kg_joint joint, kg_i32 type, const char* call, int enable,
                                   float speed, float most)
{
    kg_result res = kg_check_motor(speed, most, call);
    kg_joint_row* r = res == KG_OK ? kg_write_joint(world, joint, type, call) : NULL;
    if (!r) {
        return kg_last_result();
    }
    r->options = (r->options & ~KG_JOINT_OPT_MOTOR) | kg_option(enable, KG_JOINT_OPT_MOTOR);
    r->motor_speed = speed;
    r->max_motor_torque = most;
    if (!enable) {
        r->motor_impulse = 0.0f;
    }
    return KG_OK;
}

static kg_result kg_axis_set_spring(kg_world* world, kg_joint joint, kg_i32 type, const char* call, int enable,
                                    float hertz, float damping_ratio)
{
    kg_result res = kg_check_spring(hertz, damping_ratio, call);
    kg_joint_row* r = res == KG_OK ? kg_write_joint(world, joint, type, call) : NULL;
    if (!r) {
        return kg_last_result();
    }
    r->options = (r->options & ~KG_JOINT_OPT_SPRING) | kg_option(enable, KG_JOINT_OPT_SPRING);
    r->hertz = hertz;
    r->damping_ratio = damping_ratio;
    if (!enable) {
        r->spring_impulse = 0.0f;
    }
    return KG_OK;
}

kg_result kg_prismatic_joint_set_limits(kg_world* world, kg_joint joint, int enable, float lower, float upper)
{
    return kg_axis_set_limits(world, joint, KG_JOINT_ROW_PRISMATIC, "kg_prismatic_joint_set_limits", enable, lower,
                              upper);
}

kg_result kg_prismatic_joint_set_motor(kg_world* world, kg_joint joint, int enable, float speed, float max_force)
{
    return kg_axis_set_motor(world, joint, KG_JOINT_ROW_PRISMATIC, "kg_prismatic_joint_set_motor", enable, speed,
                             max_force);
}

kg_result kg_prismatic_joint_set_spring(kg_world* world, kg_joint joint, int enable, float hertz, float damping_ratio)
{
    return kg_axis_set_spring(world, joint, KG_JOINT_ROW_PRISMATIC, "kg_prismatic_joint_set_spring", enable, hertz,
                              damping_ratio);
}

kg_result kg_wheel_joint_set_limits(kg_world* world, kg_joint joint, int enable, float lower, float upper)
{
    return kg_axis_set_limits(world, joint, KG_JOINT_ROW_WHEEL, "kg_wheel_joint_set_limits", enable, lower, upper);
}

kg_result kg_wheel_joint_set_motor(kg_world* world, kg_joint joint, int enable, float speed, float max_torque)
{
    return kg_axis_set_motor(world, joint, KG_JOINT_ROW_WHEEL, "kg_wheel_joint_set_motor", enable, speed, max_torque);
}

kg_result kg_wheel_joint_set_spring(kg_world* world, kg_joint joint, int enable, float hertz, float damping_ratio)
{
    return kg_axis_set_spring(world, joint, KG_JOINT_ROW_WHEEL, "kg_wheel_joint_set_spring", enable, hertz,
                              damping_ratio);
}

/* A prismatic or wheel joint's axis in world axes now. */
static kg_vec2 kg_world_axis(const kg_body_pool* p, const kg_joint_row* r)
{
    return kg_rotate(r->a == KG_NULL_INDEX ? kg_rot_identity() : p->rot[r->a], r->local_axis);
}

kg_result kg_joint_get_translation(const kg_world* world, kg_joint joint, float* out)
{
    const kg_joint_row* r = kg_read_joint(world, joint, out);
    if (!r) {
        return kg_last_result();
    }
    if (r->type != KG_JOINT_ROW_PRISMATIC && r->type != KG_JOINT_ROW_WHEEL) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_joint_get_translation: not a prismatic or wheel joint");
    }
    const kg_body_pool* p = kg_world_read_pool(world);
    kg_vec2 a = r->a == KG_NULL_INDEX ? r->local_a : kg_xf_point(p->xf[r->a], r->local_a);
    kg_vec2 b = kg_xf_point(p->xf[r->b], r->local_b);
    *out = kg_dot(kg_sub(b, a), kg_world_axis(p, r));
    return KG_OK;
}

kg_result kg_joint_get_world_axis(const kg_world* world, kg_joint joint, kg_vec2* out)
{
    const kg_joint_row* r = kg_read_joint(world, joint, out);
    if (!r) {
        return kg_last_result();
    }
    if (r->type != KG_JOINT_ROW_PRISMATIC && r->type != KG_JOINT_ROW_WHEEL) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "kg_joint_get_world_axis: not a prismatic or wheel joint");
    }
    *out = kg_world_axis(kg_world_read_pool(world), r);
    return KG_OK;
}

kg_result kg_motor_joint_set_offsets(kg_world* world, kg_joint joint, kg_vec2 linear_offset, float angular_offset)
{
    const char* call = "kg_motor_joint_set_offsets";
    if (!kg_finite2(linear_offset) || !isfinite(angular_offset)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: offsets must be finite", call);
    }
    kg_joint_row* r = kg_write_joint(world, joint, KG_JOINT_ROW_MOTOR, call);
    if (!r) {
        return kg_last_result();
    }
    r->local_a = linear_offset;
    r->reference_angle = angular_offset;
    return KG_OK;
}

kg_result kg_motor_joint_set_max(kg_world* world, kg_joint joint, float max_force, float max_torque)
{
    const char* call = "kg_motor_joint_set_max";
    if (!kg_nonneg(max_force) || !kg_nonneg(max_torque)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: max_force and max_torque must be finite and >= 0", call);
    }
    kg_joint_row* r = kg_write_joint(world, joint, KG_JOINT_ROW_MOTOR, call);
    if (!r) {
        return kg_last_result();
    }
    r->max_force = max_force;
    r->max_motor_torque = max_torque;
    return KG_OK;
}

kg_result kg_mouse_joint_set_target(kg_world* world, kg_joint joint, kg_vec2 target)
{
    const char* call = "kg_mouse_joint_set_target";
    if (!kg_finite2(target)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: target must be finite", call);
    }
    kg_joint_row* r = kg_write_joint(world, joint, KG_JOINT_ROW_MOUSE, call);
    if (!r) {
        return kg_last_result();
    }
    r->local_a = target;
    return KG_OK;
}

kg_result kg_mouse_joint_set_max_force(kg_world* world, kg_joint joint, float max_force)
{
    const char* call = "kg_mouse_joint_set_max_force";
    if (!kg_nonneg(max_force)) {
        return kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: max_force must be finite and >= 0", call);
    }
    kg_joint_row* r = kg_write_joint(world, joint, KG_JOINT_ROW_MOUSE, call);
    if (!r) {
        return kg_last_result();
    }
    r->max_force = max_force;
    return KG_OK;
}

/* ---- definitions as they are now (kg_*_joint_get_def) ----------------------------------- */

/* The row of a live joint of type for reading its definition, or NULL (error set). */
static const kg_joint_row* kg_read_def(const kg_world* world, kg_joint joint, kg_i32 type, const void* out,
                                       const char* call)
{
    const kg_joint_row* r = kg_read_joint(world, joint, out);
    if (r && r->type != type) {
        kg_fail(KG_ERROR_INVALID_ARGUMENT, "%s: the joint is of another type", call);
        return NULL;
    }
    return r;
}

/* What every kind's definition shares, from row r of joint. */
static kg_joint_base_def kg_base_of(const kg_world* world, kg_joint joint, const kg_joint_row* r)
{
    const kg_joint_info* info = &world->joints->info[joint.index];
    kg_joint_base_def base = kg_default_base();
    base.body_a = kg_body_handle(world, r->a);
    base.body_b = kg_body_handle(world, r->b);
    base.collide_connected = info->collide_connected;
    base.constraint_hertz = r->constraint_hertz;
    base.constraint_damping_ratio = r->constraint_damping_ratio;
    base.break_force = info->break_force;
    base.break_torque = info->break_torque;
    base.user_data = info->user_data;
    return base;
}

static int kg_has_option(const kg_joint_row* r, kg_u32 bit) { return (r->options & bit) != 0u; }

kg_result kg_revolute_joint_get_def(const kg_world* world, kg_joint joint, kg_revolute_joint_def* out)
{
    const kg_joint_row* r = kg_read_def(world, joint, KG_JOINT_ROW_REVOLUTE, out, "kg_revolute_joint_get_def");
    if (!r) {
        return kg_last_result();
    }
    *out = kg_default_revolute_joint_def();
    out->base = kg_base_of(world, joint, r);
    out->local_anchor_a = r->local_a;
    out->local_anchor_b = r->local_b;
    out->reference_angle = r->reference_angle;
    out->enable_limit = kg_has_option(r, KG_JOINT_OPT_LIMIT);
    out->lower_angle = r->lower;
    out->upper_angle = r->upper;
    out->enable_motor = kg_has_option(r, KG_JOINT_OPT_MOTOR);
    out->motor_speed = r->motor_speed;
    out->max_motor_torque = r->max_motor_torque;
    out->enable_spring = kg_has_option(r, KG_JOINT_OPT_SPRING);
    out->hertz = r->hertz;
    out->damping_ratio = r->damping_ratio;
    return KG_OK;
}

kg_result kg_distance_joint_get_def(const kg_world* world, kg_joint joint, kg_distance_joint_def* out)
{
    const kg_joint_row* r = kg_read_def(world, joint, KG_JOINT_ROW_DISTANCE, out, "kg_distance_joint_get_def");
    if (!r) {
        return kg_last_result();
    }
    *out = kg_default_distance_joint_def();
    out->base = kg_base_of(world, joint, r);
    out->local_anchor_a = r->local_a;
    out->local_anchor_b = r->local_b;
    out->length = r->length;
    out->enable_spring = kg_has_option(r, KG_JOINT_OPT_SPRING);
    out->hertz = r->hertz;
    out->damping_ratio = r->damping_ratio;
    out->enable_limit = kg_has_option(r, KG_JOINT_OPT_LIMIT);
    out->min_length = r->lower;
    out->max_length = r->upper;
    return KG_OK;
}

kg_result kg_weld_joint_get_def(const kg_world* world, kg_joint joint, kg_weld_joint_def* out)
{
    const kg_joint_row* r = kg_read_def(world, joint, KG_JOINT_ROW_WELD, out, "kg_weld_joint_get_def");
    if (!r) {
        return kg_last_result();
    }
    *out = kg_default_weld_joint_def();
    out->base = kg_base_of(world, joint, r);
    out->local_anchor_a = r->local_a;
    out->local_anchor_b = r->local_b;
    out->reference_angle = r->reference_angle;
    out->linear_hertz = r->hertz;
    out->linear_damping_ratio = r->damping_ratio;
    out->angular_hertz = r->hertz2;
    out->angular_damping_ratio = r->damping_ratio2;
    return KG_OK;
}

kg_result kg_mouse_joint_get_def(const kg_world* world, kg_joint joint, kg_mouse_joint_def* out)
{
    const kg_joint_row* r = kg_read_def(world, joint, KG_JOINT_ROW_MOUSE, out, "kg_mouse_joint_get_def");
    if (!r) {
        return kg_last_result();
    }
    *out = kg_default_mouse_joint_def();
    out->base = kg_base_of(world, joint, r);
    out->target = r->local_a;
    out->local_anchor_b = r->local_b;
    out->hertz = r->hertz;
    out->damping_ratio = r->damping_ratio;
    out->max_force = r->max_force;
    return KG_OK;
}

kg_result kg_prismatic_joint_get_def(const kg_world* world, kg_joint joint, kg_prismatic_joint_def* out)
{
    const kg_joint_row* r = kg_read_def(world, joint, KG_JOINT_ROW_PRISMATIC, out, "kg_prismatic_joint_get_def");
    if (!r) {
        return kg_last_result();
    }
    *out = kg_default_prismatic_joint_def();
    out->base = kg_base_of(world, joint, r);
    out->local_anchor_a = r->local_a;
    out->local_anchor_b = r->local_b;
    out->local_axis_a = r->local_axis;
    out->reference_angle = r->reference_angle;
    out->enable_limit = kg_has_option(r, KG_JOINT_OPT_LIMIT);
    out->lower_translation = r->lower;
    out->upper_translation = r->upper;
    out->enable_motor = kg_has_option(r, KG_JOINT_OPT_MOTOR);
    out->motor_speed = r->motor_speed;
    out->max_motor_force = r->max_motor_torque;
    out->enable_spring = kg_has_option(r, KG_JOINT_OPT_SPRING);
    out->hertz = r->hertz;
    out->damping_ratio = r->damping_ratio;
    return KG_OK;
}

kg_result kg_wheel_joint_get_def(const kg_world* world, kg_joint joint, kg_wheel_joint_def* out)
{
    const kg_joint_row* r = kg_read_def(world, joint, KG_JOINT_ROW_WHEEL, out, "kg_wheel_joint_get_def");
    if (!r) {
        return kg_last_result();
    }
    *out = kg_default_wheel_joint_def();
    out->base = kg_base_of(world, joint, r);
    out->local_anchor_a = r->local_a;
    out->local_anchor_b = r->local_b;
    out->local_axis_a = r->local_axis;
    out->enable_limit = kg_has_option(r, KG_JOINT_OPT_LIMIT);
    out->lower_translation = r->lower;
    out->upper_translation = r->upper;
    out->enable_motor = kg_has_option(r, KG_JOINT_OPT_MOTOR);
    out->motor_speed = r->motor_speed;
    out->max_motor_torque = r->max_motor_torque;
    out->enable_spring = kg_has_option(r, KG_JOINT_OPT_SPRING);
    out->hertz = r->hertz;
    out->damping_ratio = r->damping_ratio;
    return KG_OK;
}

kg_result kg_motor_joint_get_def(const kg_world* world, kg_joint joint, kg_motor_joint_def* out)
{
    const kg_joint_row* r = kg_read_def(world, joint, KG_JOINT_ROW_MOTOR, out, "kg_motor_joint_get_def");
    if (!r) {
        return kg_last_result();
    }
    *out = kg_default_motor_joint_def();
    out->base = kg_base_of(world, joint, r);
    out->linear_offset = r->local_a;
    out->angular_offset = r->reference_angle;
    out->max_force = r->max_force;
    out->max_torque = r->max_motor_torque;
    out->correction_factor = r->length;
    return KG_OK;
}

/* ---- snapshots (core/snapshot_io.h) ---------------------------------------------------- */

/* Whether the pool has any joint slot (a world without joints writes a 0 and no more). */
static int kg_joints_present(const struct kg_joints* j) { return j && j->capacity > 0; }

void kg_joints_snapshot(const kg_world* world, kg_snap_out* out)
{
    const struct kg_joints* j = world->joints;
    kg_snap_put_i32(out, kg_joints_present(j) ? j->capacity : 0);
    if (!kg_joints_present(j)) {
        return;
    }
    kg_snap_put_i32(out, j->high_water);
    kg_snap_put_i32(out, j->count);
    kg_snap_put_u32(out, j->tag);
    kg_snap_put_i32(out, j->breakable);
    kg_snap_put_i32(out, j->iterations);
    kg_snap_put(out, j->info, (size_t)j->capacity * sizeof *j->info); /* every slot's generation */
    kg_snap_put(out, j->rows, (size_t)j->high_water * sizeof *j->rows);
}

void kg_joints_discard(struct kg_joints* j)
{
    if (j) {
        kg_free(j->rows);
        kg_free(j->info);
        kg_free(j->links);
        kg_free(j->apart);
        kg_free(j->order);
        kg_free(j);
    }
}

/* Whether slot i of a read pool is what the step can use: a live joint of a known kind
 * between two different bodies that are live slots of bodies (a may be the world), or a
 * free slot with no bodies. */
static int kg_joint_slot_sane(const struct kg_joints* j, const kg_body_pool* bodies, int i)
{
    const kg_joint_row* r = &j->rows[i];
    if (!j->info[i].alive) {
        return j->info[i].alive == 0 && r->a == KG_NULL_INDEX && r->b == KG_NULL_INDEX;
    }
    int a_ok = r->a == KG_NULL_INDEX || (r->a < (kg_u32)bodies->high_water && kg_pool_alive(bodies, (int)r->a));
    int b_ok = r->b < (kg_u32)bodies->high_water && kg_pool_alive(bodies, (int)r->b);
    return j->info[i].alive == 1 && a_ok && b_ok && r->a != r->b && r->type >= KG_JOINT_ROW_REVOLUTE &&
           r->type <= KG_JOINT_ROW_MOTOR;
}

/* The pool's arrays for capacity slots (rows and info read into them), or 0. */
static int kg_joints_arrays(struct kg_joints* j, int capacity)
{
    j->capacity = capacity;
    j->rows = kg_alloc_zeroed((size_t)capacity * sizeof *j->rows);
    j->info = kg_alloc_zeroed((size_t)capacity * sizeof *j->info);
    j->links = kg_alloc_zeroed((size_t)capacity * 2 * sizeof *j->links);
    j->apart = kg_alloc_zeroed((size_t)capacity * 2 * sizeof *j->apart);
    j->order = kg_alloc_zeroed((size_t)capacity * sizeof *j->order);
    return j->rows && j->info && j->links && j->apart && j->order;
}

/* Whether the read slots fit together: each sane, the live ones counted, none past
 * high_water. */
static int kg_joints_sane(const struct kg_joints* j, const kg_body_pool* bodies)
{
    int live = 0;
    for (int i = 0; i < j->capacity; ++i) {
        if (i < j->high_water ? !kg_joint_slot_sane(j, bodies, i) : j->info[i].alive != 0) {
            return 0;
        }
        live += i < j->high_water && j->info[i].alive;
    }
    return live == j->count;
}

kg_result kg_joints_from_snapshot(const kg_body_pool* bodies, kg_snap_in* in, struct kg_joints** out)
{
    *out = NULL;
    int capacity = kg_snap_take_i32(in, "joints");
    if (in->failed || capacity == 0) {
        return in->failed ? KG_ERROR_INVALID_ARGUMENT : KG_OK;
    }
    struct kg_joints* j = kg_alloc_zeroed(sizeof *j);
    if (!j) {
        return kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the joint pool");
    }
    j->high_water = kg_snap_take_i32(in, "joints");
    j->count = kg_snap_take_i32(in, "joints");
    j->tag = kg_snap_take_u32(in, "joints");
    j->breakable = kg_snap_take_i32(in, "joints");
    j->iterations = kg_snap_take_i32(in, "joints");
    if (!in->failed && (capacity < 0 || j->high_water < 0 || j->high_water > capacity || j->iterations < 1 ||
                        j->iterations > 64 || !kg_snap_has(in, sizeof(kg_joint_info), (uint64_t)capacity))) {
        kg_snap_reject(in, "joint counts");
    }
    if (!in->failed && !kg_joints_arrays(j, capacity)) {
        kg_snap_reject(in, "joints (out of memory)");
    }
    kg_snap_take_array(in, j->info, sizeof *j->info, (size_t)capacity, "joints");
    kg_snap_take_array(in, j->rows, sizeof *j->rows, (size_t)j->high_water, "joints");
    if (!in->failed && !kg_joints_sane(j, bodies)) {
        kg_snap_reject(in, "joints");
    }
    if (in->failed) {
        kg_joints_discard(j);
        return KG_ERROR_INVALID_ARGUMENT;
    }
    for (int i = j->high_water; i < capacity; ++i) { /* as a destroyed joint leaves its slot */
        j->rows[i].a = j->rows[i].b = KG_NULL_INDEX;
    }
    j->derived_stale = 1;
    *out = j;
    return KG_OK;
}

void kg_joints_adopt(kg_world* world, struct kg_joints* restored)
{
    kg_u32 version = world->joints ? world->joints->version : 0u;
    kg_joints_destroy(world);
    world->joints = restored;
    if (restored) {
        restored->version = version + 1u; /* the device's lists are sent again */
    }
}

uint64_t kg_joints_layout(uint64_t h) { return kg_snap_fold(kg_snap_fold(h, sizeof(kg_joint_row)), sizeof(kg_joint_info)); }
