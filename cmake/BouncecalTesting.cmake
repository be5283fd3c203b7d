# One helper registers every GoogleTest executable, unit tests beside the code and cross-module
# tests alike, so they all get the same flags, the shared-data path and CTest discovery.
#
#   bouncecal_add_tests(NAME audio_tests SOURCES src/a_test.cc ... LIBRARIES bouncecal::audio)
if(BOUNCECAL_BUILD_TESTS)
  enable_testing()
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()

function(bouncecal_add_tests)
  if(NOT BOUNCECAL_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;LIBRARIES" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LIBRARIES} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${ARG_NAME} PRIVATE
    BOUNCECAL_SHARED_DIR="${BOUNCECAL_SHARED_DIR}"
    BOUNCECAL_SOURCE_DIR="${CMAKE_SOURCE_DIR}"
    BOUNCECAL_BINARY_DIR="${CMAKE_BINARY_DIR}")
  gtest_discover_tests(${ARG_NAME} DISCOVERY_MODE PRE_TEST DISCOVERY_TIMEOUT 60
    PROPERTIES TIMEOUT 600)
endfunction()
