# test_progress checks the progress line of the tools (tools/progress.c), which is not
# in any library: it is compiled into the test itself.
if(TARGET test_progress)
  target_sources(test_progress PRIVATE ${PROJECT_SOURCE_DIR}/tools/progress.c)
  target_include_directories(test_progress PRIVATE ${PROJECT_SOURCE_DIR}/tools)
endif()
