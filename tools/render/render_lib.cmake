# kgyro_render: the software renderer (canvas, palette, world drawing, GIF and PNG
# writers) as a static library, linked by the kgyro command and by tests/test_render*.c.
# PNG goes through stb_image_write (Debian: libstb-dev, header in /usr/include/stb);
# without it PNG output reports an error and GIF still works.
if(NOT TARGET kgyro_render)
  set(KG_RENDER_DIR ${CMAKE_CURRENT_LIST_DIR})
  find_path(KGYRO_STB_INCLUDE_DIR stb_image_write.h PATH_SUFFIXES stb)
  set(KG_RENDER_SOURCES ${KG_RENDER_DIR}/canvas.c ${KG_RENDER_DIR}/draw.c ${KG_RENDER_DIR}/gif.c
                        ${KG_RENDER_DIR}/palette.c)
  if(KGYRO_STB_INCLUDE_DIR)
    list(APPEND KG_RENDER_SOURCES ${KG_RENDER_DIR}/image.c)
  else()
    message(STATUS "kgyro: stb_image_write.h not found (Debian: libstb-dev): renderings without PNG")
    list(APPEND KG_RENDER_SOURCES ${KG_RENDER_DIR}/image_none.c)
  endif()
  add_library(kgyro_render STATIC ${KG_RENDER_SOURCES})
  target_include_directories(kgyro_render PUBLIC ${KG_RENDER_DIR})
  if(KGYRO_STB_INCLUDE_DIR)
    target_include_directories(kgyro_render SYSTEM PUBLIC ${KGYRO_STB_INCLUDE_DIR})
    target_compile_definitions(kgyro_render PUBLIC KG_RENDER_HAVE_PNG=1)
  endif()
  target_compile_options(kgyro_render PRIVATE ${KG_C_FLAGS})
  target_link_libraries(kgyro_render PUBLIC kgyro)
endif()
