/* Handles, pools and bad input: every failure is reported and changes nothing. */
#include "kg_test.h"
#include "kgyro/kgyro.h"

#include <string.h>

static kg_world* make_world(int max_bodies)
{
    kg_world_def def = kg_default_world_def();
    def.max_bodies = max_bodies;
    def.backend = KG_BACKEND_CPU;
    kg_world* w = NULL;
    KG_CHECK_OK(kg_create_world(&def, &w));
    return w;
}

static kg_body add_box(kg_world* w, float x, float y)
{
    kg_body_def bd = kg_default_body_def();
    bd.position = (kg_vec2){x, y};
    bd.shape = kg_box_shape(1.0f, 1.0f);
    kg_body b = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    return b;
}

static void test_stale_handle_after_destroy(void)
{
    kg_world* w = make_world(8);
    kg_body a = add_box(w, 0, 0);
    KG_CHECK(kg_body_is_valid(w, a));
    KG_CHECK_OK(kg_destroy_body(w, a));
    KG_CHECK(!kg_body_is_valid(w, a));
    kg_vec2 p;
    KG_CHECK(kg_body_get_position(w, a, &p) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(strstr(kg_last_error(), "stale") != NULL);
    KG_CHECK(kg_destroy_body(w, a) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_body_set_velocity(w, a, (kg_vec2){1, 0}) == KG_ERROR_INVALID_HANDLE);
    kg_body null_body = KG_NULL_BODY_INIT;
    KG_CHECK(!kg_body_is_valid(w, null_body));
    kg_body foreign = {5, 1};
    KG_CHECK(kg_body_get_position(w, foreign, &p) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_world_body_count(w) == 0);
    kg_destroy_world(w);
}

static void test_reuse_gets_new_generation(void)
{
    kg_world* w = make_world(8);
    kg_body a = add_box(w, 0, 0);
    KG_CHECK_OK(kg_destroy_body(w, a));
    kg_body b = add_box(w, 1, 0);
    KG_CHECK(b.index == a.index);
    KG_CHECK(b.generation != a.generation);
    KG_CHECK(!kg_body_is_valid(w, a));
    KG_CHECK(kg_body_is_valid(w, b));
    kg_destroy_world(w);
}

/* Two worlds with a body in the same slot: each one's handles name nothing in the other
 * (types.h: a foreign handle is invalid), for bodies, shapes and applicators alike. */
static void test_foreign_handles_are_invalid(void)
{
    kg_world* mine = make_world(8);
    kg_world* other = make_world(8);
    kg_body body = add_box(mine, 0, 0);
    kg_body foreign = add_box(other, 5, 0);
    KG_CHECK(body.index == foreign.index);
    KG_CHECK(!kg_body_is_valid(mine, foreign));
    kg_vec2 p;
    KG_CHECK(kg_body_get_position(mine, foreign, &p) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(strstr(kg_last_error(), "foreign") != NULL);
    KG_CHECK(kg_body_set_velocity(mine, foreign, (kg_vec2){1, 0}) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_destroy_body(mine, foreign) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_body_is_valid(mine, body) && kg_world_body_count(mine) == 1);

    kg_shape_id foreign_shape;
    int count = 0;
    KG_CHECK_OK(kg_body_get_shapes(other, foreign, &foreign_shape, 1, &count));
    kg_body owner;
    KG_CHECK(kg_shape_get_body(mine, foreign_shape, &owner) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_destroy_shape(mine, foreign_shape) == KG_ERROR_INVALID_HANDLE);

    kg_applicator applicator, foreign_applicator;
    KG_CHECK_OK(kg_add_gravity_applicator(mine, (kg_vec2){0, 1}, NULL, 0, &applicator));
    KG_CHECK_OK(kg_add_gravity_applicator(other, (kg_vec2){0, 1}, NULL, 0, &foreign_applicator));
    KG_CHECK(applicator.index == foreign_applicator.index);
    KG_CHECK(kg_remove_applicator(mine, foreign_applicator) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK_OK(kg_remove_applicator(mine, applicator));
    kg_destroy_world(other);
    kg_destroy_world(mine);
}

static void test_full_pool_is_an_error_and_leaves_world_intact(void)
{
    kg_world* w = make_world(3);
    kg_body bodies[3];
    for (int i = 0; i < 3; ++i) {
        bodies[i] = add_box(w, (float)i * 2.0f, 0.0f);
    }
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_box_shape(1, 1);
    kg_body extra = KG_NULL_BODY_INIT;
    KG_CHECK(kg_create_body(w, &bd, &extra) == KG_ERROR_POOL_FULL);
    KG_CHECK(strstr(kg_last_error(), "max_bodies = 3") != NULL);
    KG_CHECK(extra.generation == 0);
    KG_CHECK(kg_world_body_count(w) == 3);
    for (int i = 0; i < 3; ++i) {
        kg_vec2 p;
        KG_CHECK_OK(kg_body_get_position(w, bodies[i], &p));
        KG_CHECK(p.x == (float)i * 2.0f && p.y == 0.0f);
    }
    KG_CHECK_OK(kg_world_step(w, 1.0f / 60.0f));
    kg_destroy_world(w);
}

static void test_bad_body_definitions_are_refused(void)
{
    kg_world* w = make_world(8);
    kg_body keep = add_box(w, 0, 0);
    kg_body out = KG_NULL_BODY_INIT;
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_box_shape(1, 1);
    bd.position.x = NAN;
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_INVALID_ARGUMENT);
    bd.position.x = 0.0f;
    bd.density = -1.0f;
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_INVALID_ARGUMENT);
    bd.density = 1.0f;
    bd.restitution = 1.5f;
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_INVALID_ARGUMENT);
    bd.restitution = 0.0f;
    bd.friction = INFINITY;
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_INVALID_ARGUMENT);
    bd.friction = 0.5f;
    kg_vec2 line[3] = {{0, 0}, {1, 1}, {2, 2}};
    bd.shape = kg_polygon_shape(line, 3);
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_DEGENERATE_SHAPE);
    bd.shape = kg_box_shape(0.0f, 1.0f);
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_DEGENERATE_SHAPE);
    bd.shape = kg_box_shape(-1.0f, -1.0f); /* its corners' hull is a 1 x 1 box: refused all the same */
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_DEGENERATE_SHAPE);
    KG_CHECK(strstr(kg_last_error(), "not > 0") != NULL);
    bd.shape = kg_box_shape(NAN, 1.0f);
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_INVALID_ARGUMENT);
    bd.shape = kg_polygon_shape(NULL, 3); /* no crash: nothing is read */
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_DEGENERATE_SHAPE);
    kg_tile_shape tile = kg_tile_polygon(NULL, 3);
    KG_CHECK(kg_tile_shape_check(&tile) == KG_ERROR_DEGENERATE_SHAPE);
    bd.shape = kg_circle_shape(-1.0f);
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_INVALID_ARGUMENT);
    bd.shape = kg_box_shape(1, 1);
    bd.density = 0.0f;
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_INVALID_ARGUMENT);
    bd.type = KG_BODY_PARTICLE;
    bd.shape.type = KG_SHAPE_NONE;
    KG_CHECK(kg_create_body(w, &bd, &out) == KG_ERROR_INVALID_ARGUMENT); /* a point needs a mass */
    KG_CHECK(out.generation == 0);
    KG_CHECK(kg_world_body_count(w) == 1);
    KG_CHECK(kg_body_is_valid(w, keep));
    kg_destroy_world(w);
}

static void test_bad_calls_change_nothing(void)
{
    kg_world* w = make_world(8);
    kg_body b = add_box(w, 1, 2);
    KG_CHECK_OK(kg_body_set_velocity(w, b, (kg_vec2){3, 4}));
    KG_CHECK(kg_body_set_velocity(w, b, (kg_vec2){NAN, 0}) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_body_set_transform(w, b, (kg_vec2){INFINITY, 0}, 0) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_body_apply_force(w, b, (kg_vec2){NAN, 0}, (kg_vec2){0, 0}) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_body_set_friction(w, b, -1.0f) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_body_set_inverse_mass(w, b, -1.0f, 0.0f) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_step(w, 0.0f) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_step(w, NAN) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_world_set_gravity(w, (kg_vec2){0, NAN}) == KG_ERROR_INVALID_ARGUMENT);
    kg_body_state s;
    KG_CHECK_OK(kg_body_get_state(w, b, &s));
    KG_CHECK(s.position.x == 1.0f && s.position.y == 2.0f && s.velocity.x == 3.0f && s.velocity.y == 4.0f);
    KG_CHECK(kg_world_get_gravity(w).y == -10.0f);
    KG_CHECK(kg_body_get_position(w, b, NULL) == KG_ERROR_INVALID_ARGUMENT);
    kg_destroy_world(w);
}

static void test_bad_world_definitions_are_refused(void)
{
    kg_world_def def = kg_default_world_def();
    kg_world* w = (kg_world*)&def; /* must be reset to NULL on failure */
    def.max_bodies = 0;
    KG_CHECK(kg_create_world(&def, &w) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(w == NULL);
    def = kg_default_world_def();
    def.substeps = 0;
    KG_CHECK(kg_create_world(&def, &w) == KG_ERROR_INVALID_ARGUMENT);
    def = kg_default_world_def();
    def.gravity.y = INFINITY;
    KG_CHECK(kg_create_world(&def, &w) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_create_world(NULL, &w) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strcmp(kg_result_string(KG_ERROR_POOL_FULL), "pool full") == 0);
}

static void test_get_bodies_lists_live_ones_in_slot_order(void)
{
    kg_world* w = make_world(8);
    kg_body b[4];
    for (int i = 0; i < 4; ++i) {
        b[i] = add_box(w, (float)i, 0);
    }
    KG_CHECK_OK(kg_destroy_body(w, b[1]));
    kg_body out[8];
    int n = -1;
    KG_CHECK_OK(kg_world_get_bodies(w, out, 8, &n));
    KG_CHECK(n == 3);
    KG_CHECK(out[0].index == b[0].index && out[1].index == b[2].index && out[2].index == b[3].index);
    kg_body_state states[3];
    KG_CHECK_OK(kg_world_get_body_states(w, out, 3, states));
    KG_CHECK(states[1].position.x == 2.0f);
    KG_CHECK(kg_world_get_body_states(w, b, 2, states) == KG_ERROR_INVALID_HANDLE);
    kg_destroy_world(w);
}

static void test_user_data_is_set_and_read_back(void)
{
    kg_world* w = make_world(8);
    kg_body a = add_box(w, 0, 0);
    int tag = 7;
    KG_CHECK(kg_body_get_user_data(w, a) == NULL);
    KG_CHECK_OK(kg_body_set_user_data(w, a, &tag));
    KG_CHECK(kg_body_get_user_data(w, a) == &tag);
    KG_CHECK_OK(kg_destroy_body(w, a));
    KG_CHECK(kg_body_set_user_data(w, a, &tag) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_body_get_user_data(w, a) == NULL);
    kg_body b = add_box(w, 1, 0); /* the slot reused: the old pointer is not inherited */
    KG_CHECK(kg_body_get_user_data(w, b) == NULL);
    kg_destroy_world(w);
}

KG_TEST_MAIN(KG_TEST(test_stale_handle_after_destroy), KG_TEST(test_user_data_is_set_and_read_back), KG_TEST(test_reuse_gets_new_generation),
             KG_TEST(test_foreign_handles_are_invalid),
             KG_TEST(test_full_pool_is_an_error_and_leaves_world_intact),
             KG_TEST(test_bad_body_definitions_are_refused), KG_TEST(test_bad_calls_change_nothing),
             KG_TEST(test_bad_world_definitions_are_refused), KG_TEST(test_get_bodies_lists_live_ones_in_slot_order))
