# Read by ctest after gtest_discover_tests' include file has defined cl_tspline_bezier_test_TESTS.
if(cl_tspline_bezier_test_TESTS)
  set_tests_properties(${cl_tspline_bezier_test_TESTS} PROPERTIES RESOURCE_LOCK gpu)
endif()
