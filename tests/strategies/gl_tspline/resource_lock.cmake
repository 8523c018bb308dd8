# Read by ctest after gtest_discover_tests' own include file has defined gl_tspline_test_TESTS:
# the GL tests own the (software) GPU and run one at a time.
if(gl_tspline_test_TESTS)
  set_tests_properties(${gl_tspline_test_TESTS} PROPERTIES RESOURCE_LOCK gpu)
endif()
