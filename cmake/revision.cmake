# Run at build time (cmake -P): writes OUT, a header with the source revision (git describe),
# touching it only when the revision changed so that nothing rebuilds needlessly.
execute_process(COMMAND git describe --always --dirty --tags
                WORKING_DIRECTORY "${SOURCE_DIR}"
                OUTPUT_VARIABLE revision OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT revision)
  set(revision "unknown")
endif()
set(content "#pragma once\n// Generated at build time by cmake/revision.cmake.\nnamespace edx {\ninline constexpr const char* kSourceRevision = \"${revision}\";\n}  // namespace edx\n")
if(EXISTS "${OUT}")
  file(READ "${OUT}" previous)
  if(previous STREQUAL content)
    return()
  endif()
endif()
file(WRITE "${OUT}" "${content}")
