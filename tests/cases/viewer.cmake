# The renderer and the viewer (tools/render):
# - test_render (tests/test_render.c) links the renderer library;
# - render_cli runs 'kgyro render' on a sample and checks the PNG it wrote;
# - viewer_xvfb runs 'kgyro view' under Xvfb with scripted input and checks the
#   screenshot (tools/render/viewer_test.sh; skipped when Xvfb is missing).
# kg_png_probe reads a PNG and checks pixel colours, so no image tools are needed.
if(TARGET test_render)
  include(${PROJECT_SOURCE_DIR}/tools/render/render_lib.cmake)
  target_link_libraries(test_render PRIVATE kgyro_render)
endif()

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
