# Read by ctest after gtest_discover_tests' include files have defined isolation_gpu_test_TESTS
# and camera_path_test_TESTS: tests that own the (software) GPU run one at a time.
foreach(tests IN ITEMS isolation_gpu_test_TESTS camera_path_test_TESTS)
  if(${tests})
    set_tests_properties(${${tests}} PROPERTIES RESOURCE_LOCK gpu)
  endif()
endforeach()
