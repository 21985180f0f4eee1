# The OpenCL backend's tests (tests/test_opencl_*.c; test_snapshot, test_joints and
# test_joint_samples have an OpenCL part):
# they exit 77 with a message when no OpenCL device exists, which ctest reports as
# skipped. In CI, PoCL (installed by
# scripts/install-deps.sh) is the device. KGYRO_BACKEND and KGYRO_CL_FAIL are cleared so
# each test chooses its backends and faults itself. Under AddressSanitizer, what PoCL
# keeps for the process stays reachable, but compiling a program that is not in PoCL's
# kernel cache yet (the first run after a kernel changes, every run in a fresh CI
# machine) leaks a few objects inside PoCL and LLVM: LeakSanitizer is told to ignore
# leaks allocated there, and only there.
set(kg_cl_lsan_suppressions ${CMAKE_CURRENT_BINARY_DIR}/opencl_lsan.supp)
file(WRITE ${kg_cl_lsan_suppressions} "leak:libpocl.so\nleak:libLLVM\n")
foreach(kg_cl_test test_opencl_backend test_opencl_compare test_opencl_fallback test_opencl_draw test_snapshot
                   test_joints test_joint_samples)
  if(TEST ${kg_cl_test})
    set_tests_properties(${kg_cl_test} PROPERTIES
      SKIP_RETURN_CODE 77
      LABELS opencl
      TIMEOUT 600
      ENVIRONMENT "KGYRO_BACKEND=;KGYRO_CL_FAIL=;LSAN_OPTIONS=suppressions=${kg_cl_lsan_suppressions}")
  endif()
endforeach()
# The joint samples' 60 s runs (issue 17's acceptance, four scenes on three
# configurations) are long: the release pass runs them, the sanitizer pass skips them as
# it skips the solver's (solver_slow.cmake); test_joints keeps the joints under it.
if(TEST test_joint_samples)
  set_tests_properties(test_joint_samples PROPERTIES LABELS "opencl;slow")
endif()
