# Renders the same frame with llvmpipe using 0, 1, 2 and 3 rasterizer threads
# (LP_NUM_THREADS; 0 = in the calling thread) and fails unless the image hashes agree.
#   cmake -DPROGRAM=<render_timing> -P render_threads_check.cmake
set(first_hash "")
foreach(threads 0 1 2 3)
  execute_process(
    COMMAND ${CMAKE_COMMAND} -E env LP_NUM_THREADS=${threads}
            ${PROGRAM} --width 320 --height 180 --msaa 4 --frames 1
    OUTPUT_VARIABLE output ERROR_VARIABLE errors RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "render_timing failed with LP_NUM_THREADS=${threads}: ${errors}")
  endif()
  string(REGEX MATCH "hash ([0-9a-f]+)" found "${output}")
  if(NOT found)
    message(FATAL_ERROR "no image hash in the output of render_timing: ${output}")
  endif()
  set(hash ${CMAKE_MATCH_1})
  message(STATUS "LP_NUM_THREADS=${threads}: image hash ${hash}")
  if(first_hash STREQUAL "")
    set(first_hash ${hash})
  elseif(NOT hash STREQUAL first_hash)
    message(FATAL_ERROR "LP_NUM_THREADS=${threads} gave image ${hash}, LP_NUM_THREADS=0 gave ${first_hash}")
  endif()
endforeach()
