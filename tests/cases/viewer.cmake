# The renderer and the viewer (tools/render):
# - test_render and test_render_tiles (tests/test_render*.c) link the renderer library;
# - render_cli and render_cli_tiled run 'kgyro render' on a sample scene and on a Tiled
#   map and check the PNGs they wrote;
# - viewer_xvfb runs 'kgyro view' under Xvfb with scripted input and checks the
#   screenshot, also of a Tiled map with its tiles toggled (tools/render/viewer_test.sh;
#   skipped when Xvfb is missing).
# kg_png_probe reads a PNG and checks pixel colours, so no image tools are needed.
foreach(test test_render test_render_tiles)
  if(TARGET ${test})
    include(${PROJECT_SOURCE_DIR}/tools/render/render_lib.cmake)
    target_link_libraries(${test} PRIVATE kgyro_render)
  endif()
endforeach()

if(TARGET kgyro_cli AND KGYRO_STB_INCLUDE_DIR)
  add_executable(kg_png_probe ${PROJECT_SOURCE_DIR}/tools/render/png_probe.c)
  target_compile_options(kg_png_probe PRIVATE ${KG_C_FLAGS})
  target_link_libraries(kg_png_probe PRIVATE kgyro_render)

  # 160x120 showing x in [-8, 8], y in [-1, 11] (10 px/m, centre (0, 5)): in 10 steps
  # the pyramid's bottom-left box, (-3.5, 0.5), moves 0.15 m at most, even in free fall.
  set(KG_RENDER_OUT ${CMAKE_CURRENT_BINARY_DIR}/render_cli)
  file(MAKE_DIRECTORY ${KG_RENDER_OUT})
  add_test(NAME render_cli
    COMMAND $<TARGET_FILE:kgyro_cli> render samples/demo_pyramid.json --backend cpu --steps 10 --every 5
            --size 160x120 --view -8,-1,8,11 --gif ${KG_RENDER_OUT}/pyramid.gif --png ${KG_RENDER_OUT}/pyramid.png)
  add_test(NAME render_cli_pixels
    COMMAND kg_png_probe ${KG_RENDER_OUT}/pyramid.png size 160 120 at 45 105 body at 80 117 static
            at 5 5 background not 80 95 background)
  set_tests_properties(render_cli PROPERTIES WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
    PASS_REGULAR_EXPRESSION "wrote .*pyramid.gif: 3 frames, 160x120")
  set_tests_properties(render_cli_pixels PROPERTIES DEPENDS render_cli)
  # A Tiled map: 160x80 showing x in [0, 16], y in [0, 8] (10 px/m, pixel (10x, 80 - 10y)):
  # ground at (0.5, 0.5), the slope tile (8, 2) filled lower right and empty upper left,
  # the empty cell (6, 3), the crate stack at (3, 5.5).
  add_test(NAME render_cli_tiled
    COMMAND $<TARGET_FILE:kgyro_cli> render samples/platformer.tmj --backend cpu --steps 1 --size 160x80
            --view 0,0,16,8 --png ${KG_RENDER_OUT}/platformer.png)
  add_test(NAME render_cli_tiled_pixels
    COMMAND kg_png_probe ${KG_RENDER_OUT}/platformer.png at 5 75 tile at 88 58 tile at 82 52 background
            at 65 45 background at 30 25 body)
  set_tests_properties(render_cli_tiled PROPERTIES WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
    PASS_REGULAR_EXPRESSION "wrote .*platformer.png: 160x80")
  set_tests_properties(render_cli_tiled_pixels PROPERTIES DEPENDS render_cli_tiled)
  # Compound bodies: 160x80 showing x in [-8, 8], y in [-1, 7] (10 px/m, pixel
  # (10 (x + 8), 80 - 10 (y + 1))) after one step: the dumbbell's two discs, (-6.92, 2.61)
  # and (-5.08, 3.39), the empty middle above its bar (-6, 3.5), the L's post (-1.97, 2.20).
  add_test(NAME render_cli_compound
    COMMAND $<TARGET_FILE:kgyro_cli> render samples/compound.json --backend cpu --steps 1 --size 160x80
            --view -8,-1,8,7 --png ${KG_RENDER_OUT}/compound.png)
  add_test(NAME render_cli_compound_pixels
    COMMAND kg_png_probe ${KG_RENDER_OUT}/compound.png at 11 44 body at 29 36 body at 20 34 background
            at 60 48 body)
  set_tests_properties(render_cli_compound PROPERTIES WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
    PASS_REGULAR_EXPRESSION "wrote .*compound.png: 160x80")
  set_tests_properties(render_cli_compound_pixels PROPERTIES DEPENDS render_cli_compound)
  add_test(NAME render_cli_bad_option COMMAND $<TARGET_FILE:kgyro_cli> render samples/demo_pyramid.json --size 10)
  set_tests_properties(render_cli_bad_option PROPERTIES WILL_FAIL ON)

  if(KGYRO_HAVE_SDL2)
    add_test(NAME viewer_xvfb
      COMMAND sh ${PROJECT_SOURCE_DIR}/tools/render/viewer_test.sh $<TARGET_FILE:kgyro_cli>
              $<TARGET_FILE:kg_png_probe> samples/demo_pyramid.json ${CMAKE_CURRENT_BINARY_DIR}/viewer)
    set_tests_properties(viewer_xvfb PROPERTIES SKIP_RETURN_CODE 77 WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
      TIMEOUT 300)
  endif()
endif()
