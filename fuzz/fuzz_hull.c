/* Fuzz target "hull": the polygon hull builder and mass properties (kg_polygon_shape,
 * kg_circle_shape, kg_capsule_shape, kg_segment_shape, kg_shape_mass and the internal
 * kg_shape_build), then a body made of the shape, stepped in a world.
 *
 * Input bytes: type (u8, mod 6: none, circle, polygon, an unknown type, capsule, segment),
 * vertex count (i8, may be out of range), then float32 values: density, radius, centre x,
 * y, and up to 8 vertices x, y (a capsule's centres and a segment's points are the first
 * two). Missing bytes read as zeros.
 *
 * Contracts checked:
 *  - kg_shape_mass answers OK, INVALID_ARGUMENT or DEGENERATE_SHAPE, and a failure
 *    leaves a message in kg_last_error();
 *  - a success gives a finite mass > 0 (0 for a point), a finite inertia >= 0 and a
 *    finite centre; a segment never has a mass;
 *  - a built capsule or segment keeps its two points and radius, with opposite unit
 *    normals, and a segment is refused on a dynamic body;
 *  - a built polygon has 3 to 8 finite vertices, unit outward normals, turns
 *    counter-clockwise, is convex and contains every input point (to the weld
 *    distance), and its area matches an independent double-precision hull;
 *  - well-conditioned input (a hull that is not a sliver, coordinates in a sane range)
 *    is accepted;
 *  - the shape a body reports back builds again;
 *  - a dynamic body made of the shape (a static one for a segment, with a ball dropped on
 *    it) steps with a finite state. */
#include "fuzz_common.h"

#include "collide/shape.h"
#include "kgyro/kgyro.h"

#include <math.h>

typedef struct hull_input {
    kg_shape_def def;
    float density;
    kg_vec2 points[KG_MAX_POLYGON_VERTICES]; /* as given, before the hull */
    int point_count;                          /* how many of them the def uses */
} hull_input;

static hull_input read_input(const uint8_t* data, size_t size)
{
    fuzz_reader r = fuzz_reader_make(data, size);
    hull_input in;
    memset(&in, 0, sizeof in);
    int type = fuzz_take_u8(&r) % 6;
    int count = (int8_t)fuzz_take_u8(&r);
    in.density = fuzz_take_float(&r);
    float radius = fuzz_take_float(&r);
    kg_vec2 center = {fuzz_take_float(&r), fuzz_take_float(&r)};
    for (int i = 0; i < KG_MAX_POLYGON_VERTICES; ++i) {
        in.points[i].x = fuzz_take_float(&r);
        in.points[i].y = fuzz_take_float(&r);
    }
    if (type == 1) {
        in.def = kg_circle_shape(radius);
        in.def.center = center;
    } else if (type == 2) {
        in.def = kg_polygon_shape(in.points, count);
        in.point_count = count < 0 ? 0 : (count > KG_MAX_POLYGON_VERTICES ? KG_MAX_POLYGON_VERTICES : count);
    } else if (type == 4) {
        in.def = kg_capsule_shape(in.points[0], in.points[1], radius);
    } else if (type == 5) {
        in.def = kg_segment_shape(in.points[0], in.points[1]);
    } else {
        in.def = kg_circle_shape(radius);
        in.def.type = type == 0 ? KG_SHAPE_NONE : (kg_shape_type)7;
    }
    return in;
}

static int finite_vec(kg_vec2 v) { return isfinite(v.x) && isfinite(v.y); }

static double cross_d(kg_vec2 o, kg_vec2 a, kg_vec2 b)
{
    return ((double)a.x - o.x) * ((double)b.y - o.y) - ((double)a.y - o.y) * ((double)b.x - o.x);
}

/* Area of the convex hull of the points, in double (monotone chain): the reference
 * the engine's float hull is compared with. */
static double reference_hull_area(const kg_vec2* points, int n)
{
    kg_vec2 sorted[KG_MAX_POLYGON_VERTICES], hull[2 * KG_MAX_POLYGON_VERTICES];
    memcpy(sorted, points, (size_t)n * sizeof *points);
    for (int i = 1; i < n; ++i) {
        for (int j = i; j > 0 && (sorted[j].x < sorted[j - 1].x ||
                                  (sorted[j].x == sorted[j - 1].x && sorted[j].y < sorted[j - 1].y)); --j) {
            kg_vec2 t = sorted[j];
            sorted[j] = sorted[j - 1];
            sorted[j - 1] = t;
        }
    }
    int k = 0;
    for (int i = 0; i < n; ++i) {
        while (k >= 2 && cross_d(hull[k - 2], hull[k - 1], sorted[i]) <= 0.0) {
            k--;
        }
        hull[k++] = sorted[i];
    }
    for (int i = n - 2, lower = k + 1; i >= 0; --i) {
        while (k >= lower && cross_d(hull[k - 2], hull[k - 1], sorted[i]) <= 0.0) {
            k--;
        }
        hull[k++] = sorted[i];
    }
    double area = 0.0;
    for (int i = 0; i + 1 < k; ++i) {
        area += (double)hull[i].x * hull[i + 1].y - (double)hull[i].y * hull[i + 1].x;
    }
    return 0.5 * area;
}

/* Largest coordinate magnitude: the scale rounding errors are relative to. */
static double points_scale(const kg_vec2* points, int n)
{
    double scale = 0.0;
    for (int i = 0; i < n; ++i) {
        scale = fmax(scale, fmax(fabs((double)points[i].x), fabs((double)points[i].y)));
    }
    return scale;
}

static int all_finite(const kg_vec2* points, int n)
{
    for (int i = 0; i < n; ++i) {
        if (!finite_vec(points[i])) {
            return 0;
        }
    }
    return 1;
}

/* Input the builder has no excuse to refuse: finite, sane coordinates, a hull that is
 * far from a sliver (area at least 1% of the bounding scale squared), sane density. */
static int well_conditioned(const hull_input* in)
{
    if (in->def.type != KG_SHAPE_POLYGON || in->def.count < 3 || in->def.count > KG_MAX_POLYGON_VERTICES ||
        !all_finite(in->points, in->point_count)) {
        return 0;
    }
    double scale = points_scale(in->points, in->point_count);
    double area = reference_hull_area(in->points, in->point_count);
    int density_ok = in->density >= 1.0e-3f && in->density <= 1.0e3f;
    return density_ok && scale >= 1.0 && scale <= 1.0e4 && area >= 0.01 * scale * scale;
}

static void check_polygon(const kg_shape* s, const hull_input* in)
{
    FUZZ_REQUIRE(s->count >= 3 && s->count <= KG_MAX_POLYGON_VERTICES, "hull vertex count in [3, 8]");
    double scale = points_scale(in->points, in->point_count);
    for (int i = 0; i < s->count; ++i) {
        kg_vec2 a = s->vertices[i], b = s->vertices[(i + 1) % s->count], c = s->vertices[(i + 2) % s->count];
        FUZZ_REQUIRE(finite_vec(a), "hull vertices are finite");
        FUZZ_REQUIRE(fabsf(hypotf(s->normals[i].x, s->normals[i].y) - 1.0f) < 1.0e-3f, "hull normals are unit");
        double edge = hypot((double)b.x - a.x, (double)b.y - a.y);
        double next = hypot((double)c.x - b.x, (double)c.y - b.y);
        FUZZ_REQUIRE(cross_d(a, b, c) >= -1.0e-4 * edge * next, "hull is convex and counter-clockwise");
        double along_right_perp = (double)s->normals[i].x * (b.y - a.y) - (double)s->normals[i].y * (b.x - a.x);
        FUZZ_REQUIRE(along_right_perp >= 0.999 * edge, "normal is the outward perpendicular of its edge");
        for (int k = 0; k < in->point_count; ++k) {
            double distance_inside = cross_d(a, b, in->points[k]) / edge;
            FUZZ_REQUIRE(distance_inside >= -(2.0 * KG_WELD_DISTANCE + 1.0e-5 * scale), "hull contains every input point");
        }
    }
}

static void check_mass(const kg_mass_data* md, kg_shape_type type)
{
    if (type == KG_SHAPE_NONE) {
        FUZZ_REQUIRE(md->mass == 0.0f, "a point has no mass of its own");
    } else {
        FUZZ_REQUIRE(isfinite(md->mass) && md->mass > 0.0f, "mass is finite and > 0");
    }
    FUZZ_REQUIRE(isfinite(md->inertia) && md->inertia >= 0.0f, "inertia is finite and >= 0");
    FUZZ_REQUIRE(finite_vec(md->center), "centre of mass is finite");
}

static void check_two_point(const kg_shape* s, const kg_shape_def* def)
{
    FUZZ_REQUIRE(s->count == 2 && s->radius == def->radius, "a capsule or segment keeps its count and radius");
    FUZZ_REQUIRE(memcmp(s->vertices, def->vertices, 2 * sizeof s->vertices[0]) == 0, "and its two points");
    FUZZ_REQUIRE(fabsf(hypotf(s->normals[0].x, s->normals[0].y) - 1.0f) < 1.0e-3f, "its normal is unit");
    FUZZ_REQUIRE(s->normals[1].x == -s->normals[0].x && s->normals[1].y == -s->normals[0].y, "its normals are opposite");
}

static void check_area_matches_reference(const kg_mass_data* md, const hull_input* in)
{
    double area = reference_hull_area(in->points, in->point_count);
    double scale = points_scale(in->points, in->point_count);
    double engine_area = (double)md->mass / in->density;
    FUZZ_REQUIRE(fabs(engine_area - area) <= 1.0e-3 * area + 1.0e-3 * scale, "area matches the reference hull");
}

static int body_state_finite(const kg_world* world, kg_body body)
{
    kg_body_state st;
    if (kg_body_get_state(world, body, &st) != KG_OK) {
        return 0;
    }
    return finite_vec(st.position) && isfinite(st.angle) && finite_vec(st.velocity) && isfinite(st.angular_velocity);
}

/* The shape a body reports must build again, into no more vertices than it has. */
static void check_round_trip(const kg_world* world, kg_body body, const kg_shape* built)
{
    kg_shape_def back;
    FUZZ_REQUIRE(kg_body_get_shape(world, body, &back) == KG_OK, "a live body reports its shape");
    kg_shape rebuilt;
    FUZZ_REQUIRE(kg_shape_build(&back, &rebuilt) == KG_OK, "a reported shape builds again");
    FUZZ_REQUIRE(rebuilt.count <= built->count || built->count == 1, "rebuilding never adds vertices");
}

static void step_as_body(const hull_input* in, const kg_shape* built)
{
    kg_world_def wd = kg_default_world_def();
    wd.max_bodies = 4;
    wd.backend = KG_BACKEND_CPU;
    kg_world* world = NULL;
    FUZZ_REQUIRE(kg_create_world(&wd, &world) == KG_OK, "a small world is created");
    kg_body_def ground = kg_default_body_def();
    ground.type = KG_BODY_STATIC;
    ground.shape = kg_box_shape(20.0f, 1.0f);
    kg_body ground_body;
    FUZZ_REQUIRE(kg_create_body(world, &ground, &ground_body) == KG_OK, "the ground is created");
    kg_body_def ball = kg_default_body_def();
    ball.shape = kg_circle_shape(0.25f);
    ball.position = (kg_vec2){0.1f, 4.0f};
    kg_body ball_body;
    FUZZ_REQUIRE(kg_create_body(world, &ball, &ball_body) == KG_OK, "the ball is created");
    kg_body_def bd = kg_default_body_def();
    bd.type = in->def.type == KG_SHAPE_NONE ? KG_BODY_PARTICLE : KG_BODY_DYNAMIC;
    if (in->def.type == KG_SHAPE_SEGMENT) {
        FUZZ_REQUIRE(kg_check_body_def(&(kg_body_def){.type = KG_BODY_DYNAMIC, .shape = in->def, .mass = 1.0f}) ==
                         KG_ERROR_INVALID_ARGUMENT,
                     "a segment is refused on a dynamic body");
        bd.type = KG_BODY_STATIC;
    }
    bd.shape = in->def;
    bd.density = in->density;
    bd.mass = bd.type == KG_BODY_PARTICLE ? 1.0f : 0.0f;
    bd.position = (kg_vec2){0.0f, 2.0f};
    kg_body body;
    kg_result r = kg_create_body(world, &bd, &body);
    FUZZ_REQUIRE(r == KG_OK || kg_last_error()[0] != '\0', "a refused body has a message");
    if (r == KG_OK) {
        check_round_trip(world, body, built);
        for (int i = 0; i < 8; ++i) {
            FUZZ_REQUIRE(kg_world_step(world, 1.0f / 60.0f) == KG_OK, "the world steps");
        }
        FUZZ_REQUIRE(body_state_finite(world, body), "the body's state stays finite");
        FUZZ_REQUIRE(body_state_finite(world, ground_body), "the ground's state stays finite");
        FUZZ_REQUIRE(body_state_finite(world, ball_body), "the ball's state stays finite");
    }
    kg_destroy_world(world);
}

/* A segment has no mass, so it is built and stepped (as a static body) on its own. */
static void check_segment(const hull_input* in)
{
    kg_mass_data md;
    FUZZ_REQUIRE(kg_shape_mass(&in->def, in->density, &md) != KG_OK, "a segment has no mass");
    kg_shape built;
    kg_result r = kg_shape_build(&in->def, &built);
    FUZZ_REQUIRE(r == KG_OK || r == KG_ERROR_INVALID_ARGUMENT || r == KG_ERROR_DEGENERATE_SHAPE,
                 "a segment builds or is refused with a documented code");
    if (r == KG_OK) {
        check_two_point(&built, &in->def);
        step_as_body(in, &built);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    hull_input in = read_input(data, size);
    if (in.def.type == KG_SHAPE_SEGMENT) {
        check_segment(&in);
        return 0;
    }
    kg_mass_data md;
    kg_result r = kg_shape_mass(&in.def, in.density, &md);
    FUZZ_REQUIRE(r == KG_OK || r == KG_ERROR_INVALID_ARGUMENT || r == KG_ERROR_DEGENERATE_SHAPE,
                 "kg_shape_mass answers a documented code");
    FUZZ_REQUIRE(r == KG_OK || kg_last_error()[0] != '\0', "a refused shape has a message");
    FUZZ_REQUIRE(r == KG_OK || !well_conditioned(&in), "a well-conditioned polygon is accepted");
    if (r != KG_OK) {
        return 0;
    }
    check_mass(&md, in.def.type);
    kg_shape built;
    FUZZ_REQUIRE(kg_shape_build(&in.def, &built) == KG_OK, "a shape with a mass builds");
    if (in.def.type == KG_SHAPE_POLYGON) {
        check_polygon(&built, &in);
    }
    if (in.def.type == KG_SHAPE_CAPSULE) {
        check_two_point(&built, &in.def);
    }
    if (well_conditioned(&in)) {
        check_area_matches_reference(&md, &in);
    }
    step_as_body(&in, &built);
    return 0;
}
