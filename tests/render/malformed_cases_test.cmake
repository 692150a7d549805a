# SPDX-License-Identifier: Apache-2.0
# render_case_tests on a directory of malformed cases (CTest render_case_tests_malformed): each
# case fails its own test with the file and the reason, and the runner ends as failed (exit
# status 1), not crashed. Usage: cmake -DRUNNER=<render_case_tests> [-DEMULATOR=<cmd>]
# -DWORK=<scratch dir> -P malformed_cases_test.cmake
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}/no_case_json")
file(WRITE "${WORK}/not_json/case.json" "{\n  \"scene\": \"andorra_drive\",\n  \"view\": \n")
file(WRITE "${WORK}/bad_view/case.json"
     "{\"scene\": \"andorra_drive\", \"view\": \"sideways\", \"pose\": {\"measure_m\": 10}, \"size\": [64, 32],
       \"tolerance\": {\"channel\": 10, \"max_differing_fraction\": 0.01}}")
file(WRITE "${WORK}/bad_size/case.json"
     "{\"scene\": \"andorra_drive\", \"view\": \"bird\", \"pose\": {\"measure_m\": 10}, \"size\": [64, -32],
       \"tolerance\": {\"channel\": 10, \"max_differing_fraction\": 0.01}}")
file(WRITE "${WORK}/misspelt_layer/case.json"
     "{\"scene\": \"andorra_drive\", \"view\": \"bird\", \"pose\": {\"measure_m\": 10}, \"size\": [64, 32],
       \"layers\": {\"raods\": true}, \"tolerance\": {\"channel\": 10, \"max_differing_fraction\": 0.01}}")

execute_process(COMMAND ${CMAKE_COMMAND} -E env "NAVMAP_RENDER_CASES=${WORK}" ${EMULATOR} "${RUNNER}"
                        "--gtest_filter=Cases/*"
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
message("${out}")
if(NOT status EQUAL 1)
  message(FATAL_ERROR "render_case_tests ended with '${status}', expected 1 (tests failed, no crash)")
endif()
set(expected
    "${WORK}/bad_size/case.json: \"size\" height must be an integer from 1 to 4096"
    "${WORK}/bad_view/case.json: \"view\" must be one of \"bird\", \"snail\""
    "${WORK}/misspelt_layer/case.json: unknown key \"layers.raods\" (known: "
    "${WORK}/no_case_json/case.json: cannot be read"
    "${WORK}/not_json/case.json: not JSON: parse error at line 4"
    "5 FAILED TESTS")
foreach(line IN LISTS expected)
  string(FIND "${out}" "${line}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the output lacks: ${line}")
  endif()
endforeach()
foreach(name bad_size bad_view misspelt_layer no_case_json not_json)
  string(FIND "${out}" "[  FAILED  ] Cases/RenderCaseTest.MatchesExpected/${name}, " at)
  if(at EQUAL -1)
    message(FATAL_ERROR "no failed test for the case ${name}")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK}")
