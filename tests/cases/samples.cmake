# The samples that are programs (samples/*.c): each runs to its own check, from the source
# root (they load the levels in samples/).
if(TARGET platformer_player)
  add_test(NAME sample_platformer_player COMMAND platformer_player samples/platformer.tmj
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(sample_platformer_player PROPERTIES PASS_REGULAR_EXPRESSION "reached the goal")
endif()
