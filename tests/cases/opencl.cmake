# The OpenCL backend's tests (tests/test_opencl_*.c): they exit 77 with a message when no
# OpenCL device exists, which ctest reports as skipped. In CI, PoCL (installed by
# scripts/install-deps.sh) is the device. KGYRO_BACKEND and KGYRO_CL_FAIL are cleared so
# each test chooses its backends and faults itself. Under AddressSanitizer they need no
# suppression: what PoCL keeps for the process stays reachable, so LeakSanitizer is quiet.
foreach(kg_cl_test test_opencl_backend test_opencl_compare test_opencl_fallback)
  if(TEST ${kg_cl_test})
    set_tests_properties(${kg_cl_test} PROPERTIES
      SKIP_RETURN_CODE 77
      LABELS opencl
      TIMEOUT 600
      ENVIRONMENT "KGYRO_BACKEND=;KGYRO_CL_FAIL=")
  endif()
endforeach()
