/* kgyro bench: the same scenes stepped in kgyro and in the peer engines (Box2D 2.4,
 * Chipmunk 7), side by side, with a correctness line so that nobody wins by being wrong.
 * docs/benchmarks.md explains the method and shows the numbers. */
#include "bench.h"
#include "commands.h"

#include "kgyro/kgyro.h"
#ifdef KG_HAVE_PEERS
#include "kg_peers.h"
#endif

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Box2D's benchmark set runs 4 sub-steps where the engine has them. */
enum { BENCH_MAX_ENGINES = 4, BENCH_DEFAULT_STEPS = 100, BENCH_DEFAULT_SUBSTEPS = 0 };

static const char* const kDefaultScenes[] = {"large_pyramid", "many_pyramids", "smash", "tumbler"};

typedef struct bench_options {
    bench_config config;
    const char* engines;
    const char* backends;
    const char* csv_path;
    const char* plot_dir;
    int profile;
    int scene_count;
    const char* const* scenes;
} bench_options;

/* An engine that went over the time budget on a series, or failed at one of its sizes,
 * and so sits out the larger sizes. */
typedef struct bench_stop {
    int engine;
    char family[BENCH_SCENE_NAME_MAX];
    char why[BENCH_MESSAGE_MAX];
} bench_stop;

typedef struct bench_session {
    bench_options options;
    bench_engine engines[BENCH_MAX_ENGINES];
    int engine_count;
    int solver_in_place;
    bench_row* rows;
    int row_count;
    bench_stop* stops;
    int stop_count;
    int exit_code;
} bench_session;

static void bench_usage(FILE* out)
{
    fprintf(out,
            "usage: kgyro bench [SCENE[:STEPS]...] [OPTIONS]\n"
            "\n"
            "Steps each scene in kgyro and in the peer engines and reports, per engine, the median and\n"
            "95th-percentile wall-clock ms per step over every step of every run, the ratio to kgyro's\n"
            "median, the peak memory of a run, and a correctness line (a pyramid's top box drift, bodies\n"
            "below the ground, non-finite states). Every run is a fresh world in a forked child, the\n"
            "engines taking their runs of a scene in turns; on a terminal, kgyro's runs show a progress\n"
            "line on stderr while they step.\n"
            "\n"
            "SCENE is a generator name (large_pyramid, many_pyramids, smash, tumbler, rain_N,\n"
            "particles_N, pyramid_B, stack_N); :STEPS gives that scene its own step count.\n"
            "Default: the four Box2D benchmark scenes with their own step counts.\n"
            "\n"
            "options:\n"
            "  --engines LIST   kgyro,box2d,chipmunk (default: all three)\n"
            "  --backend LIST   kgyro backends: cpu,opencl (default: cpu); KGYRO_BACKEND is ignored\n"
            "  --device N       OpenCL device of the opencl backend (default 0; kgyro info lists them)\n"
            "  --threads N      worker threads for kgyro and Chipmunk (default 1; Box2D 2.4 has one)\n"
            "  --substeps N     kgyro's solver sub-steps (default 0: the engine's own, 4, as Box2D\n"
            "                   v3's). The peers have none: Box2D 2.4 iterates, Chipmunk too\n"
            "  --steps N        steps per run for every scene (default: each scene's own)\n"
            "  --runs R         runs per scene and engine (default 3)\n"
            "  --seed S         seed of the random scenes (default 1)\n"
            "  --budget SEC     an engine whose run steps longer than SEC (or fails) skips the larger\n"
            "                   sizes of the same series (rain_N, particles_N) later on the command line\n"
            "  --timeout SEC    kill a run that takes longer than SEC\n"
            "  --csv FILE       write the table as CSV, and kgyro's stage times to FILE_stages.csv\n"
            "  --plot DIR       write gnuplot scripts to DIR and draw them as PNG: scaling.png (step\n"
            "                   time vs bodies, log-log), scenes.png, stages.png\n"
            "  --profile        print each kgyro stage's share of the step\n"
            "  --no-continuous  kgyro with continuous collision off (kg_world_def.enable_continuous),\n"
            "                   to measure what it costs\n");
}

static int bench_parse_int(const char* text, int min, int* out)
{
    char* end = NULL;
    long value = text ? strtol(text, &end, 10) : 0;
    if (!text || *text == '\0' || *end != '\0' || value < min || value > 100000000L) {
        return 0;
    }
    *out = (int)value;
    return 1;
}

static int bench_parse_seconds(const char* text, double* out)
{
    char* end = NULL;
    double value = text ? strtod(text, &end) : -1.0;
    if (!text || *text == '\0' || *end != '\0' || !(value >= 0.0) || !isfinite(value)) {
        return 0;
    }
    *out = value;
    return 1;
}

/* Sets option name (without any "=value") to value; 0 when either is not valid. */
static int bench_set_option(bench_options* o, const char* name, const char* value)
{
    bench_config* c = &o->config;
    int seed = 0;
    if (!value) {
        return 0;
    } else if (strcmp(name, "--engines") == 0) {
        o->engines = value;
    } else if (strcmp(name, "--backend") == 0) {
        o->backends = value;
    } else if (strcmp(name, "--csv") == 0) {
        o->csv_path = value;
    } else if (strcmp(name, "--plot") == 0) {
        o->plot_dir = value;
    } else if (strcmp(name, "--threads") == 0) {
        return bench_parse_int(value, 1, &c->threads);
    } else if (strcmp(name, "--device") == 0) {
        return bench_parse_int(value, 0, &c->device);
    } else if (strcmp(name, "--steps") == 0) {
        return bench_parse_int(value, 1, &c->steps);
    } else if (strcmp(name, "--substeps") == 0) {
        return bench_parse_int(value, 0, &c->substeps);
    } else if (strcmp(name, "--runs") == 0) {
        return bench_parse_int(value, 1, &c->runs);
    } else if (strcmp(name, "--seed") == 0) {
        int ok = bench_parse_int(value, 0, &seed);
        c->seed = (unsigned)seed;
        return ok;
    } else if (strcmp(name, "--budget") == 0) {
        return bench_parse_seconds(value, &c->budget_s);
    } else if (strcmp(name, "--timeout") == 0) {
        return bench_parse_seconds(value, &c->timeout_s);
    } else {
        return 0;
    }
    return 1;
}

/* Parses the option at argv[*i], "--name value" or "--name=value"; 0 when not valid. */
static int bench_parse_option(int argc, char** argv, int* i, bench_options* o)
{
    const char* arg = argv[*i];
    if (strcmp(arg, "--profile") == 0) {
        o->profile = 1;
        return 1;
    }
    if (strcmp(arg, "--no-continuous") == 0) {
        o->config.no_continuous = 1;
        return 1;
    }
    char name[32];
    const char* equals = strchr(arg, '=');
    if (equals) {
        snprintf(name, sizeof name, "%.*s", (int)(equals - arg), arg);
        return bench_set_option(o, name, equals + 1);
    }
    return bench_set_option(o, arg, *i + 1 < argc ? argv[++*i] : NULL);
}

/* 0 to go on, else the exit code (-1 after --help). Scenes are the non-option words. */
static int bench_parse_options(int argc, char** argv, bench_options* o, const char** scenes)
{
    o->config = (bench_config){.threads = 1, .substeps = BENCH_DEFAULT_SUBSTEPS, .runs = 3, .seed = 1};
    o->engines = "kgyro,box2d,chipmunk";
    o->backends = "cpu";
    for (int i = 1; i < argc; ++i) {
        const char* arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            bench_usage(stdout);
            return -1;
        }
        if (strncmp(arg, "--", 2) != 0) {
            scenes[o->scene_count++] = arg;
        } else if (!bench_parse_option(argc, argv, &i, o)) {
            fprintf(stderr, "kgyro bench: bad or incomplete option '%s' (see kgyro bench --help)\n", arg);
            return 2;
        }
    }
    o->scenes = o->scene_count > 0 ? scenes : kDefaultScenes;
    if (o->scene_count == 0) {
        o->scene_count = (int)(sizeof kDefaultScenes / sizeof kDefaultScenes[0]);
    }
    return 0;
}

/* ---- engines ---- */

/* Whether word is one of the comma-separated items of list. */
static int bench_list_has(const char* list, const char* word)
{
    size_t n = strlen(word);
    for (const char* p = list; p && *p;) {
        const char* comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        if (len == n && strncmp(p, word, n) == 0) {
            return 1;
        }
        p = comma ? comma + 1 : NULL;
    }
    return 0;
}

/* Every item of list is among the known words. */
static int bench_list_valid(const char* list, const char* const* known, int known_count)
{
    char copy[256];
    snprintf(copy, sizeof copy, "%s", list);
    for (char* item = strtok(copy, ","); item; item = strtok(NULL, ",")) {
        int found = 0;
        for (int k = 0; k < known_count; ++k) {
            found |= strcmp(item, known[k]) == 0;
        }
        if (!found) {
            fprintf(stderr, "kgyro bench: unknown engine or backend '%s'\n", item);
            return 0;
        }
    }
    return 1;
}

static void bench_add_kgyro(bench_session* s, kg_backend backend, const char* name)
{
    bench_engine* e = &s->engines[s->engine_count++];
    e->kind = BENCH_KGYRO;
    e->backend = backend;
    snprintf(e->label, sizeof e->label, "kgyro/%s", name);
    char why[BENCH_MESSAGE_MAX];
    e->available = bench_kgyro_backend_works(backend, &s->options.config, why, sizeof why);
    if (!e->available) {
        snprintf(e->about, sizeof e->about, "%s backend unavailable: %s", name, why);
        return;
    }
    const bench_config* c = &s->options.config;
    char substeps[32] = "the scene's";
    if (c->substeps > 0) {
        snprintf(substeps, sizeof substeps, "%d", c->substeps);
    }
    char device[32] = "";
    if (backend == KG_BACKEND_OPENCL) {
        snprintf(device, sizeof device, " (device %d)", c->device);
    }
    snprintf(e->about, sizeof e->about, "KineticGyro %d.%d.%d, %s backend%s, %s sub-steps, %d thread%s",
             KGYRO_VERSION_MAJOR, KGYRO_VERSION_MINOR, KGYRO_VERSION_PATCH, name, device, substeps, c->threads,
             c->threads == 1 ? "" : "s");
}

static void bench_add_peer(bench_session* s, bench_engine_kind kind, const char* name)
{
    bench_engine* e = &s->engines[s->engine_count++];
    e->kind = kind;
    snprintf(e->label, sizeof e->label, "%s", name);
#ifdef KG_HAVE_PEERS
    kg_peer_engine peer = kind == BENCH_BOX2D ? KG_PEER_BOX2D : KG_PEER_CHIPMUNK;
    e->available = kg_peer_available(peer);
    snprintf(e->about, sizeof e->about, "%s", kg_peer_describe(peer, s->options.config.threads));
#else
    snprintf(e->about, sizeof e->about, "not built into this kgyro (configured with KGYRO_BUILD_BENCH=OFF)");
#endif
}

/* kgyro first, so that every peer row can show its ratio to kgyro as soon as it is done. */
static int bench_make_engines(bench_session* s)
{
    static const char* const engines[] = {"kgyro", "box2d", "chipmunk"};
    static const char* const backends[] = {"cpu", "opencl"};
    const bench_options* o = &s->options;
    if (!bench_list_valid(o->engines, engines, 3) || !bench_list_valid(o->backends, backends, 2)) {
        return 0;
    }
    if (bench_list_has(o->engines, "kgyro")) {
        if (bench_list_has(o->backends, "cpu")) {
            bench_add_kgyro(s, KG_BACKEND_CPU, "cpu");
        }
        if (bench_list_has(o->backends, "opencl")) {
            bench_add_kgyro(s, KG_BACKEND_OPENCL, "opencl");
        }
    }
    if (bench_list_has(o->engines, "box2d")) {
        bench_add_peer(s, BENCH_BOX2D, "box2d");
    }
    if (bench_list_has(o->engines, "chipmunk")) {
        bench_add_peer(s, BENCH_CHIPMUNK, "chipmunk");
    }
    return s->engine_count > 0;
}

/* ---- the run ---- */

static void bench_print_machine(void)
{
    FILE* f = fopen("/proc/cpuinfo", "r");
    char line[256], model[256] = "unknown CPU";
    while (f && fgets(line, sizeof line, f)) {
        char* colon = strchr(line, ':');
        if (strncmp(line, "model name", 10) == 0 && colon) {
            snprintf(model, sizeof model, "%s", colon + 2);
            model[strcspn(model, "\n")] = '\0';
            break;
        }
    }
    if (f) {
        fclose(f);
    }
    printf("machine: %s, %ld logical CPUs\n", model, sysconf(_SC_NPROCESSORS_ONLN));
}

static void bench_print_intro(bench_session* s)
{
    const bench_config* c = &s->options.config;
    printf("kgyro bench: %d scene%s, %d run%s each, %d thread%s, seed %u\n", s->options.scene_count,
           s->options.scene_count == 1 ? "" : "s", c->runs, c->runs == 1 ? "" : "s", c->threads,
           c->threads == 1 ? "" : "s", c->seed);
    bench_print_machine();
    for (int i = 0; i < s->engine_count; ++i) {
        const bench_engine* e = &s->engines[i];
        printf("%-12s %s%s\n", e->label, e->available ? "" : "MISSING: ", e->about);
    }
    if (s->engines[0].kind == BENCH_KGYRO) {
        char message[BENCH_MESSAGE_MAX];
        s->solver_in_place = bench_kgyro_solver_check(message, sizeof message);
        printf("kgyro contact solver: %s\n", message);
    }
    printf("ms: wall clock per step, over every step of every run; x kgyro: median / kgyro's median "
           "(above 1 = slower than kgyro); peak MB: peak resident memory growth of a run\n");
}

/* "rain_1000" is size 1000 of the series "rain"; "large_pyramid" is a scene of its own. */
static void bench_split_name(const char* name, bench_scene_info* info)
{
    snprintf(info->family, sizeof info->family, "%s", name);
    char* underscore = strrchr(info->family, '_');
    if (!underscore || underscore[1] == '\0') {
        return;
    }
    for (const char* c = underscore + 1; *c; ++c) {
        if (!isdigit((unsigned char)*c)) {
            return;
        }
    }
    info->size = atoi(underscore + 1);
    *underscore = '\0';
}

static void bench_describe_scene(const kg_scene* scene, const char* name, int steps, const bench_config* config,
                                 bench_scene_info* info)
{
    memset(info, 0, sizeof *info);
    snprintf(info->name, sizeof info->name, "%s", name);
    bench_split_name(name, info);
    info->body_count = kg_scene_body_count(scene);
    for (int i = 0; i < info->body_count; ++i) {
        kg_body_type type = kg_scene_body_def(scene, i)->type;
        info->dynamic_count += type == KG_BODY_DYNAMIC || type == KG_BODY_PARTICLE;
    }
    info->steps = steps > 0 ? steps : config->steps > 0 ? config->steps : kg_scene_steps(scene);
    info->steps = info->steps > 0 ? info->steps : BENCH_DEFAULT_STEPS;
    info->dt = kg_scene_dt(scene);
    info->is_pyramid = strstr(name, "pyramid") != NULL;
}

static const bench_stop* bench_find_stop(const bench_session* s, int engine, const char* family)
{
    for (int i = 0; i < s->stop_count; ++i) {
        if (s->stops[i].engine == engine && strcmp(s->stops[i].family, family) == 0) {
            return &s->stops[i];
        }
    }
    return NULL;
}

/* After a size of a series: over the budget, or failed, the engine stops there. */
static void bench_note_stop(bench_session* s, int engine, const bench_scene_info* info, const bench_result* r)
{
    double budget = s->options.config.budget_s;
    int over = budget > 0.0 && r->slowest_run_s > budget;
    if ((!over && r->status == BENCH_OK) || info->size == 0 || bench_find_stop(s, engine, info->family)) {
        return;
    }
    bench_stop* grown = realloc(s->stops, (size_t)(s->stop_count + 1) * sizeof *grown);
    if (!grown) {
        return;
    }
    s->stops = grown;
    bench_stop* stop = &s->stops[s->stop_count++];
    stop->engine = engine;
    snprintf(stop->family, sizeof stop->family, "%s", info->family);
    if (r->status == BENCH_OK) {
        snprintf(stop->why, sizeof stop->why, "went over the %.0f s time budget at %s", budget, info->name);
    } else {
        snprintf(stop->why, sizeof stop->why, "stopped after it %s at %s", bench_status_name(r->status), info->name);
    }
}

/* Whether engine is not to be measured on this scene (missing, or stopped in its
 * series): then r says why. */
static int bench_unmeasured(const bench_session* s, int engine, const bench_scene_info* info, bench_result* r)
{
    const bench_engine* e = &s->engines[engine];
    const bench_stop* stop = info->size > 0 ? bench_find_stop(s, engine, info->family) : NULL;
    memset(r, 0, sizeof *r);
    if (!e->available) {
        r->status = BENCH_MISSING;
        snprintf(r->message, sizeof r->message, "%.*s", (int)sizeof r->message - 1, e->about); /* cut if long */
    } else if (stop) {
        r->status = BENCH_SKIPPED;
        snprintf(r->message, sizeof r->message, "%.*s", (int)sizeof r->message - 1, stop->why);
    }
    return !e->available || stop;
}

/* Every engine's result on the scene into results (in engine order): those to be
 * measured run together, their runs in turns (bench_run). */
static void bench_measure(bench_session* s, kg_scene* scene, const bench_scene_info* info, bench_result* results)
{
    const bench_engine* measured[BENCH_MAX_ENGINES];
    int which[BENCH_MAX_ENGINES], count = 0;
    for (int i = 0; i < s->engine_count; ++i) {
        if (!bench_unmeasured(s, i, info, &results[i])) {
            measured[count] = &s->engines[i];
            which[count++] = i;
        }
    }
    bench_result out[BENCH_MAX_ENGINES];
    bench_run(measured, count, scene, info, &s->options.config, out);
    for (int k = 0; k < count; ++k) {
        results[which[k]] = out[k];
        bench_note_stop(s, which[k], info, &out[k]);
    }
    for (int i = 0; i < s->engine_count; ++i) {
        if (results[i].status == BENCH_FAILED || results[i].status == BENCH_CRASHED) {
            s->exit_code = 1;
        }
    }
}

static bench_row* bench_new_row(bench_session* s)
{
    bench_row* grown = realloc(s->rows, (size_t)(s->row_count + 1) * sizeof *grown);
    if (!grown) {
        return NULL;
    }
    s->rows = grown;
    bench_row* row = &s->rows[s->row_count++];
    memset(row, 0, sizeof *row);
    return row;
}

static void bench_scene_engines(bench_session* s, kg_scene* scene, const bench_scene_info* info)
{
    bench_result results[BENCH_MAX_ENGINES];
    bench_measure(s, scene, info, results);
    double kgyro_median = NAN;
    for (int i = 0; i < s->engine_count; ++i) {
        bench_row* row = bench_new_row(s);
        if (!row) {
            fprintf(stderr, "kgyro bench: out of memory\n");
            s->exit_code = 1;
            return;
        }
        row->scene = *info;
        row->engine = s->engines[i];
        row->result = results[i];
        int ok = row->result.status == BENCH_OK;
        if (ok && isnan(kgyro_median) && row->engine.kind == BENCH_KGYRO) {
            kgyro_median = row->result.median_ms;
        }
        row->ratio = ok ? row->result.median_ms / kgyro_median : NAN;
        bench_print_row(row);
        if (s->options.profile) {
            bench_print_stages(row);
        }
    }
}

/* Splits "NAME:STEPS"; returns the steps, 0 when not given, -1 when malformed. */
static int bench_split_spec(const char* spec, char* name, size_t size)
{
    snprintf(name, size, "%s", spec);
    char* colon = strchr(name, ':');
    if (!colon) {
        return 0;
    }
    *colon = '\0';
    int steps = 0;
    return bench_parse_int(colon + 1, 1, &steps) ? steps : -1;
}

static void bench_scene(bench_session* s, const char* spec)
{
    char name[BENCH_SCENE_NAME_MAX];
    int steps = bench_split_spec(spec, name, sizeof name);
    kg_scene* scene = NULL;
    kg_result r = steps < 0 ? KG_ERROR_INVALID_ARGUMENT : kg_scene_generate(name, s->options.config.seed, &scene);
    if (r != KG_OK) {
        fprintf(stderr, "kgyro bench: scene '%s': %s\n", spec, steps < 0 ? "bad step count" : kg_last_error());
        s->exit_code = 2;
        return;
    }
    bench_scene_info info;
    bench_describe_scene(scene, name, steps, &s->options.config, &info);
    bench_print_scene_header(&info, &s->options.config);
    bench_scene_engines(s, scene, &info);
    kg_scene_destroy(scene);
}

/* FILE.csv -> FILE_stages.csv */
static void bench_stages_path(const char* csv, char* out, size_t size)
{
    size_t n = strlen(csv);
    int has_ext = n > 4 && strcmp(csv + n - 4, ".csv") == 0;
    snprintf(out, size, "%.*s_stages.csv", (int)(has_ext ? n - 4 : n), csv);
}

static void bench_write_outputs(bench_session* s)
{
    const bench_options* o = &s->options;
    if (o->csv_path) {
        char stages[1024];
        bench_stages_path(o->csv_path, stages, sizeof stages);
        if (bench_write_csv(o->csv_path, s->rows, s->row_count, &o->config, s->solver_in_place) != 0 ||
            bench_write_stages_csv(stages, s->rows, s->row_count, &o->config) != 0) {
            s->exit_code = 1;
        } else {
            printf("\ncsv: %s, %s\n", o->csv_path, stages);
        }
    }
    if (o->plot_dir && bench_plot(o->plot_dir, s->rows, s->row_count) != 0) {
        s->exit_code = 1;
    }
}

int kg_cmd_bench(int argc, char** argv)
{
    bench_session s;
    memset(&s, 0, sizeof s);
    s.solver_in_place = -1; /* not checked unless kgyro runs */
    const char** scenes = calloc((size_t)argc + 1, sizeof *scenes);
    if (!scenes) {
        return 1;
    }
    /* The environment's backend would turn the rows' backends into its own, and the
     * checks this process makes on the CPU into OpenCL worlds whose runtime (NVIDIA's)
     * does not survive the runs' forks: every run crashed on an H200. */
    if (getenv("KGYRO_BACKEND")) {
        fprintf(stderr, "kgyro bench: KGYRO_BACKEND=%s ignored: the rows' backends are --backend's, the device "
                        "--device's\n",
                getenv("KGYRO_BACKEND"));
        unsetenv("KGYRO_BACKEND");
    }
    int code = bench_parse_options(argc, argv, &s.options, scenes);
    if (code == 0 && !bench_make_engines(&s)) {
        code = 2;
    }
    if (code == 0) {
        bench_print_intro(&s);
        for (int i = 0; i < s.options.scene_count; ++i) {
            bench_scene(&s, s.options.scenes[i]);
        }
        bench_write_outputs(&s);
        code = s.exit_code;
    }
    free(s.rows);
    free(s.stops);
    free(scenes);
    return code < 0 ? 0 : code;
}
