# One helper registers every GoogleTest executable, unit tests beside the code and cross-module
# tests alike, so they all get the same flags, the shared-data path, the test-support library
# (tests/support: a scratch folder per test and process, whole-file reads) and CTest discovery.
#
#   bouncecal_add_tests(NAME audio_tests SOURCES src/a_test.cc ... LIBRARIES bouncecal::audio
#                       [TIER integration] LONG_TESTS Suite.Name ... EXTERNAL_TESTS Suite.Name ...)
#
# The executable's other tests get the label of its TIER: `unit` (the default: one module's code
# called in-process; the whole tier runs in well under a minute) or `integration` (tests/: round
# trips across modules, the `bouncecal` command started once or more per test, bad input; and
# pytest on the Python module).
#
# LONG_TESTS (gtest names, wildcards allowed) get the CTest label `long`: tests that are slow
# because they simulate long (paper reproductions, full packings, calibration fits, sweeps). The
# Release stage runs them like every other test; the sanitized stage skips them (`ctest -LE long`,
# scripts/run_sanitized_tests.sh) because its job is to run the code paths under ASan+UBSan, and
# each module names, beside its list, the shorter test that drives every path of each long one.
# They are also given a high COST so that `ctest -j` starts them first instead of leaving one of
# them running alone at the end. Statistical tests that repeat a short path over hundreds of
# seeds (coverage, false-alarm rates) are long in this sense too.
#
# EXTERNAL_TESTS get the label `external`: tests whose subject is another program run on our
# output (LAMMPS and LIGGGHTS on an exported deck, headless Chromium on the HTML report). They run
# in the Release stage; the sanitized stage skips them, as the time goes to the other program,
# and the deck or page they read is written by shorter tests that do run there (ExportCli.*,
# ReportCli.Page*).
#
# Tiers (CONTRIBUTING.md): `ctest -L unit` after every change, `ctest -LE 'long|external'` (unit and
# integration) before a commit.
if(BOUNCECAL_BUILD_TESTS)
  enable_testing()
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()

function(bouncecal_add_tests)
  if(NOT BOUNCECAL_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "NAME;TIER" "SOURCES;LIBRARIES;LONG_TESTS;EXTERNAL_TESTS" ${ARGN})
  if(NOT ARG_TIER)
    set(ARG_TIER unit)
  elseif(NOT ARG_TIER MATCHES "^(unit|integration)$")
    message(FATAL_ERROR "bouncecal_add_tests(${ARG_NAME}): TIER is unit or integration, not "
      "'${ARG_TIER}' (long and external tests are named in LONG_TESTS / EXTERNAL_TESTS)")
  endif()
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LIBRARIES} bouncecal::test_support GTest::gtest
    GTest::gtest_main)
  # Compile time, which CI pays twice (Release and sanitized) on 2 cores: the test files hold
  # little hot code (the work is in the libraries, still -O3), so -O1 here (the same rounding:
  # no -ffast-math, and the x86-64 baseline has no FMA to contract into, so an inline function a
  # test file and a library both instantiate gives the same bits from either copy); GoogleTest's,
  # nlohmann-json's and the commonest standard headers are parsed once per executable. Test files
  # of a Release build: 716 -> 447 CPU s (377 + 70 for the ten precompiled headers); sanitized
  # (-O0): 702 -> 586; the Release ctest time unchanged (2026-12-06, GCC 12, 2 cores).
  target_compile_options(${ARG_NAME} PRIVATE $<$<CONFIG:Release>:-O1>)
  target_precompile_headers(${ARG_NAME} PRIVATE
    <gtest/gtest.h> <nlohmann/json.hpp> <algorithm> <cmath> <filesystem> <fstream> <limits>
    <numbers> <random> <sstream> <string> <vector>)
  target_compile_definitions(${ARG_NAME} PRIVATE
    BOUNCECAL_SHARED_DIR="${BOUNCECAL_SHARED_DIR}"
    BOUNCECAL_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    BOUNCECAL_BINARY_DIR="${PROJECT_BINARY_DIR}")
  # One discovery per tier of the executable: gtest's filter splits its tests into the ordinary
  # ones and each labelled tier, so every test is registered exactly once.
  set(labelled ${ARG_LONG_TESTS} ${ARG_EXTERNAL_TESTS})
  set(ordinary_filter "")
  if(labelled)
    list(JOIN labelled ":" labelled_filter)
    set(ordinary_filter TEST_FILTER "-${labelled_filter}")
  endif()
  gtest_discover_tests(${ARG_NAME} DISCOVERY_MODE PRE_TEST DISCOVERY_TIMEOUT 60
    ${ordinary_filter}
    PROPERTIES TIMEOUT 600 LABELS ${ARG_TIER})
  # Long tests start first under `ctest -j` (highest COST) rather than run alone at the end.
  set(cost_long 1000)
  set(cost_external 100)
  foreach(tier IN ITEMS long external)
    string(TOUPPER "${tier}" tier_upper)
    if(ARG_${tier_upper}_TESTS)
      list(JOIN ARG_${tier_upper}_TESTS ":" tier_filter)
      gtest_discover_tests(${ARG_NAME} DISCOVERY_MODE PRE_TEST DISCOVERY_TIMEOUT 60
        TEST_FILTER "${tier_filter}"
        PROPERTIES TIMEOUT 600 LABELS ${tier} COST ${cost_${tier}})
    endif()
  endforeach()
endfunction()
