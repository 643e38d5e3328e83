# Project-wide warning flags, applied through the dhr_build_flags interface target.
function(dhr_apply_warnings target)
  target_compile_options(${target} INTERFACE
    -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual
    -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
  if(DHR_WERROR)
    target_compile_options(${target} INTERFACE -Werror)
  endif()
endfunction()
