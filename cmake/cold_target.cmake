# Cold code at -O1 (docs/BENCH.md, "Issue 44 point 3, cold code at -O1"). Most of what `ninja edx`
# compiles runs once per command (argument parsing, YAML configs, results databases, reports,
# printing), yet Release compiles it at -O3 like the simulation. -O1 keeps the inlining and the
# scalar optimizations that matter there and skips the costly passes (vectorization, unrolling,
# cloning): 9.5 s against 13.9 s for cli's first unity batch. Floating point stays identical:
# no -ffast-math (GCC reorders no FP arithmetic at any -O level) and no FMA on the baseline
# x86-64 target (nothing to contract a*b+c into).
# Hot code (tracing: workloads/; simulation: sim_core/, the arch/ models, the sweep's execution,
# the trace reader) stays at the build type's level.
option(EDX_COLD_O1 "Compile the cold targets (edx_cold_target) at -O1 in optimized builds" ON)

# edx_cold_target(TARGET): TARGET's own sources at -O1 in Release and RelWithDebInfo builds; the
# option comes after the build type's flags on the command line, so it wins. Debug (-O0) and
# MinSizeRel (-Os) are left alone.
function(edx_cold_target target)
  if(EDX_COLD_O1)
    target_compile_options(${target} PRIVATE $<$<CONFIG:Release,RelWithDebInfo>:-O1>)
  endif()
endfunction()
