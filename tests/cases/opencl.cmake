# The OpenCL backend's tests (tests/test_opencl_*.c; test_snapshot has an OpenCL part):
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
foreach(kg_cl_test test_opencl_backend test_opencl_compare test_opencl_fallback test_opencl_draw test_snapshot)
  if(TEST ${kg_cl_test})
    set_tests_properties(${kg_cl_test} PROPERTIES
      SKIP_RETURN_CODE 77
      LABELS opencl
      TIMEOUT 600
      ENVIRONMENT "KGYRO_BACKEND=;KGYRO_CL_FAIL=;LSAN_OPTIONS=suppressions=${kg_cl_lsan_suppressions}")
  endif()
endforeach()
