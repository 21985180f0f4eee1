# Installing and consuming kgyro. This file has two roles:
#  - included by tests/CMakeLists.txt, it builds and runs the README's API example
#    (tests/readme_example.c, as strict C99) and registers install_consumers;
#  - run as `cmake -P install.cmake`, it is install_consumers: it installs the build
#    into a fresh prefix, then builds and runs the README example (C) and a C++ program
#    (tests/install/) against it three ways: the CMake package, pkg-config, and the
#    source tree through add_subdirectory.
set(KG_README_OUTPUT "after 1 s the box is at \\(0\\.00, 4\\.9[0-9]\\)")

if(NOT CMAKE_SCRIPT_MODE_FILE)
  add_executable(readme_example ${CMAKE_CURRENT_SOURCE_DIR}/readme_example.c)
  set_target_properties(readme_example PROPERTIES C_STANDARD 99 C_STANDARD_REQUIRED ON C_EXTENSIONS OFF)
  target_compile_options(readme_example PRIVATE ${KG_C_FLAGS} -pedantic)
  target_link_libraries(readme_example PRIVATE kgyro)
  add_test(NAME readme_example COMMAND readme_example)
  set_tests_properties(readme_example PROPERTIES PASS_REGULAR_EXPRESSION "${KG_README_OUTPUT}")

  # Sanitized libraries would need the sanitizer runtime in every consumer.
  if(NOT KGYRO_SANITIZE AND (NOT DEFINED KGYRO_INSTALL OR KGYRO_INSTALL))
    add_test(NAME install_consumers
      COMMAND ${CMAKE_COMMAND} -DBUILD=${PROJECT_BINARY_DIR} -DSOURCE=${PROJECT_SOURCE_DIR}
              -DWORK=${CMAKE_CURRENT_BINARY_DIR}/install_consumers -DCC=${CMAKE_C_COMPILER}
              -P ${CMAKE_CURRENT_LIST_FILE})
    set_tests_properties(install_consumers PROPERTIES TIMEOUT 600 LABELS "slow;install")
  endif()
  return()
endif()

# Runs a command; stops with its output when it fails, or when its output does not
# match the regular expression after EXPECT.
function(kg_step what)
  cmake_parse_arguments(PARSE_ARGV 1 step "" "EXPECT" "COMMAND")
  execute_process(COMMAND ${step_COMMAND} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "${what}: exit code ${code}\n${out}\n${err}")
  endif()
  if(step_EXPECT AND NOT out MATCHES "${step_EXPECT}")
    message(FATAL_ERROR "${what}: output does not match '${step_EXPECT}':\n${out}")
  endif()
  string(STRIP "${out}" out)
  string(REGEX REPLACE ".*\n" "" last_line "${out}")
  message(STATUS "${what}: ok ${last_line}")
endfunction()

set(prefix ${WORK}/prefix)
file(REMOVE_RECURSE ${WORK})
kg_step("install" COMMAND ${CMAKE_COMMAND} --install ${BUILD} --prefix ${prefix})

file(GLOB_RECURSE pc_file ${prefix}/*/kgyro.pc)
file(GLOB_RECURSE soname ${prefix}/*/libkgyro.so.0)
file(GLOB_RECURSE static_lib ${prefix}/*/libkgyro.a)
if(NOT pc_file OR NOT soname OR NOT static_lib OR NOT EXISTS ${prefix}/include/kgyro/kgyro.h)
  message(FATAL_ERROR "the prefix lacks kgyro.pc, libkgyro.so.0, libkgyro.a or the headers")
endif()
get_filename_component(pc_dir ${pc_file} DIRECTORY)
get_filename_component(lib_dir ${soname} DIRECTORY)

# Every installed public header, alone and all together, compiles as C99 and as C++11
# with every warning on and none given.
find_program(CXX NAMES c++ g++ clang++ REQUIRED)
file(GLOB headers RELATIVE ${prefix}/include ${prefix}/include/kgyro/*.h)
set(all_headers "")
foreach(header ${headers})
  string(APPEND all_headers "#include <${header}>\n")
endforeach()
file(WRITE ${WORK}/headers/all.c "${all_headers}int kg_headers_compile;\n")
file(WRITE ${WORK}/headers/all.cpp "${all_headers}int kg_headers_compile;\n")
kg_step("headers as C99" COMMAND ${CC} -std=c99 -Wall -Wextra -pedantic -Werror -fsyntax-only
        -I${prefix}/include ${WORK}/headers/all.c)
kg_step("headers as C++11" COMMAND ${CXX} -std=c++11 -Wall -Wextra -pedantic -Werror -fsyntax-only
        -I${prefix}/include ${WORK}/headers/all.cpp)
foreach(header ${headers})
  get_filename_component(name ${header} NAME_WE)
  file(WRITE ${WORK}/headers/${name}.c "#include <${header}>\nint kg_header_compiles;\n")
  kg_step("${header} alone" COMMAND ${CC} -std=c99 -Wall -Wextra -pedantic -Werror -fsyntax-only
          -I${prefix}/include ${WORK}/headers/${name}.c)
endforeach()

# 1. find_package(kgyro): the README example on the static library, the C++ program on
#    the shared one, and a scene through kgyro::io.
set(fp ${WORK}/find_package)
kg_step("find_package: configure" COMMAND ${CMAKE_COMMAND} -S ${SOURCE}/tests/install/find_package -B ${fp}
        -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_C_COMPILER=${CC} -DCMAKE_BUILD_TYPE=Release)
kg_step("find_package: build" COMMAND ${CMAKE_COMMAND} --build ${fp})
kg_step("find_package: C" COMMAND ${fp}/readme_c EXPECT "${KG_README_OUTPUT}")
kg_step("find_package: C++" COMMAND ${fp}/consumer_cpp)
kg_step("find_package: kgyro::io" COMMAND ${fp}/consumer_scene)

# 2. pkg-config, as a Makefile would use it: cc app.c $(pkg-config --cflags --libs kgyro)
find_program(PKG_CONFIG pkg-config REQUIRED)
set(ENV{PKG_CONFIG_PATH} ${pc_dir})
execute_process(COMMAND ${PKG_CONFIG} --cflags --libs kgyro OUTPUT_VARIABLE pc_flags RESULT_VARIABLE code
                OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "pkg-config does not know kgyro (PKG_CONFIG_PATH=${pc_dir})")
endif()
separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
set(pc ${WORK}/pkg_config)
file(MAKE_DIRECTORY ${pc})
kg_step("pkg-config: build C" COMMAND ${CC} -std=c99 -Wall -Wextra -pedantic -Werror
        ${SOURCE}/tests/readme_example.c ${pc_flags} -Wl,-rpath,${lib_dir} -o ${pc}/readme_c)
kg_step("pkg-config: build C++" COMMAND ${CXX} -std=c++11 -Wall -Wextra -pedantic -Werror
        ${SOURCE}/tests/install/consumer.cpp ${pc_flags} -Wl,-rpath,${lib_dir} -o ${pc}/consumer_cpp)
kg_step("pkg-config: C" COMMAND ${pc}/readme_c EXPECT "${KG_README_OUTPUT}")
kg_step("pkg-config: C++" COMMAND ${pc}/consumer_cpp)

# 3. add_subdirectory of the source tree, as a project vendoring kgyro does.
set(sub ${WORK}/subdirectory)
kg_step("add_subdirectory: configure" COMMAND ${CMAKE_COMMAND} -S ${SOURCE}/tests/install/subdirectory -B ${sub}
        -DKGYRO_SOURCE_DIR=${SOURCE} -DCMAKE_C_COMPILER=${CC} -DCMAKE_BUILD_TYPE=Release)
kg_step("add_subdirectory: build" COMMAND ${CMAKE_COMMAND} --build ${sub} -j2)
kg_step("add_subdirectory: C" COMMAND ${sub}/readme_c EXPECT "${KG_README_OUTPUT}")
kg_step("add_subdirectory: C++" COMMAND ${sub}/consumer_cpp)
