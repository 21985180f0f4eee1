/* kgyro run: loads or generates a scene, steps it, and writes the body states (and
 * optionally the contact points) as CSV. Floats are printed with %.9g, which round-trips
 * a float exactly, so two runs can be compared bit for bit with diff. */
#include "commands.h"
#include "progress.h"
#include "render/sim.h"

#include "kgyro/collision.h"
#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct kg_run_options {
    const char* scene;
    int steps;            /* -1: the scene's suggestion */
    float dt;             /* 0: the scene's */
    const char* csv;      /* NULL: SCENE.csv */
    int every;
    const char* contacts; /* NULL: none */
    const char* events;   /* NULL: none */
    int backend;          /* -1: the scene's (auto) */
    int threads;          /* -1: the scene's */
    uint32_t seed;
    int no_continuous;    /* --no-continuous: kg_world_def.enable_continuous off */
    int max_bodies;       /* --max-bodies: the most a scene file may ask for; -1: no limit */
    const char* save;     /* --save: the scene file the world is saved as at the end; NULL: none */
} kg_run_options;

#define KG_RUN_DEFAULT_STEPS 60

static void kg_run_usage(FILE* out)
{
    fprintf(out,
            "usage: kgyro run SCENE [OPTIONS]\n"
            "\n"
            "Steps SCENE and writes every body's state as CSV, one row per body per written\n"
            "step: step,id,name,x,y,angle,vx,vy,omega (id = the body's index in the scene,\n"
            "floats as %%.9g so that runs compare bit for bit).\n"
            "\n"
            "SCENE is a JSON scene file (docs/scene-format.md), a Tiled map (.tmj, docs/tilemaps.md)\n"
            "or a generator name:\n"
            "  pyramid_B, stack_N, rain_N, particles_N, large_pyramid, many_pyramids, smash, tumbler\n"
            "\n"
            "options:\n"
            "  --steps N         steps to run (default: the scene's \"steps\", else %d)\n"
            "  --dt S            time step in seconds (default: the scene's \"dt\", else 1/60)\n"
            "  --csv FILE        where the states go (default: SCENE's name + .csv in the current\n"
            "                    directory; - for standard output)\n"
            "  --every K         write the states every K steps (default 1); step 0 and the last\n"
            "                    step are always written\n"
            "  --contacts FILE   also write step,a,b,nx,ny,px,py,depth, one row per contact point\n"
            "                    at each written step (a, b = scene body ids; - for standard output)\n"
            "  --events FILE     also write every event of every step: step,kind,a,b,x,y,nx,ny,speed\n"
            "                    (kind begin, end, hit, sensor_begin or sensor_end; a, b = body names,\n"
            "                    the sensor first, b tile:LAYER:X:Y for a tile, empty for a body\n"
            "                    destroyed; x, y the point, speed a hit's approach speed; - for\n"
            "                    standard output)\n"
            "  --backend B       auto, cpu or opencl (default auto: OpenCL when a device works)\n"
            "  --threads N       CPU worker threads (default: the library's)\n"
            "  --no-continuous   turn continuous collision off (kg_world_def.enable_continuous)\n"
            "  --seed S          seed of the random generators, rain_N and particles_N (default 1)\n"
            "  --max-bodies N    refuse a scene file, a Tiled map or a generator name asking for more\n"
            "                    than N bodies, before they are allocated: for untrusted levels\n"
            "  --save FILE       at the end, save the world as a scene file that `kgyro run FILE`\n"
            "                    continues bitwise (docs/scene-format.md)\n"
            "  -h, --help        show this help\n"
            "\n"
            "On a terminal, a progress line on stderr (percentage, steps a second, time left) while\n"
            "it runs, erased at the end; none when stderr is not a terminal.\n"
            "\n"
            "Exit status: 0 done, 1 the run failed (backend, output file), 2 a bad scene or option.\n",
            KG_RUN_DEFAULT_STEPS);
}

/* ---- options ---- */

static int kg_option_error(const char* option, const char* expected, const char* value)
{
    fprintf(stderr, "kgyro run: %s: expected %s (got '%s')\n", option, expected, value);
    return 2;
}

static int kg_parse_long(const char* text, long min, long max, long* out)
{
    char* end;
    errno = 0;
    long value = strtol(text, &end, 10);
    if (errno != 0 || end == text || *end != '\0' || value < min || value > max) {
        return 0;
    }
    *out = value;
    return 1;
}

static int kg_parse_seconds(const char* text, float* out)
{
    char* end;
    errno = 0;
    double value = strtod(text, &end);
    if (errno != 0 || end == text || *end != '\0' || !isfinite((float)value) || !((float)value > 0.0f)) {
        return 0;
    }
    *out = (float)value;
    return 1;
}

/* Applies one "--name value" option; returns an exit code on error, else 0. */
static int kg_apply_option(kg_run_options* o, const char* name, const char* value)
{
    long n;
    if (strcmp(name, "--steps") == 0) {
        if (!kg_parse_long(value, 0, 1000000000L, &n)) {
            return kg_option_error(name, "an integer >= 0", value);
        }
        o->steps = (int)n;
    } else if (strcmp(name, "--dt") == 0) {
        if (!kg_parse_seconds(value, &o->dt)) {
            return kg_option_error(name, "a number of seconds > 0", value);
        }
    } else if (strcmp(name, "--every") == 0) {
        if (!kg_parse_long(value, 1, 1000000000L, &n)) {
            return kg_option_error(name, "an integer >= 1", value);
        }
        o->every = (int)n;
    } else if (strcmp(name, "--threads") == 0) {
        if (!kg_parse_long(value, 1, KG_MAX_THREADS, &n)) {
            return kg_option_error(name, "an integer in [1, 256] (the library's limit, KG_MAX_THREADS)", value);
        }
        o->threads = (int)n;
    } else if (strcmp(name, "--max-bodies") == 0) {
        if (!kg_parse_long(value, 0, 2147483647L, &n)) {
            return kg_option_error(name, "an integer >= 0", value);
        }
        o->max_bodies = (int)n;
    } else if (strcmp(name, "--seed") == 0) {
        if (!kg_parse_long(value, 0, 4294967295L, &n)) {
            return kg_option_error(name, "an integer in [0, 4294967295]", value);
        }
        o->seed = (uint32_t)n;
    } else if (strcmp(name, "--backend") == 0) {
        kg_backend backend;
        if (kg_parse_backend(value, &backend) != 0) {
            return kg_option_error(name, "auto, cpu or opencl", value);
        }
        o->backend = (int)backend;
    } else if (strcmp(name, "--csv") == 0) {
        o->csv = value;
    } else if (strcmp(name, "--contacts") == 0) {
        o->contacts = value;
    } else if (strcmp(name, "--events") == 0) {
        o->events = value;
    } else if (strcmp(name, "--save") == 0) {
        o->save = value;
    } else {
        fprintf(stderr, "kgyro run: unknown option '%s' (see kgyro run --help)\n", name);
        return 2;
    }
    return 0;
}

static int kg_is_option_with_value(const char* arg)
{
    static const char* const names[] = {"--steps", "--dt", "--csv", "--every", "--contacts", "--events",
                                        "--backend", "--threads", "--seed", "--max-bodies", "--save"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        if (strcmp(arg, names[i]) == 0) {
            return 1;
        }
    }
    return 0;
}

/* Returns -1 to go on, else the exit code (0 after --help). Accepts "--opt value" and
 * "--opt=value". */
static int kg_parse_run_options(int argc, char** argv, kg_run_options* o)
{
    *o = (kg_run_options){NULL, -1, 0.0f, NULL, 1, NULL, NULL, -1, -1, 1u, 0, -1, NULL};
    for (int i = 1; i < argc; ++i) {
        const char* arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            kg_run_usage(stdout);
            return 0;
        }
        if (strcmp(arg, "--no-continuous") == 0) {
            o->no_continuous = 1;
            continue;
        }
        const char* equals = strchr(arg, '=');
        if (strncmp(arg, "--", 2) == 0 && equals) {
            char name[32];
            snprintf(name, sizeof name, "%.*s", (int)(equals - arg < 31 ? equals - arg : 31), arg);
            int code = kg_apply_option(o, name, equals + 1);
            if (code != 0) {
                return code;
            }
        } else if (kg_is_option_with_value(arg)) {
            if (i + 1 >= argc) {
                fprintf(stderr, "kgyro run: %s needs a value (see kgyro run --help)\n", arg);
                return 2;
            }
            int code = kg_apply_option(o, arg, argv[++i]);
            if (code != 0) {
                return code;
            }
        } else if (arg[0] == '-' && arg[1] != '\0') {
            fprintf(stderr, "kgyro run: unknown option '%s' (see kgyro run --help)\n", arg);
            return 2;
        } else if (o->scene) {
            fprintf(stderr, "kgyro run: one scene only (got '%s' and '%s')\n", o->scene, arg);
            return 2;
        } else {
            o->scene = arg;
        }
    }
    if (!o->scene) {
        fprintf(stderr, "kgyro run: no scene given\n");
        kg_run_usage(stderr);
        return 2;
    }
    return -1;
}

/* ---- the scene ---- */

static int kg_load_scene(const kg_run_options* o, kg_scene** out)
{
    if (kg_open_scene(o->scene, o->seed, o->max_bodies, out) != KG_OK) {
        fprintf(stderr, "kgyro run: %s\n", kg_last_error());
        return 2;
    }
    return 0;
}

/* "samples/box_stack.json" -> "box_stack.csv"; "level.tmj" -> "level.csv"; "pyramid_20" -> "pyramid_20.csv". */
static void kg_default_csv_name(const char* scene, char* out, size_t size)
{
    const char* base = strrchr(scene, '/');
    base = base ? base + 1 : scene;
    size_t length = strlen(base);
    if (kg_ends_with(base, ".json")) {
        length -= 5;
    } else if (kg_ends_with(base, ".tmj")) {
        length -= 4;
    }
    snprintf(out, size, "%.*s.csv", (int)(length < 200 ? length : 200), base);
}

/* ---- output ---- */

typedef struct kg_csv {
    const char* path;
    FILE* file;
    long rows;
} kg_csv;

static int kg_csv_open(kg_csv* csv, const char* path, const char* header)
{
    csv->path = path;
    csv->rows = 0;
    csv->file = strcmp(path, "-") == 0 ? stdout : fopen(path, "w");
    if (!csv->file) {
        fprintf(stderr, "kgyro run: %s: cannot write (%s)\n", path, strerror(errno));
        return 0;
    }
    fprintf(csv->file, "%s\n", header);
    return 1;
}

/* Closes the file; 0 if anything written to it was lost. */
static int kg_csv_close(kg_csv* csv)
{
    if (!csv->file) {
        return 1;
    }
    int failed = ferror(csv->file);
    failed |= csv->file == stdout ? fflush(stdout) != 0 : fclose(csv->file) != 0;
    csv->file = NULL;
    if (failed) {
        fprintf(stderr, "kgyro run: %s: write failed\n", csv->path);
    }
    return !failed;
}

typedef struct kg_run {
    const kg_scene* scene;
    kg_world* world;
    kg_body* bodies;
    kg_body_state* states;
    int* scene_ids; /* by body slot index, to name contact bodies by scene id */
    int slot_count;
    kg_csv states_csv;
    kg_csv contacts_csv;
    kg_csv events_csv;
} kg_run;

static int kg_write_states(kg_run* run, int step)
{
    int count = kg_scene_body_count(run->scene);
    if (count > 0 && kg_world_get_body_states(run->world, run->bodies, count, run->states) != KG_OK) {
        fprintf(stderr, "kgyro run: reading body states: %s\n", kg_last_error());
        return 0;
    }
    FILE* out = run->states_csv.file;
    for (int i = 0; i < count; ++i) {
        const kg_body_state* s = &run->states[i];
        fprintf(out, "%d,%d,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", step, i, kg_scene_body_name(run->scene, i),
                (double)s->position.x, (double)s->position.y, (double)s->angle, (double)s->velocity.x,
                (double)s->velocity.y, (double)s->angular_velocity);
    }
    run->states_csv.rows += count;
    return 1;
}

static int kg_scene_id(const kg_run* run, kg_body body)
{
    if (body.index >= (uint32_t)run->slot_count) {
        return -1;
    }
    int id = run->scene_ids[body.index];
    return id >= 0 && run->bodies[id].generation == body.generation ? id : -1;
}

static int kg_write_contacts(kg_run* run, int step)
{
    int count = kg_world_contact_count(run->world);
    FILE* out = run->contacts_csv.file;
    for (int c = 0; c < count; ++c) {
        kg_contact_info info;
        if (kg_world_get_contact(run->world, c, &info) != KG_OK) {
            fprintf(stderr, "kgyro run: reading contact %d: %s\n", c, kg_last_error());
            return 0;
        }
        int a = kg_scene_id(run, info.a), b = kg_scene_id(run, info.b);
        for (int p = 0; p < info.point_count; ++p) {
            fprintf(out, "%d,%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g\n", step, a, b, (double)info.normal.x,
                    (double)info.normal.y, (double)info.points[p].x, (double)info.points[p].y,
                    (double)info.depths[p]);
        }
        run->contacts_csv.rows += info.point_count;
    }
    return 1;
}

/* A body of an event as the CSV names it: its scene name, a tile as tile:LAYER:X:Y, or
 * nothing for a body destroyed or not from the scene. */
static void kg_event_party(const kg_run* run, const kg_contact_event* e, int is_b, char* out, size_t size)
{
    kg_body body = is_b ? e->b : e->a;
    int id = kg_scene_id(run, body);
    if (id >= 0) {
        snprintf(out, size, "%s", kg_scene_body_name(run->scene, id));
    } else if (is_b && body.generation == 0u && kg_tilemap_is_valid(run->world, e->map)) {
        snprintf(out, size, "tile:%d:%d:%d", e->layer, e->x, e->y);
    } else {
        out[0] = '\0';
    }
}

static void kg_write_event_list(kg_run* run, int step, const char* kind, const kg_contact_event* e, int count)
{
    for (int i = 0; i < count; ++i) {
        char a[128], b[128];
        kg_event_party(run, &e[i], 0, a, sizeof a);
        kg_event_party(run, &e[i], 1, b, sizeof b);
        fprintf(run->events_csv.file, "%d,%s,%s,%s,%.9g,%.9g,%.9g,%.9g,%.9g\n", step, kind, a, b, (double)e[i].point.x,
                (double)e[i].point.y, (double)e[i].normal.x, (double)e[i].normal.y, (double)e[i].approach_speed);
    }
    run->events_csv.rows += count;
}

/* Every step's events, kind by kind: begin, end, hit, sensor_begin, sensor_end. */
static void kg_write_events(kg_run* run, int step)
{
    kg_contact_events ev = kg_world_get_contact_events(run->world);
    kg_sensor_events se = kg_world_get_sensor_events(run->world);
    kg_write_event_list(run, step, "begin", ev.begin, ev.begin_count);
    kg_write_event_list(run, step, "end", ev.end, ev.end_count);
    kg_write_event_list(run, step, "hit", ev.hit, ev.hit_count);
    kg_write_event_list(run, step, "sensor_begin", se.begin, se.begin_count);
    kg_write_event_list(run, step, "sensor_end", se.end, se.end_count);
}

static int kg_write_step(kg_run* run, int step)
{
    return kg_write_states(run, step) && (!run->contacts_csv.file || kg_write_contacts(run, step));
}

/* ---- running ---- */

static int kg_map_scene_ids(kg_run* run)
{
    int count = kg_scene_body_count(run->scene);
    run->slot_count = 0;
    for (int i = 0; i < count; ++i) {
        if ((int)run->bodies[i].index + 1 > run->slot_count) {
            run->slot_count = (int)run->bodies[i].index + 1;
        }
    }
    run->scene_ids = malloc((size_t)(run->slot_count > 0 ? run->slot_count : 1) * sizeof *run->scene_ids);
    if (!run->scene_ids) {
        return 0;
    }
    for (int i = 0; i < run->slot_count; ++i) {
        run->scene_ids[i] = -1;
    }
    for (int i = 0; i < count; ++i) {
        run->scene_ids[run->bodies[i].index] = i;
    }
    return 1;
}

static int kg_start_world(kg_run* run, const kg_run_options* o, kg_scene* scene)
{
    kg_world_def def = *kg_scene_world_def(scene);
    if (o->backend >= 0) {
        def.backend = (kg_backend)o->backend;
    }
    if (o->threads >= 0) {
        def.threads = o->threads;
    }
    if (o->no_continuous) {
        def.enable_continuous = 0;
    }
    int count = kg_scene_body_count(scene);
    size_t slots = (size_t)(count > 0 ? count : 1);
    run->bodies = malloc(slots * sizeof *run->bodies);
    run->states = malloc(slots * sizeof *run->states);
    if (!run->bodies || !run->states) {
        fprintf(stderr, "kgyro run: out of memory\n");
        return 0;
    }
    if (kg_scene_instantiate(scene, &def, &run->world, run->bodies) != KG_OK) {
        fprintf(stderr, "kgyro run: %s: %s\n", o->scene, kg_last_error());
        return 0;
    }
    if (!kg_map_scene_ids(run)) {
        fprintf(stderr, "kgyro run: out of memory\n");
        return 0;
    }
    return 1;
}

static double kg_now_seconds(void)
{
    struct timespec t;
    timespec_get(&t, TIME_UTC);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Steps and writes; returns the seconds spent stepping, or a negative number on failure. */
static double kg_step_all(kg_run* run, int steps, float dt, int every, kg_progress* progress)
{
    double stepping = 0.0;
    if (!kg_write_step(run, 0)) {
        return -1.0;
    }
    for (int step = 1; step <= steps; ++step) {
        kg_progress_update(progress, step - 1);
        double start = kg_now_seconds();
        if (kg_scene_step(run->scene, run->world, run->bodies, dt) != KG_OK) {
            kg_progress_end(progress);
            fprintf(stderr, "kgyro run: step %d: %s\n", step, kg_last_error());
            return -1.0;
        }
        stepping += kg_now_seconds() - start;
        if (run->events_csv.file) {
            kg_write_events(run, step);
        }
        if ((step % every == 0 || step == steps) && !kg_write_step(run, step)) {
            return -1.0;
        }
    }
    return stepping;
}

static const char* kg_output_name(const char* path) { return strcmp(path, "-") == 0 ? "standard output" : path; }

static void kg_report(const kg_run* run, const kg_run_options* o, int steps, float dt, double seconds)
{
    int to_stdout = strcmp(run->states_csv.path, "-") == 0 || (o->contacts && strcmp(o->contacts, "-") == 0) ||
                    (o->events && strcmp(o->events, "-") == 0);
    FILE* out = to_stdout ? stderr : stdout;
    const char* backend = kg_world_backend(run->world) == KG_BACKEND_OPENCL ? "opencl" : "cpu";
    fprintf(out, "kgyro run: %s: %d bodies, %d steps of %.9g s on %s in %.3f s (%.3f ms/step)\n", o->scene,
            kg_scene_body_count(run->scene), steps, (double)dt, backend, seconds,
            steps > 0 ? 1000.0 * seconds / steps : 0.0);
    fprintf(out, "states: %s (%ld rows)\n", kg_output_name(run->states_csv.path), run->states_csv.rows);
    if (o->contacts) {
        fprintf(out, "contacts: %s (%ld rows)\n", kg_output_name(o->contacts), run->contacts_csv.rows);
    }
    if (o->events) {
        fprintf(out, "events: %s (%ld rows)\n", kg_output_name(o->events), run->events_csv.rows);
    }
}

/* --save: the world as it ends, as a scene file. */
static int kg_save_world(const kg_run* run, const char* path)
{
    kg_scene* saved = NULL;
    kg_result r = kg_scene_from_world_named(run->world, run->scene, run->bodies, &saved);
    if (r == KG_OK) {
        r = kg_scene_save_file(saved, path);
    }
    kg_scene_destroy(saved);
    if (r != KG_OK) {
        fprintf(stderr, "kgyro run: --save %s: %s\n", path, kg_last_error());
        return 0;
    }
    return 1;
}

static int kg_run_scene(kg_run* run, const kg_run_options* o, kg_scene* scene)
{
    int steps = o->steps >= 0 ? o->steps : kg_scene_steps(scene) > 0 ? kg_scene_steps(scene) : KG_RUN_DEFAULT_STEPS;
    float dt = o->dt > 0.0f ? o->dt : kg_scene_dt(scene);
    char default_csv[256];
    kg_default_csv_name(o->scene, default_csv, sizeof default_csv);
    if (!kg_start_world(run, o, scene) || !kg_csv_open(&run->states_csv, o->csv ? o->csv : default_csv,
                                                       "step,id,name,x,y,angle,vx,vy,omega")) {
        return 1;
    }
    if (o->contacts && !kg_csv_open(&run->contacts_csv, o->contacts, "step,a,b,nx,ny,px,py,depth")) {
        return 1;
    }
    if (o->events && !kg_csv_open(&run->events_csv, o->events, "step,kind,a,b,x,y,nx,ny,speed")) {
        return 1;
    }
    char label[256];
    snprintf(label, sizeof label, "kgyro run: %s", o->scene);
    kg_progress progress;
    kg_progress_start(&progress, label, steps);
    double seconds = kg_step_all(run, steps, dt, o->every, &progress);
    kg_progress_end(&progress);
    int written = kg_csv_close(&run->states_csv) & kg_csv_close(&run->contacts_csv) & kg_csv_close(&run->events_csv);
    if (seconds < 0.0 || !written || (o->save && !kg_save_world(run, o->save))) {
        return 1;
    }
    kg_report(run, o, steps, dt, seconds);
    return 0;
}

int kg_cmd_run(int argc, char** argv)
{
    kg_run_options options;
    int code = kg_parse_run_options(argc, argv, &options);
    if (code >= 0) {
        return code;
    }
    kg_scene* scene = NULL;
    code = kg_load_scene(&options, &scene);
    if (code != 0) {
        return code;
    }
    kg_run run;
    memset(&run, 0, sizeof run);
    run.scene = scene;
    code = kg_run_scene(&run, &options, scene);
    kg_csv_close(&run.states_csv);
    kg_csv_close(&run.contacts_csv);
    kg_csv_close(&run.events_csv);
    if (run.world) {
        kg_destroy_world(run.world);
    }
    free(run.scene_ids);
    free(run.states);
    free(run.bodies);
    kg_scene_destroy(scene);
    return code;
}
