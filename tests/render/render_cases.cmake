# SPDX-License-Identifier: Apache-2.0
# Included by CTest each time it runs (TEST_INCLUDE_FILES of tests/render): one test per
# directory of tests/render/cases, named as render_case_tests names it, label gpu. The
# NAVMAP_CASE_* variables come from the build (tests/render/CMakeLists.txt).
if(NOT EXISTS "${NAVMAP_CASE_RUNNER}")
  add_test(render_case_tests_NOT_BUILT render_case_tests_NOT_BUILT)
  return()
endif()
file(GLOB navmap_case_dirs LIST_DIRECTORIES true "${NAVMAP_CASES_DIR}/*")
list(SORT navmap_case_dirs)
foreach(navmap_case_dir IN LISTS navmap_case_dirs)
  if(NOT IS_DIRECTORY "${navmap_case_dir}")
    continue()
  endif()
  get_filename_component(navmap_case_name "${navmap_case_dir}" NAME)
  string(REGEX REPLACE "[^A-Za-z0-9_]" "_" navmap_case_name "${navmap_case_name}")
  set(navmap_case_test "Cases/RenderCaseTest.MatchesExpected/${navmap_case_name}")
  add_test("${navmap_case_test}" ${NAVMAP_CASE_EMULATOR} "${NAVMAP_CASE_RUNNER}" "--gtest_filter=${navmap_case_test}")
  set_tests_properties("${navmap_case_test}" PROPERTIES LABELS gpu TIMEOUT ${NAVMAP_CASE_TIMEOUT}
      WORKING_DIRECTORY "${NAVMAP_CASE_WORKING_DIRECTORY}")
endforeach()
