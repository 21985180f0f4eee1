# Installing KineticGyro (included at the end of the top-level CMakeLists.txt):
#   include/kgyro/*.h, libkgyro.a, libkgyro.so.VERSION (soname libkgyro.so.MAJOR),
#   libkgyro_io.a (scenes, needs cJSON and zlib), the kgyro command, the CMake package
#   (find_package(kgyro) gives kgyro::kgyro, kgyro::kgyro_shared and kgyro::io) and the
#   pkg-config file kgyro.pc. The package and kgyro.pc are relocatable: they find the
#   prefix from where they were installed, so `cmake --install BUILD --prefix DIR` works.
# Projects that vendor the source with add_subdirectory get the same target names; their
# build installs nothing of kgyro unless they set KGYRO_INSTALL.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

if(CMAKE_SOURCE_DIR STREQUAL PROJECT_SOURCE_DIR)
  set(KG_INSTALL_DEFAULT ON)
else()
  set(KG_INSTALL_DEFAULT OFF)
endif()
option(KGYRO_INSTALL "Generate kgyro's install rules" ${KG_INSTALL_DEFAULT})

add_library(kgyro::kgyro_shared ALIAS kgyro_shared)
set_target_properties(kgyro_shared PROPERTIES EXPORT_NAME kgyro_shared)
set(KG_EXPORTED kgyro kgyro_shared)
set(KG_CONFIG_WITH_IO OFF)
if(TARGET kgyro_io)
  set_target_properties(kgyro_io PROPERTIES EXPORT_NAME io)
  list(APPEND KG_EXPORTED kgyro_io)
  set(KG_CONFIG_WITH_IO ON)
endif()

if(NOT KGYRO_INSTALL)
  return()
endif()

set(KG_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/kgyro)
install(TARGETS ${KG_EXPORTED} EXPORT kgyroTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/kgyro DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  FILES_MATCHING PATTERN "*.h")
if(TARGET kgyro_cli)
  install(TARGETS kgyro_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

install(EXPORT kgyroTargets NAMESPACE kgyro:: DESTINATION ${KG_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/kgyroConfig.cmake.in
  ${PROJECT_BINARY_DIR}/kgyroConfig.cmake INSTALL_DESTINATION ${KG_CMAKE_DIR})
# Before 1.0 a minor version may change the API, so only the same minor version matches.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/kgyroConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/kgyroConfig.cmake ${PROJECT_BINARY_DIR}/kgyroConfigVersion.cmake
  DESTINATION ${KG_CMAKE_DIR})

# kgyro.pc finds the prefix from its own place (${pcfiledir}), as pkg-config allows.
file(RELATIVE_PATH KG_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
string(REGEX REPLACE "/$" "" KG_PC_TO_PREFIX "${KG_PC_TO_PREFIX}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/kgyro.pc.in ${PROJECT_BINARY_DIR}/kgyro.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/kgyro.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
