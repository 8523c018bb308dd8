# Read by ctest after gtest_discover_tests' include file has defined vk_compute_test_TESTS.
if(vk_compute_test_TESTS)
  set_tests_properties(${vk_compute_test_TESTS} PROPERTIES RESOURCE_LOCK gpu)
endif()
