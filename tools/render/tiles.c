#include "tiles.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Polygon tile shapes may list their vertices in any order (the library takes the hull),
 * but the canvas fills a polygon in outline order: sort them by angle round the centroid,
 * which is the outline order of a convex polygon. */
static void kg_sort_round(kg_vec2* points, int count)
{
    kg_vec2 centre = {0.0f, 0.0f};
    for (int i = 0; i < count; ++i) {
        centre.x += points[i].x / (float)count;
        centre.y += points[i].y / (float)count;
    }
    for (int i = 1; i < count; ++i) {
        kg_vec2 p = points[i];
        float angle = atan2f(p.y - centre.y, p.x - centre.x);
        int j = i - 1;
        while (j >= 0 && atan2f(points[j].y - centre.y, points[j].x - centre.x) > angle) {
            points[j + 1] = points[j];
            --j;
        }
        points[j + 1] = p;
    }
}

/* Circles become octagons (the look is a polygon); the radius is in tile widths. */
static kg_tile_look kg_tile_look_of(const kg_tile_shape* shape)
{
    kg_tile_look look;
    memset(&look, 0, sizeof look);
    look.one_way = shape->one_way;
    if (shape->type == KG_TILE_SHAPE_POLYGON && shape->count >= 3 && shape->count <= KG_MAX_POLYGON_VERTICES) {
        look.count = shape->count;
        memcpy(look.vertices, shape->vertices, (size_t)shape->count * sizeof shape->vertices[0]);
        kg_sort_round(look.vertices, look.count);
    } else if (shape->type == KG_TILE_SHAPE_CIRCLE) {
        look.count = KG_MAX_POLYGON_VERTICES;
        for (int i = 0; i < look.count; ++i) {
            float angle = 6.2831853f * (float)i / (float)look.count;
            look.vertices[i] = (kg_vec2){shape->center.x + shape->radius * cosf(angle),
                                         shape->center.y + shape->radius * sinf(angle)};
        }
    }
    return look;
}

/* Sizes of the buffers for the first map_count maps: looks, layers, cells. */
static void kg_count_tiles(const kg_tile_view* view, const kg_scene* scene, const kg_world* world, size_t* looks,
                           int* layers, size_t* cells)
{
    *looks = 0;
    *layers = 0;
    *cells = 0;
    for (int m = 0; m < view->map_count; ++m) {
        kg_tilemap_def def;
        if (kg_tilemap_get_def(world, view->maps[m], &def) == KG_OK) {
            *looks += (size_t)kg_scene_get_tilemap(scene, m)->shape_count;
            *layers += def.layer_count;
            *cells += (size_t)def.width * (size_t)def.height * (size_t)def.layer_count;
        }
    }
}

/* Fills in the looks and layers of map m, moving *look and *cells past what they use. */
static void kg_add_map(kg_tile_view* view, const kg_scene* scene, const kg_world* world, int m, kg_tile_look** look,
                       int** cells)
{
    kg_tilemap_def def;
    if (kg_tilemap_get_def(world, view->maps[m], &def) != KG_OK) {
        return;
    }
    const kg_tilemap_def* source = kg_scene_get_tilemap(scene, m);
    kg_tile_look* looks = *look;
    for (int id = 0; id < source->shape_count; ++id) {
        looks[id] = kg_tile_look_of(&source->shapes[id]);
    }
    *look += source->shape_count;
    for (int l = 0; l < def.layer_count; ++l) {
        int index = view->layer_count++;
        view->layers[index] = (kg_tile_layer){def.origin, def.tile_size, def.width, def.height, *cells, looks,
                                              source->shape_count};
        view->sources[index] = (kg_tile_source){m, l, *cells};
        *cells += (size_t)def.width * (size_t)def.height;
    }
}

kg_result kg_tile_view_init(kg_tile_view* view, const kg_scene* scene, const kg_world* world)
{
    memset(view, 0, sizeof *view);
    int scene_maps = kg_scene_tilemap_count(scene), world_maps = kg_world_tilemap_count(world);
    int capacity = scene_maps < world_maps ? scene_maps : world_maps;
    if (capacity <= 0) {
        return KG_OK;
    }
    view->maps = malloc((size_t)capacity * sizeof *view->maps);
    if (!view->maps || kg_world_get_tilemaps(world, view->maps, capacity, &view->map_count) != KG_OK) {
        kg_tile_view_free(view);
        return KG_ERROR_OUT_OF_MEMORY;
    }
    size_t look_count, cell_count;
    int layer_count;
    kg_count_tiles(view, scene, world, &look_count, &layer_count, &cell_count);
    view->looks = calloc(look_count + 1, sizeof *view->looks);
    view->cells = calloc(cell_count + 1, sizeof *view->cells);
    view->layers = calloc((size_t)layer_count + 1, sizeof *view->layers);
    view->sources = calloc((size_t)layer_count + 1, sizeof *view->sources);
    if (!view->looks || !view->cells || !view->layers || !view->sources) {
        kg_tile_view_free(view);
        return KG_ERROR_OUT_OF_MEMORY;
    }
    kg_tile_look* look = view->looks;
    int* cells = view->cells;
    for (int m = 0; m < view->map_count; ++m) {
        kg_add_map(view, scene, world, m, &look, &cells);
    }
    return KG_OK;
}

/* A cell that cannot be read (its map was destroyed) shows empty. */
static void kg_read_cells(const kg_tile_source* source, int width, const kg_world* world, kg_tilemap map,
                          const kg_cell_range* range)
{
    for (int y = range->y0; y <= range->y1; ++y) {
        for (int x = range->x0; x <= range->x1; ++x) {
            int* cell = &source->cells[(size_t)y * (size_t)width + (size_t)x];
            if (kg_tilemap_get_tile(world, map, source->layer, x, y, cell) != KG_OK) {
                *cell = 0;
            }
        }
    }
}

static int kg_max_int(int a, int b) { return a > b ? a : b; }
static int kg_min_int(int a, int b) { return a < b ? a : b; }

void kg_tile_view_refresh(kg_tile_view* view, const kg_world* world, const kg_camera* camera)
{
    int listed = 0;
    if (view->map_count == 0 || kg_world_get_tilemaps(world, view->maps, view->map_count, &listed) != KG_OK) {
        return;
    }
    for (int i = 0; i < view->layer_count; ++i) {
        kg_tile_layer* layer = &view->layers[i];
        kg_cell_range range;
        if (view->sources[i].map >= listed || !kg_tile_layer_visible(camera, layer, &range)) {
            continue;
        }
        range = (kg_cell_range){kg_max_int(range.x0 - 1, 0), kg_max_int(range.y0 - 1, 0),
                                kg_min_int(range.x1 + 1, layer->width - 1), kg_min_int(range.y1 + 1, layer->height - 1)};
        kg_read_cells(&view->sources[i], layer->width, world, view->maps[view->sources[i].map], &range);
    }
}

void kg_tile_view_free(kg_tile_view* view)
{
    free(view->layers);
    free(view->sources);
    free(view->maps);
    free(view->looks);
    free(view->cells);
    memset(view, 0, sizeof *view);
}
