# Included by the top-level CMakeLists.txt once kgyro_cli exists: adds the renderer to
# the kgyro command, and the SDL2 viewer when pkg-config finds sdl2 (Debian:
# libsdl2-dev); without SDL2, 'kgyro view' says how to get it.
include(${CMAKE_CURRENT_LIST_DIR}/render_lib.cmake)

target_sources(kgyro_cli PRIVATE ${KG_RENDER_DIR}/args.c ${KG_RENDER_DIR}/sim.c)
target_link_libraries(kgyro_cli PRIVATE kgyro_render)

set(KGYRO_HAVE_SDL2 OFF)
if(PkgConfig_FOUND)
  pkg_check_modules(SDL2 IMPORTED_TARGET sdl2)
  if(SDL2_FOUND)
    set(KGYRO_HAVE_SDL2 ON)
  endif()
endif()
if(KGYRO_HAVE_SDL2)
  target_sources(kgyro_cli PRIVATE ${KG_RENDER_DIR}/viewer_sdl.c)
  target_link_libraries(kgyro_cli PRIVATE PkgConfig::SDL2)
else()
  message(STATUS "kgyro: SDL2 not found (Debian: libsdl2-dev): 'kgyro view' is not built")
  target_sources(kgyro_cli PRIVATE ${KG_RENDER_DIR}/viewer_none.c)
endif()
