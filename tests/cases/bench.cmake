# The benchmark's tests. This file has two roles:
#  - included by tests/CMakeLists.txt, it links the peer engines into test_bench_scenes
#    (when they are built) and registers the smoke test of `kgyro bench` (at the bottom);
#  - run as `cmake -P bench.cmake`, it is that smoke test: tiny scenes, every engine, no
#    timing assertions; it checks the exit code, the CSV rows and the charts.
# Arguments are joined with "|" (a ";" would split them on the way through add_test).

if(CMAKE_SCRIPT_MODE_FILE)
  string(REPLACE "|" ";" run_args "${ARGS}")
  file(REMOVE_RECURSE "${OUT}")
  file(MAKE_DIRECTORY "${OUT}")
  execute_process(COMMAND "${KGYRO}" ${run_args} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "exit code ${code}\n${out}\n${err}")
  endif()
  string(FIND "${out}" "kgyro contact solver: " said)
  if(said EQUAL -1)
    message(FATAL_ERROR "the report does not say whether kgyro's contact solver is in:\n${out}")
  endif()
  file(STRINGS "${OUT}/results.csv" lines)
  list(LENGTH lines count)
  math(EXPR rows "${count} - 1")
  if(NOT rows EQUAL ROWS)
    message(FATAL_ERROR "${rows} rows in results.csv, expected ${ROWS}:\n${out}")
  endif()
  # kgyro is measured; a peer is measured or says why it is missing
  foreach(line ${lines})
    if(line MATCHES ",kgyro/cpu," AND NOT line MATCHES ",ok,\"")
      message(FATAL_ERROR "kgyro was not measured: ${line}")
    endif()
    if(line MATCHES ",(box2d|chipmunk),," AND NOT line MATCHES ",(ok|missing),\"")
      message(FATAL_ERROR "a peer neither ran nor was missing: ${line}")
    endif()
  endforeach()
  file(STRINGS "${OUT}/results_stages.csv" stage_lines)
  list(LENGTH stage_lines stage_count)
  if(stage_count LESS 2)
    message(FATAL_ERROR "no stage times in results_stages.csv")
  endif()
  find_program(GNUPLOT gnuplot)
  foreach(chart scaling scenes stages)
    if(NOT EXISTS "${OUT}/${chart}.gp" OR (GNUPLOT AND NOT EXISTS "${OUT}/${chart}.png"))
      message(FATAL_ERROR "chart ${chart} missing in ${OUT}:\n${out}")
    endif()
  endforeach()
  return()
endif()

if(TARGET test_bench_scenes AND TARGET kgyro_peers)
  target_link_libraries(test_bench_scenes PRIVATE kgyro_peers)
  target_compile_definitions(test_bench_scenes PRIVATE KG_HAVE_PEERS)
endif()

if(TARGET kgyro_cli)
  set(kg_bench_out ${CMAKE_CURRENT_BINARY_DIR}/bench_smoke)
  # 4 scenes x 3 engines: a row each, measured or missing
  add_test(NAME cli_bench_smoke
           COMMAND ${CMAKE_COMMAND} -DKGYRO=$<TARGET_FILE:kgyro_cli>
                   "-DARGS=bench|pyramid_4:20|rain_40:10|particles_40:10|tumbler:4|--runs|2|--profile|--csv|${kg_bench_out}/results.csv|--plot|${kg_bench_out}"
                   -DOUT=${kg_bench_out} -DROWS=12 -P ${CMAKE_CURRENT_LIST_FILE})
endif()
