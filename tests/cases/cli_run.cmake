# CLI tests of `kgyro run`. This file has two roles:
#  - included by tests/CMakeLists.txt, it registers the tests (the branch at the bottom);
#  - run as `cmake -P cli_run.cmake -DMODE=...`, it is the checker each test runs, since
#    a test must check the exit code, the exact stderr line and the output files at once.
# Arguments are joined with "|" (a ";" would split them on the way through add_test).

if(CMAKE_SCRIPT_MODE_FILE)
  string(REPLACE "|" ";" run_args "${ARGS}")
  execute_process(COMMAND "${KGYRO}" ${run_args}
                  WORKING_DIRECTORY "${WORKDIR}"
                  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(MODE STREQUAL "error")
    # exit code 2 and exactly one line on stderr: "kgyro COMMAND: MESSAGE" (COMMAND: run
    # unless given)
    if(NOT DEFINED COMMAND)
      set(COMMAND run)
    endif()
    if(NOT code EQUAL 2)
      message(FATAL_ERROR "exit code ${code}, expected 2; stderr: ${err}")
    endif()
    if(NOT err STREQUAL "kgyro ${COMMAND}: ${EXPECT}\n")
      message(FATAL_ERROR "stderr:\n  '${err}'\nexpected:\n  'kgyro ${COMMAND}: ${EXPECT}'")
    endif()
  elseif(MODE STREQUAL "csv")
    # exit code 0; CSV has the header and ROWS (or at least ROWS_AT_LEAST) data rows;
    # the summary names the file
    if(NOT code EQUAL 0)
      message(FATAL_ERROR "exit code ${code}: ${err}")
    endif()
    file(STRINGS "${CSV}" lines)
    list(LENGTH lines count)
    list(GET lines 0 header)
    math(EXPR rows "${count} - 1")
    if(NOT header STREQUAL "${HEADER}")
      message(FATAL_ERROR "header '${header}', expected '${HEADER}'")
    endif()
    if(DEFINED ROWS AND NOT rows EQUAL ROWS)
      message(FATAL_ERROR "${rows} rows in ${CSV}, expected ${ROWS}")
    endif()
    if(DEFINED ROWS_AT_LEAST AND rows LESS ROWS_AT_LEAST)
      message(FATAL_ERROR "${rows} rows in ${CSV}, expected at least ${ROWS_AT_LEAST}")
    endif()
    string(FIND "${out}" "${CSV}" named)
    if(named EQUAL -1)
      message(FATAL_ERROR "the summary does not say where the output went:\n${out}")
    endif()
    if(DEFINED STDERR_HAS)
      string(FIND "${err}" "${STDERR_HAS}" said)
      if(said EQUAL -1)
        message(FATAL_ERROR "stderr does not say '${STDERR_HAS}':\n${err}")
      endif()
    endif()
  elseif(MODE STREQUAL "help")
    if(NOT code EQUAL 0)
      message(FATAL_ERROR "exit code ${code}")
    endif()
    foreach(option --steps --dt --csv --every --contacts --events --backend --threads --seed --max-bodies)
      string(FIND "${out}" "${option}" found)
      if(found EQUAL -1)
        message(FATAL_ERROR "--help does not explain ${option}:\n${out}")
      endif()
    endforeach()
  elseif(MODE STREQUAL "same")
    # the same run twice gives the same bits, the second with the options AGAIN added
    # (a later option overrides an earlier one: another thread count, say)
    if(NOT code EQUAL 0)
      message(FATAL_ERROR "exit code ${code}: ${err}")
    endif()
    string(REPLACE "|" ";" again_args "${AGAIN}")
    execute_process(COMMAND "${KGYRO}" ${run_args} ${again_args} --csv "${CSV}.again"
                    WORKING_DIRECTORY "${WORKDIR}" RESULT_VARIABLE code ERROR_VARIABLE err OUTPUT_QUIET)
    execute_process(COMMAND "${CMAKE_COMMAND}" -E compare_files "${CSV}" "${CSV}.again" RESULT_VARIABLE differ)
    if(NOT code EQUAL 0 OR differ)
      message(FATAL_ERROR "second run: exit code ${code}, files differ: ${differ} ${err}")
    endif()
  else()
    message(FATAL_ERROR "unknown MODE '${MODE}'")
  endif()
  return()
endif()

if(NOT TARGET kgyro_cli)
  return()
endif()

set(kg_cli_script ${CMAKE_CURRENT_LIST_FILE})
set(kg_cli_scenes ${PROJECT_SOURCE_DIR}/tests/data/scenes)
set(kg_cli_out ${CMAKE_CURRENT_BINARY_DIR}/cli_run)
file(MAKE_DIRECTORY ${kg_cli_out})

# kg_cli_run_test(NAME MODE ARGS [VAR=VALUE...]): runs `kgyro ARGS` in the bad scenes'
# folder, so that messages name the files as the tests give them.
function(kg_cli_run_test name mode args)
  set(defines)
  foreach(define ${ARGN})
    list(APPEND defines "-D${define}")
  endforeach()
  add_test(NAME cli_run_${name}
           COMMAND ${CMAKE_COMMAND} -DMODE=${mode} -DKGYRO=$<TARGET_FILE:kgyro_cli> "-DARGS=${args}"
                   -DWORKDIR=${kg_cli_scenes} ${defines} -P ${kg_cli_script})
endfunction()

# A bad scene: exit 2, one line naming the file, the JSON path and the fault.
kg_cli_run_test(bad_radius error "run|bad_radius.json" "EXPECT=bad_radius.json: bodies[1].shape.radius: must be > 0")
kg_cli_run_test(bad_syntax error "run|bad_syntax.json"
                "EXPECT=bad_syntax.json: line 3, column 19: malformed JSON (unexpected character)")
kg_cli_run_test(bad_unknown_field error "run|bad_unknown_field.json"
                "EXPECT=bad_unknown_field.json: bodies[0].colour: unknown field")
kg_cli_run_test(bad_force_body error "run|bad_force_body.json"
                "EXPECT=bad_force_body.json: forces[0].bodies[1]: unknown body 'nobody'")
kg_cli_run_test(bad_duplicate_name error "run|bad_duplicate_name.json"
                "EXPECT=bad_duplicate_name.json: bodies[2].name: duplicate name 'box' (also bodies[1])")
kg_cli_run_test(bad_polygon error "run|bad_degenerate_polygon.json"
                "EXPECT=bad_degenerate_polygon.json: bodies[0].shape.vertices: polygon has no area (its points are collinear or coincide)")
kg_cli_run_test(bad_restitution error "run|bad_restitution.json"
                "EXPECT=bad_restitution.json: bodies[0].restitution: must be in [0, 1]")
kg_cli_run_test(bad_generator_name error "run|volcano_3"
                "EXPECT=unknown scene 'volcano_3' (generators: pyramid_B, stack_N, rain_N, particles_N, large_pyramid, many_pyramids, smash, tumbler, joint_grid, ragdoll_rain)")

# Bad options: exit 2 with a message.
kg_cli_run_test(bad_threads error "run|pyramid_3|--threads|300"
                "EXPECT=--threads: expected an integer in [1, 256] (the library's limit, KG_MAX_THREADS) (got '300')")
kg_cli_run_test(bad_steps error "run|pyramid_3|--steps|-1" "EXPECT=--steps: expected an integer >= 0 (got '-1')")
kg_cli_run_test(bad_every error "run|pyramid_3|--every=0" "EXPECT=--every: expected an integer >= 1 (got '0')")
kg_cli_run_test(bad_backend error "run|pyramid_3|--backend|cuda"
                "EXPECT=--backend: expected auto, cpu or opencl (got 'cuda')")
kg_cli_run_test(bad_dt error "run|pyramid_3|--dt|fast" "EXPECT=--dt: expected a number of seconds > 0 (got 'fast')")
kg_cli_run_test(bad_option error "run|pyramid_3|--colour|red"
                "EXPECT=unknown option '--colour' (see kgyro run --help)")
kg_cli_run_test(missing_value error "run|pyramid_3|--csv" "EXPECT=--csv needs a value (see kgyro run --help)")

kg_cli_run_test(help help "run|--help")

# pyramid_5: 1 ground + 15 boxes; steps 0, 4, 8 and the last, 10: 4 x 16 rows.
kg_cli_run_test(csv_generator csv "run|pyramid_5|--steps|10|--every|4|--backend|cpu|--csv|${kg_cli_out}/pyramid_5.csv"
                "CSV=${kg_cli_out}/pyramid_5.csv" "HEADER=step,id,name,x,y,angle,vx,vy,omega" ROWS=64)
# a scene file, with contacts: the stack rests on the ground, so every written step has some
kg_cli_run_test(csv_contacts csv
                "run|${PROJECT_SOURCE_DIR}/samples/box_stack.json|--steps|3|--contacts|${kg_cli_out}/stack_contacts.csv|--csv|${kg_cli_out}/stack.csv"
                "CSV=${kg_cli_out}/stack_contacts.csv" "HEADER=step,a,b,nx,ny,px,py,depth" ROWS_AT_LEAST=1)
# events: box_stack's bodies begin touching in the first steps (begin rows, named)
kg_cli_run_test(csv_events csv
                "run|${PROJECT_SOURCE_DIR}/samples/box_stack.json|--steps|30|--events|${kg_cli_out}/stack_events.csv|--csv|${kg_cli_out}/stack_e.csv"
                "CSV=${kg_cli_out}/stack_events.csv" "HEADER=step,kind,a,b,x,y,nx,ny,speed" ROWS_AT_LEAST=5)
# a ball through a sensor band onto the floor: sensor_begin, sensor_end, begin and hit
kg_cli_run_test(csv_sensor_events csv
                "run|${PROJECT_SOURCE_DIR}/tests/data/sensor_band.json|--steps|120|--events|${kg_cli_out}/band_events.csv|--csv|${kg_cli_out}/band.csv"
                "CSV=${kg_cli_out}/band_events.csv" "HEADER=step,kind,a,b,x,y,nx,ny,speed" ROWS=4)
kg_cli_run_test(csv_file csv "run|good_full.json|--steps=5|--every=5|--csv=${kg_cli_out}/full.csv"
                "CSV=${kg_cli_out}/full.csv" "HEADER=step,id,name,x,y,angle,vx,vy,omega" ROWS=12)
kg_cli_run_test(deterministic same "run|rain_50|--steps|30|--backend|cpu|--csv|${kg_cli_out}/rain_50.csv"
                "CSV=${kg_cli_out}/rain_50.csv")
# issue 4: the same scene with 1 and with 4 threads, every body every step: the same CSV
kg_cli_run_test(threads_same_csv same
                "run|rain_1000|--steps|240|--every|1|--backend|cpu|--threads|1|--csv|${kg_cli_out}/rain_1000.csv"
                "CSV=${kg_cli_out}/rain_1000.csv" "AGAIN=--threads|4")

# issue 18: what the loader ignored of a Tiled level (an image layer, text objects) is
# said on stderr, and the level runs
kg_cli_run_test(tiled_notes csv "run|../tiled/everything.tmj|--steps|1|--csv|${kg_cli_out}/everything.csv"
                "CSV=${kg_cli_out}/everything.csv" "HEADER=step,id,name,x,y,angle,vx,vy,omega" ROWS_AT_LEAST=2
                "STDERR_HAS=kgyro: note: ../tiled/everything.tmj: layers[3]: an image layer is ignored (pictures only)")

# issue 18: an 80-byte scene asking a generator for a million bodies is refused under
# --max-bodies before they are allocated, naming the field
kg_cli_run_test(max_bodies error "run|hostile_million_bodies.json|--max-bodies|1000"
                "EXPECT=hostile_million_bodies.json: generators[0].count: asks for 1000000 bodies, but max_bodies (1000) leaves room for 1000")
kg_cli_run_test(render_max_bodies error "render|hostile_million_bodies.json|--max-bodies|1000|--png|${kg_cli_out}/never.png"
                "EXPECT=hostile_million_bodies.json: generators[0].count: asks for 1000000 bodies, but max_bodies (1000) leaves room for 1000"
                COMMAND=render)
# ... and a generator's name asking for more (rain_N before any body is made)
kg_cli_run_test(max_bodies_generator error "run|rain_1000000|--max-bodies|1000"
                "EXPECT=scene 'rain_1000000': more than max_bodies (1000) bodies")
kg_cli_run_test(max_bodies_benchmark error "run|large_pyramid|--max-bodies|1000"
                "EXPECT=scene 'large_pyramid': more than max_bodies (1000) bodies")
kg_cli_run_test(bad_max_bodies error "run|pyramid_3|--max-bodies|-5" "EXPECT=--max-bodies: expected an integer >= 0 (got '-5')")
