/* kgyro bench: the report. The table on stdout, the CSV files, and gnuplot scripts with
 * their data inline (so each chart can be redrawn or tweaked from one file). */
#include "bench.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define BENCH_MAX_DRIFT 0.05 /* m: the pyramid stands when its top box moved less */
#define BENCH_MAX_JOINT_GAP 0.5 /* m: a hinge opened wider has come apart */

static int bench_check_passes(const bench_check* c)
{
    return !(c->top_drift > BENCH_MAX_DRIFT) && c->below_ground <= 0 && c->non_finite == 0 &&
           !(c->joint_gap > BENCH_MAX_JOINT_GAP);
}

static void bench_format_check(const bench_check* c, char* out, size_t size)
{
    char drift[64] = "";
    if (!isnan(c->top_drift)) {
        snprintf(drift, sizeof drift, "top settle %.3f m, drift %.3f m, ", c->top_settle, c->top_drift);
    }
    char ground[64] = "no ground";
    if (c->below_ground >= 0) {
        snprintf(ground, sizeof ground, "%d below ground", c->below_ground);
    }
    char gap[48] = "";
    if (!isnan(c->joint_gap)) {
        snprintf(gap, sizeof gap, ", joint gap %.1f mm", 1000.0 * c->joint_gap);
    }
    snprintf(out, size, "%s%s, %d non-finite%s: %s", drift, ground, c->non_finite, gap,
             bench_check_passes(c) ? "ok" : "WRONG");
}

void bench_print_scene_header(const bench_scene_info* info, const bench_config* config)
{
    printf("\n%s: %d bodies (%d dynamic), %d steps of %.4g s, %d run%s\n", info->name, info->body_count,
           info->dynamic_count, info->steps, (double)info->dt, config->runs, config->runs == 1 ? "" : "s");
    printf("  %-12s %10s %10s %10s %8s %9s  %s\n", "engine", "median ms", "p95 ms", "mean ms", "x kgyro", "peak MB",
           "correctness");
}

void bench_print_row(const bench_row* row)
{
    const bench_result* r = &row->result;
    if (r->status != BENCH_OK) {
        printf("  %-12s %s: %s\n", row->engine.label, bench_status_name(r->status), r->message);
        return;
    }
    char ratio[32] = "-";
    if (!isnan(row->ratio)) {
        snprintf(ratio, sizeof ratio, "%.2f", row->ratio);
    }
    char check[160];
    bench_format_check(&r->check, check, sizeof check);
    printf("  %-12s %10.3f %10.3f %10.3f %8s %9.1f  %s\n", row->engine.label, r->median_ms, r->p95_ms, r->mean_ms,
           ratio, r->peak_mb, check);
    fflush(stdout);
}

static double bench_stage_total(const bench_result* r)
{
    double total = 0.0;
    for (int k = 0; k < r->stage_count; ++k) {
        total += r->stages[k].ms;
    }
    return total;
}

void bench_print_stages(const bench_row* row)
{
    const bench_result* r = &row->result;
    double total = bench_stage_total(r);
    if (r->status != BENCH_OK || r->stage_count == 0 || !(total > 0.0)) {
        return;
    }
    printf("  %-12s stages (share of %.3f ms):", "", total);
    for (int k = 0; k < r->stage_count; ++k) {
        printf(" %s %.1f%%%s", r->stages[k].name, 100.0 * r->stages[k].ms / total, k + 1 < r->stage_count ? "," : "");
    }
    printf("\n");
}

/* ---- CSV ---- */

/* A number, or an empty field where there is none. */
static void bench_csv_number(FILE* f, double value, const char* format)
{
    if (isfinite(value)) {
        fprintf(f, format, value);
    }
    fputc(',', f);
}

static void bench_csv_text(FILE* f, const char* text)
{
    fputc('"', f);
    for (const char* c = text; *c; ++c) {
        if (*c == '"') {
            fputc('"', f);
        }
        fputc(*c, f);
    }
    fputc('"', f);
}

static void bench_csv_row(FILE* f, const bench_row* row, const bench_config* config, int solver_in_place)
{
    const bench_scene_info* s = &row->scene;
    const bench_result* r = &row->result;
    int ok = r->status == BENCH_OK;
    const char* backend = row->engine.kind == BENCH_KGYRO ? strchr(row->engine.label, '/') + 1 : "";
    fprintf(f, "%s,%s,%d,%d,%d,%s,%s,%d,%d,%d,", s->name, s->family, s->size, s->body_count, s->dynamic_count,
            row->engine.label, backend, config->threads, s->steps, config->runs);
    bench_csv_number(f, ok ? r->median_ms : NAN, "%.5f");
    bench_csv_number(f, ok ? r->p95_ms : NAN, "%.5f");
    bench_csv_number(f, ok ? r->mean_ms : NAN, "%.5f");
    bench_csv_number(f, ok ? row->ratio : NAN, "%.4f");
    bench_csv_number(f, ok ? r->peak_mb : NAN, "%.2f");
    bench_csv_number(f, ok ? r->check.top_settle : NAN, "%.5f");
    bench_csv_number(f, ok ? r->check.top_drift : NAN, "%.5f");
    bench_csv_number(f, ok && r->check.below_ground >= 0 ? r->check.below_ground : NAN, "%.0f");
    bench_csv_number(f, ok ? r->check.non_finite : NAN, "%.0f");
    fprintf(f, "%s,%s,%s,", ok ? (bench_check_passes(&r->check) ? "yes" : "no") : "",
            solver_in_place < 0 ? "" : solver_in_place ? "yes" : "no", bench_status_name(r->status));
    bench_csv_text(f, r->message);
    fputc(',', f);
    if (ok && isfinite(r->check.joint_gap)) {
        fprintf(f, "%.5f", r->check.joint_gap);
    }
    fputc('\n', f);
}

int bench_write_csv(const char* path, const bench_row* rows, int count, const bench_config* config,
                    int solver_in_place)
{
    FILE* f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "kgyro bench: cannot write %s: %s\n", path, strerror(errno));
        return 1;
    }
    fprintf(f, "scene,family,size,bodies,dynamic_bodies,engine,backend,threads,steps,runs,median_ms,p95_ms,"
               "mean_ms,ratio_to_kgyro,peak_rss_mb,top_settle_m,top_drift_m,below_ground,non_finite,correct,"
               "kgyro_solver_in_place,status,message,joint_gap_m\n");
    for (int i = 0; i < count; ++i) {
        bench_csv_row(f, &rows[i], config, solver_in_place);
    }
    return fclose(f) == 0 ? 0 : 1;
}

int bench_write_stages_csv(const char* path, const bench_row* rows, int count, const bench_config* config)
{
    FILE* f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "kgyro bench: cannot write %s: %s\n", path, strerror(errno));
        return 1;
    }
    fprintf(f, "scene,bodies,engine,threads,stage,ms_per_step,share\n");
    for (int i = 0; i < count; ++i) {
        const bench_result* r = &rows[i].result;
        double total = bench_stage_total(r);
        for (int k = 0; r->status == BENCH_OK && total > 0.0 && k < r->stage_count; ++k) {
            fprintf(f, "%s,%d,%s,%d,%s,%.5f,%.4f\n", rows[i].scene.name, rows[i].scene.body_count,
                    rows[i].engine.label, config->threads, r->stages[k].name, r->stages[k].ms,
                    r->stages[k].ms / total);
        }
    }
    return fclose(f) == 0 ? 0 : 1;
}

/* ---- charts ---- */

typedef struct bench_names {
    int count;
    const char* names[BENCH_MAX_STAGES];
} bench_names;

static int bench_names_index(bench_names* set, const char* name, int add)
{
    for (int i = 0; i < set->count; ++i) {
        if (strcmp(set->names[i], name) == 0) {
            return i;
        }
    }
    if (!add || set->count == BENCH_MAX_STAGES) {
        return -1;
    }
    set->names[set->count] = name;
    return set->count++;
}

static int bench_is_series(const bench_row* row) { return row->scene.size > 0; }

/* A fixed colour per engine, so that charts of different runs read alike. */
static int bench_engine_color(const char* label)
{
    static const char* const labels[] = {"kgyro/cpu", "kgyro/opencl", "box2d", "chipmunk"};
    for (int i = 0; i < 4; ++i) {
        if (strcmp(label, labels[i]) == 0) {
            return i + 1;
        }
    }
    return 5;
}

static void bench_plot_preamble(FILE* f, const char* dir, const char* name, const char* title, int width)
{
    fprintf(f, "set terminal pngcairo size %d,600 noenhanced font 'sans,10'\n", width);
    fprintf(f, "set output '%s/%s.png'\n", dir, name);
    fprintf(f, "set title '%s'\n", title);
    fprintf(f, "set grid\n");
}

/* One datablock per engine and series: bodies against median ms. */
static int bench_scaling_blocks(FILE* f, const bench_row* rows, int count, bench_names* engines, bench_names* families)
{
    int blocks = 0;
    for (int e = 0; e < engines->count; ++e) {
        for (int s = 0; s < families->count; ++s) {
            fprintf(f, "$e%ds%d << EOD\n", e, s);
            for (int i = 0; i < count; ++i) {
                const bench_row* row = &rows[i];
                if (bench_is_series(row) && row->result.status == BENCH_OK &&
                    strcmp(row->engine.label, engines->names[e]) == 0 &&
                    strcmp(row->scene.family, families->names[s]) == 0) {
                    fprintf(f, "%d %.6g\n", row->scene.body_count, row->result.median_ms);
                    blocks++;
                }
            }
            fprintf(f, "EOD\n");
        }
    }
    return blocks;
}

/* A slope-1 line through the first kgyro point: a linear-time engine runs parallel to it. */
static void bench_linear_reference(FILE* f, const bench_row* rows, int count)
{
    const bench_row* first = NULL;
    int max_bodies = 0;
    for (int i = 0; i < count; ++i) {
        if (bench_is_series(&rows[i]) && rows[i].result.status == BENCH_OK) {
            max_bodies = rows[i].scene.body_count > max_bodies ? rows[i].scene.body_count : max_bodies;
            if (!first && rows[i].engine.kind == BENCH_KGYRO) {
                first = &rows[i];
            }
        }
    }
    fprintf(f, "$linear << EOD\n");
    if (first) {
        double ms_per_body = first->result.median_ms / first->scene.body_count;
        fprintf(f, "%d %.6g\n%d %.6g\n", first->scene.body_count, first->result.median_ms, max_bodies,
                ms_per_body * max_bodies);
    }
    fprintf(f, "EOD\n");
}

static void bench_plot_scaling(FILE* f, const char* dir, const bench_row* rows, int count)
{
    bench_names engines = {0}, families = {0};
    for (int i = 0; i < count; ++i) {
        if (bench_is_series(&rows[i]) && rows[i].result.status == BENCH_OK) {
            bench_names_index(&engines, rows[i].engine.label, 1);
            bench_names_index(&families, rows[i].scene.family, 1);
        }
    }
    bench_plot_preamble(f, dir, "scaling", "Step time vs bodies (median ms per step, log-log)", 960);
    fprintf(f, "set logscale xy\nset xlabel 'bodies'\nset ylabel 'ms per step'\nset key top left\n");
    fprintf(f, "set format x '%%.0s%%c'\n");
    bench_scaling_blocks(f, rows, count, &engines, &families);
    bench_linear_reference(f, rows, count);
    fprintf(f, "plot $linear with lines lc 'dark-gray' lw 1.5 dt 2 title 'linear (slope 1)'");
    for (int e = 0; e < engines.count; ++e) {
        for (int s = 0; s < families.count; ++s) {
            fprintf(f, ", \\\n  $e%ds%d with linespoints lc %d dt %d pt %d title '%s %s_N'", e, s,
                    bench_engine_color(engines.names[e]), s + 1,
                    5 + 2 * s, engines.names[e], families.names[s]);
        }
    }
    fprintf(f, "\n");
}

static const bench_row* bench_find_row(const bench_row* rows, int count, const char* scene, const char* engine)
{
    for (int i = 0; i < count; ++i) {
        if (strcmp(rows[i].scene.name, scene) == 0 && strcmp(rows[i].engine.label, engine) == 0) {
            return &rows[i];
        }
    }
    return NULL;
}

/* The fixed-size scenes side by side: one cluster per scene, one bar per engine. */
static void bench_plot_scenes(FILE* f, const char* dir, const bench_row* rows, int count)
{
    bench_names engines = {0}, scenes = {0};
    for (int i = 0; i < count; ++i) {
        if (!bench_is_series(&rows[i]) && rows[i].result.status == BENCH_OK) {
            bench_names_index(&engines, rows[i].engine.label, 1);
            bench_names_index(&scenes, rows[i].scene.name, 1);
        }
    }
    bench_plot_preamble(f, dir, "scenes", "Benchmark scenes: median ms per step (log scale, lower is faster)", 960);
    fprintf(f, "set style data histogram\nset style histogram clustered gap 1\n");
    fprintf(f, "set style fill solid 0.85 border -1\nset logscale y\nset ylabel 'ms per step'\n");
    fprintf(f, "set datafile missing '-'\nset key top left\n$scenes << EOD\nscene");
    for (int e = 0; e < engines.count; ++e) {
        fprintf(f, " \"%s\"", engines.names[e]);
    }
    for (int s = 0; s < scenes.count; ++s) {
        fprintf(f, "\n\"%s\"", scenes.names[s]);
        for (int e = 0; e < engines.count; ++e) {
            const bench_row* row = bench_find_row(rows, count, scenes.names[s], engines.names[e]);
            if (row && row->result.status == BENCH_OK) {
                fprintf(f, " %.6g", row->result.median_ms);
            } else {
                fprintf(f, " -");
            }
        }
    }
    fprintf(f, "\nEOD\nplot");
    for (int e = 0; e < engines.count; ++e) {
        fprintf(f, "%s $scenes using %d:xtic(1) lc %d title columnheader(%d)", e ? "," : "", e + 2,
                bench_engine_color(engines.names[e]), e + 2);
    }
    fprintf(f, "\n");
}

static int bench_has_stages(const bench_row* row)
{
    return row->result.status == BENCH_OK && bench_stage_total(&row->result) > 0.0;
}

/* A fixed-size scene, or the largest size of a series that this engine measured. */
static int bench_stage_row_wanted(const bench_row* rows, int count, int index)
{
    const bench_row* row = &rows[index];
    if (!bench_has_stages(row)) {
        return 0;
    }
    for (int i = 0; bench_is_series(row) && i < count; ++i) {
        if (bench_has_stages(&rows[i]) && rows[i].scene.size > row->scene.size &&
            strcmp(rows[i].scene.family, row->scene.family) == 0 &&
            strcmp(rows[i].engine.label, row->engine.label) == 0) {
            return 0;
        }
    }
    return 1;
}

static void bench_stage_bar(FILE* f, const bench_row* row, const bench_names* stages)
{
    const bench_result* r = &row->result;
    double total = bench_stage_total(r);
    fprintf(f, "\n\"%s %s\"", row->scene.name, strchr(row->engine.label, '/') + 1);
    for (int k = 0; k < stages->count; ++k) {
        double ms = 0.0;
        for (int j = 0; j < r->stage_count; ++j) {
            ms += strcmp(r->stages[j].name, stages->names[k]) == 0 ? r->stages[j].ms : 0.0;
        }
        fprintf(f, " %.3f", 100.0 * ms / total);
    }
}

/* Each stage's share of kgyro's step: one stacked bar per backend and scene, for the
 * fixed-size scenes and the largest size of each series. */
static void bench_plot_stages(FILE* f, const char* dir, const bench_row* rows, int count)
{
    bench_names stages = {0}, engines = {0};
    for (int i = 0; i < count; ++i) {
        for (int k = 0; bench_stage_row_wanted(rows, count, i) && k < rows[i].result.stage_count; ++k) {
            bench_names_index(&stages, rows[i].result.stages[k].name, 1);
            bench_names_index(&engines, rows[i].engine.label, 1);
        }
    }
    bench_plot_preamble(f, dir, "stages", "kgyro: share of the step per stage (scene, backend)", 1000);
    fprintf(f, "set style data histogram\nset style histogram rowstacked\nset style fill solid 0.85 border -1\n");
    fprintf(f, "set yrange [0:100]\nset ylabel 'share of the step (%%)'\nset xtics rotate by -35\n");
    fprintf(f, "set key outside right\n$stages << EOD\nrun");
    for (int k = 0; k < stages.count; ++k) {
        fprintf(f, " \"%s\"", stages.names[k]);
    }
    for (int e = 0; e < engines.count; ++e) {
        for (int i = 0; i < count; ++i) {
            if (bench_stage_row_wanted(rows, count, i) && strcmp(rows[i].engine.label, engines.names[e]) == 0) {
                bench_stage_bar(f, &rows[i], &stages);
            }
        }
    }
    fprintf(f, "\nEOD\nplot for [i=2:%d] $stages using i:xtic(1) title columnheader(i)\n", stages.count + 1);
}

static int bench_run_gnuplot(const char* script)
{
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        execlp("gnuplot", "gnuplot", script, (char*)NULL);
        _exit(127);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) < 0) {
        return -1;
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

typedef void bench_chart_fn(FILE* f, const char* dir, const bench_row* rows, int count);

/* Writes DIR/NAME.gp and draws it; 0 when the script was written. */
static int bench_chart(const char* dir, const char* name, bench_chart_fn* fn, const bench_row* rows, int count)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.gp", dir, name);
    FILE* f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "kgyro bench: cannot write %s: %s\n", path, strerror(errno));
        return 1;
    }
    fn(f, dir, rows, count);
    if (fclose(f) != 0) {
        return 1;
    }
    int status = bench_run_gnuplot(path);
    if (status == 0) {
        printf("chart: %s/%s.png\n", dir, name);
    } else if (status == 127) {
        printf("chart: %s written; gnuplot is not installed, so no PNG (apt-get install gnuplot-nox)\n", path);
    } else {
        fprintf(stderr, "kgyro bench: gnuplot failed on %s\n", path);
    }
    return 0;
}

static int bench_count_rows(const bench_row* rows, int count, int series, int with_stages)
{
    int n = 0;
    for (int i = 0; i < count; ++i) {
        const bench_result* r = &rows[i].result;
        if (r->status == BENCH_OK && (with_stages ? bench_stage_total(r) > 0.0 : bench_is_series(&rows[i]) == series)) {
            n++;
        }
    }
    return n;
}

int bench_plot(const char* dir, const bench_row* rows, int count)
{
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "kgyro bench: cannot create %s: %s\n", dir, strerror(errno));
        return 1;
    }
    int failed = 0;
    if (bench_count_rows(rows, count, 1, 0) > 0) {
        failed |= bench_chart(dir, "scaling", bench_plot_scaling, rows, count);
    }
    if (bench_count_rows(rows, count, 0, 0) > 0) {
        failed |= bench_chart(dir, "scenes", bench_plot_scenes, rows, count);
    }
    if (bench_count_rows(rows, count, 0, 1) > 0) {
        failed |= bench_chart(dir, "stages", bench_plot_stages, rows, count);
    }
    return failed;
}
