/* The whole Tiled level: tests/data/tiled/everything.tmj (made by make_everything.py in
 * that folder) has every object kind, every property type, every layer kind and every
 * tile layer encoding and compression. Every property, layer, marker and note is read back
 * through the API and checked; the compressed layers must hold the CSV layer's tiles. */
#include "kg_test.h"
#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <string.h>

#define DATA KG_SOURCE_DIR "/tests/data/tiled/"
#define PI 3.14159265358979323846

static kg_scene* load_everything(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_load_file(DATA "everything.tmj", &scene));
    return scene;
}

static int same_text(const char* a, const char* b)
{
    return a && b && strcmp(a, b) == 0;
}

/* The owner's property called name has the type and, as type says, the value. */
static void check_property(const kg_scene* scene, kg_scene_owner owner, int index, const char* name,
                           kg_scene_property_type type, const char* text, double number)
{
    kg_scene_property p;
    kg_result r = kg_scene_find_property(scene, owner, index, name, &p);
    if (r != KG_OK) {
        printf("owner %d/%d: no property %s: %s\n", (int)owner, index, name, kg_last_error());
        KG_CHECK(r == KG_OK);
        return;
    }
    KG_CHECK(same_text(p.name, name));
    KG_CHECK(p.type == type);
    if (type == KG_PROPERTY_STRING || type == KG_PROPERTY_FILE || type == KG_PROPERTY_COLOR) {
        if (!same_text(p.text, text)) {
            printf("%s: text '%s', expected '%s'\n", name, p.text ? p.text : "(null)", text);
        }
        KG_CHECK(same_text(p.text, text));
    } else {
        KG_CHECK(p.text == NULL);
    }
    double got = type == KG_PROPERTY_BOOL ? p.boolean : type == KG_PROPERTY_OBJECT ? p.integer : p.number;
    KG_CHECK_NEAR(got, number, 0.0);
    if (type == KG_PROPERTY_INT) {
        KG_CHECK(p.integer == (int)number);
    }
}

static void test_map_properties(void)
{
    kg_scene* scene = load_everything();
    KG_CHECK(kg_scene_property_count(scene, KG_SCENE_MAP, 0) == 8);
    KG_CHECK(kg_scene_property_count(scene, KG_SCENE_MAP, 1) == 0);
    check_property(scene, KG_SCENE_MAP, 0, "title", KG_PROPERTY_STRING, "Everything", 0.0);
    check_property(scene, KG_SCENE_MAP, 0, "level", KG_PROPERTY_INT, NULL, 3.0);
    check_property(scene, KG_SCENE_MAP, 0, "gravity_scale", KG_PROPERTY_FLOAT, NULL, 0.5);
    check_property(scene, KG_SCENE_MAP, 0, "night", KG_PROPERTY_BOOL, NULL, 0.0);
    check_property(scene, KG_SCENE_MAP, 0, "sky", KG_PROPERTY_COLOR, "#336699", 0.0);
    check_property(scene, KG_SCENE_MAP, 0, "music", KG_PROPERTY_FILE, "music/theme.ogg", 0.0);
    check_property(scene, KG_SCENE_MAP, 0, "boss", KG_PROPERTY_OBJECT, NULL, 0.0);
    check_property(scene, KG_SCENE_MAP, 0, "friction", KG_PROPERTY_FLOAT, NULL, 0.5);
    kg_scene_property sky;
    KG_CHECK_OK(kg_scene_find_property(scene, KG_SCENE_MAP, 0, "sky", &sky));
    KG_CHECK(sky.color == 0xFF336699u); /* #rrggbb: opaque */
    /* the interpreted map property still does its work */
    KG_CHECK_NEAR(kg_scene_get_tilemap(scene, 0)->friction, 0.5, 0.0);
    kg_scene_destroy(scene);
}

typedef struct expected_layer {
    const char* name;
    const char* kind;
    int parent, tile_layer, markers;
} expected_layer;

static void test_layers_and_their_properties(void)
{
    static const expected_layer expected[] = {
        {"terrain", "group", -1, -1, 0},   {"csv", "tilelayer", 0, 0, 0},        {"base64", "tilelayer", 0, 1, 0},
        {"zlib", "tilelayer", 0, 2, 0},    {"deeper", "group", 0, -1, 0},        {"gzip", "tilelayer", 4, 3, 0},
        {"bodies", "objectgroup", -1, -1, 0}, {"markers", "objectgroup", -1, -1, 1}, {"sky", "imagelayer", -1, -1, 0},
    };
    kg_scene* scene = load_everything();
    int count = (int)(sizeof expected / sizeof expected[0]);
    KG_CHECK(kg_scene_layer_count(scene) == count);
    for (int i = 0; i < count && i < kg_scene_layer_count(scene); ++i) {
        kg_scene_layer layer;
        KG_CHECK_OK(kg_scene_get_layer(scene, i, &layer));
        int ok = same_text(layer.name, expected[i].name) && same_text(layer.kind, expected[i].kind) &&
                 layer.map == 0 && layer.parent == expected[i].parent && layer.tile_layer == expected[i].tile_layer &&
                 layer.markers == expected[i].markers;
        if (!ok) {
            printf("layer %d: %s %s parent %d tile layer %d markers %d\n", i, layer.name, layer.kind, layer.parent,
                   layer.tile_layer, layer.markers);
        }
        KG_CHECK(ok);
        KG_CHECK(kg_scene_find_layer(scene, expected[i].name) == i);
    }
    KG_CHECK(kg_scene_find_layer(scene, "nowhere") == -1);
    KG_CHECK(kg_scene_get_layer(scene, count, &(kg_scene_layer){0}) == KG_ERROR_INVALID_ARGUMENT);
    check_property(scene, KG_SCENE_LAYER, 0, "theme", KG_PROPERTY_STRING, "cave", 0.0);
    check_property(scene, KG_SCENE_LAYER, 1, "depth", KG_PROPERTY_INT, NULL, 2.0);
    check_property(scene, KG_SCENE_LAYER, 6, "type", KG_PROPERTY_STRING, "static", 0.0);
    check_property(scene, KG_SCENE_LAYER, 6, "layer_tag", KG_PROPERTY_STRING, "solid", 0.0);
    check_property(scene, KG_SCENE_LAYER, 7, "physics", KG_PROPERTY_BOOL, NULL, 0.0);
    check_property(scene, KG_SCENE_LAYER, 7, "purpose", KG_PROPERTY_STRING, "triggers", 0.0);
    KG_CHECK(kg_scene_property_count(scene, KG_SCENE_LAYER, 2) == 0);
    KG_CHECK(kg_scene_property_count(scene, KG_SCENE_LAYER, 7) == 2);
    kg_scene_destroy(scene);
}

/* The crate: every property type, a class-typed one flattened, in file order. */
static void check_crate_properties(const kg_scene* scene, int crate)
{
    static const char* const order[] = {"label", "hp", "weight", "breakable", "tint", "sound", "target",
                                        "loot.coins", "loot.chance", "loot.item", "loot.rare", "loot.bonus.gems",
                                        "friction"};
    int count = (int)(sizeof order / sizeof order[0]);
    KG_CHECK(kg_scene_property_count(scene, KG_SCENE_BODY, crate) == count);
    for (int k = 0; k < count; ++k) {
        kg_scene_property p;
        KG_CHECK_OK(kg_scene_get_property(scene, KG_SCENE_BODY, crate, k, &p));
        KG_CHECK(same_text(p.name, order[k]));
    }
    kg_scene_property p;
    KG_CHECK(kg_scene_get_property(scene, KG_SCENE_BODY, crate, count, &p) == KG_ERROR_NOT_FOUND);
    check_property(scene, KG_SCENE_BODY, crate, "label", KG_PROPERTY_STRING, "wooden crate", 0.0);
    check_property(scene, KG_SCENE_BODY, crate, "hp", KG_PROPERTY_INT, NULL, -7.0);
    check_property(scene, KG_SCENE_BODY, crate, "weight", KG_PROPERTY_FLOAT, NULL, 2.75);
    check_property(scene, KG_SCENE_BODY, crate, "breakable", KG_PROPERTY_BOOL, NULL, 1.0);
    check_property(scene, KG_SCENE_BODY, crate, "tint", KG_PROPERTY_COLOR, "#80ff8000", 0.0);
    check_property(scene, KG_SCENE_BODY, crate, "sound", KG_PROPERTY_FILE, "sounds/crack.wav", 0.0);
    check_property(scene, KG_SCENE_BODY, crate, "target", KG_PROPERTY_OBJECT, NULL, 2.0);
    check_property(scene, KG_SCENE_BODY, crate, "loot.coins", KG_PROPERTY_INT, NULL, 12.0);
    check_property(scene, KG_SCENE_BODY, crate, "loot.chance", KG_PROPERTY_FLOAT, NULL, 0.25);
    check_property(scene, KG_SCENE_BODY, crate, "loot.item", KG_PROPERTY_STRING, "key", 0.0);
    check_property(scene, KG_SCENE_BODY, crate, "loot.rare", KG_PROPERTY_BOOL, NULL, 0.0);
    check_property(scene, KG_SCENE_BODY, crate, "loot.bonus.gems", KG_PROPERTY_INT, NULL, 1.0);
    check_property(scene, KG_SCENE_BODY, crate, "friction", KG_PROPERTY_FLOAT, NULL, 0.25);
    KG_CHECK_OK(kg_scene_body_property(scene, crate, "tint", &p));
    KG_CHECK(p.color == 0x80FF8000u);
}

static void test_bodies_properties_and_classes(void)
{
    kg_scene* scene = load_everything();
    KG_CHECK(kg_scene_body_count(scene) == 4); /* crate, ball, the polygon and the polyline */
    int crate = kg_scene_find_body(scene, "crate#1"), ball = kg_scene_find_body(scene, "ball#2");
    int polygon = kg_scene_find_body(scene, "object#3"), ledge = kg_scene_find_body(scene, "ledge#4");
    KG_CHECK(crate == 0 && ball == 1 && polygon == 2 && ledge == 3);
    check_crate_properties(scene, crate);
    /* the interpreted properties: read as any other, and applied */
    check_property(scene, KG_SCENE_BODY, ball, "sensor", KG_PROPERTY_BOOL, NULL, 1.0);
    KG_CHECK(kg_scene_body_def(scene, ball)->is_sensor == 1);
    KG_CHECK_NEAR(kg_scene_body_def(scene, crate)->friction, 0.25, 0.0);
    KG_CHECK(kg_scene_body_def(scene, crate)->type == KG_BODY_STATIC); /* the layer's "type" */
    KG_CHECK_NEAR(kg_scene_body_def(scene, crate)->position.x, 1.5, 0.0);
    KG_CHECK_NEAR(kg_scene_body_def(scene, crate)->position.y, 2.5, 0.0);
    KG_CHECK(kg_scene_property_count(scene, KG_SCENE_BODY, polygon) == 0);
    /* the polyline is a chain, the polygon on a static layer a loop */
    KG_CHECK(kg_scene_body_chain_count(scene, ledge) == 1 && kg_scene_body_chain_count(scene, polygon) == 1);
    /* classes: Tiled 1.9's "class", the older "type", none */
    KG_CHECK(same_text(kg_scene_body_class(scene, crate), "Crate"));
    KG_CHECK(same_text(kg_scene_body_class(scene, ball), "Ball"));
    KG_CHECK(same_text(kg_scene_body_class(scene, polygon), ""));
    KG_CHECK(kg_scene_body_class(scene, 4) == NULL);
    for (int i = 0; i < 4; ++i) {
        KG_CHECK(kg_scene_body_layer(scene, i) == 6);
    }
    KG_CHECK(kg_scene_body_layer(scene, 4) == -1);
    /* absent, out of range, NULL */
    kg_scene_property p;
    KG_CHECK(kg_scene_body_property(scene, crate, "nope", &p) == KG_ERROR_NOT_FOUND);
    KG_CHECK(strstr(kg_last_error(), "no property 'nope'") != NULL);
    KG_CHECK(kg_scene_body_property(scene, 99, "label", &p) == KG_ERROR_NOT_FOUND);
    KG_CHECK(kg_scene_body_property(scene, crate, NULL, &p) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_scene_body_property(NULL, crate, "label", &p) == KG_ERROR_INVALID_ARGUMENT);
    KG_CHECK(kg_scene_property_count(NULL, KG_SCENE_BODY, 0) == 0);
    kg_scene_destroy(scene);
}

typedef struct expected_marker {
    const char* name;
    const char* class_name;
    int id;
    kg_scene_marker_shape shape;
    double x, y, width, height, angle;
    int layer, property_count;
} expected_marker;

static void check_marker(const kg_scene* scene, int index, const expected_marker* e)
{
    kg_scene_marker m;
    KG_CHECK_OK(kg_scene_get_marker(scene, index, &m));
    int ok = same_text(m.name, e->name) && same_text(m.class_name, e->class_name) && m.id == e->id &&
             m.shape == e->shape && m.layer == e->layer;
    if (!ok) {
        printf("marker %d: '%s' '%s' id %d shape %d layer %d\n", index, m.name, m.class_name, m.id, (int)m.shape,
               m.layer);
    }
    KG_CHECK(ok);
    KG_CHECK_NEAR(m.position.x, e->x, 1e-6);
    KG_CHECK_NEAR(m.position.y, e->y, 1e-6);
    KG_CHECK_NEAR(m.size.x, e->width, 0.0);
    KG_CHECK_NEAR(m.size.y, e->height, 0.0);
    KG_CHECK_NEAR(m.angle, e->angle, 1e-6);
    KG_CHECK(kg_scene_property_count(scene, KG_SCENE_MARKER, index) == e->property_count);
    if (e->name[0]) {
        KG_CHECK(kg_scene_find_marker(scene, e->name) == index);
    }
}

static void test_markers(void)
{
    /* metres, y up from the map's bottom (4 tiles of 16 px, 1 m each) */
    static const expected_marker expected[] = {
        {"spawn", "Spawn", 5, KG_MARKER_POINT, 0.5, 1.5, 0, 0, 0, 6, 2},
        {"checkpoint", "", 10, KG_MARKER_POINT, 2.5, 2.5, 0, 0, 0, 7, 0},
        {"goal", "Trigger", 11, KG_MARKER_RECTANGLE, 5.0, 2.5, 2, 1, 0, 7, 2},
        {"zone", "", 12, KG_MARKER_ELLIPSE, 1.0, 3.5, 1, 2, -PI / 2, 7, 0}, /* turned 90 degrees clockwise */
        {"area", "", 13, KG_MARKER_POLYGON, 3.0, 3.5, 0, 0, 0, 7, 0},
        {"path", "", 14, KG_MARKER_POLYLINE, 0.0, 3.5, 0, 0, 0, 7, 0},
        {"coin", "Pickup", 15, KG_MARKER_TILE, 5.5, 0.5, 1, 1, 0, 7, 0}, /* a tile object's origin: bottom-left */
    };
    kg_scene* scene = load_everything();
    int count = (int)(sizeof expected / sizeof expected[0]);
    KG_CHECK(kg_scene_marker_count(scene) == count);
    for (int i = 0; i < count && i < kg_scene_marker_count(scene); ++i) {
        check_marker(scene, i, &expected[i]);
    }
    check_property(scene, KG_SCENE_MARKER, 0, "team", KG_PROPERTY_STRING, "red", 0.0);
    check_property(scene, KG_SCENE_MARKER, 0, "facing", KG_PROPERTY_INT, NULL, 1.0);
    check_property(scene, KG_SCENE_MARKER, 2, "message", KG_PROPERTY_STRING, "well done", 0.0);
    check_property(scene, KG_SCENE_MARKER, 2, "delay", KG_PROPERTY_FLOAT, NULL, 1.5);
    KG_CHECK(kg_scene_find_marker(scene, "crate") == -1);
    KG_CHECK(kg_scene_get_marker(scene, count, &(kg_scene_marker){0}) == KG_ERROR_INVALID_ARGUMENT);
    kg_scene_destroy(scene);
}

static void test_ignored_things_are_noted(void)
{
    static const char* const expected[] = {
        "everything.tmj: layers[1].objects[5]: a text object is ignored",
        "everything.tmj: layers[2].objects[6]: a text object is ignored",
        "everything.tmj: layers[3]: an image layer is ignored",
    };
    kg_scene* scene = load_everything();
    KG_CHECK(kg_scene_note_count(scene) == 3);
    for (int i = 0; i < 3; ++i) {
        const char* note = kg_scene_get_note(scene, i);
        if (!note || !strstr(note, expected[i])) {
            printf("note %d: '%s', expected '%s'\n", i, note ? note : "(null)", expected[i]);
        }
        KG_CHECK(note && strstr(note, expected[i]));
    }
    KG_CHECK(kg_scene_get_note(scene, 3) == NULL);
    kg_scene_destroy(scene);
}

/* CSV, base64, base64 + zlib and base64 + gzip (in a nested group): the same tiles. */
static void test_every_encoding_gives_the_same_tiles(void)
{
    kg_scene* scene = load_everything();
    KG_CHECK(kg_scene_tilemap_count(scene) == 1);
    const kg_tilemap_def* def = kg_scene_get_tilemap(scene, 0);
    if (!def) {
        kg_scene_destroy(scene);
        return;
    }
    KG_CHECK(def->layer_count == 4 && def->width == 6 && def->height == 4);
    int cells = def->width * def->height, differing = 0;
    for (int layer = 1; layer < def->layer_count; ++layer) {
        differing += memcmp(def->tiles, def->tiles + layer * cells, (size_t)cells * sizeof *def->tiles) != 0;
    }
    KG_CHECK(differing == 0);
    /* rows from the bottom: the ground (its last tile flipped, an id after the 5 gids), the
     * one-way tiles two rows up, the shapeless tile between */
    static const int ground[6] = {1, 1, 1, 1, 1, 5};
    for (int x = 0; x < 6; ++x) {
        KG_CHECK(def->tiles[x] == ground[x]);
    }
    KG_CHECK(def->tiles[2 * 6 + 3] == 2 && def->tiles[2 * 6 + 4] == 2 && def->tiles[1 * 6 + 5] == 3);
    KG_CHECK(def->shape_count == 6 && def->shapes[2].one_way == 1);
    kg_scene_destroy(scene);
}

/* The level instantiates and runs: the physics part is untouched by the rest. */
static void test_everything_runs(void)
{
    kg_scene* scene = load_everything();
    kg_world* world = NULL;
    kg_body bodies[4];
    KG_CHECK_OK(kg_scene_instantiate(scene, NULL, &world, bodies));
    for (int i = 0; world && i < 10; ++i) {
        KG_CHECK_OK(kg_scene_step(scene, world, bodies, 1.0f / 60.0f));
    }
    kg_destroy_world(world);
    kg_scene_destroy(scene);
}

/* "physics" false on one object of a layer of bodies makes that object a marker; on a
 * layer, its body properties ("type": "spawner" here) are not read as a body's. */
static void test_physics_false_makes_markers(void)
{
    static const char json[] =
        "{\"type\": \"map\", \"width\": 2, \"height\": 2, \"tilewidth\": 16, \"tileheight\": 16, \"layers\": ["
        " {\"type\": \"objectgroup\", \"name\": \"things\", \"properties\": [{\"name\": \"density\", \"type\":"
        "  \"float\", \"value\": 2}], \"objects\": ["
        "  {\"id\": 1, \"name\": \"box\", \"x\": 0, \"y\": 0, \"width\": 16, \"height\": 16},"
        "  {\"id\": 2, \"name\": \"ghost\", \"x\": 16, \"y\": 0, \"width\": 16, \"height\": 8, \"properties\":"
        "   [{\"name\": \"physics\", \"type\": \"bool\", \"value\": false}]}]},"
        " {\"type\": \"objectgroup\", \"name\": \"spawns\", \"offsetx\": 8, \"properties\": ["
        "  {\"name\": \"physics\", \"type\": \"bool\", \"value\": false},"
        "  {\"name\": \"type\", \"type\": \"string\", \"value\": \"spawner\"}], \"objects\": ["
        "  {\"id\": 3, \"name\": \"enemy\", \"gid\": 0, \"x\": 0, \"y\": 32, \"width\": 16, \"height\": 16}]}]}";
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_parse(json, sizeof json - 1, "inline.tmj", &scene));
    KG_CHECK(kg_scene_body_count(scene) == 1 && kg_scene_find_body(scene, "box#1") == 0);
    KG_CHECK(kg_scene_marker_count(scene) == 2);
    kg_scene_marker ghost, enemy;
    KG_CHECK_OK(kg_scene_get_marker(scene, kg_scene_find_marker(scene, "ghost"), &ghost));
    KG_CHECK_OK(kg_scene_get_marker(scene, kg_scene_find_marker(scene, "enemy"), &enemy));
    KG_CHECK(ghost.shape == KG_MARKER_RECTANGLE && ghost.layer == 0);
    KG_CHECK_NEAR(ghost.position.x, 1.5, 0.0);
    KG_CHECK_NEAR(ghost.position.y, 1.75, 0.0);
    KG_CHECK(enemy.shape == KG_MARKER_TILE && enemy.layer == 1);
    KG_CHECK_NEAR(enemy.position.x, 1.0, 0.0); /* the layer's offset of 8 px applied */
    KG_CHECK_NEAR(enemy.position.y, 0.5, 0.0);
    kg_scene_layer spawns;
    KG_CHECK_OK(kg_scene_get_layer(scene, 1, &spawns));
    KG_CHECK(spawns.markers == 1 && same_text(spawns.name, "spawns"));
    check_property(scene, KG_SCENE_LAYER, 1, "type", KG_PROPERTY_STRING, "spawner", 0.0);
    kg_scene_destroy(scene);
}

/* A scene built from code has none of it. */
static void test_scenes_from_code_have_no_level_data(void)
{
    kg_scene* scene = NULL;
    KG_CHECK_OK(kg_scene_create(&scene));
    kg_body_def def = kg_default_body_def();
    def.shape = kg_circle_shape(0.5f);
    KG_CHECK_OK(kg_scene_add_body(scene, "a", &def));
    kg_scene_property p;
    KG_CHECK(kg_scene_body_property(scene, 0, "x", &p) == KG_ERROR_NOT_FOUND);
    KG_CHECK(same_text(kg_scene_body_class(scene, 0), ""));
    KG_CHECK(kg_scene_body_layer(scene, 0) == -1);
    KG_CHECK(kg_scene_layer_count(scene) == 0 && kg_scene_marker_count(scene) == 0);
    KG_CHECK(kg_scene_note_count(scene) == 0 && kg_scene_find_marker(scene, "a") == -1);
    KG_CHECK(kg_scene_property_count(scene, KG_SCENE_MAP, 0) == 0);
    KG_CHECK(strcmp(kg_result_string(KG_ERROR_NOT_FOUND), "not found") == 0);
    kg_scene_destroy(scene);
}

KG_TEST_MAIN(KG_TEST(test_map_properties), KG_TEST(test_layers_and_their_properties),
             KG_TEST(test_bodies_properties_and_classes), KG_TEST(test_markers), KG_TEST(test_ignored_things_are_noted),
             KG_TEST(test_every_encoding_gives_the_same_tiles), KG_TEST(test_everything_runs),
             KG_TEST(test_physics_false_makes_markers), KG_TEST(test_scenes_from_code_have_no_level_data))
