# The soak program (tests/soak/soak.c). It runs for minutes, so it is not a ctest and
# not built by default: scripts/soak.sh (`make soak`) builds the kg_soak target and
# runs it, once in a release build and once under ASan+UBSan with LeakSanitizer.
add_executable(kg_soak EXCLUDE_FROM_ALL ${CMAKE_CURRENT_SOURCE_DIR}/soak/soak.c)
target_include_directories(kg_soak PRIVATE ${PROJECT_SOURCE_DIR}/src)
target_compile_options(kg_soak PRIVATE ${KG_C_FLAGS})
target_link_libraries(kg_soak PRIVATE kgyro)

# What the soak ran into, kept as scenes (tests/regress/soak/*.json) and replayed with
# the soak's checks by a quick ctest.
file(GLOB KG_SOAK_REGRESSIONS CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/regress/soak/*.json)
if(TARGET kgyro_io AND KG_SOAK_REGRESSIONS)
  add_executable(kg_soak_replay ${CMAKE_CURRENT_SOURCE_DIR}/soak/replay.c)
  target_compile_options(kg_soak_replay PRIVATE ${KG_C_FLAGS})
  target_link_libraries(kg_soak_replay PRIVATE kgyro_io kgyro)
  add_test(NAME soak_regress COMMAND kg_soak_replay ${KG_SOAK_REGRESSIONS})
endif()
