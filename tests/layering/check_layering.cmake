# cmake -DBUILD_DIR=... -P check_layering.cmake: the allowed probe builds, the wrong-way one fails because
# its header is not visible (not for any other reason).
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target dhr_layering_math_includes_math
                RESULT_VARIABLE ok_rc OUTPUT_VARIABLE ok_out ERROR_VARIABLE ok_out)
if(NOT ok_rc EQUAL 0)
  message(FATAL_ERROR "the allowed probe (math/ from dhr_math) did not build:\n${ok_out}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target dhr_layering_math_includes_scene
                RESULT_VARIABLE bad_rc OUTPUT_VARIABLE bad_out ERROR_VARIABLE bad_out)
if(bad_rc EQUAL 0)
  message(FATAL_ERROR "a wrong-way include (scene/ from dhr_math's layer) compiled: the layering is not enforced")
endif()
if(NOT bad_out MATCHES "scene/scene.hpp: No such file or directory")
  message(FATAL_ERROR "the wrong-way probe failed, but not for the missing header:\n${bad_out}")
endif()
message(STATUS "layering enforced: scene/scene.hpp is not visible from dhr_math's layer")
