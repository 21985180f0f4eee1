/* kgyro view: parses the options and opens the SDL2 viewer (tools/render/viewer_sdl.c). */
#include "commands.h"
#include "render/args.h"
#include "render/sim.h"
#include "render/viewer.h"

#include <stdio.h>
#include <string.h>

static void kg_view_usage(FILE* out)
{
    fprintf(out,
            "usage: kgyro view SCENE [OPTIONS]\n"
            "Opens SCENE (a scene file, a Tiled map (.tmj) or a generator name such as pyramid_10) in\n"
            "a window. Sensors are drawn as outlines; a hit (kg_world_get_contact_events) flashes a\n"
            "ring at its point, larger for a harder hit. Needs a display: without one it exits 1 with\n"
            "SDL's message (SDL_VIDEODRIVER=offscreen runs it unseen, with --frames and --screenshot).\n\n"
            "  mouse: left drag moves a body (a mouse joint, kg_create_mouse_joint); left click on empty\n"
            "         space spawns a box, with shift a circle;\n"
            "         right drag pans; the wheel zooms\n"
            "  keys:  space pause, . or n single step, c contacts, b bounding boxes, t tiles,\n"
            "         o switch backend (CPU / OpenCL), arrows pan, + and - zoom, r restart, q or Esc quit\n\n"
            "  --size WxH          window size (default 960x640)\n"
            "  --view X0,Y0,X1,Y1  world box to show first, in metres (default: the whole level, every\n"
            "                      body and tile map)\n"
            "  --frames N          quit by itself after N frames\n"
            "  --screenshot FILE   write the last frame shown as PNG\n"
            "  --script TEXT       scripted input, one command per frame, separated by ';':\n"
            "                      click X Y, shift-click X Y, down X Y, move X Y, up X Y,\n"
            "                      wheel N, key NAME (SDL key names: space, n, c, o, ...), wait N\n"
            "  --seed S            seed for generated scenes (default 1)\n"
            "  --backend B         auto, cpu or opencl (default auto)\n"
            "  --max-bodies N      refuse a scene or generator asking for more than N bodies (untrusted levels)\n");
}

/* Options that take a value; 0 parsed, -1 bad or missing value, 1 not one of them. */
static int kg_parse_view_valued(int argc, char** argv, int* i, kg_view_config* c)
{
    static const char* const kValued[] = {"--size",   "--view", "--frames",  "--screenshot",
                                          "--script", "--seed", "--backend", "--max-bodies", NULL};
    const char* name = argv[*i];
    const char* value = NULL;
    int taken = kg_option_value("kgyro view", argc, argv, i, kValued, &value);
    if (taken <= 0) {
        return taken < 0 ? -1 : 1;
    }
    int bad = 0, seed = 1;
    if (strcmp(name, "--size") == 0) {
        bad = kg_parse_size(value, &c->width, &c->height);
    } else if (strcmp(name, "--view") == 0) {
        bad = kg_parse_box(value, &c->view);
        c->has_view = 1;
    } else if (strcmp(name, "--frames") == 0) {
        bad = kg_parse_int(value, 1, 100000000, &c->frames);
    } else if (strcmp(name, "--screenshot") == 0) {
        c->screenshot = value;
    } else if (strcmp(name, "--script") == 0) {
        c->script = value;
    } else if (strcmp(name, "--seed") == 0) {
        bad = kg_parse_int(value, 0, 2147483647, &seed);
        c->seed = (uint32_t)seed;
    } else if (strcmp(name, "--max-bodies") == 0) {
        bad = kg_parse_int(value, 0, 2147483647, &c->max_bodies);
    } else {
        bad = kg_parse_backend(value, &c->backend);
    }
    if (bad) {
        fprintf(stderr, "kgyro view: bad value for %s: '%s'\n", name, value);
    }
    return bad ? -1 : 0;
}

int kg_cmd_view(int argc, char** argv)
{
    kg_view_config config = {.seed = 1, .max_bodies = -1, .backend = KG_BACKEND_AUTO, .width = 960, .height = 640};
    for (int i = 1; i < argc; ++i) {
        int valued = kg_parse_view_valued(argc, argv, &i, &config);
        if (valued < 0) {
            return 2;
        } else if (valued == 0) {
            continue;
        }
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            kg_view_usage(stdout);
            return 0;
        } else if (argv[i][0] != '-' && !config.scene) {
            config.scene = argv[i];
        } else {
            fprintf(stderr, "kgyro view: unexpected argument '%s'\n", argv[i]);
            return 2;
        }
    }
    if (!config.scene) {
        fprintf(stderr, "kgyro view: need a SCENE (see --help)\n");
        return 2;
    }
    return kg_view_run(&config);
}
