/* A C program against installed kgyro::io: a generated scene, instantiated and stepped.
 * Exits 0 when the scene has the bodies its generator promises. */
#include <kgyro/kgyro.h>
#include <kgyro/scene.h>
#include <stdio.h>

int main(void)
{
    kg_scene* scene;
    if (kg_scene_generate("pyramid_4", 1, &scene) != KG_OK) {
        fprintf(stderr, "kgyro: %s\n", kg_last_error());
        return 1;
    }
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    kg_world* world;
    if (kg_scene_instantiate(scene, &def, &world, NULL) != KG_OK) {
        fprintf(stderr, "kgyro: %s\n", kg_last_error());
        kg_scene_destroy(scene);
        return 1;
    }
    for (int i = 0; i < 10; ++i) {
        kg_world_step(world, kg_scene_dt(scene));
    }
    int bodies = kg_world_body_count(world);
    printf("scene: pyramid_4 has %d bodies\n", bodies);
    kg_destroy_world(world);
    kg_scene_destroy(scene);
    return bodies == 11 ? 0 : 1; /* the ground and 4 + 3 + 2 + 1 boxes */
}
