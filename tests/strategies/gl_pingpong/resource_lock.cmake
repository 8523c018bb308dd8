# Read by ctest after gtest_discover_tests' own include files have defined gl_pingpong_test_TESTS
# and gl_pingpong_lod_test_TESTS: the GL tests own the (software) GPU and run one at a time.
foreach(tests IN ITEMS gl_pingpong_test_TESTS gl_pingpong_lod_test_TESTS)
  if(${tests})
    set_tests_properties(${${tests}} PROPERTIES RESOURCE_LOCK gpu)
  endif()
endforeach()
