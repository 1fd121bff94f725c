// Fuzzes the KITTI odometry reader (workloads/datasets/kitti_dataset.hpp): calib.txt and
// times.txt, each replaced in turn in a valid two-frame sequence; what opens is also read.
#include <exception>

#include "fuzz/dataset_skeleton.hpp"
#include "workloads/datasets/dataset.hpp"

namespace {

const edx::fuzz::DatasetSkeleton& skeleton() {
  static const edx::fuzz::DatasetSkeleton s = [] {
    edx::fuzz::DatasetSkeleton k;
    k.root = edx::fuzz::scratch_dir() / "kitti" / "sequences" / "00";
    k.contents = {{"calib.txt",
                   "P0: 60 0 48 0 0 60 32 0 0 0 1 0\nP1: 60 0 48 -32 0 60 32 0 0 0 1 0\n"
                   "P2: 60 0 48 0 0 60 32 0 0 0 1 0\nP3: 60 0 48 0 0 60 32 0 0 0 1 0\n"},
                  {"times.txt", "0.000000e+00\n1.000000e-01\n"}};
    for (const auto& [file, text] : k.contents) k.files.push_back(file);
    k.write(
        {"image_0/000000.png", "image_0/000001.png", "image_1/000000.png", "image_1/000001.png"});
    return k;
  }();
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const edx::fuzz::DatasetSkeleton& k = skeleton();
  const std::string replaced = k.replace(data, size);
  try {
    const auto dataset = edx::datasets::open_dataset(k.root, edx::datasets::DatasetFormat::kKitti);
    if (dataset->frame_count() > 0) (void)dataset->load_frame(0);
  } catch (const std::exception&) {
  }
  k.restore(replaced);
  return 0;
}
