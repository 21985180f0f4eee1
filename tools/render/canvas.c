#include "canvas.h"
#include "palette.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Beyond this many pixels off the canvas a coordinate is treated as off screen, which
 * keeps float to int conversions defined for bodies that fell far away. */
#define KG_FAR_OFF 1.0e6f

int kg_canvas_init(kg_canvas* canvas, int width, int height)
{
    canvas->width = width;
    canvas->height = height;
    canvas->pixels = NULL;
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        return -1;
    }
    canvas->pixels = calloc((size_t)width * (size_t)height, 1);
    return canvas->pixels ? 0 : -1;
}

void kg_canvas_free(kg_canvas* canvas)
{
    free(canvas->pixels);
    canvas->pixels = NULL;
}

void kg_canvas_clear(kg_canvas* canvas, uint8_t color)
{
    memset(canvas->pixels, color, (size_t)canvas->width * (size_t)canvas->height);
}

int kg_canvas_get(const kg_canvas* canvas, int x, int y)
{
    if (x < 0 || y < 0 || x >= canvas->width || y >= canvas->height) {
        return -1;
    }
    return canvas->pixels[(size_t)y * (size_t)canvas->width + (size_t)x];
}

static void kg_plot(kg_canvas* canvas, int x, int y, uint8_t color)
{
    if (x >= 0 && y >= 0 && x < canvas->width && y < canvas->height) {
        canvas->pixels[(size_t)y * (size_t)canvas->width + (size_t)x] = color;
    }
}

/* Fills pixels x0..x1-1 of row y, clipped. */
static void kg_span(kg_canvas* canvas, int y, int x0, int x1, uint8_t color)
{
    if (y < 0 || y >= canvas->height) {
        return;
    }
    x0 = x0 < 0 ? 0 : x0;
    x1 = x1 > canvas->width ? canvas->width : x1;
    if (x1 > x0) {
        memset(canvas->pixels + (size_t)y * (size_t)canvas->width + (size_t)x0, color, (size_t)(x1 - x0));
    }
}

static int kg_finite_point(kg_point p) { return fabsf(p.x) < KG_FAR_OFF && fabsf(p.y) < KG_FAR_OFF; }

/* The first pixel whose centre is at or after coordinate v. */
static int kg_first_center(float v) { return (int)ceilf(v - 0.5f); }

void kg_canvas_fill_convex(kg_canvas* canvas, const kg_point* points, int count, uint8_t color)
{
    float top = KG_FAR_OFF, bottom = -KG_FAR_OFF;
    for (int i = 0; i < count; ++i) {
        if (!kg_finite_point(points[i])) {
            return;
        }
        top = fminf(top, points[i].y);
        bottom = fmaxf(bottom, points[i].y);
    }
    int y0 = kg_first_center(top), y1 = kg_first_center(bottom);
    y0 = y0 < 0 ? 0 : y0;
    y1 = y1 > canvas->height ? canvas->height : y1;
    for (int y = y0; y < y1; ++y) {
        float center = (float)y + 0.5f, left = KG_FAR_OFF, right = -KG_FAR_OFF;
        for (int i = 0; i < count; ++i) {
            kg_point a = points[i], b = points[(i + 1) % count];
            if ((a.y <= center && b.y > center) || (b.y <= center && a.y > center)) {
                float x = a.x + (center - a.y) * (b.x - a.x) / (b.y - a.y);
                left = fminf(left, x);
                right = fmaxf(right, x);
            }
        }
        if (left <= right) {
            kg_span(canvas, y, kg_first_center(left), kg_first_center(right), color);
        }
    }
}

void kg_canvas_outline(kg_canvas* canvas, const kg_point* points, int count, uint8_t color)
{
    for (int i = 0; i < count; ++i) {
        kg_canvas_line(canvas, points[i], points[(i + 1) % count], color);
    }
}

void kg_canvas_fill_circle(kg_canvas* canvas, kg_point center, float radius, uint8_t color)
{
    if (!kg_finite_point(center) || !(radius < KG_FAR_OFF)) {
        return;
    }
    int y0 = kg_first_center(center.y - radius), y1 = kg_first_center(center.y + radius);
    y0 = y0 < 0 ? 0 : y0;
    y1 = y1 > canvas->height ? canvas->height : y1;
    for (int y = y0; y < y1; ++y) {
        float dy = (float)y + 0.5f - center.y;
        float half = sqrtf(fmaxf(radius * radius - dy * dy, 0.0f));
        kg_span(canvas, y, kg_first_center(center.x - half), kg_first_center(center.x + half), color);
    }
}

/* A circle outline as a polygon fine enough that its segments are about 3 pixels long. */
void kg_canvas_circle(kg_canvas* canvas, kg_point center, float radius, uint8_t color)
{
    if (!kg_finite_point(center) || !(radius < KG_FAR_OFF)) {
        return;
    }
    int segments = (int)(2.0f * 3.14159265f * radius / 3.0f);
    segments = segments < 8 ? 8 : (segments > 256 ? 256 : segments);
    kg_point previous = {center.x + radius, center.y};
    for (int i = 1; i <= segments; ++i) {
        float angle = 2.0f * 3.14159265f * (float)i / (float)segments;
        kg_point next = {center.x + radius * cosf(angle), center.y + radius * sinf(angle)};
        kg_canvas_line(canvas, previous, next, color);
        previous = next;
    }
}

/* Liang-Barsky: clips the segment to the canvas (with a pixel of slack); 0 when none of
 * it is left. */
static int kg_clip_line(const kg_canvas* canvas, kg_point* a, kg_point* b)
{
    float t0 = 0.0f, t1 = 1.0f, dx = b->x - a->x, dy = b->y - a->y;
    float p[4] = {-dx, dx, -dy, dy};
    float q[4] = {a->x + 1.0f, (float)canvas->width - a->x, a->y + 1.0f, (float)canvas->height - a->y};
    for (int i = 0; i < 4; ++i) {
        if (p[i] == 0.0f) {
            if (q[i] < 0.0f) {
                return 0;
            }
            continue;
        }
        float t = q[i] / p[i];
        if (p[i] < 0.0f) {
            t0 = fmaxf(t0, t);
        } else {
            t1 = fminf(t1, t);
        }
    }
    if (t0 > t1) {
        return 0;
    }
    kg_point start = {a->x + t0 * dx, a->y + t0 * dy}, end = {a->x + t1 * dx, a->y + t1 * dy};
    *a = start;
    *b = end;
    return 1;
}

/* Bresenham between the pixels holding the two end points. */
void kg_canvas_line(kg_canvas* canvas, kg_point a, kg_point b, uint8_t color)
{
    if (!kg_finite_point(a) || !kg_finite_point(b) || !kg_clip_line(canvas, &a, &b)) {
        return;
    }
    int x0 = (int)floorf(a.x), y0 = (int)floorf(a.y), x1 = (int)floorf(b.x), y1 = (int)floorf(b.y);
    int dx = abs(x1 - x0), dy = -abs(y1 - y0);
    int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    int error = dx + dy;
    for (;;) {
        kg_plot(canvas, x0, y0, color);
        if (x0 == x1 && y0 == y1) {
            break;
        }
        int twice = 2 * error;
        if (twice >= dy) {
            error += dy;
            x0 += sx;
        }
        if (twice <= dx) {
            error += dx;
            y0 += sy;
        }
    }
}

void kg_canvas_rect(kg_canvas* canvas, kg_point lower, kg_point upper, uint8_t color)
{
    kg_point corners[4] = {lower, {upper.x, lower.y}, upper, {lower.x, upper.y}};
    kg_canvas_outline(canvas, corners, 4, color);
}

void kg_canvas_fill_rect(kg_canvas* canvas, int x, int y, int width, int height, uint8_t color)
{
    for (int row = y; row < y + height; ++row) {
        kg_span(canvas, row, x, x + width, color);
    }
}

/* 3x5 glyphs for ' ' to '_', one bit per pixel, rows from the top, most significant
 * bit first: bit 14 is the top-left pixel. */
static const uint16_t kGlyphs[64] = {
    0x0000, 0x2482, 0x5a00, 0x5f7d, 0x3c9e, 0x52a5, 0x2aab, 0x2400, /*  !"#$%&' */
    0x2922, 0x224a, 0x0aa8, 0x05d0, 0x0014, 0x01c0, 0x0002, 0x12a4, /* ()*+,-./ */
    0x7b6f, 0x2c97, 0x73e7, 0x72cf, 0x5bc9, 0x79cf, 0x79ef, 0x7292, /* 01234567 */
    0x7bef, 0x7bcf, 0x0410, 0x0414, 0x1511, 0x0e38, 0x4454, 0x72c2, /* 89:;<=>? */
    0x2be3, 0x2bed, 0x6bae, 0x3923, 0x6b6e, 0x79a7, 0x79a4, 0x396b, /* @ABCDEFG */
    0x5bed, 0x7497, 0x126a, 0x5bad, 0x4927, 0x5fed, 0x6b6d, 0x2b6a, /* HIJKLMNO */
    0x6ba4, 0x2b73, 0x6bad, 0x388e, 0x7492, 0x5b6f, 0x5b6a, 0x5bfd, /* PQRSTUVW */
    0x5aad, 0x5a92, 0x72a7, 0x3493, 0x4889, 0x6496, 0x2a00, 0x0007, /* XYZ[\]^_ */
};

static uint16_t kg_glyph(char c)
{
    if (c >= 'a' && c <= 'z') {
        c = (char)(c - 'a' + 'A');
    }
    if (c < ' ' || c > '_') {
        c = '?';
    }
    return kGlyphs[c - ' '];
}

int kg_text_width(const char* text, int scale) { return (int)strlen(text) * 4 * scale; }

int kg_canvas_text(kg_canvas* canvas, int x, int y, int scale, const char* text, uint8_t color)
{
    for (; *text; ++text, x += 4 * scale) {
        uint16_t glyph = kg_glyph(*text);
        for (int bit = 0; bit < 15; ++bit) {
            if (glyph & (1u << (14 - bit))) {
                kg_canvas_fill_rect(canvas, x + (bit % 3) * scale, y + (bit / 3) * scale, scale, scale, color);
            }
        }
    }
    return x;
}

int kg_canvas_label(kg_canvas* canvas, int x, int y, int scale, const char* text)
{
    kg_canvas_text(canvas, x + 1, y + 1, scale, text, KG_COLOR_TEXT_SHADOW);
    return kg_canvas_text(canvas, x, y, scale, text, KG_COLOR_TEXT);
}
