# Read by ctest after gtest_discover_tests' include file has defined cl_stair_test_TESTS.
if(cl_stair_test_TESTS)
  set_tests_properties(${cl_stair_test_TESTS} PROPERTIES RESOURCE_LOCK gpu)
endif()
