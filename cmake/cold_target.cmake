# Cold code at -O1 (docs/BENCH.md, "Issue 44 point 3, cold code at -O1"). Much of what `ninja edx`
# compiles runs once per command (argument parsing, YAML configs, results databases, reports,
# printing), yet Release compiles it at -O3 like the simulation. -O1 keeps the scalar
# optimizations and the inlining of small functions and skips the costly passes (vectorization,
# unrolling, cloning, most inlining): 9.5 s against 13.9 s for cli's first unity batch.
# Floating point stays identical: no -ffast-math (GCC reorders no FP arithmetic at any -O level)
# and no FMA on the baseline x86-64 target (nothing to contract a*b+c into).
# Hot code (tracing: workloads/; simulation: sim_core/, the arch/ models, the sweep's execution,
# the trace reader) stays at the build type's level.
option(EDX_COLD_O1 "Compile the cold targets (edx_cold_target) at -O1 in Release builds" ON)

# edx_cold_target(TARGET): TARGET's own sources at -O1 in Release builds (the other build types
# keep their levels; the fuzz build's RelWithDebInfo is -O1 already). The option comes after the
# build type's -O3 on the command line, so it wins. The test code uses it too (tests/).
function(edx_cold_target target)
  if(EDX_COLD_O1)
    target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:-O1>)
  endif()
endfunction()
