/* The gather, scatter and pass loop of contact_wide.h for one width (no include guard:
 * included once per width, C only, each width in a file of its own). Before including:
 * contact_row.h for the width (contact_solver.h has made width 1), and KG_LANE_OF(v,
 * lane), one lane of a lane value as an lvalue. */

#define KG_WIDE3(name, w) name##_w##w
#define KG_WIDE2(name, w) KG_WIDE3(name, w)
#define KG_WIDE(name) KG_WIDE2(name, KG_W)
#if KG_W == 1
#define KG_ROWFN(name) name
#define kg_wrow kg_contact_constraint
#define kg_wmotion kg_body_motion
#else
#define KG_ROWFN(name) KG_WIDE(name)
#define kg_wrow KG_WIDE(kg_contact_constraint)
#define kg_wmotion KG_WIDE(kg_body_motion)
#endif

static void KG_WIDE(kg_pack_point)(kg_wrow* r, int j, int lane, const kg_constraint_point* p)
{
    KG_LANE_OF(r->points[j].anchor_a.x, lane) = p->anchor_a.x;
    KG_LANE_OF(r->points[j].anchor_a.y, lane) = p->anchor_a.y;
    KG_LANE_OF(r->points[j].anchor_b.x, lane) = p->anchor_b.x;
    KG_LANE_OF(r->points[j].anchor_b.y, lane) = p->anchor_b.y;
    KG_LANE_OF(r->points[j].base_separation, lane) = p->base_separation;
    KG_LANE_OF(r->points[j].normal_impulse, lane) = p->normal_impulse;
    KG_LANE_OF(r->points[j].tangent_impulse, lane) = p->tangent_impulse;
    KG_LANE_OF(r->points[j].max_normal_impulse, lane) = p->max_normal_impulse;
    KG_LANE_OF(r->points[j].normal_mass, lane) = p->normal_mass;
    KG_LANE_OF(r->points[j].tangent_mass, lane) = p->tangent_mass;
    KG_LANE_OF(r->points[j].relative_velocity, lane) = p->relative_velocity;
    KG_LANE_OF(r->points[j].pad, lane) = p->pad;
}

static void KG_WIDE(kg_pack)(void* blocks, int block, int lane, const kg_contact_constraint* c)
{
    static const kg_contact_constraint empty = {{{{0.0f, 0.0f}, {0.0f, 0.0f}, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f},
                                                 {{0.0f, 0.0f}, {0.0f, 0.0f}, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f}},
                                                {0.0f, 0.0f},
                                                0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.5f, 0.0f, 0.0f, 0.0f, 0.0f,
                                                KG_NULL_INDEX, KG_NULL_INDEX, 0u, 0};
    kg_wrow* r = (kg_wrow*)blocks + block;
    if (!c) {
        c = &empty;
    }
    for (int j = 0; j < 2; ++j) {
        KG_WIDE(kg_pack_point)(r, j, lane, &c->points[j]);
    }
    KG_LANE_OF(r->normal.x, lane) = c->normal.x;
    KG_LANE_OF(r->normal.y, lane) = c->normal.y;
    KG_LANE_OF(r->inv_mass_a, lane) = c->inv_mass_a;
    KG_LANE_OF(r->inv_i_a, lane) = c->inv_i_a;
    KG_LANE_OF(r->inv_mass_b, lane) = c->inv_mass_b;
    KG_LANE_OF(r->inv_i_b, lane) = c->inv_i_b;
    KG_LANE_OF(r->friction, lane) = c->friction;
    KG_LANE_OF(r->restitution, lane) = c->restitution;
    KG_LANE_OF(r->bias_rate, lane) = c->bias_rate;
    KG_LANE_OF(r->mass_scale, lane) = c->mass_scale;
    KG_LANE_OF(r->impulse_scale, lane) = c->impulse_scale;
    KG_LANE_OF(r->share_b, lane) = c->share_b;
    KG_LANE_OF(r->inv_k11, lane) = c->inv_k11;
    KG_LANE_OF(r->inv_k12, lane) = c->inv_k12;
    KG_LANE_OF(r->inv_k22, lane) = c->inv_k22;
    KG_LANE_OF(r->block, lane) = c->block;
    KG_LANE_OF(r->a, lane) = c->a;
    KG_LANE_OF(r->b, lane) = c->b;
    KG_LANE_OF(r->contact, lane) = c->contact;
    KG_LANE_OF(r->point_count, lane) = c->point_count;
}

static void KG_WIDE(kg_unpack)(const void* blocks, int block, int lane, kg_contact_constraint* c)
{
    const kg_wrow* r = (const kg_wrow*)blocks + block;
    c->contact = KG_LANE_OF(r->contact, lane);
    c->point_count = KG_LANE_OF(r->point_count, lane);
    for (int j = 0; j < 2; ++j) {
        c->points[j].normal_impulse = KG_LANE_OF(r->points[j].normal_impulse, lane);
        c->points[j].tangent_impulse = KG_LANE_OF(r->points[j].tangent_impulse, lane);
        c->points[j].relative_velocity = KG_LANE_OF(r->points[j].relative_velocity, lane);
    }
}

static const kg_body_motion KG_WIDE(kg_still) = {{0.0f, 0.0f}, 0.0f, {0.0f, 0.0f}, {1.0f, 0.0f}};

#ifndef KG_GATHER_TRANSPOSED
/* The motions of the bodies slot[lane] into lanes; a lane without a body is still. (A
 * width may bring its own, a transpose of whole solver bodies: KG_GATHER_TRANSPOSED.) */
static kg_wmotion KG_WIDE(kg_gather)(const kg_solver_body* bodies, const kg_wrow* r, int is_b)
{
    kg_wmotion m;
    for (int lane = 0; lane < KG_W; ++lane) {
        kg_u32 slot = is_b ? KG_LANE_OF(r->b, lane) : KG_LANE_OF(r->a, lane);
        const kg_body_motion* s = slot == KG_NULL_INDEX ? &KG_WIDE(kg_still) : &bodies[slot].motion;
        KG_LANE_OF(m.v.x, lane) = s->v.x;
        KG_LANE_OF(m.v.y, lane) = s->v.y;
        KG_LANE_OF(m.w, lane) = s->w;
        KG_LANE_OF(m.dp.x, lane) = s->dp.x;
        KG_LANE_OF(m.dp.y, lane) = s->dp.y;
        KG_LANE_OF(m.dq.c, lane) = s->dq.c;
        KG_LANE_OF(m.dq.s, lane) = s->dq.s;
    }
    return m;
}

/* Velocities back to the bodies that take impulses (the passes change nothing else). */
static void KG_WIDE(kg_scatter)(kg_solver_body* bodies, const kg_wrow* r, int is_b, const kg_wmotion* m)
{
    for (int lane = 0; lane < KG_W; ++lane) {
        kg_u32 slot = is_b ? KG_LANE_OF(r->b, lane) : KG_LANE_OF(r->a, lane);
        if (slot != KG_NULL_INDEX && bodies[slot].moves) {
            bodies[slot].motion.v.x = KG_LANE_OF(m->v.x, lane);
            bodies[slot].motion.v.y = KG_LANE_OF(m->v.y, lane);
            bodies[slot].motion.w = KG_LANE_OF(m->w, lane);
        }
    }
}
#endif

static void KG_WIDE(kg_run)(void* blocks, int begin, int end, kg_solver_body* bodies, kg_solver_params prm,
                            kg_constraint_pass pass)
{
    for (int k = begin; k < end; ++k) {
        kg_wrow* r = (kg_wrow*)blocks + k;
        kg_wmotion a = KG_WIDE(kg_gather)(bodies, r, 0), b = KG_WIDE(kg_gather)(bodies, r, 1);
        switch (pass) {
        case KG_PASS_WARM_START: KG_ROWFN(kg_contact_warm_start)(r, &a, &b); break;
        case KG_PASS_SOLVE: KG_ROWFN(kg_contact_solve)(r, &a, &b, prm, 1); break;
        case KG_PASS_RELAX: KG_ROWFN(kg_contact_solve)(r, &a, &b, prm, 0); break;
        case KG_PASS_RESTITUTION: KG_ROWFN(kg_contact_restitution)(r, &a, &b, prm); break;
        }
        KG_WIDE(kg_scatter)(bodies, r, 0, &a);
        KG_WIDE(kg_scatter)(bodies, r, 1, &b);
    }
}

const kg_contact_rows KG_WIDE(kg_contact_rows) = {KG_W, sizeof(kg_wrow), KG_WIDE(kg_pack), KG_WIDE(kg_unpack),
                                                  KG_WIDE(kg_run)};
