# Included by the benchmark checks: runs EXE with ARGS (a|b) and requires exit status 0; leaves stdout in `out`.
string(REPLACE "|" ";" args "${ARGS}")
execute_process(COMMAND "${EXE}" ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("exit status ${rc}; stderr:\n${err}")
if(NOT rc STREQUAL "0")
  message(FATAL_ERROR "expected exit status 0, got ${rc}")
endif()
