# dhr_add_library(NAME <target> SOURCES <src/...> [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# A topic library laid out as  <dir>/include/<prefix>/*.hpp  (public, included as "<prefix>/x.hpp") and
# <dir>/src/ (sources and private headers). Only include/ is published, and only through
# target_link_libraries: a target that does not link this library cannot include its headers, so an
# include against the declared dependency direction fails to compile.
function(dhr_add_library)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${ARG_NAME} STATIC ${ARG_SOURCES})
  target_include_directories(${ARG_NAME} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
                                         PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(${ARG_NAME} PUBLIC dhr_build_flags ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
endfunction()
