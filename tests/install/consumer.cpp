// A C++ program against installed kgyro: every public header, the extern "C" linkage,
// and a body in free fall for one second. Exits 0 when it fell as far as it should.
#include <kgyro/kgyro.h>
#include <kgyro/opencl.h>
#include <kgyro/scene.h>

#include <cmath>
#include <cstdio>

int main()
{
    kg_world_def def = kg_default_world_def();
    def.backend = KG_BACKEND_CPU;
    kg_world* world = nullptr;
    if (kg_create_world(&def, &world) != KG_OK) {
        std::fprintf(stderr, "kgyro: %s\n", kg_last_error());
        return 1;
    }
    kg_body_def ball_def = kg_default_body_def();
    ball_def.position.y = 10.0f;
    ball_def.shape = kg_circle_shape(0.5f);
    kg_body ball;
    kg_create_body(world, &ball_def, &ball);
    for (int i = 0; i < 60; ++i) {
        kg_world_step(world, 1.0f / 60.0f);
    }
    kg_body_state state;
    kg_body_get_state(world, ball, &state);
    kg_destroy_world(world);
    std::printf("c++: after 1 s the ball is at y = %.3f, moving at %.3f m/s\n", state.position.y, state.velocity.y);
    // 1 s of free fall from 10 m at 10 m/s^2: about 5 m down, at 10 m/s
    return std::fabs(state.position.y - 5.0f) < 0.2f && std::fabs(state.velocity.y + 10.0f) < 0.01f ? 0 : 1;
}
