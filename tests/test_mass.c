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

KG_TEST_MAIN(KG_TEST(test_box_mass_is_analytic), KG_TEST(test_circle_mass_is_analytic),
             KG_TEST(test_random_polygons_match_reference), KG_TEST(test_hull_drops_duplicates_and_collinear_points),
             KG_TEST(test_explicit_mass_scales_inertia))
