# The narrowphase header must compile as OpenCL C 1.2, the language of the kernels: a tiny
# kernel that includes it is checked by clang with warnings as errors. Only where clang is
# found. clang does not define __OPENCL_VERSION__ (the device's version, which runtimes
# such as PoCL define), so it is given here; kg_shared.h keys the OpenCL side on it.
find_program(KG_NARROWPHASE_CLANG NAMES clang clang-14)
if(KG_NARROWPHASE_CLANG)
  set(kg_narrowphase_cl ${CMAKE_CURRENT_BINARY_DIR}/narrowphase_check.cl)
  file(WRITE ${kg_narrowphase_cl} [=[
#include "collide/chain.h"

__kernel void kg_narrowphase_check(__global const kg_shape* shapes, __global const kg_xf* poses,
                                   __global kg_manifold* manifolds, float speculative_distance)
{
    int i = (int)get_global_id(0);
    kg_shape a = shapes[2 * i];
    kg_shape b = shapes[2 * i + 1];
    manifolds[i] = kg_collide_shapes(&a, poses[2 * i], &b, poses[2 * i + 1], speculative_distance);
}
]=])
  add_test(NAME narrowphase_opencl_c
    COMMAND ${KG_NARROWPHASE_CLANG} -x cl -cl-std=CL1.2 -Xclang -finclude-default-header
            -D__OPENCL_VERSION__=120 -fsyntax-only -Wall -Wextra -Wshadow -Wdouble-promotion -Werror
            -I ${PROJECT_SOURCE_DIR}/src ${kg_narrowphase_cl})
endif()
