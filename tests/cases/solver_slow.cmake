# The contact solver's long acceptance tests (issue 4). test_stacking and test_determinism
# run their quick set as plain ctest entries (the sanitizer pass runs those too); the long
# runs are registered here, one ctest entry per test so that each stays under a minute in
# a release build, and labelled slow so that `make test`'s sanitizer pass (ctest -LE slow)
# skips them. The release pass runs them all.
set(kg_solver_slow_tests
  "test_stacking_stack_20_for_60_s|test_stacking|test_stack_of_20_stands_60_s"
  "test_stacking_pyramid_20_for_60_s|test_stacking|test_pyramid_20_stands_60_s"
  "test_stacking_pyramid_100_from_2_5_to_8_3_s|test_stacking|test_pyramid_100_holds_from_2_5_to_8_3_s"
  "test_stacking_pile_of_1000_comes_to_rest|test_stacking|test_pile_of_1000_comes_to_rest"
  "test_stacking_rain_of_100000_stays_bounded|test_stacking|test_rain_of_100000_stays_bounded"
  "test_determinism_pyramid_40|test_determinism|test_pyramid_40_hit_by_ball_same_bits_with_1_to_4_threads"
  "test_determinism_pile_of_1000|test_determinism|test_pile_of_1000_same_bits_with_1_to_4_threads")
foreach(kg_entry ${kg_solver_slow_tests})
  string(REPLACE "|" ";" kg_fields "${kg_entry}")
  list(GET kg_fields 0 kg_name)
  list(GET kg_fields 1 kg_target)
  list(GET kg_fields 2 kg_case)
  if(TARGET ${kg_target})
    add_test(NAME ${kg_name} COMMAND ${kg_target} ${kg_case} WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR})
    set_tests_properties(${kg_name} PROPERTIES LABELS "slow;solver" TIMEOUT 300)
  endif()
endforeach()
foreach(kg_quick test_solver test_stacking test_determinism)
  if(TEST ${kg_quick})
    set_tests_properties(${kg_quick} PROPERTIES LABELS solver)
  endif()
endforeach()
