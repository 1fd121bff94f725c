// Fuzzes the KITTI odometry reader (workloads/datasets/kitti_dataset.hpp): calib.txt and
// times.txt, each replaced in turn in a valid two-frame sequence; what opens is also read.
#include "fuzz/dataset_skeleton.hpp"

namespace {

const edx::fuzz::DatasetSkeleton& skeleton() {
  static const edx::fuzz::DatasetSkeleton s = [] {
    edx::fuzz::DatasetSkeleton k;
    k.root = edx::fuzz::scratch_dir() / "kitti" / "sequences" / "00";
    k.contents = {{"calib.txt",
                   "P0: 60 0 48 0 0 60 32 0 0 0 1 0\nP1: 60 0 48 -32 0 60 32 0 0 0 1 0\n"
                   "P2: 60 0 48 0 0 60 32 0 0 0 1 0\nP3: 60 0 48 0 0 60 32 0 0 0 1 0\n"},
                  {"times.txt", "0.000000e+00\n1.000000e-01\n"}};
    k.write(
        {"image_0/000000.png", "image_0/000001.png", "image_1/000000.png", "image_1/000001.png"});
    return k;
  }();
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  skeleton().run(data, size, edx::datasets::DatasetFormat::kKitti);
  return 0;
}
