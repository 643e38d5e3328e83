# cmake -DBUILD_DIR=... -DPAIRS=allowed:forbidden:header[,...] -P check_layering.cmake: for each pair, the allowed
# probe builds, and the wrong-way one fails because its header is not visible (not for any other reason).
string(REPLACE "," ";" pairs "${PAIRS}")
foreach(pair ${pairs})
  string(REPLACE ":" ";" parts "${pair}")
  list(GET parts 0 allowed)
  list(GET parts 1 forbidden)
  list(GET parts 2 header)
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target dhr_layering_${allowed}
                  RESULT_VARIABLE ok_rc OUTPUT_VARIABLE ok_out ERROR_VARIABLE ok_out)
  if(NOT ok_rc EQUAL 0)
    message(FATAL_ERROR "the allowed probe ${allowed} did not build:\n${ok_out}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target dhr_layering_${forbidden}
                  RESULT_VARIABLE bad_rc OUTPUT_VARIABLE bad_out ERROR_VARIABLE bad_out)
  if(bad_rc EQUAL 0)
    message(FATAL_ERROR "a wrong-way include (${forbidden}) compiled: the layering is not enforced")
  endif()
  string(REPLACE "." "\\." header_re "${header}")
  if(NOT bad_out MATCHES "${header_re}: No such file or directory")
    message(FATAL_ERROR "the wrong-way probe ${forbidden} failed, but not for the missing header:\n${bad_out}")
  endif()
  message(STATUS "layering enforced: ${header} is not visible from ${forbidden}'s layer")
endforeach()
