/* Drawing a kgyro world on a canvas: a camera that maps metres to pixels, bodies in
 * flat colours with outlines, and optional contacts, bounding boxes and tile maps, all
 * walked by the library's debug draw (kg_world_draw) and rasterised here. */
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

/* The box a camera should show for a world: the whole level, every body (static ones
 * included) and every tile map whole. Returns 0 when the world has neither bodies nor
 * tile maps. */
int kg_world_view_box(const kg_world* world, kg_aabb* out);

typedef struct kg_draw_options {
    int contacts; /* contact points and normals */
    int aabbs;    /* bounding boxes */
    int tiles;    /* the tile maps */
    int grid;     /* a faint metre grid under everything */
} kg_draw_options;

/* Clears the canvas and draws what the camera shows of the world through kg_world_draw
 * (kgyro/debug_draw.h): tiles, bodies, then the overlays. */
void kg_draw_world(kg_canvas* canvas, const kg_camera* camera, const kg_world* world,
                   const kg_draw_options* options);

#endif
