#pragma once
// Benchmarks of `edx-bench`, one subcommand each, each in its own file. A benchmark adds its
// subcommand to the app; its callback runs the benchmark and prints the figures (a table, or
// only a JSON object on stdout with --json). Failures are thrown as std::runtime_error.
#include <CLI/CLI.hpp>

namespace edx::bench {

/// `edx-bench des`: edx's discrete-event engine (sim_core) against SystemC 2.3.4 on the same
/// models (bench/des/).
void add_des_bench(CLI::App& app);
/// `edx-bench render`: synthetic-world render speed (workloads/datasets/synthetic).
void add_render_bench(CLI::App& app);
/// `edx-bench frontend`: stereo frontend frames/s (workloads/frontend).
void add_frontend_bench(CLI::App& app);
/// `edx-bench system`: the whole-system model of `edx simulate` (arch/system).
void add_system_bench(CLI::App& app);
/// `edx-bench sweep`: design points per second of `edx sweep` (arch/system/sweep).
void add_sweep_bench(CLI::App& app);
/// `edx-bench sweep-mpi`: a workload sweep under mpirun -np 1 and -np N (arch/sweep MPI).
void add_sweep_mpi_bench(CLI::App& app);
/// `edx-bench host-load`: measured host times quiet vs beside busy siblings
/// (workloads/modes/host_load_study.hpp).
void add_host_load_bench(CLI::App& app);

}  // namespace edx::bench
