/* A player in the Tiled level samples/platformer.tmj, the way a game drives one: each
 * frame it asks the world whether the player stands on something (a shape cast of the
 * player's own capsule a little way down), whether a wall or a gap is ahead (ray casts),
 * runs right and jumps when it must; a sensor at the far side of the first hills is the
 * goal, and the crates it bumps are heard through hit events.
 *
 *   build/platformer_player [samples/platformer.tmj]
 *
 * Prints what happens and exits 0 when the player reached the goal within 20 s. */
#include "kgyro/kgyro.h"
#include "kgyro/scene.h"

#include <stdio.h>

#define DT (1.0f / 60.0f)
#define RUN_SPEED 4.0f
#define JUMP_SPEED 8.0f

typedef struct player {
    kg_body body;
    int grounded;
} player;

static kg_query_filter solid_only(void)
{
    kg_query_filter f = kg_default_query_filter();
    f.flags = KG_QUERY_SKIP_SENSORS;
    return f;
}

/* Standing: the capsule swept 5 cm down meets something below it. */
static int stands(const kg_world* w, kg_body body)
{
    kg_ray_result hit;
    return kg_world_cast_body_closest(w, body, (kg_vec2){0.0f, -0.05f}, solid_only(), &hit) == KG_OK && hit.hit &&
           hit.normal.y > 0.5f;
}

/* Something to jump: a wall at knee height within 0.7 m, or no ground within 2 m below a
 * point 0.8 m ahead. */
static int must_jump(const kg_world* w, kg_vec2 at)
{
    kg_ray_result wall, floor;
    kg_world_cast_ray_closest(w, (kg_vec2){at.x, at.y - 0.4f}, (kg_vec2){0.7f, 0.0f}, solid_only(), &wall);
    kg_world_cast_ray_closest(w, (kg_vec2){at.x + 0.8f, at.y}, (kg_vec2){0.0f, -2.0f}, solid_only(), &floor);
    return (wall.hit && wall.normal.x < -0.5f) || !floor.hit;
}

static void drive(kg_world* w, player* p)
{
    kg_vec2 at, v;
    kg_body_get_position(w, p->body, &at);
    kg_body_get_velocity(w, p->body, &v);
    p->grounded = stands(w, p->body);
    v.x = RUN_SPEED;
    if (p->grounded && must_jump(w, at)) {
        v.y = JUMP_SPEED;
    }
    kg_body_set_velocity(w, p->body, v);
}

static kg_body add_player(kg_world* w)
{
    kg_body_def bd = kg_default_body_def();
    bd.position = (kg_vec2){1.5f, 4.5f};
    bd.shape = kg_capsule_shape((kg_vec2){0.0f, -0.35f}, (kg_vec2){0.0f, 0.35f}, 0.3f);
    bd.fixed_rotation = 1;
    bd.friction = 0.0f;
    kg_body body = KG_NULL_BODY_INIT;
    kg_create_body(w, &bd, &body);
    return body;
}

/* The goal: a static sensor box on the first hill's far side. */
static kg_body add_goal(kg_world* w)
{
    kg_body_def bd = kg_default_body_def();
    bd.type = KG_BODY_STATIC;
    bd.position = (kg_vec2){20.5f, 4.0f};
    bd.shape = kg_box_shape(1.0f, 2.0f);
    bd.is_sensor = 1;
    kg_body body = KG_NULL_BODY_INIT;
    kg_create_body(w, &bd, &body);
    return body;
}

static int reached(const kg_world* w, kg_body goal, kg_body who)
{
    kg_sensor_events se = kg_world_get_sensor_events(w);
    for (int i = 0; i < se.begin_count; ++i) {
        if (se.begin[i].a.index == goal.index && se.begin[i].b.index == who.index) {
            return 1;
        }
    }
    return 0;
}

int main(int argc, char** argv)
{
    const char* level = argc > 1 ? argv[1] : "samples/platformer.tmj";
    kg_scene* scene = NULL;
    kg_world* w = NULL;
    kg_world_def def;
    if (kg_scene_load_tiled(level, &scene) == KG_OK) {
        def = *kg_scene_world_def(scene);
        def.max_bodies = kg_scene_body_count(scene) + 2; /* the level's, the player and the goal */
    }
    if (!scene || kg_scene_instantiate(scene, &def, &w, NULL) != KG_OK) {
        fprintf(stderr, "platformer_player: %s\n", kg_last_error());
        kg_scene_destroy(scene);
        return 1;
    }
    player p = {add_player(w), 0};
    kg_body goal = add_goal(w);
    int jumps = 0, was_grounded = 0, hits = 0, step = 0, done = 0;
    for (step = 1; step <= 1200 && !done; ++step) {
        drive(w, &p);
        jumps += was_grounded && !p.grounded;
        was_grounded = p.grounded;
        kg_world_step(w, DT);
        kg_contact_events ev = kg_world_get_contact_events(w);
        for (int i = 0; i < ev.hit_count; ++i) {
            if (ev.hit[i].a.index == p.body.index || ev.hit[i].b.index == p.body.index) {
                hits += 1;
                printf("step %4d: thud at (%.2f, %.2f), %.2f m/s\n", step, (double)ev.hit[i].point.x,
                       (double)ev.hit[i].point.y, (double)ev.hit[i].approach_speed);
            }
        }
        done = reached(w, goal, p.body);
    }
    kg_vec2 at;
    kg_body_get_position(w, p.body, &at);
    if (done) {
        printf("the player reached the goal at step %d (%.2f s), at (%.2f, %.2f), after %d jumps and %d hits\n",
               step - 1, (double)((float)(step - 1) * DT), (double)at.x, (double)at.y, jumps, hits);
    } else {
        printf("the player did not reach the goal: it is at (%.2f, %.2f) after %d jumps\n", (double)at.x,
               (double)at.y, jumps);
    }
    kg_destroy_world(w);
    kg_scene_destroy(scene);
    return done ? 0 : 1;
}
