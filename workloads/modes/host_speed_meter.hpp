#pragma once
// The machine-speed reference suite, version trace::kHostSpeedSuite (docs/TRACE.md, "Host speed"):
// a fixed piece of the pipeline's own work on fixed inputs, so that a trace says how fast the
// machine that made it is, and arch can map its host times to any platform's host through the
// two machines' suite times (arch/host/host_model.hpp).
//
// Version 1, two parts, each timed as a trace's frame totals are (trace/host_clock.hpp): the
// frontend part by the frames' own work clock (FrontendFrame::host_ns) in the trace's threading
// (its chains on OpenCV's pool when the trace runs them so), the backend part in thread CPU time:
//   frontend  StereoFrontend with default options on two consecutive stereo frames of a
//             generated 1280x720 textured scene (FD/IF/FC on four images, MO and DR on both
//             pairs, DC and LSS tracking the first frame's features into the second). The images
//             come from OpenCV's seeded RNG: the same bytes on every machine (`inputs`, checked
//             by tests/workloads/modes/host_speed_meter_test.cpp).
//   backend   Eigen double kernels of the backends' kind on seeded matrices: GEMM 96^3 and 384^3
//             (with the SPD product 256x256), Cholesky (LLT) 256, triangular solve 256x64,
//             symmetric eigen-decomposition 160 (the SLAM host's pseudo-inverse), Householder QR
//             480x120 (VIO measurement compression).
// A sample runs each part once. The runners take samples before the first frame, after every
// stretch of frames that took `work_per_sample` times a sample's CPU time, and after the last,
// and record them all with the frames traced before each (and their medians): a machine whose
// speed drifts during a trace (another tenant, frequency) is measured beside the frames it
// slowed, and arch maps each frame by the samples nearest it (arch/host/host_model.hpp).
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "workloads/trace/host_speed.hpp"
#include "workloads/trace/writer.hpp"

namespace edx::modes {

struct HostSpeedMeterOptions {
  int initial_samples = 3;  ///< samples before the first frame (after one warm-up pass)
  /// One more sample once the frames traced since the last one took this many times a sample's
  /// own CPU time (about 1 / (1 + ratio) of the trace's time goes to the suite; 0: none).
  double work_per_sample = 15.0;
  int final_samples = 2;  ///< samples after the last frame
  /// Run the frontend part as the trace runs its frontend (FrontendOptions::parallel_images):
  /// with its chains on OpenCV's pool, so that the suite sees what that costs on this machine
  /// (docs/TRACE.md, "Host speed"). The suite's figures are then for that threading.
  bool parallel_images = false;
};

class HostSpeedMeter {
 public:
  explicit HostSpeedMeter(HostSpeedMeterOptions options = {});
  /// Warm-up pass (not recorded) and the initial samples.
  void start();
  /// Call after each traced frame with its host CPU time (frontend + backend), ns: samples
  /// once the frames since the last sample took work_per_sample times that sample's time.
  void after_frame(std::int64_t frame_cpu_ns);
  /// The final samples; result() is complete after this.
  void finish();
  /// finish(), then the trace's meta host_speed and frames (the rows written) into `writer`.
  void finish_into(trace::TraceWriter& writer);
  /// Runs one pass of both parts and records their CPU times.
  void sample();
  /// Medians over the samples so far (throws std::invalid_argument when there are none).
  trace::HostSpeed result() const;
  const std::vector<double>& frontend_samples_ms() const { return frontend_ms_; }
  const std::vector<double>& backend_samples_ms() const { return backend_ms_; }

  /// The suite's generated images (left0, right0, left1, right1), 1280x720 8-bit grayscale.
  static std::vector<cv::Mat> inputs();
  /// FNV-1a 64 (hex) of the images' bytes, row by row.
  static std::string fingerprint(const std::vector<cv::Mat>& images);

 private:
  double run_frontend_part() const;  ///< CPU ms of one frontend pass
  double run_backend_part() const;   ///< CPU ms of one backend pass

  HostSpeedMeterOptions options_;
  std::vector<cv::Mat> images_;
  std::int64_t frames_done_ = 0;  ///< frames traced so far (after_frame)
  std::int64_t work_since_sample_ns_ = 0;
  double last_sample_ms_ = 0;  ///< CPU ms of the last sample (both parts)
  std::vector<std::int64_t> sample_frames_;
  std::vector<double> frontend_ms_, backend_ms_;
};

}  // namespace edx::modes
