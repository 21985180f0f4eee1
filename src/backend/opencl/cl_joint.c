/* Joints on the OpenCL backend (docs/joints.md): the rows live on the device during a
 * step and on the host between steps, so that a fallback redoes a step from the host's
 * copy and getters and setters need no read. In a step:
 *
 *   collide  the pairs of bodies joined by a joint that does not collide_connected make
 *            no contact (their touching flag cleared before the prefix sum)
 *   wake     a joint wakes its sleeping body's island like a contact
 *   solve    the rows written, prepared after the bodies are loaded, then each pass over
 *            the joints before the contacts': a colour's joints in parallel, the
 *            overflow's serially, as the CPU
 *   sleep    the joints' links in the islands
 *   end      the rows read back after the drain (their impulses warm start the next step)
 *
 * The links and the pairs kept apart are written when they change (kg_joints_version).
 * Every kernel is kernels/kg_joint.cl's, calling the CPU's functions. */
#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_backend.h"
#include "core/joint.h"

static const char* const kLabel = "kg_joints";

/* *buffer able to hold needed items of item bytes (at least one), grown by doubling. */
static kg_result kg_cl_fit(kg_cl_backend* b, cl_mem* buffer, int* capacity, int needed, size_t item)
{
    if (*buffer && needed <= *capacity) {
        return KG_OK;
    }
    int next = *capacity > 16 ? *capacity : 16;
    while (next < needed) {
        next *= 2;
    }
    kg_cl_release(b, buffer);
    *capacity = 0;
    KG_TRY(kg_cl_buffer(b, (size_t)next * item, buffer));
    *capacity = next;
    return KG_OK;
}

/* The links and the pairs kept apart on the device as the host's are. */
static kg_result kg_cl_joint_lists(kg_world* world, kg_cl_backend* b)
{
    if (b->joint_lists_sent && b->joint_version == kg_joints_version(world)) {
        return KG_OK;
    }
    int links = 0, apart = 0;
    const kg_u32* link_list = kg_joints_links(world, &links);
    const kg_u32* apart_list = kg_joints_apart(world, &apart);
    const kg_i32* order = kg_joints_order(world, b->joint_colors);
    int ordered = b->joint_colors[KG_JOINT_COLORS + 1];
    KG_TRY(kg_cl_fit(b, &b->joint_links, &b->joint_link_capacity, links, 2 * sizeof(kg_u32)));
    KG_TRY(kg_cl_fit(b, &b->joint_apart, &b->joint_apart_capacity, apart, 2 * sizeof(kg_u32)));
    KG_TRY(kg_cl_fit(b, &b->joint_order, &b->joint_order_capacity, ordered, sizeof(kg_i32)));
    if (!b->joint_color_start) {
        KG_TRY(kg_cl_buffer(b, sizeof b->joint_colors, &b->joint_color_start));
    }
    KG_TRY(kg_cl_write(b, b->joint_color_start, 0, sizeof b->joint_colors, b->joint_colors, 1));
    if (ordered > 0) {
        KG_TRY(kg_cl_write(b, b->joint_order, 0, (size_t)ordered * sizeof(kg_i32), order, 1));
    }
    if (links > 0) {
        KG_TRY(kg_cl_write(b, b->joint_links, 0, (size_t)links * 2 * sizeof(kg_u32), link_list, 1));
    }
    if (apart > 0) {
        KG_TRY(kg_cl_write(b, b->joint_apart, 0, (size_t)apart * 2 * sizeof(kg_u32), apart_list, 1));
    }
    b->joint_link_count = links;
    b->joint_apart_count = apart;
    b->joint_version = kg_joints_version(world);
    b->joint_lists_sent = 1;
    return KG_OK;
}

kg_result kg_cl_drop_joined(kg_world* world, kg_cl_backend* b, cl_mem pairs, int count, int shape_pairs,
                            cl_mem touching)
{
    if (kg_joints_live(world) == 0 || count == 0) {
        return KG_OK;
    }
    KG_TRY(kg_cl_joint_lists(world, b));
    if (b->joint_apart_count == 0) {
        return KG_OK;
    }
    if (shape_pairs) {
        KG_LAUNCH(b, DROP_JOINED_SHAPE_PAIRS, count, "kg_narrowphase", KG_INT(count), KG_MEM(pairs),
                  KG_MEM(b->joint_apart), KG_INT(b->joint_apart_count), KG_MEM(touching));
    } else {
        KG_LAUNCH(b, DROP_JOINED_PAIRS, count, "kg_narrowphase", KG_INT(count), KG_MEM(pairs), KG_MEM(b->joint_apart),
                  KG_INT(b->joint_apart_count), KG_MEM(touching));
    }
    return KG_OK;
}

kg_result kg_cl_wake_joined(kg_world* world, kg_cl_backend* b)
{
    if (kg_joints_live(world) == 0) {
        return KG_OK;
    }
    KG_TRY(kg_cl_joint_lists(world, b));
    int links = b->joint_link_count;
    if (links > 0) {
        KG_LAUNCH(b, WAKE_JOINED, links, "kg_sleep", KG_INT(links), KG_MEM(b->joint_links), KG_MEM(KG_A(FLAGS)),
                  KG_MEM(KG_A(VELOCITY)), KG_MEM(KG_A(OMEGA)), KG_MEM(KG_A(ISLAND)), KG_MEM(b->wake_marks));
    }
    return KG_OK;
}

int kg_cl_joint_links(kg_world* world, kg_cl_backend* b)
{
    if (kg_joints_live(world) == 0 || kg_cl_joint_lists(world, b) != KG_OK) {
        return 0;
    }
    return b->joint_link_count;
}

kg_result kg_cl_prepare_joints(kg_world* world, kg_cl_backend* b)
{
    int slots = 0;
    const kg_joint_row* rows = kg_joints_rows(world, &slots);
    b->joint_slots = slots;
    if (slots == 0) {
        return KG_OK;
    }
    KG_TRY(kg_cl_joint_lists(world, b)); /* the order */
    KG_TRY(kg_cl_fit(b, &b->joint_rows, &b->joint_row_capacity, slots, sizeof(kg_joint_row)));
    KG_TRY(kg_cl_write(b, b->joint_rows, 0, (size_t)slots * sizeof(kg_joint_row), rows, 1));
    KG_LAUNCH(b, PREPARE_JOINTS, slots, kLabel, KG_INT(slots), KG_MEM(b->solver_params), KG_MEM(b->joint_rows),
              KG_MEM(b->solver_bodies), KG_MEM(KG_A(INV_MASS)), KG_MEM(KG_A(INV_INERTIA)), KG_MEM(KG_A(CENTER)),
              KG_MEM(KG_A(ROT)), KG_MEM(KG_A(LOCAL_CENTER)));
    return KG_OK;
}

kg_result kg_cl_solve_joints(kg_world* world, kg_cl_backend* b, int pass)
{
    const int* start = b->joint_colors;
    if (b->joint_slots == 0 || start[KG_JOINT_COLORS + 1] == 0) {
        return KG_OK;
    }
    int iterations = pass == KG_PASS_WARM_START ? 1 : kg_world_get_joint_iterations(world);
    if (start[KG_JOINT_COLORS + 1] <= b->joint_group_max) { /* few: the pass in one launch */
        KG_LAUNCH(b, SOLVE_JOINT_COLORS_IN_GROUP, (int)b->group_size[KG_CL_K_SOLVE_JOINT_COLORS_IN_GROUP], kLabel,
                  KG_INT(iterations), KG_INT(pass), KG_MEM(b->joint_color_start), KG_MEM(b->solver_params),
                  KG_MEM(b->joint_order), KG_MEM(b->joint_rows), KG_MEM(b->solver_bodies));
        return KG_OK;
    }
    for (int it = 0; it < iterations; ++it) {
        for (int c = 0; c <= KG_JOINT_COLORS; ++c) {
            int serial = c == KG_JOINT_COLORS, count = start[c + 1] - start[c];
            int items = serial ? 1 : count < b->joint_color_items ? count : b->joint_color_items;
            if (count > 0) {
                KG_LAUNCH(b, SOLVE_JOINT_COLOR, items, kLabel, KG_INT(start[c]), KG_INT(count),
                          KG_INT(serial), KG_INT(pass), KG_INT(it == iterations - 1), KG_MEM(b->solver_params),
                          KG_MEM(b->joint_order),
                          KG_MEM(b->joint_rows), KG_MEM(b->solver_bodies));
            }
        }
    }
    return KG_OK;
}

kg_result kg_cl_joints_to_host(kg_world* world, kg_cl_backend* b)
{
    int slots = 0;
    kg_joint_row* rows = kg_joints_rows(world, &slots);
    if (b->joint_slots == 0 || slots < b->joint_slots) {
        return KG_OK; /* no joint solved this step */
    }
    return kg_cl_read(b, b->joint_rows, 0, (size_t)b->joint_slots * sizeof(kg_joint_row), rows);
}

void kg_cl_release_joints(kg_cl_backend* b)
{
    kg_cl_release(b, &b->joint_rows);
    kg_cl_release(b, &b->joint_links);
    kg_cl_release(b, &b->joint_apart);
    kg_cl_release(b, &b->joint_order);
    kg_cl_release(b, &b->joint_color_start);
    b->joint_row_capacity = b->joint_link_capacity = b->joint_apart_capacity = b->joint_order_capacity = 0;
    b->joint_lists_sent = 0;
    b->joint_slots = 0;
}
#endif
