/* The interactive viewer: the software renderer's canvas shown in an SDL2 window, with
 * mouse and keyboard control of the camera and the simulation. Scripted input goes
 * through the same SDL event queue as real input, so tests exercise the real paths. */
#define SDL_MAIN_HANDLED
#include <SDL.h>

#include "draw.h"
#include "image.h"
#include "palette.h"
#include "sim.h"
#include "viewer.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define KG_ADD_ROOM 4096        /* bodies the user may add by clicking */
#define KG_DRAG_HERTZ 4.0f      /* the mouse joint's natural frequency */
#define KG_DRAG_DAMPING 0.7f    /* and damping ratio: firm, without overshoot */
#define KG_DRAG_ACCELERATION 1000.0f /* m/s2: its largest pull, times the body's mass */
#define KG_SPAWN_PIXELS 32.0f   /* a spawned body's size on screen */
#define KG_FRAME_MS (1000.0 / 60.0)
#define KG_MESSAGE_FRAMES 180   /* how long a message stays on screen */
#define KG_TEXT_SCALE 2

/* A body held by the mouse: a mouse joint from the grabbed point to the pointer. */
typedef struct kg_drag {
    int active;
    kg_joint joint;
} kg_drag;

typedef struct kg_script {
    const char* next; /* the commands not run yet */
    int wait;         /* frames to skip before the next one */
    int shift;        /* a scripted shift-click holds shift for this frame */
} kg_script;

/* A hit event shown as a ring that shrinks over a few frames, sized by its speed. */
#define KG_MAX_FLASHES 64
#define KG_FLASH_FRAMES 12

typedef struct kg_flash {
    kg_vec2 point;
    float speed; /* m/s */
    int frames;  /* left; 0: free */
} kg_flash;

typedef struct kg_viewer {
    const kg_view_config* config;
    kg_sim sim;
    int scene_bodies;
    kg_body_def* added; /* definitions of the bodies added by clicks, to rebuild them */
    kg_canvas canvas;
    kg_camera camera;
    kg_draw_options draw;
    SDL_Window* window;
    SDL_Surface* frame; /* the canvas pixels as an 8-bit palette surface */
    int paused, single_step, quit, panning;
    kg_point mouse;
    kg_drag drag;
    kg_script script;
    int frame_index;
    double step_ms; /* smoothed over recent steps */
    char message[96];
    int message_frames;
    kg_flash flashes[KG_MAX_FLASHES];
    int next_flash;
} kg_viewer;

static void kg_show_message(kg_viewer* v, const char* text)
{
    snprintf(v->message, sizeof v->message, "%s", text);
    v->message_frames = KG_MESSAGE_FRAMES;
}

/* ---- bodies under the mouse, spawning, dragging ---- */

static kg_vec2 kg_to_body(const kg_body_state* s, kg_vec2 world)
{
    float c = cosf(s->angle), sn = sinf(s->angle), dx = world.x - s->position.x, dy = world.y - s->position.y;
    return (kg_vec2){c * dx + sn * dy, -sn * dx + c * dy};
}

/* Within radius of the core from c1 to c2: nearer the segment than radius. */
static int kg_capsule_contains(const kg_shape_def* shape, kg_vec2 p)
{
    kg_vec2 c1 = shape->vertices[0], c2 = shape->vertices[1];
    float ex = c2.x - c1.x, ey = c2.y - c1.y;
    float t = ((p.x - c1.x) * ex + (p.y - c1.y) * ey) / (ex * ex + ey * ey);
    t = fminf(fmaxf(t, 0.0f), 1.0f);
    float dx = p.x - (c1.x + t * ex), dy = p.y - (c1.y + t * ey);
    return dx * dx + dy * dy <= shape->radius * shape->radius;
}

/* Inside a convex polygon when the point is on the same side of every edge. A segment has
 * no inside: it is never picked. */
static int kg_shape_contains(const kg_shape_def* shape, kg_vec2 p)
{
    if (shape->type == KG_SHAPE_CIRCLE) {
        float dx = p.x - shape->center.x, dy = p.y - shape->center.y;
        return dx * dx + dy * dy <= shape->radius * shape->radius;
    }
    if (shape->type == KG_SHAPE_CAPSULE) {
        return kg_capsule_contains(shape, p);
    }
    int sides = 0;
    for (int i = 0; shape->type == KG_SHAPE_POLYGON && i < shape->count; ++i) {
        kg_vec2 a = shape->vertices[i], b = shape->vertices[(i + 1) % shape->count];
        float cross = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
        sides |= cross >= 0.0f ? 1 : 2;
    }
    return shape->type == KG_SHAPE_POLYGON && sides != 3;
}

/* Whether a shape of body holds the body-frame point p. */
static int kg_body_contains(const kg_world* world, kg_body body, kg_vec2 p)
{
    kg_shape_id shapes[64];
    int count = 0;
    if (kg_body_get_shapes(world, body, shapes, 64, &count) != KG_OK) {
        return 0;
    }
    for (int k = 0; k < count && k < 64; ++k) {
        kg_body_shape_def def;
        if (kg_shape_get_def(world, shapes[k], &def) == KG_OK && kg_shape_contains(&def.geometry, p)) {
            return 1;
        }
    }
    return 0;
}

/* The last drawn dynamic body or particle under world point p. */
static int kg_pick_body(const kg_viewer* v, kg_vec2 p, kg_body* out)
{
    for (int i = v->sim.body_count - 1; i >= 0; --i) {
        kg_body body = v->sim.bodies[i];
        kg_body_type type;
        kg_body_state state;
        if (kg_body_get_type(v->sim.world, body, &type) != KG_OK || type == KG_BODY_STATIC ||
            type == KG_BODY_KINEMATIC || kg_body_get_state(v->sim.world, body, &state) != KG_OK) {
            continue;
        }
        if (kg_body_contains(v->sim.world, body, kg_to_body(&state, p))) {
            *out = body;
            return 1;
        }
    }
    return 0;
}

static void kg_spawn(kg_viewer* v, kg_vec2 at, int circle)
{
    float size = fminf(fmaxf(KG_SPAWN_PIXELS / v->camera.scale, 0.05f), 20.0f);
    kg_body_def def = kg_default_body_def();
    def.position = at;
    def.shape = circle ? kg_circle_shape(0.5f * size) : kg_box_shape(size, size);
    kg_body body;
    if (kg_sim_add_body(&v->sim, &def, &body) != KG_OK) {
        kg_show_message(v, "no room for more bodies");
        return;
    }
    v->added[v->sim.body_count - v->scene_bodies - 1] = def;
}

/* Grabs body at the world point at with a mouse joint that pulls with up to
 * KG_DRAG_ACCELERATION times its mass: light and heavy bodies follow alike. */
static void kg_grab(kg_viewer* v, kg_body body, kg_vec2 at)
{
    kg_body_state state;
    kg_mass_data mass;
    kg_mouse_joint_def def = kg_default_mouse_joint_def();
    def.base.body_b = body;
    def.target = at;
    def.hertz = KG_DRAG_HERTZ;
    def.damping_ratio = KG_DRAG_DAMPING;
    if (kg_body_get_state(v->sim.world, body, &state) != KG_OK ||
        kg_body_get_mass_data(v->sim.world, body, &mass) != KG_OK) {
        return;
    }
    def.local_anchor_b = kg_to_body(&state, at);
    def.max_force = KG_DRAG_ACCELERATION * mass.mass;
    if (kg_create_mouse_joint(v->sim.world, &def, &v->drag.joint) != KG_OK) {
        kg_show_message(v, kg_last_error());
        return;
    }
    v->drag.active = 1;
}

static void kg_release(kg_viewer* v)
{
    if (v->drag.active) {
        kg_destroy_joint(v->sim.world, v->drag.joint); /* gone already with its body: no matter */
    }
    v->drag.active = 0;
}

static void kg_press(kg_viewer* v, kg_point screen, int shift)
{
    kg_vec2 at = kg_camera_to_world(&v->camera, screen);
    kg_body body;
    if (kg_pick_body(v, at, &body)) {
        kg_grab(v, body, at);
    } else {
        kg_spawn(v, at, shift);
    }
}

/* ---- rebuilding the world: restart, and switching backend ---- */

/* Gives the new world the old one's body poses and velocities, and adds the clicked
 * bodies again where they were. */
static kg_result kg_copy_bodies(kg_viewer* v, kg_world* world, kg_body* handles)
{
    int count = v->sim.body_count;
    kg_body_state* states = malloc((size_t)(count > 0 ? count : 1) * sizeof *states);
    kg_result r = states ? kg_world_get_body_states(v->sim.world, v->sim.bodies, count, states) : KG_ERROR_OUT_OF_MEMORY;
    for (int i = 0; r == KG_OK && i < v->scene_bodies; ++i) {
        r = kg_body_set_transform(world, handles[i], states[i].position, states[i].angle);
        r = r == KG_OK ? kg_body_set_velocity(world, handles[i], states[i].velocity) : r;
        r = r == KG_OK ? kg_body_set_angular_velocity(world, handles[i], states[i].angular_velocity) : r;
    }
    for (int i = v->scene_bodies; r == KG_OK && i < count; ++i) {
        kg_body_def def = v->added[i - v->scene_bodies];
        def.position = states[i].position;
        def.angle = states[i].angle;
        def.velocity = states[i].velocity;
        def.angular_velocity = states[i].angular_velocity;
        r = kg_create_body(world, &def, &handles[i]);
    }
    free(states);
    return r;
}

/* A new world from the scene on backend, keeping the current motion when keep_state. */
static kg_result kg_rebuild(kg_viewer* v, kg_backend backend, int keep_state)
{
    kg_world_def def = *kg_world_get_def(v->sim.world);
    def.backend = backend;
    kg_body* handles = malloc((size_t)v->sim.body_capacity * sizeof *handles);
    kg_world* world = NULL;
    kg_result r = handles ? kg_scene_instantiate(v->sim.scene, &def, &world, handles) : KG_ERROR_OUT_OF_MEMORY;
    if (r == KG_OK && keep_state) {
        r = kg_copy_bodies(v, world, handles);
    }
    if (r != KG_OK) {
        kg_destroy_world(world);
        free(handles);
        return r;
    }
    kg_destroy_world(v->sim.world);
    free(v->sim.bodies);
    v->sim.world = world;
    v->sim.bodies = handles;
    v->sim.body_count = keep_state ? v->sim.body_count : v->scene_bodies;
    v->drag.active = 0;
    return KG_OK;
}

static void kg_switch_backend(kg_viewer* v)
{
    kg_backend from = kg_world_backend(v->sim.world);
    kg_backend to = from == KG_BACKEND_OPENCL ? KG_BACKEND_CPU : KG_BACKEND_OPENCL;
    char text[96];
    if (kg_rebuild(v, to, 1) != KG_OK) {
        snprintf(text, sizeof text, "switching failed: %s", kg_last_error());
    } else if (kg_world_backend(v->sim.world) != to) {
        snprintf(text, sizeof text, "%s is not available here: still on %s", kg_backend_label(to),
                 kg_backend_label(kg_world_backend(v->sim.world)));
    } else {
        snprintf(text, sizeof text, "now on %s", kg_backend_label(to));
    }
    kg_show_message(v, text);
}

/* ---- input ---- */

static void kg_pan(kg_viewer* v, float dx_pixels, float dy_pixels)
{
    v->camera.center.x -= dx_pixels / v->camera.scale;
    v->camera.center.y += dy_pixels / v->camera.scale;
}

static void kg_toggle(kg_viewer* v, int* flag, const char* what)
{
    char text[64];
    *flag = !*flag;
    snprintf(text, sizeof text, "%s %s", what, *flag ? "on" : "off");
    kg_show_message(v, text);
}

static void kg_handle_key(kg_viewer* v, SDL_Keycode key)
{
    kg_point middle = {0.5f * (float)v->camera.width, 0.5f * (float)v->camera.height};
    float step = 0.1f * (float)v->camera.width;
    switch (key) {
    case SDLK_SPACE: v->paused = !v->paused; break;
    case SDLK_PERIOD:
    case SDLK_n: v->paused = v->single_step = 1; break;
    case SDLK_c: kg_toggle(v, &v->draw.contacts, "contacts"); break;
    case SDLK_b: kg_toggle(v, &v->draw.aabbs, "bounding boxes"); break;
    case SDLK_t: kg_toggle(v, &v->draw.tiles, "tiles"); break;
    case SDLK_o: kg_switch_backend(v); break;
    case SDLK_r:
        if (kg_rebuild(v, kg_world_backend(v->sim.world), 0) == KG_OK) {
            kg_show_message(v, "restarted");
        }
        break;
    case SDLK_LEFT: kg_pan(v, step, 0.0f); break;
    case SDLK_RIGHT: kg_pan(v, -step, 0.0f); break;
    case SDLK_UP: kg_pan(v, 0.0f, step); break;
    case SDLK_DOWN: kg_pan(v, 0.0f, -step); break;
    case SDLK_PLUS:
    case SDLK_EQUALS:
    case SDLK_KP_PLUS: kg_camera_zoom_at(&v->camera, middle, 1.25f); break;
    case SDLK_MINUS:
    case SDLK_KP_MINUS: kg_camera_zoom_at(&v->camera, middle, 0.8f); break;
    case SDLK_q:
    case SDLK_ESCAPE: v->quit = 1; break;
    default: break;
    }
}

static void kg_handle_button(kg_viewer* v, const SDL_MouseButtonEvent* e, int down)
{
    v->mouse = (kg_point){(float)e->x, (float)e->y};
    if (e->button == SDL_BUTTON_RIGHT) {
        v->panning = down;
    } else if (e->button == SDL_BUTTON_LEFT && down) {
        kg_press(v, v->mouse, (SDL_GetModState() & KMOD_SHIFT) || v->script.shift);
    } else if (e->button == SDL_BUTTON_LEFT) {
        kg_release(v);
    }
}

static void kg_handle_event(kg_viewer* v, const SDL_Event* e)
{
    switch (e->type) {
    case SDL_QUIT: v->quit = 1; break;
    case SDL_KEYDOWN: kg_handle_key(v, e->key.keysym.sym); break;
    case SDL_MOUSEBUTTONDOWN: kg_handle_button(v, &e->button, 1); break;
    case SDL_MOUSEBUTTONUP: kg_handle_button(v, &e->button, 0); break;
    case SDL_MOUSEMOTION:
        v->mouse = (kg_point){(float)e->motion.x, (float)e->motion.y};
        if (v->panning) {
            kg_pan(v, (float)e->motion.xrel, (float)e->motion.yrel);
        }
        if (v->drag.active &&
            kg_mouse_joint_set_target(v->sim.world, v->drag.joint, kg_camera_to_world(&v->camera, v->mouse)) != KG_OK) {
            v->drag.active = 0; /* its body was destroyed, and the joint with it */
        }
        break;
    case SDL_MOUSEWHEEL: kg_camera_zoom_at(&v->camera, v->mouse, powf(1.15f, (float)e->wheel.y)); break;
    default: break;
    }
}

/* ---- scripted input ---- */

typedef struct kg_script_command {
    char verb[16];
    char name[32]; /* key name */
    int x, y;
} kg_script_command;

static int kg_is_point_verb(const char* verb)
{
    static const char* const kVerbs[] = {"click", "shift-click", "down", "move", "up"};
    for (size_t i = 0; i < sizeof kVerbs / sizeof kVerbs[0]; ++i) {
        if (strcmp(verb, kVerbs[i]) == 0) {
            return 1;
        }
    }
    return 0;
}

/* Reads one command from *text (moving it past the ';'). 0 when none is left, -1 when
 * the command is malformed. Key names need SDL to be started. */
static int kg_script_read(const char** text, kg_script_command* c)
{
    while (**text == ' ' || **text == ';') {
        ++*text;
    }
    if (**text == '\0') {
        return 0;
    }
    size_t length = strcspn(*text, ";");
    char line[96], extra[2];
    snprintf(line, sizeof line, "%.*s", (int)(length < sizeof line - 1 ? length : sizeof line - 1), *text);
    *text += length;
    memset(c, 0, sizeof *c);
    if (sscanf(line, "%15s", c->verb) != 1) {
        return -1;
    }
    if (kg_is_point_verb(c->verb)) {
        return sscanf(line, "%*s %d %d %1s", &c->x, &c->y, extra) == 2 ? 1 : -1;
    }
    if (strcmp(c->verb, "wait") == 0 || strcmp(c->verb, "wheel") == 0) {
        return sscanf(line, "%*s %d %1s", &c->x, extra) == 1 ? 1 : -1;
    }
    if (strcmp(c->verb, "key") == 0) {
        return sscanf(line, "%*s %31s %1s", c->name, extra) == 1 && SDL_GetKeyFromName(c->name) != SDLK_UNKNOWN ? 1
                                                                                                                : -1;
    }
    return -1;
}

static int kg_script_check(const char* text)
{
    kg_script_command c;
    const char* command = text;
    int r;
    while ((r = kg_script_read(&text, &c)) > 0) {
        command = text;
    }
    if (r < 0) {
        command += strspn(command, "; ");
        fprintf(stderr, "kgyro view: bad --script command '%.*s'\n", (int)(text - command), command);
    }
    return r;
}

static void kg_push_button(kg_viewer* v, Uint32 type, int x, int y)
{
    SDL_Event e;
    memset(&e, 0, sizeof e);
    e.type = type;
    e.button.windowID = SDL_GetWindowID(v->window);
    e.button.button = SDL_BUTTON_LEFT;
    e.button.state = type == SDL_MOUSEBUTTONDOWN ? SDL_PRESSED : SDL_RELEASED;
    e.button.clicks = 1;
    e.button.x = x;
    e.button.y = y;
    SDL_PushEvent(&e);
}

static void kg_push_motion(kg_viewer* v, int x, int y)
{
    SDL_Event e;
    memset(&e, 0, sizeof e);
    e.type = SDL_MOUSEMOTION;
    e.motion.windowID = SDL_GetWindowID(v->window);
    e.motion.x = x;
    e.motion.y = y;
    e.motion.xrel = x - (int)v->mouse.x;
    e.motion.yrel = y - (int)v->mouse.y;
    SDL_PushEvent(&e);
}

static void kg_push_key(kg_viewer* v, SDL_Keycode key)
{
    SDL_Event e;
    memset(&e, 0, sizeof e);
    e.key.windowID = SDL_GetWindowID(v->window);
    e.key.keysym.sym = key;
    e.key.keysym.scancode = SDL_GetScancodeFromKey(key);
    e.type = SDL_KEYDOWN;
    e.key.state = SDL_PRESSED;
    SDL_PushEvent(&e);
    e.type = SDL_KEYUP;
    e.key.state = SDL_RELEASED;
    SDL_PushEvent(&e);
}

static void kg_push_wheel(kg_viewer* v, int amount)
{
    SDL_Event e;
    memset(&e, 0, sizeof e);
    e.type = SDL_MOUSEWHEEL;
    e.wheel.windowID = SDL_GetWindowID(v->window);
    e.wheel.y = amount;
    SDL_PushEvent(&e);
}

/* Runs the next script command as input events for this frame. */
static void kg_script_tick(kg_viewer* v)
{
    kg_script_command c;
    if (v->script.wait > 0) {
        v->script.wait--;
        return;
    }
    if (!v->script.next || kg_script_read(&v->script.next, &c) <= 0) {
        v->script.next = NULL;
        return;
    }
    if (strcmp(c.verb, "wait") == 0) {
        v->script.wait = c.x - 1;
    } else if (strcmp(c.verb, "key") == 0) {
        kg_push_key(v, SDL_GetKeyFromName(c.name));
    } else if (strcmp(c.verb, "wheel") == 0) {
        kg_push_wheel(v, c.x);
    } else {
        int click = strstr(c.verb, "click") != NULL;
        v->script.shift = strcmp(c.verb, "shift-click") == 0;
        kg_push_motion(v, c.x, c.y);
        if (click || strcmp(c.verb, "down") == 0) {
            kg_push_button(v, SDL_MOUSEBUTTONDOWN, c.x, c.y);
        }
        if (click || strcmp(c.verb, "up") == 0) {
            kg_push_button(v, SDL_MOUSEBUTTONUP, c.x, c.y);
        }
    }
}

/* ---- stepping and drawing ---- */

static void kg_step(kg_viewer* v)
{
    Uint64 start = SDL_GetPerformanceCounter();
    if (kg_sim_step(&v->sim) != KG_OK) {
        kg_show_message(v, kg_last_error());
        v->paused = 1;
        return;
    }
    double ms = 1000.0 * (double)(SDL_GetPerformanceCounter() - start) / (double)SDL_GetPerformanceFrequency();
    v->step_ms = v->step_ms > 0.0 ? 0.9 * v->step_ms + 0.1 * ms : ms;
    kg_contact_events ev = kg_world_get_contact_events(v->sim.world);
    for (int i = 0; i < ev.hit_count; ++i) {
        kg_flash* f = &v->flashes[v->next_flash];
        v->next_flash = (v->next_flash + 1) % KG_MAX_FLASHES;
        *f = (kg_flash){ev.hit[i].point, ev.hit[i].approach_speed, KG_FLASH_FRAMES};
    }
}

/* The hits of the last frames as rings at their points (the newest largest). */
static void kg_draw_flashes(kg_viewer* v)
{
    for (int i = 0; i < KG_MAX_FLASHES; ++i) {
        kg_flash* f = &v->flashes[i];
        if (f->frames > 0) {
            float radius = (2.0f + 1.5f * f->speed) * (float)f->frames / (float)KG_FLASH_FRAMES;
            kg_canvas_circle(&v->canvas, kg_camera_to_screen(&v->camera, f->point), radius, KG_COLOR_SELECTION);
            f->frames -= 1;
        }
    }
}

/* Appends to the text in buffer, cutting it at size. */
static void kg_append(char* text, size_t size, const char* format, ...)
{
    size_t used = strlen(text);
    va_list args;
    va_start(args, format);
    vsnprintf(text + used, size - used, format, args);
    va_end(args);
}

/* "CPU  PAUSED  BODIES 58  CONTACTS 12  STEP 0.41 MS (COLLIDE 0.10 SOLVE 0.25 ...)" */
static void kg_format_stats(const kg_viewer* v, char* text, size_t size)
{
    text[0] = '\0';
    kg_append(text, size, "%s%s  bodies %d  contacts %d  step %.2f ms", kg_backend_label(kg_world_backend(v->sim.world)),
              v->paused ? "  paused" : "", kg_world_body_count(v->sim.world), kg_world_contact_count(v->sim.world),
              v->step_ms);
    kg_stage_times stages;
    if (kg_world_get_stage_times(v->sim.world, &stages) == KG_OK && stages.count > 0) {
        for (int i = 0; i < stages.count && i < 16; ++i) {
            kg_append(text, size, "%s%s %.2f", i == 0 ? " (" : " ", stages.names[i], stages.ms[i]);
        }
        kg_append(text, size, ")");
    }
}

static void kg_draw_overlay(kg_viewer* v)
{
    char stats[256];
    kg_format_stats(v, stats, sizeof stats);
    int line = 7 * KG_TEXT_SCALE;
    kg_canvas_label(&v->canvas, 6, 6, KG_TEXT_SCALE, stats);
    if (v->message_frames > 0) {
        v->message_frames--;
        kg_canvas_label(&v->canvas, 6, 6 + line, KG_TEXT_SCALE, v->message);
    }
    kg_canvas_label(&v->canvas, 6, v->canvas.height - line, KG_TEXT_SCALE,
                    "drag: move  click: box  shift+click: circle  space: pause  n: step  c b t: show  o: backend");
}

static void kg_present(kg_viewer* v)
{
    SDL_Surface* window = SDL_GetWindowSurface(v->window);
    if (window) {
        SDL_BlitSurface(v->frame, NULL, window, NULL);
        SDL_UpdateWindowSurface(v->window);
    }
}

/* The screenshot is read back from the window's own surface, what SDL handed to the
 * display, not from the canvas. */
static int kg_screenshot(kg_viewer* v, const char* path)
{
    SDL_Surface* window = SDL_GetWindowSurface(v->window);
    SDL_Surface* rgb = window ? SDL_ConvertSurfaceFormat(window, SDL_PIXELFORMAT_RGB24, 0) : NULL;
    int r = rgb ? kg_write_png_rgb(path, rgb->w, rgb->h, rgb->pixels, rgb->pitch) : -1;
    SDL_FreeSurface(rgb);
    if (r != 0) {
        fprintf(stderr, "kgyro view: cannot write screenshot %s\n", path);
    }
    return r;
}

/* ---- setting up and the frame loop ---- */

/* SDL falls back to its headless drivers ("offscreen", "dummy") when no display works,
 * and the viewer would then run unseen until killed. Unless SDL_VIDEODRIVER asks for one
 * of them, only the drivers that show something are tried, so that without a display SDL
 * fails and says why. */
static void kg_want_visible_driver(void)
{
    if (getenv("SDL_VIDEODRIVER")) {
        return;
    }
    char drivers[256] = "";
    for (int i = 0; i < SDL_GetNumVideoDrivers(); ++i) {
        const char* name = SDL_GetVideoDriver(i);
        if (strcmp(name, "offscreen") != 0 && strcmp(name, "dummy") != 0) {
            size_t used = strlen(drivers);
            snprintf(drivers + used, sizeof drivers - used, "%s%s", used > 0 ? "," : "", name);
        }
    }
    SDL_SetHint(SDL_HINT_VIDEODRIVER, drivers);
}

static int kg_open_window(kg_viewer* v)
{
    const kg_view_config* c = v->config;
    kg_want_visible_driver();
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
        fprintf(stderr, "kgyro view: cannot open a window: %s (no display? set DISPLAY or WAYLAND_DISPLAY, or "
                        "SDL_VIDEODRIVER=offscreen to run unseen)\n", SDL_GetError());
        return 1;
    }
    char title[160];
    snprintf(title, sizeof title, "kgyro view: %s", c->scene);
    v->window = SDL_CreateWindow(title, SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, c->width, c->height, 0);
    v->frame = SDL_CreateRGBSurfaceWithFormatFrom(v->canvas.pixels, c->width, c->height, 8, c->width,
                                                  SDL_PIXELFORMAT_INDEX8);
    if (!v->window || !v->frame) {
        fprintf(stderr, "kgyro view: cannot open a window: %s\n", SDL_GetError());
        return 1;
    }
    SDL_Color colors[256];
    for (int i = 0; i < 256; ++i) {
        kg_rgb rgb = kg_palette_color((uint8_t)i);
        colors[i] = (SDL_Color){rgb.r, rgb.g, rgb.b, 255};
    }
    SDL_SetPaletteColors(v->frame->format->palette, colors, 0, 256);
    return 0;
}

static int kg_viewer_start(kg_viewer* v)
{
    const kg_view_config* c = v->config;
    kg_scene* scene = NULL;
    if (kg_open_scene(c->scene, c->seed, c->max_bodies, &scene) != KG_OK || kg_sim_start(&v->sim, scene, c->backend, KG_ADD_ROOM) != KG_OK) {
        fprintf(stderr, "kgyro view: %s\n", kg_last_error());
        if (!v->sim.scene) {
            kg_scene_destroy(scene);
        }
        return 2;
    }
    v->scene_bodies = v->sim.body_count;
    v->added = malloc(KG_ADD_ROOM * sizeof *v->added);
    kg_aabb view = c->view;
    if (!c->has_view && !kg_world_view_box(v->sim.world, &view)) {
        view = (kg_aabb){{-10.0f, -10.0f}, {10.0f, 10.0f}};
    }
    v->camera = kg_camera_fit(view, c->width, c->height, c->has_view ? 0.0f : 0.05f);
    v->script.next = c->script;
    if (!v->added || kg_canvas_init(&v->canvas, c->width, c->height) != 0) {
        fprintf(stderr, "kgyro view: out of memory\n");
        return 1;
    }
    v->draw = (kg_draw_options){0, 0, 1, 1};
    if (kg_open_window(v) != 0) {
        return 1;
    }
    return c->script && kg_script_check(c->script) < 0 ? 2 : 0;
}

static void kg_viewer_stop(kg_viewer* v)
{
    SDL_FreeSurface(v->frame);
    if (v->window) {
        SDL_DestroyWindow(v->window);
    }
    SDL_Quit();
    kg_canvas_free(&v->canvas);
    free(v->added);
    kg_sim_stop(&v->sim);
}

static void kg_run_frame(kg_viewer* v)
{
    kg_script_tick(v);
    SDL_Event e;
    while (SDL_PollEvent(&e)) {
        kg_handle_event(v, &e);
    }
    v->script.shift = 0;
    if (!v->paused || v->single_step) {
        kg_step(v);
        v->single_step = 0;
    }
    kg_draw_world(&v->canvas, &v->camera, v->sim.world, &v->draw);
    kg_draw_flashes(v);
    kg_draw_overlay(v);
    kg_present(v);
    v->frame_index++;
    if (v->config->frames > 0 && v->frame_index >= v->config->frames) {
        v->quit = 1;
    }
}

int kg_view_run(const kg_view_config* config)
{
    kg_viewer v;
    memset(&v, 0, sizeof v);
    v.config = config;
    int status = kg_viewer_start(&v);
    while (status == 0 && !v.quit) {
        Uint64 start = SDL_GetPerformanceCounter();
        kg_run_frame(&v);
        double ms = 1000.0 * (double)(SDL_GetPerformanceCounter() - start) / (double)SDL_GetPerformanceFrequency();
        if (ms < KG_FRAME_MS) {
            SDL_Delay((Uint32)(KG_FRAME_MS - ms));
        }
    }
    if (status == 0 && config->screenshot) {
        status = kg_screenshot(&v, config->screenshot) != 0;
    }
    if (status == 0) {
        printf("kgyro view: %d frames, %d bodies (%d added), %s, %s, video driver %s\n", v.frame_index,
               kg_world_body_count(v.sim.world), v.sim.body_count - v.scene_bodies,
               kg_backend_label(kg_world_backend(v.sim.world)), v.paused ? "paused" : "running",
               SDL_GetCurrentVideoDriver());
    }
    kg_viewer_stop(&v);
    return status;
}
