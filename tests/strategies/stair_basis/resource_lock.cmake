# Read by ctest after gtest_discover_tests' include file has defined stair_basis_test_TESTS.
if(stair_basis_test_TESTS)
  set_tests_properties(${stair_basis_test_TESTS} PROPERTIES RESOURCE_LOCK gpu)
endif()
