/* The README's API example, built and run by `make test` (tests/cases/install.cmake)
 * and built against the installed package, three ways. Keep the two in step. */
#include <kgyro/kgyro.h>
#include <stdio.h>

int main(void)
{
    kg_world_def world_def = kg_default_world_def(); /* gravity (0, -10) m/s^2 */
    kg_world* world;
    if (kg_create_world(&world_def, &world) != KG_OK) {
        fprintf(stderr, "kgyro: %s\n", kg_last_error());
        return 1;
    }

    kg_body_def box_def = kg_default_body_def(); /* dynamic, density 1 */
    box_def.position = (kg_vec2){0.0f, 10.0f};
    box_def.shape = kg_box_shape(1.0f, 1.0f);
    kg_body box;
    kg_create_body(world, &box_def, &box);

    for (int i = 0; i < 60; ++i) { /* one second */
        kg_world_step(world, 1.0f / 60.0f);
    }

    kg_vec2 p;
    kg_body_get_position(world, box, &p);
    printf("after 1 s the box is at (%.2f, %.2f)\n", p.x, p.y);
    kg_destroy_world(world);
    return 0;
}
