/* kgyro render: runs a scene offscreen and writes it as an animated GIF and a PNG of
 * the last frame, timing each step on the way. */
#include "commands.h"
#include "progress.h"
#include "render/args.h"
#include "render/draw.h"
#include "render/gif.h"
#include "render/image.h"
#include "render/palette.h"
#include "render/sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct kg_render_options {
    const char* scene;
    const char* gif;
    const char* png;
    int steps; /* -1: the scene's suggestion */
    int width, height;
    int every; /* 0: about 150 frames in all */
    int contacts, aabbs, grid;
    int seed;
    int max_bodies; /* -1: no limit */
    kg_backend backend;
    int has_view;
    kg_aabb view;
} kg_render_options;

typedef struct kg_step_stats {
    int steps;
    double total_ms, max_ms;
    kg_stage_times stages; /* summed over the steps */
} kg_step_stats;

static void kg_render_usage(FILE* out)
{
    fprintf(out,
            "usage: kgyro render SCENE [--gif FILE] [--png FILE] [OPTIONS]\n"
            "Runs SCENE (a scene file, a Tiled map (.tmj) or a generator name such as pyramid_10 or\n"
            "rain_2000) offscreen and writes an animated GIF and/or a PNG of the last frame, tile maps\n"
            "drawn under the bodies. On a terminal, a progress line on stderr while it steps.\n\n"
            "  --gif FILE        animated GIF, one frame every K steps\n"
            "  --png FILE        the last frame as PNG\n"
            "  --steps N         steps to run (default: the scene's, else 300)\n"
            "  --every K         steps per GIF frame (default: about 150 frames in all)\n"
            "  --size WxH        image size in pixels (default 640x480)\n"
            "  --view X0,Y0,X1,Y1  world box to show in metres (default: the whole level, every body\n"
            "                      and tile map)\n"
            "  --contacts        draw contact points and normals\n"
            "  --aabb            draw bounding boxes\n"
            "  --no-grid         no metre grid in the background\n"
            "  --seed S          seed for generated scenes (default 1)\n"
            "  --backend B       auto, cpu or opencl (default auto)\n"
            "  --max-bodies N    refuse a scene or generator asking for more than N bodies (untrusted levels)\n");
}

/* Options that take a value; returns 0 when parsed, -1 when the value is bad or
 * missing, 1 when argv[*i] is not one of them. */
static int kg_parse_valued(int argc, char** argv, int* i, kg_render_options* o)
{
    static const char* const kValued[] = {"--gif",  "--png",  "--steps", "--every", "--size",
                                          "--view", "--seed", "--backend", "--max-bodies", NULL};
    const char* name = argv[*i];
    const char* value = NULL;
    int taken = kg_option_value("kgyro render", argc, argv, i, kValued, &value);
    if (taken <= 0) {
        return taken < 0 ? -1 : 1;
    }
    int bad = 0;
    if (strcmp(name, "--gif") == 0) {
        o->gif = value;
    } else if (strcmp(name, "--png") == 0) {
        o->png = value;
    } else if (strcmp(name, "--steps") == 0) {
        bad = kg_parse_int(value, 0, 10000000, &o->steps);
    } else if (strcmp(name, "--every") == 0) {
        bad = kg_parse_int(value, 1, 1000000, &o->every);
    } else if (strcmp(name, "--size") == 0) {
        bad = kg_parse_size(value, &o->width, &o->height);
    } else if (strcmp(name, "--view") == 0) {
        bad = kg_parse_box(value, &o->view);
        o->has_view = 1;
    } else if (strcmp(name, "--seed") == 0) {
        bad = kg_parse_int(value, 0, 2147483647, &o->seed);
    } else if (strcmp(name, "--max-bodies") == 0) {
        bad = kg_parse_int(value, 0, 2147483647, &o->max_bodies);
    } else {
        bad = kg_parse_backend(value, &o->backend);
    }
    if (bad) {
        fprintf(stderr, "kgyro render: bad value for %s: '%s'\n", name, value);
    }
    return bad ? -1 : 0;
}

/* 0: run; 1: help was asked for; 2: bad usage (already reported). */
static int kg_parse_render_options(int argc, char** argv, kg_render_options* o)
{
    *o = (kg_render_options){.steps = -1, .width = 640, .height = 480, .grid = 1, .seed = 1, .max_bodies = -1, .backend = KG_BACKEND_AUTO};
    for (int i = 1; i < argc; ++i) {
        int valued = kg_parse_valued(argc, argv, &i, o);
        if (valued < 0) {
            return 2;
        } else if (valued == 0) {
            continue;
        }
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            kg_render_usage(stdout);
            return 1;
        } else if (strcmp(argv[i], "--contacts") == 0) {
            o->contacts = 1;
        } else if (strcmp(argv[i], "--aabb") == 0) {
            o->aabbs = 1;
        } else if (strcmp(argv[i], "--no-grid") == 0) {
            o->grid = 0;
        } else if (argv[i][0] != '-' && !o->scene) {
            o->scene = argv[i];
        } else {
            fprintf(stderr, "kgyro render: unexpected argument '%s'\n", argv[i]);
            return 2;
        }
    }
    if (!o->scene || (!o->gif && !o->png)) {
        fprintf(stderr, "kgyro render: need a SCENE and --gif or --png (see --help)\n");
        return 2;
    }
    return 0;
}

static double kg_now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static kg_result kg_timed_step(kg_sim* sim, kg_step_stats* stats)
{
    double start = kg_now_ms();
    kg_result r = kg_sim_step(sim);
    double ms = kg_now_ms() - start;
    stats->steps++;
    stats->total_ms += ms;
    stats->max_ms = ms > stats->max_ms ? ms : stats->max_ms;
    kg_stage_times stages;
    if (r == KG_OK && kg_world_get_stage_times(sim->world, &stages) == KG_OK) {
        stats->stages.count = stages.count;
        for (int i = 0; i < stages.count && i < 16; ++i) {
            stats->stages.names[i] = stages.names[i];
            stats->stages.ms[i] += stages.ms[i];
        }
    }
    return r;
}

static void kg_print_stats(const kg_step_stats* stats)
{
    if (stats->steps == 0) {
        return;
    }
    printf("  step time: mean %.3f ms, max %.3f ms", stats->total_ms / stats->steps, stats->max_ms);
    for (int i = 0; i < stats->stages.count && i < 16; ++i) {
        printf("%s%s %.3f", i == 0 ? " (" : ", ", stats->stages.names[i], stats->stages.ms[i] / stats->steps);
    }
    printf("%s\n", stats->stages.count > 0 ? ")" : "");
}

typedef struct kg_render_job {
    const kg_render_options* options;
    kg_sim sim;
    kg_camera camera;
    kg_canvas canvas;
    kg_draw_options draw;
    kg_gif* gif;
    int frames;
    kg_step_stats stats;
} kg_render_job;

static void kg_draw_frame(kg_render_job* job)
{
    kg_draw_world(&job->canvas, &job->camera, job->sim.world, &job->draw);
}

static int kg_add_gif_frame(kg_render_job* job, int delay_cs)
{
    kg_draw_frame(job);
    job->frames++;
    return kg_gif_add_frame(job->gif, job->canvas.pixels, delay_cs);
}

static int kg_default_every(int steps) { return steps > 150 ? (steps + 149) / 150 : 1; }

/* Steps the scene, adding a GIF frame every so many steps. 0 on success. */
static int kg_run_frames(kg_render_job* job, int steps, kg_progress* progress)
{
    int every = job->options->every > 0 ? job->options->every : kg_default_every(steps);
    int delay_cs = (int)lround(100.0 * every * job->sim.dt);
    delay_cs = delay_cs < 2 ? 2 : delay_cs; /* viewers slow down anything shorter */
    if (job->gif && kg_add_gif_frame(job, delay_cs) != 0) {
        return -1;
    }
    for (int step = 1; step <= steps; ++step) {
        kg_progress_update(progress, step - 1);
        kg_result r = kg_timed_step(&job->sim, &job->stats);
        if (r != KG_OK) {
            kg_progress_end(progress);
            fprintf(stderr, "kgyro render: step %d: %s\n", step, kg_last_error());
            return -1;
        }
        if (job->gif && step % every == 0 && kg_add_gif_frame(job, delay_cs) != 0) {
            return -1;
        }
    }
    return 0;
}

static int kg_setup_job(kg_render_job* job, kg_scene* scene)
{
    const kg_render_options* o = job->options;
    kg_result r = kg_sim_start(&job->sim, scene, o->backend, 0);
    if (r != KG_OK) {
        fprintf(stderr, "kgyro render: %s: %s\n", o->scene, kg_last_error());
        return 2;
    }
    kg_aabb view = o->view;
    if (!o->has_view && !kg_world_view_box(job->sim.world, &view)) {
        view = (kg_aabb){{-10.0f, -10.0f}, {10.0f, 10.0f}};
    }
    job->camera = kg_camera_fit(view, o->width, o->height, o->has_view ? 0.0f : 0.05f);
    if (kg_canvas_init(&job->canvas, o->width, o->height) != 0) {
        fprintf(stderr, "kgyro render: out of memory\n");
        return 1;
    }
    job->draw = (kg_draw_options){o->contacts, o->aabbs, 1, o->grid};
    if (o->gif && !(job->gif = kg_gif_open(o->gif, o->width, o->height, kg_palette_rgb()))) {
        fprintf(stderr, "kgyro render: cannot write %s\n", o->gif);
        return 1;
    }
    return 0;
}

static int kg_finish_job(kg_render_job* job)
{
    const kg_render_options* o = job->options;
    int failed = 0;
    if (job->gif) {
        failed |= kg_gif_close(job->gif) != 0;
        job->gif = NULL;
        if (failed) {
            fprintf(stderr, "kgyro render: cannot write %s\n", o->gif);
        } else {
            printf("  wrote %s: %d frames, %dx%d\n", o->gif, job->frames, o->width, o->height);
        }
    }
    if (o->png) {
        kg_draw_frame(job);
        if (kg_write_png(o->png, &job->canvas) != 0) {
            fprintf(stderr, "kgyro render: cannot write %s\n", o->png);
            failed = 1;
        } else {
            printf("  wrote %s: %dx%d\n", o->png, o->width, o->height);
        }
    }
    return failed;
}

static void kg_free_job(kg_render_job* job)
{
    if (job->gif) {
        kg_gif_close(job->gif);
    }
    kg_canvas_free(&job->canvas);
    kg_sim_stop(&job->sim);
}

int kg_cmd_render(int argc, char** argv)
{
    kg_render_options o;
    int parsed = kg_parse_render_options(argc, argv, &o);
    if (parsed != 0) {
        return parsed == 1 ? 0 : 2;
    }
    kg_scene* scene = NULL;
    if (kg_open_scene(o.scene, (uint32_t)o.seed, o.max_bodies, &scene) != KG_OK) {
        fprintf(stderr, "kgyro render: %s\n", kg_last_error());
        return 2;
    }
    int steps = o.steps >= 0 ? o.steps : (kg_scene_steps(scene) > 0 ? kg_scene_steps(scene) : 300);
    kg_render_job job;
    memset(&job, 0, sizeof job);
    job.options = &o;
    int status = kg_setup_job(&job, scene);
    if (status == 0) {
        printf("kgyro render: %s, %d bodies, %d steps on %s\n", o.scene, kg_world_body_count(job.sim.world), steps,
               kg_backend_label(kg_world_backend(job.sim.world)));
        char label[256];
        snprintf(label, sizeof label, "kgyro render: %s", o.scene);
        kg_progress progress;
        kg_progress_start(&progress, label, steps);
        status = kg_run_frames(&job, steps, &progress) != 0 ? 1 : 0;
        kg_progress_end(&progress);
        kg_print_stats(&job.stats);
        status = status != 0 ? status : kg_finish_job(&job);
    }
    kg_free_job(&job);
    return status;
}
