/* Drawing a kgyro world on a canvas: a camera that maps metres to pixels, bodies in
 * flat colours with outlines, and optional contacts, bounding boxes and tile layers. */
#ifndef KG_RENDER_DRAW_H
#define KG_RENDER_DRAW_H

#include "canvas.h"

#include "kgyro/kgyro.h"

/* World y points up, screen y down. center is the world point at the canvas centre. */
typedef struct kg_camera {
    kg_vec2 center;
    float scale; /* pixels per metre */
    int width, height;
} kg_camera;

kg_point kg_camera_to_screen(const kg_camera* camera, kg_vec2 world);
kg_vec2 kg_camera_to_world(const kg_camera* camera, kg_point screen);
/* The camera that shows box whole, centred, with margin (a fraction of the box size)
 * on every side, on a width x height canvas. */
kg_camera kg_camera_fit(kg_aabb box, int width, int height, float margin);
/* Zooms by factor keeping the world point under screen point fixed. */
void kg_camera_zoom_at(kg_camera* camera, kg_point screen, float factor);

/* The box a camera should show for a world: every moving body, and the static ones and
 * tile maps only where they are near the moving ones, so that a long floor does not
 * shrink the scene. Returns 0 when the world has neither bodies nor tile maps. */
int kg_world_view_box(const kg_world* world, kg_aabb* out);

/* One tile id's look: a convex polygon in the tile's unit square (0..1, y up), filled,
 * outlined, or drawn as a one-way platform. count 0 is an empty tile. */
typedef struct kg_tile_look {
    int count;
    kg_vec2 vertices[KG_MAX_POLYGON_VERTICES];
    int one_way;
} kg_tile_look;

/* A grid of tile ids as the renderer sees it; the adapter from a world's tile maps
 * (tiles.h) fills one of these per layer. cells[y * width + x] with row 0 at the
 * bottom, at world origin + (x, y) * tile_size. ids outside [0, look_count) are empty. */
typedef struct kg_tile_layer {
    kg_vec2 origin;
    kg_vec2 tile_size;
    int width, height;
    const int* cells;
    const kg_tile_look* looks;
    int look_count;
} kg_tile_layer;

typedef struct kg_draw_options {
    int contacts; /* contact points and normals */
    int aabbs;    /* bounding boxes */
    int tiles;    /* the tile layers */
    int grid;     /* a faint metre grid under everything */
    const kg_tile_layer* tile_layers;
    int tile_layer_count;
} kg_draw_options;

/* Clears the canvas and draws the world: tiles, bodies, then the overlays. */
void kg_draw_world(kg_canvas* canvas, const kg_camera* camera, const kg_world* world,
                   const kg_draw_options* options);

void kg_draw_tile_layer(kg_canvas* canvas, const kg_camera* camera, const kg_tile_layer* layer);

/* Cells x0..x1, y0..y1, bounds included. */
typedef struct kg_cell_range {
    int x0, y0, x1, y1;
} kg_cell_range;

/* The cells of layer that camera shows; 0 when it shows none. */
int kg_tile_layer_visible(const kg_camera* camera, const kg_tile_layer* layer, kg_cell_range* out);
/* One body with its shape at its current pose, in the colours of its type. */
void kg_draw_body(kg_canvas* canvas, const kg_camera* camera, const kg_world* world, kg_body body);
/* The fill and outline colours of a body by type and handle index. */
void kg_body_colors(kg_body_type type, kg_body body, uint8_t* fill, uint8_t* line);

#endif
