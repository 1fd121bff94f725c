// The machine-speed reference suite (workloads/modes/host_speed_meter.hpp): its inputs are the
// same bytes everywhere, its frontend part is real stereo-and-tracking work, and the meter
// samples when it says it does.
#include "workloads/modes/host_speed_meter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "workloads/frontend/stereo_frontend.hpp"

namespace edx::modes {
namespace {

TEST(HostSpeedMeter, InputsAreTheSameBytesOnEveryMachine) {
  const std::vector<cv::Mat> images = HostSpeedMeter::inputs();
  ASSERT_EQ(images.size(), 4u);
  for (const cv::Mat& image : images) {
    EXPECT_EQ(image.size(), cv::Size(1280, 720));
    EXPECT_EQ(image.type(), CV_8U);
  }
  // Suite v1's images (integer generation and OpenCV's bit-exact 8-bit Gaussian). A change here
  // is a new suite: bump trace::kHostSpeedSuite and restate the platforms' suite times.
  EXPECT_EQ(HostSpeedMeter::fingerprint(images), "7087ba3184e69cb7");
  EXPECT_EQ(trace::kHostSpeedSuite, 1);
}

TEST(HostSpeedMeter, FrontendPartMatchesAStereoPairAndTracksIntoTheNextFrame) {
  const std::vector<cv::Mat> images = HostSpeedMeter::inputs();
  frontend::FrontendOptions options;
  options.parallel_images = false;
  frontend::StereoFrontend frontend(options, {450.0, 0.11});
  frontend.process(images[0], images[1]);
  const frontend::FrontendFrame second = frontend.process(images[2], images[3]);
  // The right view is the left one shifted by 12 px, the second frame by (5, 3) px: most
  // features match at disparity 12 and most of the first frame's features are tracked.
  EXPECT_GT(second.stats.left_keypoints, 500);
  EXPECT_GT(second.stats.tracked, 400);
  EXPECT_GT(second.stats.stereo_matches, 300);
  std::vector<float> disparities;
  for (const frontend::Feature& f : second.features) {
    if (f.stereo) disparities.push_back(f.disparity);
  }
  ASSERT_FALSE(disparities.empty());
  std::nth_element(disparities.begin(), disparities.begin() + disparities.size() / 2,
                   disparities.end());
  EXPECT_NEAR(disparities[disparities.size() / 2], 12.0, 0.5);
}

TEST(HostSpeedMeter, SamplesAtStartEveryIntervalAndAtTheEnd) {
  HostSpeedMeterOptions options;
  options.initial_samples = 2;
  options.work_per_sample = 2.0;
  options.final_samples = 1;
  HostSpeedMeter meter(options);
  meter.start();
  EXPECT_EQ(meter.frontend_samples_ms().size(), 2u);
  // Frames of 0.8 times the last sample's CPU time each: a sample once the frames since the
  // last one reach twice its time, i.e. after the 3rd and the 6th frame.
  for (int frame = 0; frame < 7; ++frame) {
    const double last = meter.frontend_samples_ms().back() + meter.backend_samples_ms().back();
    meter.after_frame(static_cast<std::int64_t>(0.8 * last * 1e6));
  }
  meter.finish();
  const trace::HostSpeed speed = meter.result();
  EXPECT_EQ(speed.samples, 5);
  EXPECT_EQ(speed.sample_frames, (std::vector<std::int64_t>{0, 0, 3, 6, 7}));
  EXPECT_EQ(meter.backend_samples_ms().size(), 5u);
  EXPECT_EQ(speed.suite, trace::kHostSpeedSuite);
  std::vector<double> fe = meter.frontend_samples_ms();
  std::sort(fe.begin(), fe.end());
  EXPECT_DOUBLE_EQ(speed.frontend_ms, fe[2]);  // the median of five
  EXPECT_GT(speed.backend_ms, 0.0);
  EXPECT_EQ(speed.inputs, HostSpeedMeter::fingerprint(HostSpeedMeter::inputs()));
  // Round trip through the trace's meta value.
  EXPECT_EQ(trace::host_speed_of({{"host_speed", trace::to_meta_value(speed)}}, "t.db"), speed);
}

TEST(HostSpeedMeter, BadOptionsAreRefused) {
  HostSpeedMeterOptions options;
  options.initial_samples = 0;
  EXPECT_THROW(HostSpeedMeter{options}, std::invalid_argument);
}

}  // namespace
}  // namespace edx::modes
