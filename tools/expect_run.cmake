# Runs an executable and checks its exit status and output: cmake -DEXE=... -DARGS=a|b|c -DEXPECT_RC=2
#   -DEXPECT_OUTPUT=regex (stdout + stderr) -DWORK_DIR=dir [-DINPUT_TEXT=text with \n] [-DCHECK_FILE=f
#   -DCHECK_REGEX=regex] [-DDATA_DIR=dir] [-DEMULATOR=qemu-aarch64|-L|dir] -P expect_run.cmake
# EMULATOR (cross builds) is the command line EXE runs under, '|'-separated like ARGS.
# In ARGS, @INPUT@ stands for WORK_DIR/input.csv (written from INPUT_TEXT) and @DATA@ for DATA_DIR; a test
# that needs DATA_DIR when it is absent prints "SKIPPED:" (the test's SKIP_REGULAR_EXPRESSION).
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
if(ARGS MATCHES "@DATA@" AND NOT IS_DIRECTORY "${DATA_DIR}")
  message("SKIPPED: test data not available: ${DATA_DIR}")
  return()
endif()
if(NOT INPUT_TEXT STREQUAL "")
  string(REPLACE "\\n" "\n" text "${INPUT_TEXT}")
  file(WRITE "${WORK_DIR}/input.csv" "${text}")
endif()
string(REPLACE "@INPUT@" "${WORK_DIR}/input.csv" args "${ARGS}")
string(REPLACE "@DATA@" "${DATA_DIR}" args "${args}")
string(REPLACE "|" ";" args "${args}")
string(REPLACE "|" ";" emulator "${EMULATOR}")
execute_process(COMMAND ${emulator} "${EXE}" ${args} WORKING_DIRECTORY "${WORK_DIR}"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}${err}")
message("exit status ${rc}; output:\n${all}")
if(NOT rc STREQUAL "${EXPECT_RC}")
  message(FATAL_ERROR "expected exit status ${EXPECT_RC}, got ${rc}")
endif()
if(NOT all MATCHES "${EXPECT_OUTPUT}")
  message(FATAL_ERROR "output does not match the regular expression: ${EXPECT_OUTPUT}")
endif()
if(NOT CHECK_FILE STREQUAL "")
  if(NOT EXISTS "${WORK_DIR}/${CHECK_FILE}")
    message(FATAL_ERROR "expected output file ${CHECK_FILE} was not written")
  endif()
  file(READ "${WORK_DIR}/${CHECK_FILE}" content)
  if(NOT content MATCHES "${CHECK_REGEX}")
    message(FATAL_ERROR "${CHECK_FILE} does not match the regular expression: ${CHECK_REGEX}")
  endif()
endif()
