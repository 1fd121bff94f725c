// Fuzzes the EuRoC ASL reader (workloads/datasets/euroc_dataset.hpp): camera and IMU sensor.yaml,
// the image lists, the IMU and ground-truth CSVs, each replaced in turn in a valid skeleton;
// what opens is also read (first frame, streams).
#include "fuzz/dataset_skeleton.hpp"

namespace {

const char* kCamera = R"(%YAML:1.0
sensor_type: camera
T_BS:
  cols: 4
  rows: 4
  data: [1.0, 0.0, 0.0, OFFSET, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]
rate_hz: 20
resolution: [96, 64]
camera_model: pinhole
intrinsics: [60.0, 60.0, 48.0, 32.0]
distortion_model: radial-tangential
distortion_coefficients: [-0.28, 0.07, 0.0002, 0.00002]
)";

const edx::fuzz::DatasetSkeleton& skeleton() {
  static const edx::fuzz::DatasetSkeleton s = [] {
    edx::fuzz::DatasetSkeleton k;
    k.root = edx::fuzz::scratch_dir() / "euroc";
    std::string left = kCamera, right = kCamera;
    left.replace(left.find("OFFSET"), 6, "0.0");
    right.replace(right.find("OFFSET"), 6, "0.11");
    const std::string list =
        "#timestamp [ns],filename\n1000000000,1000000000.png\n"
        "1050000000,1050000000.png\n";
    k.contents = {
        {"mav0/cam0/sensor.yaml", left},
        {"mav0/cam1/sensor.yaml", right},
        {"mav0/cam0/data.csv", list},
        {"mav0/cam1/data.csv", list},
        {"mav0/imu0/data.csv",
         "#timestamp,wx,wy,wz,ax,ay,az\n1000000000,0,0,0,0,0,9.81\n1005000000,0,0,0,0,0,9.81\n"},
        {"mav0/imu0/sensor.yaml",
         "%YAML:1.0\nrate_hz: 200\ngyroscope_noise_density: 1.7e-04\ngyroscope_random_walk: "
         "1.9e-05\naccelerometer_noise_density: 2.0e-3\naccelerometer_random_walk: 3.0e-3\n"},
        {"mav0/state_groundtruth_estimate0/data.csv",
         "#timestamp,px,py,pz,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz\n"
         "1000000000,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n"
         "1050000000,0.1,0,0,1,0,0,0,2,0,0,0,0,0,0,0,0\n"}};
    k.write({"mav0/cam0/data/1000000000.png", "mav0/cam0/data/1050000000.png",
             "mav0/cam1/data/1000000000.png", "mav0/cam1/data/1050000000.png"});
    return k;
  }();
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  skeleton().run(data, size, edx::datasets::DatasetFormat::kEuroc);
  return 0;
}
