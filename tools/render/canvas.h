/* A software canvas of palette indices and the few primitives a physics debug view
 * needs: filled convex polygons and circles, lines, rectangles and text. Coordinates are
 * pixels, x right and y down, as floats; a pixel is covered when its centre is inside.
 * Everything is clipped to the canvas, so callers may pass shapes far off screen. */
#ifndef KG_RENDER_CANVAS_H
#define KG_RENDER_CANVAS_H

#include <stdint.h>

typedef struct kg_canvas {
    int width, height;
    uint8_t* pixels; /* width * height palette indices, row by row from the top */
} kg_canvas;

typedef struct kg_point {
    float x, y;
} kg_point;

/* 0 on success, -1 when out of memory or the size is not in [1, 16384]. */
int kg_canvas_init(kg_canvas* canvas, int width, int height);
void kg_canvas_free(kg_canvas* canvas);

void kg_canvas_clear(kg_canvas* canvas, uint8_t color);
/* The colour at (x, y), or -1 outside the canvas. */
int kg_canvas_get(const kg_canvas* canvas, int x, int y);

/* points go round the polygon in either direction; it must be convex. */
void kg_canvas_fill_convex(kg_canvas* canvas, const kg_point* points, int count, uint8_t color);
void kg_canvas_outline(kg_canvas* canvas, const kg_point* points, int count, uint8_t color);
void kg_canvas_fill_circle(kg_canvas* canvas, kg_point center, float radius, uint8_t color);
void kg_canvas_circle(kg_canvas* canvas, kg_point center, float radius, uint8_t color);
void kg_canvas_line(kg_canvas* canvas, kg_point a, kg_point b, uint8_t color);
void kg_canvas_rect(kg_canvas* canvas, kg_point lower, kg_point upper, uint8_t color);
void kg_canvas_fill_rect(kg_canvas* canvas, int x, int y, int width, int height, uint8_t color);

/* Text in the built-in 3x5 font, each font pixel drawn as scale x scale pixels; lower
 * case is shown as upper case. Returns the x after the last character. */
int kg_canvas_text(kg_canvas* canvas, int x, int y, int scale, const char* text, uint8_t color);
/* Text with a one-pixel dark shadow, readable over any scene. */
int kg_canvas_label(kg_canvas* canvas, int x, int y, int scale, const char* text);
/* Width in pixels of text drawn at scale. */
int kg_text_width(const char* text, int scale);

#endif
