# Read by ctest after gtest_discover_tests' include file has defined isolation_gpu_test_TESTS.
if(isolation_gpu_test_TESTS)
  set_tests_properties(${isolation_gpu_test_TESTS} PROPERTIES RESOURCE_LOCK gpu)
endif()
