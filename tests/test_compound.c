/* Compound bodies (kgyro/shape.h): mass data from the shapes against analytic values,
 * rest and tipping as physics predicts, shapes of one body never colliding, filters and
 * sensors per shape, shapes added and removed, handles, and determinism across threads. */
#include "kg_test.h"
#include "kg_twin.h"
#include "kgyro/kgyro.h"

#define KG_DT (1.0f / 60.0f)
#define KG_PI 3.14159265358979

static kg_world* kg_world_new(int threads)
{
    kg_world_def def = kg_default_world_def();
    def.max_bodies = 256;
    def.enable_sleep = 0;
    def.threads = threads;
    kg_world* world = NULL;
    KG_CHECK_OK(kg_create_world(&def, &world));
    return world;
}

static kg_body kg_floor(kg_world* world)
{
    kg_body_def def = kg_default_body_def();
    def.type = KG_BODY_STATIC;
    def.position = (kg_vec2){0.0f, -0.5f};
    def.shape = kg_box_shape(40.0f, 1.0f);
    kg_body body = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    return body;
}

/* A floor and a 1 m box resting on it: the box. */
static kg_body kg_box_on_floor(kg_world* world)
{
    kg_floor(world);
    kg_body_def def = kg_default_body_def();
    def.position = (kg_vec2){0.0f, 0.5f};
    def.shape = kg_box_shape(1.0f, 1.0f);
    kg_body body = KG_NULL_BODY_INIT;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    return body;
}

static kg_shape_id kg_add_shape(kg_world* world, kg_body body, kg_shape_def geometry, float density)
{
    kg_body_shape_def def = kg_default_body_shape_def();
    def.geometry = geometry;
    def.density = density;
    kg_shape_id shape = KG_NULL_SHAPE_INIT;
    KG_CHECK_OK(kg_create_shape(world, body, &def, &shape));
    return shape;
}

static void kg_step_for(kg_world* world, float seconds)
{
    int steps = (int)(seconds / KG_DT + 0.5f);
    for (int s = 0; s < steps; ++s) {
        KG_CHECK_OK(kg_world_step(world, KG_DT));
    }
}

static double kg_rel(double measured, double expected) { return fabs(measured - expected) / fabs(expected); }

/* ---- analytic mass data --------------------------------------------------------------- */

/* A rectangle's or a disc's mass data (kg, centre, inertia about its centre), double. */
typedef struct mass3 {
    double m, x, y, i;
} mass3;

static mass3 kg_rect(double w, double h, double x, double y, double density)
{
    double m = density * w * h;
    return (mass3){m, x, y, m * (w * w + h * h) / 12.0};
}

static mass3 kg_disc(double r, double x, double y, double density)
{
    double m = density * KG_PI * r * r;
    return (mass3){m, x, y, 0.5 * m * r * r};
}

/* The parallel axis theorem over parts. */
static mass3 kg_combine(const mass3* parts, int n)
{
    mass3 t = {0.0, 0.0, 0.0, 0.0};
    for (int k = 0; k < n; ++k) {
        t.m += parts[k].m;
        t.x += parts[k].m * parts[k].x;
        t.y += parts[k].m * parts[k].y;
    }
    t.x /= t.m;
    t.y /= t.m;
    for (int k = 0; k < n; ++k) {
        double dx = parts[k].x - t.x, dy = parts[k].y - t.y;
        t.i += parts[k].i + parts[k].m * (dx * dx + dy * dy);
    }
    return t;
}

static void kg_check_mass(kg_world* world, kg_body body, mass3 expected)
{
    kg_mass_data md;
    KG_CHECK_OK(kg_body_get_mass_data(world, body, &md));
    measured("     mass %.7g (expected %.7g), centre (%.7g, %.7g) (expected (%.7g, %.7g)), inertia %.7g (expected %.7g)\n",
             (double)md.mass, expected.m, (double)md.center.x, (double)md.center.y, expected.x, expected.y,
             (double)md.inertia, expected.i);
    KG_CHECK(kg_rel(md.mass, expected.m) <= 1e-5);
    KG_CHECK(kg_rel(md.inertia, expected.i) <= 1e-5);
    double size = sqrt(expected.i / expected.m); /* the radius of gyration: the scale of a centre's error */
    KG_CHECK_NEAR(md.center.x, expected.x, 1e-5 * size);
    KG_CHECK_NEAR(md.center.y, expected.y, 1e-5 * size);
    float inv_mass = 0.0f, inv_inertia = 0.0f;
    KG_CHECK_OK(kg_body_get_inverse_mass(world, body, &inv_mass, &inv_inertia));
    KG_CHECK(kg_rel(inv_mass, 1.0 / expected.m) <= 1e-5);
    KG_CHECK(kg_rel(inv_inertia, 1.0 / expected.i) <= 1e-5);
}

/* An L of two boxes of different densities, the second one turned a quarter turn (a
 * rectangle turned by 90 degrees is the same rectangle standing). */
static void test_l_mass(void)
{
    kg_world* world = kg_world_new(1);
    kg_body_def def = kg_default_body_def();
    def.position = (kg_vec2){3.0f, 2.0f};
    def.angle = 0.7f;
    def.shape = kg_offset_box_shape(2.0f, 0.5f, (kg_vec2){1.0f, 0.25f}, 0.0f);
    def.density = 1.0f;
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    kg_add_shape(world, body, kg_shape_moved(kg_box_shape(1.5f, 0.5f), (kg_vec2){0.25f, 1.25f}, 0.5f * (float)KG_PI),
                 2.0f);
    mass3 parts[2] = {kg_rect(2.0, 0.5, 1.0, 0.25, 1.0), kg_rect(0.5, 1.5, 0.25, 1.25, 2.0)};
    kg_check_mass(world, body, kg_combine(parts, 2));
    KG_CHECK(kg_body_shape_count(world, body) == 2);
    kg_vec2 origin;
    KG_CHECK_OK(kg_body_get_position(world, body, &origin));
    KG_CHECK_NEAR(origin.x, 3.0, 1e-6); /* the origin stays (to rounding); the centre of mass moves */
    KG_CHECK_NEAR(origin.y, 2.0, 1e-6);
    kg_destroy_world(world);
}

/* A dumbbell: two discs at the ends of a bar, built shape by shape on a body whose first
 * shape is the bar. */
static void test_dumbbell_mass(void)
{
    kg_world* world = kg_world_new(1);
    kg_body_def def = kg_default_body_def();
    def.shape = kg_box_shape(2.0f, 0.1f);
    def.density = 3.0f;
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    kg_add_shape(world, body, kg_shape_moved(kg_circle_shape(0.3f), (kg_vec2){-1.0f, 0.0f}, 0.0f), 1.0f);
    kg_add_shape(world, body, kg_shape_moved(kg_circle_shape(0.3f), (kg_vec2){1.0f, 0.0f}, 0.0f), 1.0f);
    mass3 parts[3] = {kg_rect(2.0, 0.1, 0.0, 0.0, 3.0), kg_disc(0.3, -1.0, 0.0, 1.0), kg_disc(0.3, 1.0, 0.0, 1.0)};
    kg_check_mass(world, body, kg_combine(parts, 3));
    kg_destroy_world(world);
}

/* Removing shapes recomputes the mass data; back to one shape it is the single shape's,
 * to the bit. An explicit mass is kept whatever the shapes. */
static void test_mass_follows_shapes(void)
{
    kg_world* world = kg_world_new(1);
    kg_body_def def = kg_default_body_def();
    def.shape = kg_box_shape(1.0f, 0.5f);
    kg_body body, alone;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    KG_CHECK_OK(kg_create_body(world, &def, &alone));
    kg_shape_id extra = kg_add_shape(world, body, kg_offset_box_shape(1.0f, 1.0f, (kg_vec2){2.0f, 0.0f}, 0.0f), 1.0f);
    kg_mass_data two, one, single;
    KG_CHECK_OK(kg_body_get_mass_data(world, body, &two));
    KG_CHECK_NEAR(two.mass, 1.5, 1e-6);
    KG_CHECK_OK(kg_destroy_shape(world, extra));
    KG_CHECK_OK(kg_body_get_mass_data(world, body, &one));
    KG_CHECK_OK(kg_body_get_mass_data(world, alone, &single));
    KG_CHECK(memcmp(&one, &single, sizeof one) == 0);
    KG_CHECK(kg_body_shape_count(world, body) == 1);

    def.mass = 5.0f;
    kg_body heavy;
    KG_CHECK_OK(kg_create_body(world, &def, &heavy));
    kg_add_shape(world, heavy, kg_offset_box_shape(1.0f, 1.0f, (kg_vec2){2.0f, 0.0f}, 0.0f), 1.0f);
    kg_mass_data given;
    KG_CHECK_OK(kg_body_get_mass_data(world, heavy, &given));
    KG_CHECK(given.mass == 5.0f && given.center.x == 0.0f);
    kg_destroy_world(world);
}

/* ---- physics ------------------------------------------------------------------------ */

static kg_body kg_dumbbell(kg_world* world, kg_vec2 position, float angle)
{
    kg_body_def def = kg_default_body_def();
    def.position = position;
    def.angle = angle;
    def.shape = kg_box_shape(2.0f, 0.1f);
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    kg_add_shape(world, body, kg_shape_moved(kg_circle_shape(0.3f), (kg_vec2){-1.0f, 0.0f}, 0.0f), 1.0f);
    kg_add_shape(world, body, kg_shape_moved(kg_circle_shape(0.3f), (kg_vec2){1.0f, 0.0f}, 0.0f), 1.0f);
    return body;
}

/* Dropped tilted from 1 m, it comes to rest on both discs: its axis at their radius above
 * the floor, level. */
static void test_dumbbell_comes_to_rest(void)
{
    kg_world* world = kg_world_new(1);
    kg_floor(world);
    kg_body body = kg_dumbbell(world, (kg_vec2){0.0f, 1.0f}, 0.3f);
    kg_step_for(world, 4.0f);
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(world, body, &st));
    measured("     at rest: height %.5f m (expected 0.3), angle %.4f degrees, speed %.2g m/s\n", (double)st.position.y,
             (double)st.angle * 180.0 / KG_PI, (double)sqrtf(st.velocity.x * st.velocity.x + st.velocity.y * st.velocity.y));
    KG_CHECK_NEAR(st.position.y, 0.3, 0.005);
    KG_CHECK_NEAR(st.angle * 180.0 / KG_PI, 0.0, 0.5);
    KG_CHECK(kg_world_contact_count(world) == 2); /* each disc on the floor; the bar clear of it */
    kg_destroy_world(world);
}

/* An L: a foot 1 m long and 0.2 m high, a post 0.2 m wide and 2 m high on its left end.
 * Stood on the foot's right corner, tilted by theta with no velocity, it tips over the
 * corner exactly when its centre of mass is past it: theta > atan(dx / dy), (dx, dy)
 * the centre from the corner. Returns the angle it ends at: about -90 degrees (-112: the
 * post's top and the foot's corner on the floor) when it tipped over; when it fell back
 * it lands on its foot hard enough to roll on over the foot's left corner, onto its back
 * (+90 degrees). */
static float kg_tilted_l_ends_at(double tilt)
{
    kg_world* world = kg_world_new(1);
    kg_floor(world);
    kg_vec2 corner = {1.0f, 0.0f}; /* body frame */
    float angle = (float)-tilt;
    kg_vec2 turned = {cosf(angle) * corner.x - sinf(angle) * corner.y, sinf(angle) * corner.x + cosf(angle) * corner.y};
    kg_body_def def = kg_default_body_def();
    def.position = (kg_vec2){-turned.x, -turned.y}; /* the corner on the floor at x = 0 */
    def.angle = angle;
    def.shape = kg_offset_box_shape(1.0f, 0.2f, (kg_vec2){0.5f, 0.1f}, 0.0f);
    def.friction = 1.0f;
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    kg_body_shape_def post = kg_default_body_shape_def();
    post.geometry = kg_offset_box_shape(0.2f, 2.0f, (kg_vec2){0.1f, 1.2f}, 0.0f);
    post.friction = 1.0f;
    kg_shape_id id;
    KG_CHECK_OK(kg_create_shape(world, body, &post, &id));
    kg_step_for(world, 5.0f);
    float end = 0.0f;
    KG_CHECK_OK(kg_body_get_angle(world, body, &end));
    kg_destroy_world(world);
    return end;
}

static void test_l_tips_when_its_centre_passes_the_edge(void)
{
    mass3 parts[2] = {kg_rect(1.0, 0.2, 0.5, 0.1, 1.0), kg_rect(0.2, 2.0, 0.1, 1.2, 1.0)};
    mass3 l = kg_combine(parts, 2);
    double critical = atan2(1.0 - l.x, l.y);
    measured("     critical tilt %.3f degrees (centre of mass (%.4f, %.4f))\n", critical * 180.0 / KG_PI, l.x, l.y);
    const double offsets[] = {-3.0, -1.0, -0.5, 0.5, 1.0, 3.0};
    for (int k = 0; k < 6; ++k) {
        double tilt = critical + offsets[k] * KG_PI / 180.0;
        float end = kg_tilted_l_ends_at(tilt);
        int tipped = end < -0.25f * (float)KG_PI;
        measured("     tilted %.3f degrees: ends at %.2f degrees, %s\n", tilt * 180.0 / KG_PI, (double)end * 180.0 / KG_PI,
                 tipped ? "tipped over" : "fell back");
        KG_CHECK(tipped == (offsets[k] > 0.0));
        KG_CHECK(tipped || end > 0.0f); /* fell back the way it came */
    }
}

/* Overlapping shapes of one body falling freely: no contact, no spin, free fall. */
static void test_shapes_of_one_body_never_collide(void)
{
    kg_world* world = kg_world_new(1);
    kg_body_def def = kg_default_body_def();
    def.position = (kg_vec2){0.0f, 10.0f};
    def.shape = kg_box_shape(1.0f, 1.0f);
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    kg_add_shape(world, body, kg_offset_box_shape(1.0f, 1.0f, (kg_vec2){0.3f, 0.2f}, 0.4f), 1.0f);
    kg_add_shape(world, body, kg_shape_moved(kg_circle_shape(0.6f), (kg_vec2){-0.2f, 0.1f}, 0.0f), 1.0f);
    int contacts = 0;
    for (int s = 0; s < 30; ++s) {
        KG_CHECK_OK(kg_world_step(world, KG_DT));
        contacts += kg_world_contact_count(world);
    }
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(world, body, &st));
    KG_CHECK(contacts == 0);
    KG_CHECK(st.angular_velocity == 0.0f);
    KG_CHECK_NEAR(st.velocity.x, 0.0, 1e-6);
    KG_CHECK_NEAR(st.velocity.y, -10.0 * 0.5, 1e-3); /* 30 steps of 1/60 s at g = 10 */
    kg_destroy_world(world);
}

/* Per shape: a sensor never pushes, a filtered shape passes through, the solid one lands. */
static void test_filter_and_sensor_per_shape(void)
{
    kg_world* world = kg_world_new(1);
    kg_body body = kg_box_on_floor(world);
    kg_body_shape_def sensor = kg_default_body_shape_def();
    sensor.geometry = kg_offset_box_shape(1.0f, 1.0f, (kg_vec2){2.0f, -0.6f}, 0.0f); /* in the floor */
    sensor.is_sensor = 1;
    kg_shape_id sensor_id, ghost_id;
    KG_CHECK_OK(kg_create_shape(world, body, &sensor, &sensor_id));
    kg_body_shape_def ghost = sensor;
    ghost.is_sensor = 0;
    ghost.geometry = kg_offset_box_shape(1.0f, 1.0f, (kg_vec2){-2.0f, -0.6f}, 0.0f);
    ghost.mask = 0u; /* collides with nothing */
    KG_CHECK_OK(kg_create_shape(world, body, &ghost, &ghost_id));
    kg_step_for(world, 1.0f);
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(world, body, &st));
    KG_CHECK_NEAR(st.position.y, 0.5, 0.01); /* on its first box, as if alone */
    KG_CHECK(kg_world_contact_count(world) == 1);
    kg_contact_info info;
    KG_CHECK_OK(kg_world_get_contact(world, 0, &info));
    kg_shape_id first;
    int count = 0;
    KG_CHECK_OK(kg_body_get_shapes(world, body, &first, 1, &count));
    KG_CHECK(count == 3);
    int names_first = (info.shape_a.index == first.index && info.shape_a.generation == first.generation) ||
                      (info.shape_b.index == first.index && info.shape_b.generation == first.generation);
    KG_CHECK(names_first);
    kg_body_shape_def back;
    KG_CHECK_OK(kg_shape_get_def(world, sensor_id, &back));
    KG_CHECK(back.is_sensor == 1 && back.geometry.type == KG_SHAPE_POLYGON);
    /* the ghost made solid: it now stands in the floor and is pushed out */
    KG_CHECK_OK(kg_shape_set_filter(world, ghost_id, 1u, 0xFFFFFFFFu));
    KG_CHECK_OK(kg_world_step(world, KG_DT));
    KG_CHECK(kg_world_contact_count(world) == 2);
    kg_destroy_world(world);
}

/* A box resting on the floor: a second box added beside it makes a second contact with
 * the floor; destroyed, the contact goes and the mass is back. */
static void test_adding_and_destroying_shapes(void)
{
    kg_world* world = kg_world_new(1);
    kg_body body = kg_box_on_floor(world);
    kg_step_for(world, 0.5f);
    KG_CHECK(kg_world_contact_count(world) == 1);
    kg_shape_id side = kg_add_shape(world, body, kg_offset_box_shape(1.0f, 1.0f, (kg_vec2){1.5f, 0.0f}, 0.0f), 1.0f);
    kg_mass_data md;
    KG_CHECK_OK(kg_body_get_mass_data(world, body, &md));
    KG_CHECK_NEAR(md.mass, 2.0, 1e-6);
    KG_CHECK_NEAR(md.center.x, 0.75, 1e-6);
    kg_step_for(world, 1.0f);
    KG_CHECK(kg_world_contact_count(world) == 2);
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(world, body, &st));
    KG_CHECK_NEAR(st.position.y, 0.5, 0.005);
    KG_CHECK_NEAR(st.angle, 0.0, 0.5 * KG_PI / 180.0);
    KG_CHECK_OK(kg_destroy_shape(world, side));
    KG_CHECK_OK(kg_world_step(world, KG_DT));
    KG_CHECK(kg_world_contact_count(world) == 1);
    KG_CHECK_OK(kg_body_get_mass_data(world, body, &md));
    KG_CHECK_NEAR(md.mass, 1.0, 1e-6);
    kg_destroy_world(world);
}

/* A resting box's shape replaced between two steps by a box twice as tall, reaching
 * 0.5 m into the floor: the new shape's contact is its own (no manifold of the old shape
 * kept, though the pose has not moved), and the floor pushes it out to rest on its new
 * bottom. */
static void test_replaced_shape_gets_its_own_contact(void)
{
    kg_world* world = kg_world_new(1);
    kg_body body = kg_box_on_floor(world);
    kg_step_for(world, 1.0f);
    kg_shape_id old;
    int count = 0;
    KG_CHECK_OK(kg_body_get_shapes(world, body, &old, 1, &count));
    KG_CHECK_OK(kg_destroy_shape(world, old));
    kg_add_shape(world, body, kg_box_shape(1.0f, 2.0f), 1.0f);
    kg_step_for(world, 2.0f);
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(world, body, &st));
    measured("     replaced by a box 2 m tall: rests at %.4f m (expected 1.0)\n", (double)st.position.y);
    KG_CHECK_NEAR(st.position.y, 1.0, 0.005);
    kg_destroy_world(world);
}

/* Two discs of different radii at different heights of one body (r 0.3 at (-1, 0), r 0.1
 * at (1, 0.5)) dropped on a tile map's floor: it rests on both discs, tilted so that
 * 2 sin(t) + 0.5 cos(t) = -0.2 (their centres at their radii above the floor), each disc
 * in a contact of its own; not on the box that bounds them. */
static void test_compound_on_tiles(void)
{
    kg_world* world = kg_world_new(1);
    kg_tile_shape shapes[2] = {kg_tile_empty(), kg_tile_box()};
    uint16_t tiles[20];
    for (int k = 0; k < 20; ++k) {
        tiles[k] = 1;
    }
    kg_tilemap_def map = kg_default_tilemap_def();
    map.width = 20;
    map.height = 1;
    map.origin = (kg_vec2){-10.0f, -1.0f};
    map.shapes = shapes;
    map.shape_count = 2;
    map.tiles = tiles;
    kg_tilemap handle;
    KG_CHECK_OK(kg_create_tilemap(world, &map, &handle));
    kg_body_def def = kg_default_body_def();
    def.position = (kg_vec2){0.0f, 1.0f};
    def.shape = kg_shape_moved(kg_circle_shape(0.3f), (kg_vec2){-1.0f, 0.0f}, 0.0f);
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    kg_add_shape(world, body, kg_shape_moved(kg_circle_shape(0.1f), (kg_vec2){1.0f, 0.5f}, 0.0f), 1.0f);
    kg_step_for(world, 4.0f);
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(world, body, &st));
    /* 2 sin t + 0.5 cos t = -0.2: with R = sqrt(4.25), t = asin(-0.2 / R) - atan2(0.5, 2) */
    double expected = asin(-0.2 / sqrt(4.25)) - atan2(0.5, 2.0);
    measured("     on the tiles: angle %.3f degrees (expected %.3f), big disc's centre %.4f m up (expected 0.3)\n",
             (double)st.angle * 180.0 / KG_PI, expected * 180.0 / KG_PI,
             (double)st.position.y + sin((double)st.angle) * -1.0);
    KG_CHECK_NEAR(st.angle * 180.0 / KG_PI, expected * 180.0 / KG_PI, 0.5);
    KG_CHECK_NEAR(st.position.y - sinf(st.angle), 0.3, 0.005);
    KG_CHECK(kg_world_contact_count(world) == 2);
    kg_contact_info a, b;
    KG_CHECK_OK(kg_world_get_contact(world, 0, &a));
    KG_CHECK_OK(kg_world_get_contact(world, 1, &b));
    KG_CHECK(a.shape_a.index != b.shape_a.index);
    kg_destroy_world(world);
}

/* Sleeping bodies wake when a shape added reaches them: one added to the static floor
 * under a sleeping box (the floor cannot wake it through a contact), and one added to a
 * dynamic body beside another sleeping box (its contact wakes it in the wake stage). */
static void test_new_shapes_wake_what_they_reach(void)
{
    kg_world_def wd = kg_default_world_def();
    wd.max_bodies = 16;
    kg_world* world = NULL;
    KG_CHECK_OK(kg_create_world(&wd, &world));
    kg_body floor = kg_floor(world);
    kg_body_def def = kg_default_body_def();
    def.shape = kg_box_shape(1.0f, 1.0f);
    def.position = (kg_vec2){-3.0f, 0.5f};
    kg_body on_floor;
    KG_CHECK_OK(kg_create_body(world, &def, &on_floor));
    def.position = (kg_vec2){3.0f, 0.5f};
    kg_body neighbour, other;
    KG_CHECK_OK(kg_create_body(world, &def, &neighbour));
    def.position = (kg_vec2){5.0f, 0.5f};
    KG_CHECK_OK(kg_create_body(world, &def, &other));
    kg_step_for(world, 2.0f);
    KG_CHECK(!kg_body_is_awake(world, on_floor) && !kg_body_is_awake(world, neighbour));
    kg_add_shape(world, floor, kg_offset_box_shape(1.0f, 0.2f, (kg_vec2){-3.0f, 0.55f}, 0.0f), 1.0f);
    KG_CHECK(kg_body_is_awake(world, on_floor));
    kg_add_shape(world, other, kg_offset_box_shape(1.0f, 0.5f, (kg_vec2){-1.0f, 0.0f}, 0.0f), 1.0f);
    KG_CHECK_OK(kg_world_step(world, KG_DT));
    KG_CHECK(kg_body_is_awake(world, neighbour));
    kg_step_for(world, 1.0f);
    kg_body_state st;
    KG_CHECK_OK(kg_body_get_state(world, on_floor, &st));
    KG_CHECK_NEAR(st.position.y, 0.65, 0.005); /* on the floor's new step, its top at 0.15 (floor origin -0.5) */
    kg_destroy_world(world);
}

/* Stale, foreign and null handles are refused; a destroyed body takes its shapes. */
static void test_handles(void)
{
    kg_world* world = kg_world_new(1);
    kg_world* other = kg_world_new(1);
    kg_body_def def = kg_default_body_def();
    def.shape = kg_box_shape(1.0f, 1.0f);
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &def, &body));
    kg_shape_id extra = kg_add_shape(world, body, kg_circle_shape(0.5f), 1.0f);
    kg_shape_id null_shape = KG_NULL_SHAPE_INIT, foreign = {200u, 1u};
    kg_body owner;
    KG_CHECK(kg_shape_get_body(world, null_shape, &owner) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_shape_get_body(world, foreign, &owner) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_shape_get_body(other, extra, &owner) == KG_ERROR_INVALID_HANDLE); /* another world's */
    KG_CHECK_OK(kg_shape_get_body(world, extra, &owner));
    KG_CHECK(owner.index == body.index && owner.generation == body.generation);
    KG_CHECK_OK(kg_destroy_shape(world, extra));
    KG_CHECK(!kg_shape_is_valid(world, extra));
    KG_CHECK(kg_destroy_shape(world, extra) == KG_ERROR_INVALID_HANDLE);
    KG_CHECK(kg_shape_set_friction(world, extra, 0.5f) == KG_ERROR_INVALID_HANDLE);
    kg_body_shape_def bad = kg_default_body_shape_def();
    bad.geometry = kg_circle_shape(0.5f);
    bad.friction = -1.0f;
    kg_shape_id out;
    KG_CHECK(kg_create_shape(world, body, &bad, &out) == KG_ERROR_INVALID_ARGUMENT);
    bad.friction = 0.5f;
    bad.geometry.type = KG_SHAPE_NONE;
    KG_CHECK(kg_create_shape(world, body, &bad, &out) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_body_shape_count(world, body) == 1);

    kg_shape_id again = kg_add_shape(world, body, kg_circle_shape(0.5f), 1.0f);
    KG_CHECK(again.index != extra.index); /* a destroyed shape's slot waits for a step */
    KG_CHECK_OK(kg_destroy_shape(world, again));
    KG_CHECK_OK(kg_world_step(world, KG_DT));
    again = kg_add_shape(world, body, kg_circle_shape(0.5f), 1.0f);
    KG_CHECK(again.index == extra.index && again.generation != extra.generation); /* the slot reused, not the handle */
    kg_shape_id first;
    int count = 0;
    KG_CHECK_OK(kg_body_get_shapes(world, body, &first, 1, &count));
    KG_CHECK_OK(kg_destroy_body(world, body));
    KG_CHECK(!kg_shape_is_valid(world, first) && !kg_shape_is_valid(world, again));
    KG_CHECK(kg_create_shape(world, body, &bad, &out) == KG_ERROR_INVALID_HANDLE);
    kg_destroy_world(other);
    kg_destroy_world(world);
}

/* kg_body_set_friction, _restitution and _filter set every shape of the body;
 * kg_shape_set_friction one. */
static void test_body_setters_reach_every_shape(void)
{
    kg_world* world = kg_world_new(1);
    kg_body body = kg_box_on_floor(world);
    kg_shape_id side = kg_add_shape(world, body, kg_offset_box_shape(1.0f, 1.0f, (kg_vec2){1.5f, 0.0f}, 0.0f), 1.0f);
    KG_CHECK_OK(kg_body_set_friction(world, body, 0.25f));
    KG_CHECK_OK(kg_body_set_restitution(world, body, 0.5f));
    KG_CHECK_OK(kg_body_set_filter(world, body, 2u, 5u));
    kg_shape_id shapes[2];
    int count = 0;
    KG_CHECK_OK(kg_body_get_shapes(world, body, shapes, 2, &count));
    for (int k = 0; k < count; ++k) {
        kg_body_shape_def def;
        KG_CHECK_OK(kg_shape_get_def(world, shapes[k], &def));
        KG_CHECK(def.friction == 0.25f && def.restitution == 0.5f && def.category == 2u && def.mask == 5u);
    }
    KG_CHECK_OK(kg_body_set_filter(world, body, 1u, 0xFFFFFFFFu));
    KG_CHECK_OK(kg_shape_set_friction(world, side, 1.0f));
    KG_CHECK_OK(kg_world_step(world, KG_DT));
    KG_CHECK(kg_world_contact_count(world) == 2); /* the filter back: both boxes on the floor */
    kg_body_shape_def def;
    KG_CHECK_OK(kg_shape_get_def(world, side, &def));
    KG_CHECK(def.friction == 1.0f);
    kg_destroy_world(world);
}

/* NULL, NaN and out-of-range arguments are refused with a clear error and change nothing. */
static void test_bad_arguments(void)
{
    kg_world* world = kg_world_new(1);
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_box_shape(1.0f, 1.0f);
    kg_body body;
    KG_CHECK_OK(kg_create_body(world, &bd, &body));
    kg_body_shape_def def = kg_default_body_shape_def();
    def.geometry = kg_circle_shape(0.5f);
    kg_shape_id id;
    KG_CHECK(kg_create_shape(NULL, body, &def, &id) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_create_shape(world, body, NULL, &id) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_create_shape(world, body, &def, NULL) == KG_ERROR_INVALID_ARGUMENT);
    def.density = NAN;
    KG_CHECK(kg_create_shape(world, body, &def, &id) == KG_ERROR_INVALID_ARGUMENT);
    def.density = 1.0f;
    def.restitution = 1.5f;
    KG_CHECK(kg_create_shape(world, body, &def, &id) == KG_ERROR_INVALID_ARGUMENT);
    def.restitution = 0.0f;
    def.geometry.radius = -1.0f;
    KG_CHECK(kg_create_shape(world, body, &def, &id) != KG_OK);
    def.geometry = kg_polygon_shape((const kg_vec2[]){{0, 0}, {1, 0}, {2, 0}}, 3); /* no area */
    KG_CHECK(kg_create_shape(world, body, &def, &id) == KG_ERROR_DEGENERATE_SHAPE);
    KG_CHECK(kg_body_shape_count(world, body) == 1);
    int count = -1;
    KG_CHECK(kg_body_get_shapes(world, body, NULL, 4, &count) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_body_get_shapes(world, body, NULL, 0, NULL) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK_OK(kg_body_get_shapes(world, body, NULL, 0, &count)); /* counting only */
    KG_CHECK(count == 1);
    KG_CHECK_OK(kg_body_get_shapes(world, body, &id, 1, &count));
    KG_CHECK(kg_shape_get_def(world, id, NULL) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_shape_get_body(world, id, NULL) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_shape_set_friction(world, id, -0.5f) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_shape_set_friction(world, id, INFINITY) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_shape_set_restitution(world, id, NAN) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_shape_set_filter(NULL, id, 1u, 1u) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_destroy_shape(NULL, id) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(!kg_shape_is_valid(NULL, id));
    KG_CHECK(kg_body_shape_count(NULL, body) == 0);
    kg_body_shape_def back;
    KG_CHECK_OK(kg_shape_get_def(world, id, &back));
    KG_CHECK(back.friction == 0.6f && back.density == 1.0f); /* unchanged by the refused calls */
    kg_destroy_world(world);
}

/* ---- determinism -------------------------------------------------------------------- */

/* Dumbbells, Ls and crosses piled on the floor with boxes. */
static void kg_compound_pile(kg_world* world)
{
    kg_floor(world);
    for (int k = 0; k < 60; ++k) {
        float x = -6.0f + (float)(k % 6) * 2.2f, y = 1.0f + (float)(k / 6) * 1.3f;
        if (k % 3 == 0) {
            kg_dumbbell(world, (kg_vec2){x, y}, 0.1f * (float)(k % 5));
            continue;
        }
        kg_body_def def = kg_default_body_def();
        def.position = (kg_vec2){x, y};
        def.angle = 0.2f * (float)(k % 7);
        def.shape = kg_box_shape(1.2f, 0.3f);
        kg_body body;
        KG_CHECK_OK(kg_create_body(world, &def, &body));
        if (k % 3 == 1) {
            kg_add_shape(world, body, kg_offset_box_shape(0.3f, 1.2f, (kg_vec2){0.45f, 0.45f}, 0.0f), 2.0f);
        }
    }
}

static int kg_same_states(kg_world* a, kg_world* b)
{
    static kg_body bodies[256];
    int count = 0;
    kg_world_get_bodies(a, bodies, 256, &count);
    int same = count == kg_world_body_count(b);
    for (int i = 0; same && i < count; ++i) {
        kg_body_state sa, sb;
        KG_CHECK_OK(kg_body_get_state(a, bodies[i], &sa));
        KG_CHECK_OK(kg_body_get_state(b, kg_twin_body(b, bodies[i]), &sb));
        same = memcmp(&sa, &sb, sizeof sa) == 0;
    }
    return same;
}

static void test_threads_bitwise(void)
{
    kg_world* worlds[3] = {kg_world_new(1), kg_world_new(2), kg_world_new(4)};
    for (int w = 0; w < 3; ++w) {
        kg_compound_pile(worlds[w]);
    }
    int contacts = 0;
    for (int s = 0; s < 240; ++s) {
        for (int w = 0; w < 3; ++w) {
            KG_CHECK_OK(kg_world_step(worlds[w], KG_DT));
        }
        contacts = kg_world_contact_count(worlds[0]);
    }
    measured("     %d bodies, %d contacts at the end\n", kg_world_body_count(worlds[0]), contacts);
    KG_CHECK(contacts > 60);
    KG_CHECK(kg_same_states(worlds[0], worlds[1]));
    KG_CHECK(kg_same_states(worlds[0], worlds[2]));
    for (int w = 0; w < 3; ++w) {
        kg_destroy_world(worlds[w]);
    }
}

int main(void)
{
    static const kg_test_case tests[] = {KG_TEST(test_l_mass),
                                         KG_TEST(test_dumbbell_mass),
                                         KG_TEST(test_mass_follows_shapes),
                                         KG_TEST(test_dumbbell_comes_to_rest),
                                         KG_TEST(test_l_tips_when_its_centre_passes_the_edge),
                                         KG_TEST(test_shapes_of_one_body_never_collide),
                                         KG_TEST(test_filter_and_sensor_per_shape),
                                         KG_TEST(test_adding_and_destroying_shapes),
                                         KG_TEST(test_replaced_shape_gets_its_own_contact),
                                         KG_TEST(test_compound_on_tiles),
                                         KG_TEST(test_new_shapes_wake_what_they_reach),
                                         KG_TEST(test_handles),
                                         KG_TEST(test_bad_arguments),
                                         KG_TEST(test_body_setters_reach_every_shape),
                                         KG_TEST(test_threads_bitwise)};
    return kg_run_tests(tests, (int)(sizeof tests / sizeof tests[0]));
}
