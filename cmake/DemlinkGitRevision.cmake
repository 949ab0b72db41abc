# Script mode (cmake -P), run at every build by the demlink_version_source target:
# writes OUTPUT from INPUT with @DEMLINK_GIT_REVISION@ = `git describe --always --dirty`
# of SOURCE_DIR, or "unknown" without git or outside a checkout (a source archive, a
# container build without .git). configure_file rewrites OUTPUT only when the text
# changes, so an unchanged revision recompiles nothing.
set(DEMLINK_GIT_REVISION "unknown")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND "${GIT_EXECUTABLE}" describe --always --dirty
                  WORKING_DIRECTORY "${SOURCE_DIR}"
                  OUTPUT_VARIABLE revision OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE status ERROR_QUIET)
  if(status EQUAL 0 AND NOT revision STREQUAL "")
    set(DEMLINK_GIT_REVISION "${revision}")
  endif()
endif()
configure_file("${INPUT}" "${OUTPUT}" @ONLY)
