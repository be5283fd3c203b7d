# One helper registers every GoogleTest executable, unit tests beside the code and cross-module
# tests alike, so they all get the same flags, the shared-data path and CTest discovery.
#
#   bouncecal_add_tests(NAME audio_tests SOURCES src/a_test.cc ... LIBRARIES bouncecal::audio
#                       LONG_TESTS Suite.Name ...)
#
# LONG_TESTS (gtest names, wildcards allowed) get the CTest label `long`: tests that are slow
# because they simulate long (paper reproductions, full packings, calibration fits, sweeps). The
# Release stage runs them like every other test; the sanitized stage skips them (`ctest -LE long`,
# scripts/run_sanitized_tests.sh) because its job is to run the code paths under ASan+UBSan, and
# each module names, beside its list, the shorter test that drives every path of each long one.
# They are also given a high COST so that `ctest -j` starts them first instead of leaving one of
# them running alone at the end.
if(BOUNCECAL_BUILD_TESTS)
  enable_testing()
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()

function(bouncecal_add_tests)
  if(NOT BOUNCECAL_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;LIBRARIES;LONG_TESTS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LIBRARIES} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${ARG_NAME} PRIVATE
    BOUNCECAL_SHARED_DIR="${BOUNCECAL_SHARED_DIR}"
    BOUNCECAL_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    BOUNCECAL_BINARY_DIR="${PROJECT_BINARY_DIR}")
  if(NOT ARG_LONG_TESTS)
    gtest_discover_tests(${ARG_NAME} DISCOVERY_MODE PRE_TEST DISCOVERY_TIMEOUT 60
      PROPERTIES TIMEOUT 600)
    return()
  endif()
  # Two discoveries of one executable: gtest's filter splits its tests into the ordinary ones
  # and the long ones, so every test is registered exactly once.
  list(JOIN ARG_LONG_TESTS ":" long_filter)
  gtest_discover_tests(${ARG_NAME} DISCOVERY_MODE PRE_TEST DISCOVERY_TIMEOUT 60
    TEST_FILTER "-${long_filter}"
    PROPERTIES TIMEOUT 600)
  gtest_discover_tests(${ARG_NAME} DISCOVERY_MODE PRE_TEST DISCOVERY_TIMEOUT 60
    TEST_FILTER "${long_filter}"
    PROPERTIES TIMEOUT 600 LABELS long COST 1000)
endfunction()
