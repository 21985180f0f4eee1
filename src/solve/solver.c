#include "solve/solver.h"
#include "core/alloc.h"
#include "core/error.h"
#include "solve/integrate.h"

struct kg_solver {
    int unused;
};

kg_result kg_solver_create(kg_world* world)
{
    world->solver = kg_alloc_zeroed(sizeof *world->solver);
    return world->solver ? KG_OK : kg_fail(KG_ERROR_OUT_OF_MEMORY, "cannot allocate the solver");
}

void kg_solver_destroy(kg_world* world)
{
    kg_free(world->solver);
    world->solver = NULL;
}

static void kg_integrate_velocities(kg_body_pool* p, kg_integrate_params prm)
{
    for (int i = 0; i < p->high_water; ++i) {
        if (kg_pool_is_simulated(p, i)) {
            kg_integrate_velocity(&p->velocity[i], &p->omega[i], p->force[i], p->torque[i], p->inv_mass[i],
                                  p->inv_inertia[i], p->linear_damping[i], p->angular_damping[i], prm);
        }
    }
}

static void kg_integrate_positions(kg_body_pool* p, float h)
{
    for (int i = 0; i < p->high_water; ++i) {
        kg_body_type t = kg_pool_type(p, i);
        if (kg_pool_alive(p, i) && t != KG_BODY_STATIC && !(p->flags[i] & KG_FLAG_FROZEN)) {
            kg_integrate_position(&p->center[i], &p->rot[i], p->velocity[i], p->omega[i], h);
        }
    }
}

void kg_stage_solve(kg_world* world, float dt)
{
    int n = world->def.substeps;
    kg_integrate_params prm = {world->def.gravity, dt / (float)n, world->def.max_linear_speed};
    for (int s = 0; s < n; ++s) {
        kg_integrate_velocities(&world->bodies, prm);
        kg_integrate_positions(&world->bodies, prm.h);
    }
}

static int kg_body_state_finite(const kg_body_pool* p, int i)
{
    return kg_vec_is_finite(p->center[i]) && kg_vec_is_finite(p->velocity[i]) && kg_is_finite(p->omega[i]) &&
           kg_is_finite(p->rot[i].c) && kg_is_finite(p->rot[i].s);
}

void kg_stage_finalize(kg_world* world)
{
    kg_body_pool* p = &world->bodies;
    for (int i = 0; i < p->high_water; ++i) {
        if (!kg_pool_alive(p, i)) {
            continue;
        }
        p->force[i] = kg_v2(0.0f, 0.0f);
        p->torque[i] = 0.0f;
        if ((p->flags[i] & KG_FLAG_FROZEN) == 0 && !kg_body_state_finite(p, i)) {
            kg_warn_once("non-finite", "body %d got a non-finite state and was frozen", i);
            p->flags[i] |= KG_FLAG_FROZEN;
            p->velocity[i] = kg_v2(0.0f, 0.0f);
            p->omega[i] = 0.0f;
            p->rot[i] = p->xf[i].q; /* back to the last finite pose */
            p->center[i] = kg_xf_point(p->xf[i], p->local_center[i]);
            continue;
        }
        if (kg_pool_type(p, i) != KG_BODY_STATIC) {
            kg_body_update_transform(p, i);
        }
    }
}
