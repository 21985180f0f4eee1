/* kgyro bench: one engine on one scene. Every run is a forked child: engines share no
 * allocator history, a crash or a hang costs one run instead of the whole bench, and the
 * peak memory a child reports is its own. */
#include "bench.h"
#include "progress.h"

#include "kgyro/kgyro.h"
#ifdef KG_HAVE_PEERS
#include "kg_peers.h"
#endif

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* ---- the engines behind one face ---- */

typedef struct bench_sim {
    const bench_engine* engine;
    kg_scene* scene;
    int body_count;
    kg_world* world;
    kg_body* handles;
#ifdef KG_HAVE_PEERS
    kg_peer_world* peer;
#endif
} bench_sim;

static int bench_kgyro_create(bench_sim* sim, const bench_config* config, char* why, size_t size)
{
    kg_world_def def = *kg_scene_world_def(sim->scene);
    def.backend = sim->engine->backend;
    def.device_index = config->device;
    def.threads = config->threads;
    def.substeps = config->substeps > 0 ? config->substeps : def.substeps;
    def.enable_sleep = 0; /* the peers run with sleeping off: every engine simulates every body */
    def.enable_continuous = !config->no_continuous;
    sim->handles = malloc((size_t)(sim->body_count + 1) * sizeof *sim->handles);
    if (!sim->handles) {
        snprintf(why, size, "out of memory");
        return 0;
    }
    kg_result r = kg_scene_instantiate(sim->scene, &def, &sim->world, sim->handles);
    if (r != KG_OK) {
        snprintf(why, size, "%s: %s", kg_result_string(r), kg_last_error());
        return 0;
    }
    if (kg_world_backend(sim->world) != def.backend) {
        snprintf(why, size, "the world fell back to another backend");
        return 0;
    }
    return 1;
}

static int bench_sim_create(bench_sim* sim, const bench_config* config, char* why, size_t size)
{
    if (sim->engine->kind == BENCH_KGYRO) {
        return bench_kgyro_create(sim, config, why, size);
    }
#ifdef KG_HAVE_PEERS
    kg_peer_engine peer = sim->engine->kind == BENCH_BOX2D ? KG_PEER_BOX2D : KG_PEER_CHIPMUNK;
    if (kg_peer_create(peer, sim->scene, config->threads, &sim->peer) == KG_OK) {
        return 1;
    }
    snprintf(why, size, "%s", kg_peer_last_error());
#else
    (void)config;
    snprintf(why, size, "the peer engines are not built into this kgyro");
#endif
    return 0;
}

static int bench_sim_step(bench_sim* sim, float dt, char* why, size_t size)
{
    if (sim->engine->kind == BENCH_KGYRO) {
        kg_result r = kg_scene_step(sim->scene, sim->world, sim->handles, dt);
        if (r != KG_OK) {
            snprintf(why, size, "step failed: %s: %s", kg_result_string(r), kg_last_error());
            return 0;
        }
        return 1;
    }
#ifdef KG_HAVE_PEERS
    kg_peer_step(sim->peer, dt);
#endif
    return 1;
}

static void bench_sim_states(const bench_sim* sim, kg_body_state* out)
{
    if (sim->engine->kind == BENCH_KGYRO) {
        kg_world_get_body_states(sim->world, sim->handles, sim->body_count, out);
        /* A frozen body keeps its last finite pose, but its state did go non-finite:
         * count it as such, or the correctness line would miss a blow-up. */
        for (int i = 0; i < sim->body_count; ++i) {
            if (kg_body_is_frozen(sim->world, sim->handles[i])) {
                out[i].angular_velocity = NAN;
            }
        }
        return;
    }
#ifdef KG_HAVE_PEERS
    kg_peer_get_states(sim->peer, out);
#endif
}

static void bench_sim_destroy(bench_sim* sim)
{
    if (sim->world) {
        kg_destroy_world(sim->world);
    }
    free(sim->handles);
#ifdef KG_HAVE_PEERS
    kg_peer_destroy(sim->peer);
#endif
}

/* ---- correctness ---- */

static int bench_is_dynamic(kg_body_type type) { return type == KG_BODY_DYNAMIC || type == KG_BODY_PARTICLE; }

/* The highest dynamic body at the start: a pyramid's top box. -1 when none. */
static int bench_top_body(const kg_scene* scene)
{
    int top = -1;
    for (int i = 0; i < kg_scene_body_count(scene); ++i) {
        const kg_body_def* def = kg_scene_body_def(scene, i);
        if (bench_is_dynamic(def->type) &&
            (top < 0 || def->position.y > kg_scene_body_def(scene, top)->position.y)) {
            top = i;
        }
    }
    return top;
}

/* The shape's points in the world at its start pose, with the radius around each. */
static int bench_shape_points(const kg_body_def* def, kg_vec2* out, float* radius)
{
    float c = cosf(def->angle), s = sinf(def->angle);
    const kg_shape_def* shape = &def->shape;
    int has_vertices = shape->type == KG_SHAPE_POLYGON || shape->type == KG_SHAPE_CAPSULE || shape->type == KG_SHAPE_SEGMENT;
    int count = has_vertices ? shape->count : 1;
    kg_vec2 local = shape->type == KG_SHAPE_CIRCLE ? shape->center : (kg_vec2){0.0f, 0.0f};
    *radius = shape->type == KG_SHAPE_CIRCLE || shape->type == KG_SHAPE_CAPSULE ? shape->radius : 0.0f;
    for (int i = 0; i < count; ++i) {
        kg_vec2 p = has_vertices ? shape->vertices[i] : local;
        out[i] = (kg_vec2){def->position.x + c * p.x - s * p.y, def->position.y + s * p.x + c * p.y};
    }
    return count;
}

/* Whether body i is an end of a joint: then a body, not a ground, whatever its type. */
static int bench_jointed(const kg_scene* scene, int i)
{
    for (int k = 0; k < kg_scene_joint_count(scene); ++k) {
        const kg_scene_joint* j = kg_scene_get_joint(scene, k);
        if (j->body_a == i || j->body_b == i) {
            return 1;
        }
    }
    return 0;
}

/* The lowest point a ground reaches: static bodies where they are, walls turning about a
 * pivot anywhere on their circle; a static body that holds joints is not a ground (the
 * bodies hanging from it end below it). NAN when the scene has no ground (smash). */
static double bench_ground_floor(const kg_scene* scene)
{
    double floor = NAN;
    for (int i = 0; i < kg_scene_body_count(scene); ++i) {
        const kg_body_def* def = kg_scene_body_def(scene, i);
        kg_vec2 pivot, points[KG_MAX_POLYGON_VERTICES];
        int pivoted = def->type == KG_BODY_KINEMATIC && kg_scene_body_pivot(scene, i, &pivot);
        if ((def->type != KG_BODY_STATIC && !pivoted) || bench_jointed(scene, i)) {
            continue;
        }
        float radius;
        int count = bench_shape_points(def, points, &radius);
        for (int k = 0; k < count; ++k) {
            double low = pivoted ? pivot.y - hypot(points[k].x - pivot.x, points[k].y - pivot.y) - radius
                                 : points[k].y - radius;
            floor = isnan(floor) || low < floor ? low : floor;
        }
    }
    return floor;
}

static int bench_state_finite(const kg_body_state* s)
{
    return isfinite(s->position.x) && isfinite(s->position.y) && isfinite(s->angle) && isfinite(s->velocity.x) &&
           isfinite(s->velocity.y) && isfinite(s->angular_velocity);
}

/* Where a point fixed to body i at its start lies in its state now. */
static kg_vec2 bench_carried_point(const kg_body_def* start, const kg_body_state* now, kg_vec2 point)
{
    float c0 = cosf(start->angle), s0 = sinf(start->angle), c = cosf(now->angle), s = sinf(now->angle);
    kg_vec2 d = {point.x - start->position.x, point.y - start->position.y};
    kg_vec2 local = {c0 * d.x + s0 * d.y, -s0 * d.x + c0 * d.y};
    return (kg_vec2){now->position.x + c * local.x - s * local.y, now->position.y + s * local.x + c * local.y};
}

/* The widest a hinge's anchors ended apart: each carried by its body from the start (the
 * world's stays put), as any engine's states give them. NAN without hinges. */
static double bench_joint_gap(const kg_scene* scene, const kg_body_state* states)
{
    double gap = NAN;
    for (int k = 0; k < kg_scene_joint_count(scene); ++k) {
        const kg_scene_joint* j = kg_scene_get_joint(scene, k);
        if (j->type != KG_JOINT_REVOLUTE && j->type != KG_JOINT_WELD) {
            continue;
        }
        kg_vec2 a = j->body_a < 0 ? j->anchor_a
                                  : bench_carried_point(kg_scene_body_def(scene, j->body_a), &states[j->body_a],
                                                        j->anchor_a);
        kg_vec2 b = bench_carried_point(kg_scene_body_def(scene, j->body_b), &states[j->body_b], j->anchor_a);
        double open = hypot(b.x - a.x, b.y - a.y);
        gap = isnan(gap) || open > gap ? open : gap;
    }
    return gap;
}

/* settled: where the top body was once the pyramid had settled (NAN when not a pyramid). */
static bench_check bench_check_states(const kg_scene* scene, const bench_scene_info* info,
                                      const kg_body_state* states, kg_vec2 settled)
{
    bench_check check = BENCH_NO_CHECK;
    double floor = bench_ground_floor(scene);
    check.below_ground = isnan(floor) ? -1 : 0;
    for (int i = 0; i < info->body_count; ++i) {
        const kg_body_def* def = kg_scene_body_def(scene, i);
        check.non_finite += !bench_state_finite(&states[i]);
        if (check.below_ground >= 0 && bench_is_dynamic(def->type) && def->position.y >= floor &&
            states[i].position.y < floor) {
            check.below_ground += 1;
        }
    }
    check.joint_gap = bench_joint_gap(scene, states);
    int top = info->is_pyramid ? bench_top_body(scene) : -1;
    if (top >= 0) {
        kg_vec2 start = kg_scene_body_def(scene, top)->position;
        check.top_settle = hypot(settled.x - start.x, settled.y - start.y);
        check.top_drift = hypot(states[top].position.x - settled.x, states[top].position.y - settled.y);
    }
    return check;
}

/* ---- the child: build, step, measure ---- */

typedef struct bench_child_report {
    bench_status status;
    char message[BENCH_MESSAGE_MAX];
    int steps_done;
    double peak_mb;
    bench_check check;
    int stage_count;
    bench_stage stages[BENCH_MAX_STAGES]; /* ms summed over the run */
} bench_child_report;

static double bench_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static long bench_status_kb(const char* field)
{
    FILE* f = fopen("/proc/self/status", "r");
    char line[256];
    long kb = -1;
    size_t n = strlen(field);
    while (f && fgets(line, sizeof line, f)) {
        if (strncmp(line, field, n) == 0 && line[n] == ':') {
            kb = atol(line + n + 1);
        }
    }
    if (f) {
        fclose(f);
    }
    return kb;
}

/* Resets the peak resident size to the current one (Linux: "5" into clear_refs) and
 * returns the current one, the baseline the run's growth is measured from. */
static long bench_reset_peak_kb(void)
{
    FILE* f = fopen("/proc/self/clear_refs", "w");
    if (f) {
        fputs("5", f);
        fclose(f);
    }
    return bench_status_kb("VmRSS");
}

/* Reads every body of the scene once, so that faulting in the parent's scene pages
 * (shared after fork) is not counted as the engine's memory. */
static void bench_touch_scene(const kg_scene* scene)
{
    volatile float sum = 0.0f;
    for (int i = 0; i < kg_scene_body_count(scene); ++i) {
        sum += kg_scene_body_def(scene, i)->position.x;
    }
    (void)sum;
}

static void bench_add_stage_times(const kg_world* world, bench_child_report* report)
{
    kg_stage_times times;
    if (kg_world_get_stage_times(world, &times) != KG_OK) {
        return;
    }
    for (int i = 0; i < times.count; ++i) {
        int k = 0;
        while (k < report->stage_count && strcmp(report->stages[k].name, times.names[i]) != 0) {
            k++;
        }
        if (k == report->stage_count && k < BENCH_MAX_STAGES) {
            snprintf(report->stages[k].name, sizeof report->stages[k].name, "%s", times.names[i]);
            report->stage_count++;
        }
        if (k < report->stage_count) {
            report->stages[k].ms += times.ms[i];
        }
    }
}

/* Steps [first, last); 0 when a step failed. */
static int bench_step_range(bench_sim* sim, const bench_scene_info* info, int first, int last, double* step_ms,
                            bench_child_report* report, kg_progress* progress)
{
    for (int s = first; s < last; ++s) {
        kg_progress_update(progress, s);
        double t0 = bench_now_ms();
        int ok = bench_sim_step(sim, info->dt, report->message, sizeof report->message);
        step_ms[s] = bench_now_ms() - t0;
        if (!ok) {
            report->status = BENCH_FAILED;
            return 0;
        }
        if (sim->engine->kind == BENCH_KGYRO) {
            bench_add_stage_times(sim->world, report);
        }
        report->steps_done = s + 1;
    }
    return 1;
}

/* The first quarter of the run lets a pyramid settle: every contact sinks to the
 * engine's allowed overlap (about 5 mm each, half a metre over 100 rows). Drift is what
 * the top box does after that. */
static void bench_simulate(bench_sim* sim, const bench_scene_info* info, const bench_config* config,
                           double* step_ms, kg_body_state* states, bench_child_report* report,
                           kg_progress* progress)
{
    if (!bench_sim_create(sim, config, report->message, sizeof report->message)) {
        report->status = BENCH_FAILED;
        return;
    }
    int settle_steps = info->steps / 4;
    int top = info->is_pyramid ? bench_top_body(sim->scene) : -1;
    kg_vec2 settled = top >= 0 ? kg_scene_body_def(sim->scene, top)->position : (kg_vec2){NAN, NAN};
    if (!bench_step_range(sim, info, 0, settle_steps, step_ms, report, progress)) {
        return;
    }
    if (top >= 0) {
        bench_sim_states(sim, states);
        settled = states[top].position;
    }
    if (bench_step_range(sim, info, settle_steps, info->steps, step_ms, report, progress)) {
        bench_sim_states(sim, states);
        report->check = bench_check_states(sim->scene, info, states, settled);
    }
}

static int bench_write_all(int fd, const void* data, size_t size)
{
    const char* p = data;
    while (size > 0) {
        ssize_t n = write(fd, p, size);
        if (n <= 0) {
            return 0;
        }
        p += n;
        size -= (size_t)n;
    }
    return 1;
}

static void bench_silence(FILE* stream)
{
    if (!freopen("/dev/null", "w", stream)) {
        fclose(stream);
    }
}

/* Memory written once, so that its pages are resident before the baseline is taken. */
static void* bench_alloc_touched(size_t size)
{
    void* p = malloc(size);
    if (p) {
        memset(p, 0, size);
    }
    return p;
}

static void bench_child(const bench_engine* engine, kg_scene* scene, const bench_scene_info* info,
                        const bench_config* config, int fd)
{
    if (config->timeout_s > 0.0) {
        alarm((unsigned)ceil(config->timeout_s));
    }
    /* The child reports through the pipe only. Debian's Chipmunk is a debug build: it
     * prints a banner on stdout in every run, and warnings ("High EPA iterations") on
     * stderr by the hundred in smash. kgyro keeps its stderr: its warnings matter here. */
    bench_silence(stdout);
    if (engine->kind != BENCH_KGYRO) {
        bench_silence(stderr);
    }
    bench_child_report report;
    memset(&report, 0, sizeof report);
    report.check = BENCH_NO_CHECK;
    /* the bench's own buffers are in place (and touched) before the baseline */
    double* step_ms = bench_alloc_touched(((size_t)info->steps + 1) * sizeof *step_ms);
    kg_body_state* states = bench_alloc_touched(((size_t)info->body_count + 1) * sizeof *states);
    bench_touch_scene(scene);
    long baseline_kb = bench_reset_peak_kb();
    bench_sim sim = {.engine = engine, .scene = scene, .body_count = info->body_count};
    if (step_ms && states) {
        /* A peer's stderr is silenced above, so only kgyro's runs show the line. */
        char label[BENCH_LABEL_MAX + BENCH_SCENE_NAME_MAX + 16];
        snprintf(label, sizeof label, "kgyro bench: %s %s", engine->label, info->name);
        kg_progress progress;
        kg_progress_start(&progress, label, info->steps);
        bench_simulate(&sim, info, config, step_ms, states, &report, &progress);
        kg_progress_end(&progress);
    } else {
        report.status = BENCH_FAILED;
        snprintf(report.message, sizeof report.message, "out of memory");
    }
    report.peak_mb = (double)(bench_status_kb("VmHWM") - baseline_kb) / 1024.0;
    bench_sim_destroy(&sim);
    int ok = bench_write_all(fd, &report, sizeof report) &&
             bench_write_all(fd, step_ms, (size_t)report.steps_done * sizeof *step_ms);
    free(step_ms);
    free(states);
    _exit(ok ? 0 : 1);
}

/* ---- the parent: one child per run ---- */

static size_t bench_read_all(int fd, void* data, size_t size)
{
    char* p = data;
    size_t got = 0;
    while (got < size) {
        ssize_t n = read(fd, p + got, size - got);
        if (n <= 0) {
            break;
        }
        got += (size_t)n;
    }
    return got;
}

static void bench_judge_exit(int wait_status, int complete, const bench_config* config, bench_child_report* report)
{
    if (WIFSIGNALED(wait_status) && WTERMSIG(wait_status) == SIGALRM) {
        report->status = BENCH_TIMED_OUT;
        snprintf(report->message, sizeof report->message, "killed after the %.0f s time limit", config->timeout_s);
    } else if (WIFSIGNALED(wait_status)) {
        report->status = BENCH_CRASHED;
        snprintf(report->message, sizeof report->message, "crashed: %s", strsignal(WTERMSIG(wait_status)));
    } else if (!complete) {
        report->status = BENCH_CRASHED;
        snprintf(report->message, sizeof report->message, "exited (status %d) without a report",
                 WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : -1);
    }
}

static void bench_run_once(const bench_engine* engine, kg_scene* scene, const bench_scene_info* info,
                           const bench_config* config, bench_child_report* report, double* step_ms)
{
    memset(report, 0, sizeof *report);
    int fds[2];
    if (pipe(fds) != 0) {
        report->status = BENCH_FAILED;
        snprintf(report->message, sizeof report->message, "pipe: %s", strerror(errno));
        return;
    }
    fflush(NULL); /* or the child would print the parent's buffered output again */
    pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        bench_child(engine, scene, info, config, fds[1]);
    }
    close(fds[1]);
    int complete = 0;
    if (pid > 0 && bench_read_all(fds[0], report, sizeof *report) == sizeof *report) {
        size_t bytes = (size_t)report->steps_done * sizeof *step_ms;
        complete = report->steps_done <= info->steps && bench_read_all(fds[0], step_ms, bytes) == bytes;
    }
    close(fds[0]);
    int wait_status = 0;
    if (pid < 0 || waitpid(pid, &wait_status, 0) < 0) {
        report->status = BENCH_FAILED;
        snprintf(report->message, sizeof report->message, "cannot run a child: %s", strerror(errno));
        return;
    }
    bench_judge_exit(wait_status, complete, config, report);
}

static int bench_compare_double(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

/* Nearest-rank percentile of sorted values. */
static double bench_percentile(const double* sorted, size_t count, double fraction)
{
    size_t rank = (size_t)ceil(fraction * (double)count);
    return sorted[rank > 0 ? rank - 1 : 0];
}

static void bench_summarize_times(double* all_ms, size_t count, bench_result* out)
{
    double total = 0.0;
    for (size_t i = 0; i < count; ++i) {
        total += all_ms[i];
    }
    qsort(all_ms, count, sizeof *all_ms, bench_compare_double);
    out->median_ms = bench_percentile(all_ms, count, 0.5);
    out->p95_ms = bench_percentile(all_ms, count, 0.95);
    out->mean_ms = total / (double)count;
}

static void bench_add_run(const bench_child_report* report, const double* step_ms, int run, bench_result* out)
{
    double run_ms = 0.0;
    for (int s = 0; s < report->steps_done; ++s) {
        run_ms += step_ms[s];
    }
    out->slowest_run_s = fmax(out->slowest_run_s, run_ms / 1e3);
    out->peak_mb = fmax(out->peak_mb, report->peak_mb);
    if (run == 0) {
        out->check = report->check;
        out->stage_count = report->stage_count;
        memcpy(out->stages, report->stages, sizeof out->stages);
        return;
    }
    for (int k = 0; k < out->stage_count && k < report->stage_count; ++k) {
        out->stages[k].ms += report->stages[k].ms;
    }
}

static void bench_finish_stages(bench_result* out, int runs, int steps)
{
    for (int k = 0; k < out->stage_count; ++k) {
        out->stages[k].ms /= (double)runs * (double)steps;
    }
}

/* Runs one scene in engines [0, count), their runs taken in turns (run 1 of each, then
 * run 2 of each, ...), into out[i]: on a shared machine a burst of another tenant's load
 * then falls on every engine alike instead of on one engine's runs (one engine's runs in
 * a row, then the next engine's, moved a scene's ratio by up to a quarter here). An
 * engine stops at its first run that does not end well. */
void bench_run(const bench_engine* const* engines, int count, kg_scene* scene, const bench_scene_info* info,
               const bench_config* config, bench_result* out)
{
    size_t per_run = (size_t)info->steps, per_engine = (size_t)config->runs * per_run + 1;
    double* all_ms = malloc(((size_t)count * per_engine + 1) * sizeof *all_ms);
    int* runs = calloc((size_t)count + 1, sizeof *runs); /* each engine's runs made */
    for (int e = 0; e < count; ++e) {
        memset(&out[e], 0, sizeof out[e]);
        out[e].check = BENCH_NO_CHECK;
        if (!all_ms || !runs) {
            out[e].status = BENCH_FAILED;
            snprintf(out[e].message, sizeof out[e].message, "out of memory");
        }
    }
    bench_child_report report;
    for (int run = 0; run < config->runs; ++run) {
        for (int e = 0; e < count; ++e) {
            if (out[e].status != BENCH_OK) {
                continue;
            }
            double* step_ms = all_ms + (size_t)e * per_engine + (size_t)run * per_run;
            bench_run_once(engines[e], scene, info, config, &report, step_ms);
            bench_add_run(&report, step_ms, run, &out[e]);
            runs[e] = run + 1;
            if (report.status != BENCH_OK) {
                out[e].status = report.status;
                snprintf(out[e].message, sizeof out[e].message, "run %d: %.200s", run + 1, report.message);
            }
        }
    }
    for (int e = 0; e < count; ++e) {
        if (out[e].status == BENCH_OK) {
            bench_summarize_times(all_ms + (size_t)e * per_engine, (size_t)runs[e] * per_run, &out[e]);
            bench_finish_stages(&out[e], runs[e], info->steps);
        }
    }
    free(all_ms);
    free(runs);
}

const char* bench_status_name(bench_status status)
{
    static const char* const names[] = {"ok", "missing", "skipped", "failed", "crashed", "timed out"};
    return names[status];
}

/* ---- can kgyro run on this backend? ---- */

static void bench_try_backend(kg_backend backend, const bench_config* config, int fd)
{
    char message[BENCH_MESSAGE_MAX] = "";
    kg_world_def def = kg_default_world_def();
    def.backend = backend;
    def.device_index = config->device;
    def.threads = config->threads;
    kg_world* world = NULL;
    kg_result r = kg_create_world(&def, &world);
    if (r != KG_OK) {
        snprintf(message, sizeof message, "%s: %s", kg_result_string(r), kg_last_error());
    } else if (kg_world_backend(world) != backend) {
        snprintf(message, sizeof message, "the world fell back to another backend");
    }
    kg_destroy_world(world);
    bench_write_all(fd, message, strlen(message));
    _exit(message[0] ? 1 : 0);
}

/* Tried in a child: an OpenCL runtime started in this process would not survive the
 * forks of the runs. */
int bench_kgyro_backend_works(kg_backend backend, const bench_config* config, char* why, size_t size)
{
    int fds[2];
    if (pipe(fds) != 0) {
        snprintf(why, size, "pipe: %s", strerror(errno));
        return 0;
    }
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        bench_try_backend(backend, config, fds[1]);
    }
    close(fds[1]);
    size_t got = pid > 0 ? bench_read_all(fds[0], why, size - 1) : 0;
    why[got] = '\0';
    close(fds[0]);
    int status = 0;
    int ok = pid > 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
    if (!ok && got == 0) {
        snprintf(why, size, "the backend could not be started (the trial world %s)",
                 WIFSIGNALED(status) ? "crashed" : "failed");
    }
    return ok;
}

/* ---- is kgyro's contact solver in? ---- */

static kg_result bench_drop_box(kg_world* world, float* rest_y)
{
    kg_body_def ground = kg_default_body_def();
    ground.type = KG_BODY_STATIC;
    ground.position = (kg_vec2){0.0f, -1.0f};
    ground.shape = kg_box_shape(40.0f, 2.0f);
    kg_body_def box = kg_default_body_def();
    box.position = (kg_vec2){0.0f, 2.0f};
    box.shape = kg_box_shape(1.0f, 1.0f);
    kg_body ground_body, box_body;
    kg_result r = kg_create_body(world, &ground, &ground_body);
    if (r == KG_OK) {
        r = kg_create_body(world, &box, &box_body);
    }
    for (int i = 0; r == KG_OK && i < 120; ++i) {
        r = kg_world_step(world, 1.0f / 60.0f);
    }
    kg_vec2 p = {NAN, NAN};
    if (r == KG_OK) {
        r = kg_body_get_position(world, box_body, &p);
    }
    *rest_y = p.y;
    return r;
}

int bench_kgyro_solver_check(char* message, size_t size)
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    kg_world* world = NULL;
    float y = NAN;
    kg_result r = kg_create_world(&def, &world);
    if (r == KG_OK) {
        r = bench_drop_box(world, &y);
    }
    kg_destroy_world(world);
    if (r != KG_OK) {
        snprintf(message, size, "could not be checked: %s", kg_last_error());
        return 0;
    }
    int rests = fabsf(y - 0.5f) < 0.05f;
    if (rests) {
        snprintf(message, size, "in place: a box dropped on a static ground box rests on it (y = %.3f m)", (double)y);
    } else {
        snprintf(message, size,
                 "NOT in place: a box dropped on a static ground box ended at y = %.3f m instead of resting at "
                 "0.5 m, so kgyro's times below leave out contact solving",
                 (double)y);
    }
    return rests;
}
