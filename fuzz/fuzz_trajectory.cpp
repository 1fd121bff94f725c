// Fuzzes the trajectory parser (workloads/eval/trajectory_io.hpp): the first byte picks the
// format (kitti, tum, euroc), the rest is the file; what parses is also associated with itself.
#include <exception>
#include <sstream>

#include "fuzz/fuzz_input.hpp"
#include "workloads/eval/evaluate.hpp"
#include "workloads/eval/trajectory_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  using edx::eval::TrajectoryFormat;
  constexpr TrajectoryFormat kFormats[] = {TrajectoryFormat::kKitti, TrajectoryFormat::kTum,
                                           TrajectoryFormat::kEuroc};
  const TrajectoryFormat format = kFormats[data[0] % 3];
  std::istringstream in(std::string(edx::fuzz::as_text(data + 1, size - 1)));
  try {
    const edx::eval::Trajectory t = edx::eval::parse_trajectory(in, "fuzz.txt", format);
    (void)edx::eval::evaluate(t, t, edx::eval::EvalOptions{});
  } catch (const std::exception&) {
  }
  return 0;
}
