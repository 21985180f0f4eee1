# Fuzz regressions: every fuzz target fuzz/fuzz_NAME.c is also linked, without
# libFuzzer, with fuzz/replay_main.c into replay_NAME, and the ctest fuzz_regress_NAME
# replays through it every input that ever crashed it (tests/regress/NAME, where
# scripts/fuzz.sh puts them) and its seeds (fuzz/corpus/NAME and the directories listed
# in fuzz/NAME.seeds). A target whose source mentions kgyro_io needs the scene/map
# library and is left out without it.
file(GLOB KG_FUZZ_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/fuzz/fuzz_*.c)
foreach(src ${KG_FUZZ_SOURCES})
  get_filename_component(file_name ${src} NAME_WE)
  string(REGEX REPLACE "^fuzz_" "" name ${file_name})
  file(STRINGS ${src} needs_io REGEX "kgyro_io")
  if(needs_io AND NOT TARGET kgyro_io)
    continue()
  endif()
  add_executable(replay_${name} ${src} ${PROJECT_SOURCE_DIR}/fuzz/replay_main.c)
  target_include_directories(replay_${name} PRIVATE ${PROJECT_SOURCE_DIR}/src ${PROJECT_SOURCE_DIR}/fuzz)
  target_compile_options(replay_${name} PRIVATE ${KG_C_FLAGS})
  if(TARGET kgyro_io)
    target_link_libraries(replay_${name} PRIVATE kgyro_io)
  endif()
  target_link_libraries(replay_${name} PRIVATE kgyro)
  set(seed_dirs "")
  if(EXISTS ${PROJECT_SOURCE_DIR}/fuzz/${name}.seeds)
    file(STRINGS ${PROJECT_SOURCE_DIR}/fuzz/${name}.seeds seed_dirs REGEX "^[^#]")
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/fuzz/${name}.seeds)
  endif()
  add_test(NAME fuzz_regress_${name}
           COMMAND replay_${name} tests/regress/${name} fuzz/corpus/${name} ${seed_dirs}
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
endforeach()
