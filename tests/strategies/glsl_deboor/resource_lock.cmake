# Read by ctest after gtest_discover_tests' own include file has defined glsl_deboor_gl_test_TESTS:
# the GL tests own the (software) GPU and run one at a time.
if(glsl_deboor_gl_test_TESTS)
  set_tests_properties(${glsl_deboor_gl_test_TESTS} PROPERTIES RESOURCE_LOCK gpu)
endif()
