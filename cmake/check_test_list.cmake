# cmake -DEXE=<c_tests> -DEXPECTED=<a,b,c> -P check_test_list.cmake
# Fails if `c_tests --list` differs from the names CMake read from c_tests/tests.def.
execute_process(COMMAND "${EXE}" --list OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${EXE} --list failed: ${rc}")
endif()
string(STRIP "${out}" out)
string(REPLACE "\n" "," listed "${out}")
if(NOT "${listed}" STREQUAL "${EXPECTED}")
  message(FATAL_ERROR "c_tests --list gives\n  ${listed}\nbut CTest registered\n  ${EXPECTED}\n"
                      "re-run cmake so that it re-reads c_tests/tests.def")
endif()
