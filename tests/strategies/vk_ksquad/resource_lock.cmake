# Read by ctest after gtest_discover_tests' include file has defined vk_ksquad_test_TESTS.
if(vk_ksquad_test_TESTS)
  set_tests_properties(${vk_ksquad_test_TESTS} PROPERTIES RESOURCE_LOCK gpu)
endif()
