# One precompiled header for the libraries and commands (docs/BENCH.md, "Issue 44 point 3, library
# build time"): the standard and third-party headers most of their sources include, parsed once
# (target edx_library_pch) instead of once per translation unit, and reused by every library and
# command target under the given source folders (REUSE_FROM).
#
# GCC takes a precompiled header only where every macro defined when it was built is defined alike
# (a macro defined only where it is used is harmless unless the header mentions it) and the -m
# flags are the same. So the header's own target is built with fmt's usage requirements
# (FMT_SHARED) and nothing else of the project; every user gets fmt's usage requirements too (CMake
# adds -Winvalid-pch: with -Werror a header GCC refuses is a build error, not a silent slowdown). Targets
# with their own -m flags (-mpopcnt: edx_bow, edx_backend_registration) parse their headers as
# before. GCC only: clang (the fuzz build) takes no precompiled header here.
function(edx_library_pch)
  set(_edx_pch_cpp ${CMAKE_BINARY_DIR}/edx_library_pch.cpp)
  file(CONFIGURE OUTPUT ${_edx_pch_cpp}
       CONTENT "// The precompiled header's own translation unit (cmake/library_pch.cmake).\n")
  add_library(edx_library_pch OBJECT ${_edx_pch_cpp})
  target_link_libraries(edx_library_pch PRIVATE Eigen3::Eigen fmt::fmt nlohmann_json::nlohmann_json)
  target_precompile_headers(edx_library_pch PRIVATE
    <algorithm> <array> <cmath> <cstdint> <filesystem> <functional> <map> <memory> <optional>
    <set> <stdexcept> <string> <string_view> <unordered_map> <utility> <vector>
    <Eigen/Dense> <fmt/format.h> <nlohmann/json.hpp>)
  set(_edx_dirs ${ARGN})
  while(_edx_dirs)
    list(POP_FRONT _edx_dirs _edx_dir)
    get_property(_edx_sub DIRECTORY ${_edx_dir} PROPERTY SUBDIRECTORIES)
    list(APPEND _edx_dirs ${_edx_sub})
    get_property(_edx_targets DIRECTORY ${_edx_dir} PROPERTY BUILDSYSTEM_TARGETS)
    foreach(_edx_target IN LISTS _edx_targets)
      get_target_property(_edx_type ${_edx_target} TYPE)
      get_target_property(_edx_options ${_edx_target} COMPILE_OPTIONS)
      if(NOT _edx_type MATCHES "^(STATIC_LIBRARY|EXECUTABLE)$" OR "${_edx_options}" MATCHES "(^|[;:>])-m")
        continue()
      endif()
      target_compile_definitions(${_edx_target} PRIVATE
                                 $<TARGET_PROPERTY:fmt::fmt,INTERFACE_COMPILE_DEFINITIONS>)
      target_precompile_headers(${_edx_target} REUSE_FROM edx_library_pch)
    endforeach()
  endwhile()
endfunction()
