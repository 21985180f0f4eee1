# `kgyro run --save`: a world saved as a scene continues bitwise (docs/scene-format.md,
# "Saved worlds"). Like cli_run.cmake, this file registers the tests when included by
# tests/CMakeLists.txt and is their checker when run with `cmake -P`:
#  - continues: `run SCENE --steps A --save F` then `run F --steps B` gives, byte for
#    byte, every body's row (id, name, x, y, angle, vx, vy, omega) of `run SCENE --steps A+B`;
#  - idempotent: `run F --steps 0 --save G` writes G identical to F (save, load, save).
# The scene is samples/demo_platformer.json: a Tiled tile map (slopes, one-way
# platforms), boxes and balls raining on it, particles, winds, sleeping on.

if(CMAKE_SCRIPT_MODE_FILE)
  function(kg_run)
    execute_process(COMMAND "${KGYRO}" run ${ARGN} --every 100000 --backend ${BACKEND}
                    WORKING_DIRECTORY "${WORKDIR}" RESULT_VARIABLE code OUTPUT_QUIET ERROR_VARIABLE err)
    if(NOT code EQUAL 0)
      message(FATAL_ERROR "kgyro run ${ARGN}: exit code ${code}: ${err}")
    endif()
  endfunction()
  # The rows of the last step written to csv, without the step column (the names, kept
  # by --save, are compared too).
  function(kg_last_states csv step out)
    file(STRINGS "${csv}" lines REGEX "^${step},")
    set(states "")
    foreach(line ${lines})
      string(REGEX REPLACE "^[0-9]+,(.*)$" "\\1" row "${line}")
      list(APPEND states "${row}")
    endforeach()
    set(${out} "${states}" PARENT_SCOPE)
  endfunction()
  set(dir "${WORKDIR}/cli_save_${BACKEND}")
  file(MAKE_DIRECTORY "${dir}")
  math(EXPR total "${FIRST} + ${SECOND}")
  if(MODE STREQUAL "continues")
    kg_run("${SCENE}" --steps ${total} --csv "${dir}/whole.csv")
    kg_run("${SCENE}" --steps ${FIRST} --csv "${dir}/first.csv" --save "${dir}/saved.json")
    kg_run("${dir}/saved.json" --steps ${SECOND} --csv "${dir}/second.csv")
    kg_last_states("${dir}/whole.csv" ${total} whole)
    kg_last_states("${dir}/second.csv" ${SECOND} continued)
    list(LENGTH whole count)
    if(count EQUAL 0 OR NOT whole STREQUAL continued)
      message(FATAL_ERROR "the saved world, run on, differs from the whole run (${count} bodies): see ${dir}")
    endif()
  elseif(MODE STREQUAL "idempotent")
    kg_run("${SCENE}" --steps ${FIRST} --csv "${dir}/first.csv" --save "${dir}/once.json")
    kg_run("${dir}/once.json" --steps 0 --csv "${dir}/none.csv" --save "${dir}/twice.json")
    file(READ "${dir}/once.json" once)
    file(READ "${dir}/twice.json" twice)
    if(NOT once STREQUAL twice)
      message(FATAL_ERROR "saving a loaded saved world gives another file: ${dir}/once.json, twice.json")
    endif()
  endif()
  return()
endif()

if(NOT TARGET kgyro_cli)
  return()
endif()

set(KG_SAVE_SCENE ${PROJECT_SOURCE_DIR}/samples/demo_platformer.json)
foreach(mode continues idempotent)
  add_test(NAME cli_save_${mode}
           COMMAND ${CMAKE_COMMAND} -DMODE=${mode} -DKGYRO=$<TARGET_FILE:kgyro_cli> -DBACKEND=cpu
                   -DSCENE=${KG_SAVE_SCENE} -DFIRST=200 -DSECOND=100 -DWORKDIR=${CMAKE_CURRENT_BINARY_DIR}
                   -P ${CMAKE_CURRENT_LIST_FILE})
endforeach()
