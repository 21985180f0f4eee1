/* kgyro bench: what cmd_bench.c shares with its helpers, bench_run.c (one engine on one
 * scene, measured in forked children) and bench_report.c (table, CSV, gnuplot charts). */
#ifndef KG_TOOLS_BENCH_H
#define KG_TOOLS_BENCH_H

#include "kgyro/scene.h"

#include <stddef.h>

enum {
    BENCH_LABEL_MAX = 32,
    BENCH_SCENE_NAME_MAX = 64,
    BENCH_MESSAGE_MAX = 256,
    BENCH_MAX_STAGES = 24
};

typedef enum bench_engine_kind { BENCH_KGYRO, BENCH_BOX2D, BENCH_CHIPMUNK } bench_engine_kind;

typedef struct bench_engine {
    bench_engine_kind kind;
    kg_backend backend;              /* kgyro only */
    char label[BENCH_LABEL_MAX];     /* "kgyro/cpu", "box2d", "chipmunk" */
    int available;
    char about[2 * BENCH_MESSAGE_MAX]; /* its settings, or why it is missing */
} bench_engine;

typedef struct bench_config {
    int threads;
    int substeps;     /* kgyro's solver sub-steps; 0: the scene's own */
    int steps;        /* 0: each scene's own */
    int runs;
    unsigned seed;
    double budget_s;  /* a run stepping longer skips the larger sizes of its series; 0 = none */
    double timeout_s; /* a run taking longer is killed; 0 = none */
    int no_continuous; /* kgyro with continuous collision off */
    int device;        /* OpenCL device of kgyro's opencl backend (kgyro info lists them) */
} bench_config;

typedef struct bench_scene_info {
    char name[BENCH_SCENE_NAME_MAX];
    char family[BENCH_SCENE_NAME_MAX]; /* "rain" for rain_1000; the name itself otherwise */
    int size;                          /* 1000 for rain_1000; 0 for a scene of fixed size */
    int body_count;
    int dynamic_count;
    int steps;
    float dt;
    int is_pyramid;                    /* judged by its top box staying put */
} bench_scene_info;

typedef enum bench_status {
    BENCH_OK,
    BENCH_MISSING,   /* engine not built */
    BENCH_SKIPPED,   /* over the time budget at a smaller size of the series */
    BENCH_FAILED,    /* the engine refused the scene or a step failed */
    BENCH_CRASHED,   /* the child died of a signal */
    BENCH_TIMED_OUT
} bench_status;

typedef struct bench_stage {
    char name[BENCH_LABEL_MAX];
    double ms; /* mean per step */
} bench_stage;

/* So that nobody wins by being wrong. */
typedef struct bench_check {
    double top_settle; /* m: how far the highest dynamic body moved in the first quarter of
                          the run, as the contacts settled; pyramids only, else NAN */
    double top_drift;  /* m: how far it moved in the rest of the run */
    int below_ground; /* dynamic bodies that started above the lowest ground and whose centre
                         ended below it; -1: no ground */
    int non_finite;   /* bodies whose final state is not finite */
    double joint_gap; /* m: the widest a hinge (revolute or weld joint) ended open, its two
                         anchors apart; NAN without hinges */
} bench_check;

/* Nothing checked yet. */
#define BENCH_NO_CHECK ((bench_check){NAN, NAN, -1, 0, NAN})

typedef struct bench_result {
    bench_status status;
    char message[BENCH_MESSAGE_MAX];
    double median_ms, p95_ms, mean_ms; /* per step, over every step of every run */
    double peak_mb;                    /* largest peak resident memory growth of a run */
    double slowest_run_s;              /* stepping time of the slowest run */
    bench_check check;
    int stage_count;
    bench_stage stages[BENCH_MAX_STAGES];
} bench_result;

/* One line of the report: a scene in an engine. ratio is median / kgyro's median. */
typedef struct bench_row {
    bench_scene_info scene;
    bench_engine engine;
    bench_result result;
    double ratio;
} bench_row;

/* bench_run.c */
/* The scene in each of engines[0, count) into out[i], the engines' runs taken in turns. */
void bench_run(const bench_engine* const* engines, int count, kg_scene* scene, const bench_scene_info* info,
               const bench_config* config, bench_result* out);
/* Whether kgyro can make a world on backend; if not, why says why. */
int bench_kgyro_backend_works(kg_backend backend, const bench_config* config, char* why, size_t size);
/* Whether kgyro's contact solver is in: a box dropped on a static ground box must come
 * to rest on it. Writes what happened to message. */
int bench_kgyro_solver_check(char* message, size_t size);
const char* bench_status_name(bench_status status);

/* bench_report.c */
void bench_print_scene_header(const bench_scene_info* info, const bench_config* config);
void bench_print_row(const bench_row* row);
void bench_print_stages(const bench_row* row);
/* solver_in_place: 1, 0, or -1 when not checked. */
int bench_write_csv(const char* path, const bench_row* rows, int count, const bench_config* config,
                    int solver_in_place);
int bench_write_stages_csv(const char* path, const bench_row* rows, int count, const bench_config* config);
/* Writes the gnuplot scripts (data inline) into dir and draws them as PNG when gnuplot
 * is installed; returns 0 when the scripts were written, whether or not drawn. */
int bench_plot(const char* dir, const bench_row* rows, int count);

#endif
