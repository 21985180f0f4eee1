/* Mass properties against analytic values and an independent double-precision
 * computation (shoelace / Green's theorem), for boxes, circles and random polygons. */
#include "kg_test.h"
#include "kgyro/kgyro.h"

#include <string.h>

static uint32_t g_seed = 12345u;
static double rnd(double lo, double hi)
{
    g_seed = g_seed * 1664525u + 1013904223u;
    return lo + (hi - lo) * (double)(g_seed >> 8) / 16777216.0;
}

#define PI_D 3.14159265358979323846

typedef struct ref_mass {
    double mass, cx, cy, inertia;
} ref_mass;

/* Green's theorem over a counter-clockwise polygon, in double. */
static ref_mass polygon_reference(const double* x, const double* y, int n, double density)
{
    double a = 0, cx = 0, cy = 0, ixx = 0;
    for (int i = 0; i < n; ++i) {
        int j = (i + 1) % n;
        double cr = x[i] * y[j] - x[j] * y[i];
        a += cr;
        cx += (x[i] + x[j]) * cr;
        cy += (y[i] + y[j]) * cr;
        ixx += cr * (x[i] * x[i] + x[i] * x[j] + x[j] * x[j] + y[i] * y[i] + y[i] * y[j] + y[j] * y[j]);
    }
    a *= 0.5;
    ref_mass r;
    r.mass = density * a;
    r.cx = cx / (6.0 * a);
    r.cy = cy / (6.0 * a);
    r.inertia = density * ixx / 12.0 - r.mass * (r.cx * r.cx + r.cy * r.cy);
    return r;
}

/* A vertex this close to the line through its neighbours is dropped by the hull on
 * purpose (as collinear), so such inputs cannot be compared with the raw polygon. */
static int has_near_collinear_vertex(const double* x, const double* y, int n)
{
    for (int i = 0; i < n; ++i) {
        int a = (i + n - 1) % n, b = (i + 1) % n;
        double ex = x[b] - x[a], ey = y[b] - y[a];
        double dist = fabs(ex * (y[i] - y[a]) - ey * (x[i] - x[a])) / hypot(ex, ey);
        if (dist < 1e-3) {
            return 1;
        }
    }
    return 0;
}

static void test_box_mass_is_analytic(void)
{
    kg_shape_def box = kg_box_shape(2.0f, 0.5f);
    kg_mass_data md;
    KG_CHECK_OK(kg_shape_mass(&box, 3.0f, &md));
    KG_CHECK_NEAR(md.mass, 3.0 * 2.0 * 0.5, 1e-6);
    KG_CHECK_NEAR(md.inertia, md.mass * (4.0 + 0.25) / 12.0, 1e-6);
    KG_CHECK_NEAR(md.center.x, 0.0, 1e-7);
    KG_CHECK_NEAR(md.center.y, 0.0, 1e-7);
    kg_shape_def off = kg_offset_box_shape(1.0f, 1.0f, (kg_vec2){3.0f, -2.0f}, 0.7f);
    KG_CHECK_OK(kg_shape_mass(&off, 1.0f, &md));
    KG_CHECK_NEAR(md.mass, 1.0, 1e-5);
    KG_CHECK_NEAR(md.center.x, 3.0, 1e-5);
    KG_CHECK_NEAR(md.center.y, -2.0, 1e-5);
    KG_CHECK_NEAR(md.inertia, 1.0 / 6.0, 1e-5); /* about the centroid, whatever the offset */
}

static void test_circle_mass_is_analytic(void)
{
    kg_shape_def c = kg_circle_shape(0.75f);
    kg_mass_data md;
    KG_CHECK_OK(kg_shape_mass(&c, 2.0f, &md));
    double m = 2.0 * 3.14159265358979 * 0.75 * 0.75;
    KG_CHECK_NEAR(md.mass, m, 1e-5 * m);
    KG_CHECK_NEAR(md.inertia, 0.5 * m * 0.75 * 0.75, 1e-5 * m);
}

/* Random convex polygons (points on random ellipses), handed over shuffled and with a
 * duplicate and a collinear point added: the hull must recover the same polygon. */
static void test_random_polygons_match_reference(void)
{
    int cases = 2000, worst_case = -1, skipped = 0;
    double worst = 0.0;
    for (int c = 0; c < cases; ++c) {
        int n = 3 + (int)rnd(0, 4.999); /* 3..7, leaving room for one extra point */
        double ax = rnd(0.1, 4.0), ay = rnd(0.1, 4.0), ox = rnd(-10, 10), oy = rnd(-10, 10);
        double angles[8], x[8], y[8];
        for (int i = 0; i < n; ++i) {
            angles[i] = rnd(0, 6.283185307);
        }
        for (int i = 1; i < n; ++i) { /* sort: counter-clockwise order for the reference */
            for (int j = i; j > 0 && angles[j] < angles[j - 1]; --j) {
                double t = angles[j];
                angles[j] = angles[j - 1];
                angles[j - 1] = t;
            }
        }
        for (int i = 0; i < n; ++i) {
            x[i] = ox + ax * cos(angles[i]);
            y[i] = oy + ay * sin(angles[i]);
        }
        ref_mass ref = polygon_reference(x, y, n, 1.5);
        if (ref.mass < 0.05 || has_near_collinear_vertex(x, y, n)) {
            skipped++;
            continue;
        }
        kg_vec2 v[8];
        int m = 0;
        for (int i = n - 1; i >= 0; --i) { /* clockwise order: any order is accepted */
            v[m++] = (kg_vec2){(float)x[i], (float)y[i]};
        }
        v[m++] = c % 2 ? v[0] : (kg_vec2){(float)(0.5 * (x[0] + x[1])), (float)(0.5 * (y[0] + y[1]))};
        kg_shape_def def = kg_polygon_shape(v, m);
        kg_mass_data md;
        KG_CHECK_OK(kg_shape_mass(&def, 1.5f, &md));
        double err_m = fabs(md.mass - ref.mass) / ref.mass;
        double size = sqrt(ref.mass / 1.5);
        double err_c = hypot(md.center.x - ref.cx, md.center.y - ref.cy) / size;
        double err_i = fabs(md.inertia - ref.inertia) / ref.inertia;
        double err = fmax(err_m, fmax(err_c, err_i));
        if (err > worst) {
            worst = err;
            worst_case = c;
        }
    }
    if (worst > 2e-4) {
        fprintf(stderr, "worst relative error %.3g in case %d\n", worst, worst_case);
    }
    KG_CHECK(worst <= 2e-4);
    KG_CHECK(skipped < cases / 10);
}

static void test_hull_drops_duplicates_and_collinear_points(void)
{
    kg_vec2 pts[8] = {{0, 0}, {2, 0}, {1, 0}, {2, 2}, {0, 2}, {2, 2}, {1, 1}, {0, 1}};
    kg_world_def wd = kg_default_world_def();
    wd.backend = KG_BACKEND_CPU;
    kg_world* w;
    KG_CHECK_OK(kg_create_world(&wd, &w));
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_polygon_shape(pts, 8);
    kg_body b;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    kg_shape_def out;
    KG_CHECK_OK(kg_body_get_shape(w, b, &out));
    KG_CHECK(out.type == KG_SHAPE_POLYGON);
    KG_CHECK(out.count == 4);
    kg_mass_data md;
    KG_CHECK_OK(kg_body_get_mass_data(w, b, &md));
    KG_CHECK_NEAR(md.mass, 4.0, 1e-5);
    KG_CHECK_NEAR(md.center.x, 1.0, 1e-6);
    kg_vec2 too_many[9] = {{0, 0}, {1, 0}, {2, 0}, {3, 1}, {3, 2}, {2, 3}, {1, 3}, {0, 2}, {-1, 1}};
    bd.shape = kg_polygon_shape(too_many, 9);
    KG_CHECK(bd.shape.count == 9);
    KG_CHECK(kg_create_body(w, &bd, &b) == KG_ERROR_DEGENERATE_SHAPE);
    kg_destroy_world(w);
}

static void test_explicit_mass_scales_inertia(void)
{
    kg_world_def wd = kg_default_world_def();
    kg_world* w;
    KG_CHECK_OK(kg_create_world(&wd, &w));
    kg_body_def bd = kg_default_body_def();
    bd.shape = kg_box_shape(1.0f, 3.0f);
    bd.mass = 6.0f;
    kg_body b;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    float im, ii;
    KG_CHECK_OK(kg_body_get_inverse_mass(w, b, &im, &ii));
    KG_CHECK_NEAR(im, 1.0 / 6.0, 1e-7);
    KG_CHECK_NEAR(ii, 1.0 / (6.0 * (1.0 + 9.0) / 12.0), 1e-6);
    bd.fixed_rotation = 1;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    KG_CHECK_OK(kg_body_get_inverse_mass(w, b, &im, &ii));
    KG_CHECK(ii == 0.0f);
    bd.type = KG_BODY_STATIC;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    KG_CHECK_OK(kg_body_get_inverse_mass(w, b, &im, &ii));
    KG_CHECK(im == 0.0f && ii == 0.0f);
    kg_destroy_world(w);
}

/* A capsule of core length L and radius r, about its middle: the 2r by L rectangle, and two
 * half discs, each taken about its flat side's middle (half a disc's m r^2 / 2), moved to its
 * centroid 4r / (3 pi) out and from there to the capsule's middle (parallel axis twice). */
static ref_mass capsule_analytic(double length, double r, double density)
{
    double box = density * 2.0 * r * length, disc = density * PI_D * r * r;
    double half_disc_centroid = 4.0 * r / (3.0 * PI_D); /* from its flat side */
    double h = 0.5 * length;
    /* one half disc about the capsule's middle: about its centroid, then shifted out */
    double own = 0.5 * (0.5 * disc) * r * r - 0.5 * disc * half_disc_centroid * half_disc_centroid;
    double shifted = own + 0.5 * disc * (h + half_disc_centroid) * (h + half_disc_centroid);
    ref_mass m;
    m.mass = box + disc;
    m.cx = 0.0;
    m.cy = 0.0;
    m.inertia = box * (length * length + 4.0 * r * r) / 12.0 + 2.0 * shifted;
    return m;
}

/* The same capsule as a polygon of 2 x 4000 points round its outline, by Green's theorem:
 * an independent check of the closed form (the polygon's missing slivers are of order n^-2). */
static ref_mass capsule_outline(double length, double r, double density)
{
    enum { N = 4000 };
    static double x[2 * N], y[2 * N];
    for (int i = 0; i < N; ++i) {
        double a = -0.5 * PI_D + PI_D * i / (N - 1);
        x[i] = 0.5 * length + r * cos(a);
        y[i] = r * sin(a);
        x[N + i] = -x[i];
        y[N + i] = -y[i];
    }
    return polygon_reference(x, y, 2 * N, density);
}

static void test_capsule_mass_is_analytic(void)
{
    const double cases[][2] = {{2.0, 0.5}, {0.1, 0.5}, {3.0, 0.05}, {0.0002, 1.0}};
    for (int k = 0; k < 4; ++k) {
        double length = cases[k][0], r = cases[k][1], angle = 0.6, cx = 1.5, cy = -0.25;
        kg_vec2 half = {(float)(0.5 * length * cos(angle)), (float)(0.5 * length * sin(angle))};
        kg_vec2 center = {(float)cx, (float)cy};
        kg_shape_def capsule = kg_capsule_shape((kg_vec2){center.x - half.x, center.y - half.y},
                                                (kg_vec2){center.x + half.x, center.y + half.y}, (float)r);
        kg_mass_data md;
        KG_CHECK_OK(kg_shape_mass(&capsule, 2.0f, &md));
        /* the core length the float centres really have */
        double dx = (double)capsule.vertices[1].x - capsule.vertices[0].x;
        double dy = (double)capsule.vertices[1].y - capsule.vertices[0].y;
        ref_mass want = capsule_analytic(hypot(dx, dy), r, 2.0);
        ref_mass outline = capsule_outline(hypot(dx, dy), r, 2.0);
        measured("  capsule L %g r %g: mass %.9g (analytic %.9g), inertia %.9g (analytic %.9g, outline %.9g)\n", length, r,
                 md.mass, want.mass, md.inertia, want.inertia, outline.inertia);
        KG_CHECK_NEAR(want.inertia, outline.inertia, 1e-6 * want.inertia);
        KG_CHECK_NEAR(md.mass, want.mass, 1e-5 * want.mass);
        KG_CHECK_NEAR(md.inertia, want.inertia, 1e-5 * want.inertia);
        KG_CHECK_NEAR(md.center.x, cx, 1e-6);
        KG_CHECK_NEAR(md.center.y, cy, 1e-6);
    }
}

/* A segment has no area: no mass from a density, and no dynamic body or particle of it,
 * whatever mass is given; static and kinematic ones are fine. A capsule and a segment come
 * back from a body as they went in, and a capsule's bounds hold its round ends. */
static void test_segment_mass_and_round_trip(void)
{
    kg_shape_def segment = kg_segment_shape((kg_vec2){-1.0f, 0.5f}, (kg_vec2){2.0f, 0.5f});
    kg_mass_data md;
    KG_CHECK(kg_shape_mass(&segment, 1.0f, &md) == KG_ERROR_INVALID_ARGUMENT);
    kg_world_def wd = kg_default_world_def();
    kg_world* w;
    KG_CHECK_OK(kg_create_world(&wd, &w));
    kg_body_def bd = kg_default_body_def();
    bd.shape = segment;
    bd.mass = 3.0f;
    kg_body b;
    KG_CHECK(kg_create_body(w, &bd, &b) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(strstr(kg_last_error(), "only static and kinematic") != NULL);
    bd.type = KG_BODY_PARTICLE;
    KG_CHECK(kg_create_body(w, &bd, &b) == KG_ERROR_INVALID_ARGUMENT);
    bd.type = KG_BODY_KINEMATIC;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    bd.type = KG_BODY_STATIC;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    KG_CHECK_OK(kg_body_get_mass_data(w, b, &md));
    KG_CHECK(md.mass == 0.0f && md.center.x == 0.5f && md.center.y == 0.5f);
    kg_shape_def back;
    KG_CHECK_OK(kg_body_get_shape(w, b, &back));
    KG_CHECK(back.type == KG_SHAPE_SEGMENT && memcmp(&back, &segment, sizeof back) == 0);

    kg_shape_def capsule = kg_capsule_shape((kg_vec2){0.25f, -1.0f}, (kg_vec2){0.25f, 1.0f}, 0.3f);
    bd = kg_default_body_def();
    bd.shape = capsule;
    KG_CHECK_OK(kg_create_body(w, &bd, &b));
    KG_CHECK_OK(kg_body_get_shape(w, b, &back));
    KG_CHECK(back.type == KG_SHAPE_CAPSULE && memcmp(&back, &capsule, sizeof back) == 0);
    kg_aabb box; /* the core's bounds grown by the radius */
    KG_CHECK_OK(kg_body_get_aabb(w, b, &box));
    KG_CHECK_NEAR(box.lower.x, -0.05, 1e-6);
    KG_CHECK_NEAR(box.upper.x, 0.55, 1e-6);
    KG_CHECK_NEAR(box.lower.y, -1.3, 1e-6);
    KG_CHECK_NEAR(box.upper.y, 1.3, 1e-6);
    kg_destroy_world(w);
}

/* Bad capsules and segments are refused with a clear error, never built. */
static void test_bad_capsules_and_segments_refused(void)
{
    kg_vec2 p = {1.0f, 2.0f}, q = {1.0f, 3.0f}, nan = {NAN, 0.0f}, inf = {INFINITY, 0.0f};
    kg_shape_def bad[] = {kg_capsule_shape(p, p, 0.5f), kg_capsule_shape(p, q, 0.0f), kg_capsule_shape(p, q, -1.0f),
                          kg_capsule_shape(p, q, NAN), kg_capsule_shape(nan, q, 0.5f), kg_capsule_shape(p, inf, 0.5f),
                          kg_segment_shape(p, p), kg_segment_shape(nan, q), kg_segment_shape(p, inf),
                          kg_capsule_shape((kg_vec2){-3e38f, 0.0f}, (kg_vec2){3e38f, 0.0f}, 1.0f)};
    for (int i = 0; i < (int)(sizeof bad / sizeof bad[0]); ++i) {
        kg_body_def bd = kg_default_body_def();
        bd.shape = bad[i];
        bd.type = KG_BODY_STATIC;
        kg_result r = kg_check_body_def(&bd);
        KG_CHECK(r == KG_ERROR_INVALID_ARGUMENT || r == KG_ERROR_DEGENERATE_SHAPE);
        KG_CHECK(strlen(kg_last_error()) > 0);
    }
    KG_CHECK(kg_check_body_def(&(kg_body_def){.type = KG_BODY_DYNAMIC, .shape = kg_capsule_shape(p, q, INFINITY), .density = 1.0f}) != KG_OK);
}

KG_TEST_MAIN(KG_TEST(test_box_mass_is_analytic), KG_TEST(test_circle_mass_is_analytic),
             KG_TEST(test_random_polygons_match_reference), KG_TEST(test_hull_drops_duplicates_and_collinear_points),
             KG_TEST(test_explicit_mass_scales_inertia), KG_TEST(test_capsule_mass_is_analytic),
             KG_TEST(test_segment_mass_and_round_trip), KG_TEST(test_bad_capsules_and_segments_refused))
