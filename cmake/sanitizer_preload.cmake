# An uninstrumented program (the Python interpreter) that loads the sanitized library needs the ASan
# runtime loaded first, and libstdc++ with it so ASan can intercept C++ exceptions thrown inside the
# library. statfilter_sanitizer_preload(VAR) sets VAR to the two, as LD_PRELOAD takes them.
function(statfilter_sanitizer_preload var)
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libasan.so
                  OUTPUT_VARIABLE libasan OUTPUT_STRIP_TRAILING_WHITESPACE)
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libstdc++.so
                  OUTPUT_VARIABLE libstdcxx OUTPUT_STRIP_TRAILING_WHITESPACE)
  set(${var} "${libasan}:${libstdcxx}" PARENT_SCOPE)
endfunction()
