# The OpenCL backend. Compiled in when the OpenCL headers are found (Debian's
# opencl-headers); libOpenCL itself is never linked: the backend loads libOpenCL.so.1
# with dlopen at run time, so the library needs only libc and libm to load, and a
# machine without OpenCL simply runs the CPU backend.
#
# The kernel sources (src/backend/opencl/kernels/*.cl and the shared headers they
# include) are embedded into the library as C string arrays at build time, so a user
# ships one library file and the device compiler needs no include path.
option(KGYRO_OPENCL "Build the OpenCL backend when the OpenCL headers are found" ON)

find_path(KG_OPENCL_INCLUDE_DIR CL/cl.h)
if(NOT KGYRO_OPENCL OR NOT KG_OPENCL_INCLUDE_DIR)
  message(STATUS "kgyro: OpenCL backend not built (no CL/cl.h; install opencl-headers)")
  return()
endif()
message(STATUS "kgyro: OpenCL backend built (headers in ${KG_OPENCL_INCLUDE_DIR}, libOpenCL loaded at run time)")

set(KG_CL_DIR ${CMAKE_CURRENT_SOURCE_DIR}/src/backend/opencl)
file(GLOB KG_CL_KERNELS CONFIGURE_DEPENDS ${KG_CL_DIR}/kernels/*.cl)
file(GLOB KG_CL_SHARED_HEADERS CONFIGURE_DEPENDS
  ${CMAKE_CURRENT_SOURCE_DIR}/src/core/*.h ${CMAKE_CURRENT_SOURCE_DIR}/src/collide/*.h
  ${CMAKE_CURRENT_SOURCE_DIR}/src/solve/*.h ${KG_CL_DIR}/kernels/*.h)
set(KG_CL_EMBEDDED ${CMAKE_CURRENT_BINARY_DIR}/generated/kg_cl_kernels.c)
string(REPLACE ";" "|" KG_CL_KERNEL_LIST "${KG_CL_KERNELS}") # one command-line argument

add_custom_command(
  OUTPUT ${KG_CL_EMBEDDED}
  COMMAND ${CMAKE_COMMAND} -DKG_KERNELS=${KG_CL_KERNEL_LIST} -DKG_OUTPUT=${KG_CL_EMBEDDED}
          -DKG_SEARCH=${CMAKE_CURRENT_SOURCE_DIR}/src
          -P ${KG_CL_DIR}/embed_kernels.cmake
  DEPENDS ${KG_CL_KERNELS} ${KG_CL_SHARED_HEADERS} ${KG_CL_DIR}/embed_kernels.cmake
  COMMENT "Embedding the OpenCL kernels"
  VERBATIM)

target_sources(kgyro_objects PRIVATE ${KG_CL_EMBEDDED})
target_include_directories(kgyro_objects SYSTEM PRIVATE ${KG_OPENCL_INCLUDE_DIR})
target_compile_definitions(kgyro_objects PRIVATE KG_HAVE_OPENCL CL_TARGET_OPENCL_VERSION=120)
