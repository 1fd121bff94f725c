// `edx-bench sweep-mpi`: the same workload sweep under `mpirun -np 1` and `-np N` (issue 20's
// bar: speedup >= 1.8 at N = 2 on this 2-core machine). The spec traces 8 workload points (the
// paper mix at seeds 1..8: equal work each, every seed its own worlds and vocabulary) and
// simulates 3 platform points on each; every run starts from an empty results database and
// trace store, so each traces all 8 points. Wall time of the whole mpirun, startup included.
#include <fmt/core.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <thread>

#include "bench/benches.hpp"

namespace edx::bench {
namespace {

/// The built edx beside this benchmark binary.
std::filesystem::path edx_binary() {
  return std::filesystem::read_symlink("/proc/self/exe").parent_path() / "edx";
}

}  // namespace

void add_sweep_mpi_bench(CLI::App& app) {
  struct Args {
    int ranks = 2;
    int frames = 40;
    std::string resolution = "320x240";
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand(
      "sweep-mpi", "edx sweep of 8 workload points under mpirun -np 1 and -np N: the speedup");
  sub->add_option("--ranks", args->ranks, "N: ranks of the second run")
      ->check(CLI::Range(2, 1024))
      ->capture_default_str();
  sub->add_option("--frames", args->frames, "frames of each workload point's mix")
      ->check(CLI::Range(8, 100000))
      ->capture_default_str();
  sub->add_option("--resolution", args->resolution, "resolution of the mix")->capture_default_str();
  sub->add_flag("--json", args->json, "print only a JSON object");
  sub->callback([args] {
    if (std::string(EDX_MPIEXEC).empty()) {
      throw std::runtime_error("sweep-mpi: edx was built without MPI (install libopenmpi-dev)");
    }
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / fmt::format("edx-bench-sweep-mpi-{}", ::getpid());
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "spec.yaml") << fmt::format(
        "name: sweep_mpi\nbase: {}/configs/edx_car.yaml\n"
        "workload: {{mix: paper, frames: {}, resolution: {}}}\n"
        "parameters:\n  workload.seed: {{values: [1, 2, 3, 4, 5, 6, 7, 8]}}\n"
        "  backend.units.gemm.block: {{values: [1, 2, 4]}}\n"
        "objectives: [{{minimize: e2e_latency_mean}}, {{minimize: energy_mean}}]\n",
        EDX_SOURCE_DIR, args->frames, args->resolution);
    const auto run = [&](int ranks) {
      const std::string db = (dir / fmt::format("np{}.db", ranks)).string();
      const std::string command = fmt::format(
          "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 {} -np {} --oversubscribe "
          "{} sweep {} --db {} --json > {}.json 2> {}.log",
          EDX_MPIEXEC, ranks, edx_binary().string(), (dir / "spec.yaml").string(), db, db, db);
      const auto start = std::chrono::steady_clock::now();
      if (std::system(command.c_str()) != 0) {
        throw std::runtime_error(
            fmt::format("sweep-mpi: mpirun -np {} failed (log: {}.log)", ranks, db));
      }
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::ifstream out(db + ".json");
      const nlohmann::json j = nlohmann::json::parse(out);
      if (j.at("traced") != 8 || j.at("computed") != 24) {
        throw std::runtime_error(fmt::format("sweep-mpi: -np {} traced {} and simulated {}", ranks,
                                             j.at("traced").dump(), j.at("computed").dump()));
      }
      return seconds;
    };
    const double one = run(1);
    const double many = run(args->ranks);
    std::filesystem::remove_all(dir);
    const unsigned cores = std::thread::hardware_concurrency();
    const nlohmann::json result = {
        {"workload_points", 8},           {"platform_points", 24}, {"frames", args->frames},
        {"resolution", args->resolution}, {"cores", cores},        {"seconds_np1", one},
        {"ranks", args->ranks},           {"seconds_npN", many},   {"speedup", one / many}};
    if (args->json) {
      fmt::print("{}\n", result.dump(2));
      return;
    }
    fmt::print(
        "sweep-mpi: 8 workload points (paper mix, {} frames at {}) x 3 platform points, "
        "{} cores\n",
        args->frames, args->resolution, cores);
    fmt::print("  mpirun -np 1   {:8.1f} s\n", one);
    fmt::print("  mpirun -np {}   {:8.1f} s\n", args->ranks, many);
    fmt::print("  speedup        {:8.2f}x (goal >= 1.8 at -np 2)\n", one / many);
  });
}

}  // namespace edx::bench
