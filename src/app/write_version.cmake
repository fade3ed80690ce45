# Writes app/version.h at every build: the Tissu version and the git commit of the source
# tree being built, with whether its tracked files differed from that commit. The header
# is rewritten only when its text changes, so an unchanged tree rebuilds nothing.
# Inputs: SOURCE_DIR, OUTPUT, VERSION, GIT (empty outside git).
set(commit unknown)
set(modified false)
if(GIT AND EXISTS "${GIT}")
  execute_process(COMMAND ${GIT} rev-parse HEAD WORKING_DIRECTORY ${SOURCE_DIR}
                  OUTPUT_VARIABLE head OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE head_result ERROR_QUIET)
  if(head_result EQUAL 0 AND head MATCHES "^[0-9a-f]+$")
    set(commit ${head})
    execute_process(COMMAND ${GIT} status --porcelain --untracked-files=no
                    WORKING_DIRECTORY ${SOURCE_DIR}
                    OUTPUT_VARIABLE changes RESULT_VARIABLE status_result ERROR_QUIET)
    if(status_result EQUAL 0 AND NOT changes STREQUAL "")
      set(modified true)
    endif()
  endif()
endif()
set(text "// Generated at build time by src/app/write_version.cmake: the Tissu version (project()
// in the top CMakeLists.txt) and the git commit built (\"unknown\" outside git), with whether
// the tracked files differed from it.
#pragma once

#define TISSU_VERSION \"${VERSION}\"
#define TISSU_GIT_COMMIT \"${commit}\"
#define TISSU_GIT_MODIFIED ${modified}
")
set(old "")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUTPUT} "${text}")
endif()
