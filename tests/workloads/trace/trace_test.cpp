// The trace database: round trip, refusal of bad output paths, nothing half written, and
// the reader's checks of version, layout and rows.
#include <SQLiteCpp/Database.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "workloads/trace/codec.hpp"
#include "workloads/trace/reader.hpp"
#include "workloads/trace/schema.hpp"
#include "workloads/trace/validate.hpp"
#include "workloads/trace/writer.hpp"

namespace edx::trace {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

TraceMeta sample_meta() {
  TraceMeta meta;
  for (const auto& key : kRequiredMetaKeys) meta[std::string(key)] = "test";
  meta["precision"] = "fp64";
  return meta;
}

FrameTrace sample_frame(std::int64_t id) {
  FrameTrace trace;
  trace.frame.frame_id = id;
  trace.frame.timestamp_ns = 1'000'000 * (id + 1);
  trace.frame.sequence = "synthetic:test";
  trace.frame.scenario = Scenario::OutdoorUnknown;
  trace.frame.mode = BackendMode::Vio;
  trace.frame.gps_available = true;
  trace.frame.estimated_pose = PoseArray{1.0 * id, 2, 3, 1, 0, 0, 0};
  trace.frame.frontend_host_ns = 5'000'000;
  trace.frame.backend_host_ns = 2'000'000;
  TaskRecord fd;
  fd.task = Task::FD;
  fd.image = Image::Left;
  fd.host_ns = 1200;
  fd.pixels = 640 * 480 + 320 * 240;
  fd.levels = 2;
  fd.candidates = 4000;
  fd.keypoints = 1000;
  fd.per_level = {{0, 640, 480, 640 * 480, 0, 0}, {1, 320, 240, 320 * 240, 0, 0}};
  TaskRecord lss;
  lss.task = Task::LSS;
  lss.image = Image::Left;
  lss.points = 800;
  lss.iterations = 5600;
  trace.tasks = {fd, lss};
  KernelRecord gain;
  gain.kernel = "kalman_gain";
  gain.accelerable = true;
  gain.m = 120;
  gain.n = 195;
  gain.host_ns = 300000;
  gain.detail_json = R"({"clones":30})";
  gain.ops = {{Op::Syrk, 120, 120, 195, op_flags::kSymmetric, 1000},
              {Op::Potrf, 120, 120, 0, op_flags::kSymmetric | op_flags::kLower, 800},
              {Op::Trsm, 120, 195, 0, op_flags::kLower, 900},
              {Op::Qr, 9, 3, 0, 0, 0, 14}};
  KernelRecord propagate;
  propagate.kernel = "imu_propagation";
  propagate.host_ns = 15000;
  trace.kernels = {propagate, gain};
  return trace;
}

class TraceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("edx-trace-test-" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write_sample(int frames) {
    const fs::path path = dir_ / "trace.db";
    TraceWriter writer(path, sample_meta());
    for (int i = 0; i < frames; ++i) writer.append(sample_frame(i));
    writer.finish();
    return path;
  }

  fs::path dir_;
};

TEST_F(TraceTest, RoundTripPreservesEveryField) {
  const fs::path path = write_sample(130);  // crosses two transaction batches of 64
  TraceReader reader(path);
  EXPECT_EQ(reader.frame_count(), 130u);
  EXPECT_EQ(reader.meta().at("schema_version"), std::to_string(kSchemaVersion));
  const auto frames = reader.read_all();
  ASSERT_EQ(frames.size(), 130u);
  for (int i = 0; i < 130; ++i) EXPECT_EQ(frames[i], sample_frame(i)) << "frame " << i;
}

TEST_F(TraceTest, RefusesExistingOutputUnlessOverwrite) {
  const fs::path path = write_sample(1);
  EXPECT_THAT([&] { TraceWriter(path, sample_meta()); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("output exists")));
  TraceWriter writer(path, sample_meta(), {.overwrite = true});
  writer.append(sample_frame(0));
  writer.finish();
  EXPECT_EQ(TraceReader(path).frame_count(), 1u);
}

TEST_F(TraceTest, UnfinishedWriterLeavesNothing) {
  const fs::path path = dir_ / "trace.db";
  {
    TraceWriter writer(path, sample_meta());
    writer.append(sample_frame(0));
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_empty(dir_));
}

// Issue 45: a frame's work is bounded by its images (meta.resolution), so that no accepted trace
// drives the model past what it holds; each limit is read at its edge and refused past it.
TEST(TraceLimits, WorkIsBoundedByTheImagesAndOperandsByHostMemory) {
  EXPECT_EQ(parse_image_size("640x480")->width, 640);
  EXPECT_EQ(parse_image_size("640x480")->height, 480);
  EXPECT_FALSE(parse_image_size("640x"));
  EXPECT_FALSE(parse_image_size("70000x480"));
  EXPECT_FALSE(parse_image_size("640x480x2"));
  const ImageSize image{640, 480};
  const std::int64_t pyramid = 64 * 640 * 480;  // kMaxLevels x W x H = 19660800
  const auto error = [&](const FrameTrace& frame) -> std::string {
    try {
      validate_frame(frame, "t.db", image);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "no error";
  };
  FrameTrace frame = sample_frame(0);
  frame.tasks[0].keypoints = frame.tasks[0].descriptors = pyramid;
  frame.tasks[0].window_size = 640;
  frame.kernels[1].ops[0] = {Op::Gemm, 65536, 65536, 65536, 0, 0};  // 2^32 elements each
  EXPECT_EQ(error(frame), "no error");
  frame.tasks[0].keypoints = pyramid + 1;
  EXPECT_EQ(error(frame),
            "t.db: frame 0, task 0 (FD): keypoints is 19660801, more than the 19660800 pixels of "
            "a 64-level pyramid of the 640x480 images (meta.resolution)");
  frame = sample_frame(0);
  frame.tasks[0].window_size = 641;
  EXPECT_EQ(error(frame),
            "t.db: frame 0, task 0 (FD): window_size is 641, more than the 640 pixels of the "
            "images' longer side");
  frame = sample_frame(0);
  frame.tasks[0].levels = 65;
  EXPECT_EQ(error(frame),
            "t.db: frame 0, task 0 (FD): levels is 65, more than the 64 levels a pyramid has");
  frame = sample_frame(0);
  frame.kernels[1].ops[0] = {Op::Gemm, 65536, 65537, 1, 0, 0};
  EXPECT_EQ(error(frame),
            "t.db: frame 0, kernel 1 (kalman_gain), op 0: an operand of m x n = 65536 x 65537 "
            "elements, above the 2^32 no host holds");
}

// A kernel's detail must be a JSON object: accepted exactly when nlohmann's parser makes an
// object of it (the check only validates, without building the object), with the row named.
TEST(TraceLimits, KernelDetailIsAcceptedExactlyWhenItParsesToAnObject) {
  for (const std::string& detail :
       {std::string("{}"), std::string(" {\"a\": [1, 2]}\n"), std::string("\xEF\xBB\xBF{}"),
        std::string("[]"), std::string("1"), std::string("\"{}\""), std::string("{"),
        std::string("{} {}"), std::string(""), std::string("  "), std::string("{\"a\": }"),
        std::string("\xEF\xBB\xBF[]")}) {
    SCOPED_TRACE(detail);
    FrameTrace frame = sample_frame(0);
    frame.kernels[1].detail_json = detail;
    const auto parsed = nlohmann::json::parse(detail, nullptr, false);
    const bool object = !parsed.is_discarded() && parsed.is_object();
    if (object) {
      EXPECT_NO_THROW(validate_frame(frame, "t.db"));
    } else {
      EXPECT_THAT([&] { validate_frame(frame, "t.db"); },
                  ::testing::ThrowsMessage<std::runtime_error>(
                      HasSubstr("t.db: frame 0, kernel 1 (kalman_gain): detail is not a JSON "
                                "object: '" +
                                detail + "'")));
    }
  }
}

TEST_F(TraceTest, WriterRejectsBadFrames) {
  TraceWriter writer(dir_ / "trace.db", sample_meta());
  EXPECT_THAT([&] { writer.append(sample_frame(1)); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("out of order")));
  FrameTrace bad = sample_frame(0);
  bad.tasks[0].pixels += 1;
  EXPECT_THAT([&] { writer.append(bad); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("per_level pixels sum")));
  bad = sample_frame(0);
  bad.frame.estimated_pose = PoseArray{0, 0, 0, 0.5, 0, 0, 0};
  EXPECT_THAT([&] { writer.append(bad); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("quaternion norm")));
  bad = sample_frame(0);
  bad.kernels[1].ops[0].flags = 1u << 20;
  EXPECT_THAT([&] { writer.append(bad); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("unknown flag bits")));
  // Values no run reaches are named before they overflow a model (issue 21).
  bad = sample_frame(0);
  bad.kernels[1].host_ns = 9'000'000'000'000'000'000;
  EXPECT_THAT([&] { writer.append(bad); },
              ::testing::ThrowsMessage<std::runtime_error>(
                  HasSubstr("host_ns is 9000000000000000000, above the plausible 10000000000000")));
  bad = sample_frame(0);
  bad.kernels[1].ops[0].m = 2'000'000'000;
  EXPECT_THAT([&] { writer.append(bad); },
              ::testing::ThrowsMessage<std::runtime_error>(
                  HasSubstr("op 0: m is 2000000000, above the plausible 10000000")));
}

TEST_F(TraceTest, ReaderRefusesAFrameCountThatDisagreesWithTheRows) {
  TraceMeta meta = sample_meta();
  meta["frames"] = "5";
  const fs::path path = dir_ / "trace.db";
  {
    TraceWriter writer(path, meta);
    for (int i = 0; i < 3; ++i) writer.append(sample_frame(i));
    writer.finish();
  }
  EXPECT_THAT([&] { TraceReader{path}; },
              ::testing::ThrowsMessage<std::runtime_error>(::testing::HasSubstr(
                  "trace.db: meta.frames says 5 but the trace has 3 frame rows")));
}

TEST_F(TraceTest, WriterRequiresMetadata) {
  TraceMeta meta = sample_meta();
  meta.erase("host_cpu");
  EXPECT_THAT([&] { TraceWriter(dir_ / "trace.db", meta); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("'host_cpu'")));
}

TEST_F(TraceTest, ReaderRejectsOtherSchemaVersion) {
  const fs::path path = write_sample(2);
  {
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE);
    db.exec("UPDATE meta SET value = '99' WHERE key = 'schema_version'");
  }
  EXPECT_THAT([&] { TraceReader{path}; },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("schema version 99")));
}

// A version 3 trace (no ops.batch) is read with every batch 1; a batch below 1 is refused.
TEST_F(TraceTest, ReaderUpgradesVersion3AndChecksTheBatch) {
  const fs::path path = write_sample(2);
  {
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE);
    db.exec("UPDATE ops SET batch = 0 WHERE frame_id = 1 AND seq = 3");
  }
  EXPECT_THAT([&] { TraceReader(path).read_all(); },
              ::testing::ThrowsMessage<std::runtime_error>(
                  HasSubstr("frame 1, kernel 1 (kalman_gain), op 3: batch must be at least 1")));
  {
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE);
    db.exec("ALTER TABLE ops DROP COLUMN batch");
    db.exec("UPDATE meta SET value = '3' WHERE key = 'schema_version'");
  }
  TraceReader reader(path);
  EXPECT_EQ(reader.schema_version(), 3);
  const auto frames = reader.read_all();
  ASSERT_EQ(frames.size(), 2u);
  FrameTrace expected = sample_frame(1);
  expected.kernels[1].ops[3].batch = 1;
  EXPECT_EQ(frames[1], expected);
}

// Version 4 had no meta precision: its backends computed in double, so it reads as fp64. A
// version 5 trace must say, and say fp64 or fp32.
TEST_F(TraceTest, ReaderReadsVersion4AsFp64AndChecksThePrecision) {
  const fs::path path = write_sample(2);
  {
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE);
    db.exec("UPDATE meta SET value = 'fp16' WHERE key = 'precision'");
  }
  EXPECT_THAT([&] { TraceReader{path}; },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr(
                  "trace.db: meta precision: unknown precision 'fp16' (expected fp64|fp32)")));
  {
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE);
    db.exec("DELETE FROM meta WHERE key = 'precision'");
  }
  EXPECT_THAT([&] { TraceReader{path}; },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("lacks key 'precision'")));
  {
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE);
    db.exec("UPDATE meta SET value = '4' WHERE key = 'schema_version'");
  }
  const TraceReader reader(path);
  EXPECT_EQ(trace_precision(reader.meta()), Precision::kFp64);
}

TEST_F(TraceTest, ReaderRejectsChangedLayout) {
  const fs::path path = write_sample(2);
  {
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE);
    db.exec("ALTER TABLE ops ADD COLUMN extra INTEGER");
  }
  EXPECT_THAT([&] { TraceReader{path}; },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("table ops does not match")));
}

TEST_F(TraceTest, ReaderNamesTheBadRow) {
  const fs::path path = write_sample(3);
  {
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE);
    db.exec("UPDATE tasks SET task = 'XX' WHERE frame_id = 2 AND seq = 1");
  }
  TraceReader reader(path);
  EXPECT_THAT([&] { reader.read_all(); }, ::testing::ThrowsMessage<std::runtime_error>(HasSubstr(
                                              "tasks row (frame 2, seq 1): unknown task 'XX'")));
}

TEST_F(TraceTest, ReaderNamesTheBadRowOfEachTableAndColumn) {
  // The row's place is formatted only when a check fails: each table's still names its row.
  const auto error_after = [&](const std::string& sql) {
    fs::remove(dir_ / "trace.db");
    const fs::path path = write_sample(3);
    {
      SQLite::Database db(path.string(), SQLite::OPEN_READWRITE);
      db.exec(sql);
    }
    try {
      TraceReader(path).read_all();
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error_after("UPDATE frames SET frontend_host_ns = -5 WHERE frame_id = 1"),
              HasSubstr("frames row 1: column frontend_host_ns is negative (-5)"));
  EXPECT_THAT(error_after("UPDATE frames SET gps_available = 2 WHERE frame_id = 0"),
              HasSubstr("frames row 0: column gps_available must be 0 or 1, is 2"));
  EXPECT_THAT(error_after("UPDATE tasks SET pixels = 'many' WHERE frame_id = 1 AND seq = 0"),
              HasSubstr("tasks row (frame 1, seq 0): column pixels is not an integer"));
  EXPECT_THAT(error_after("UPDATE kernels SET kernel = x'41' WHERE frame_id = 2 AND seq = 1"),
              HasSubstr("kernels row (frame 2, seq 1): column kernel is not text"));
  EXPECT_THAT(error_after("UPDATE ops SET m = -1 WHERE frame_id = 0 AND kernel_seq = 1"),
              HasSubstr("ops row (frame 0, kernel 1, seq 0): column m is negative (-1)"));
  EXPECT_THAT(error_after("UPDATE tasks SET per_level = '[{}' WHERE frame_id = 0 AND seq = 0"),
              HasSubstr("tasks row (frame 0, seq 0): per_level is not a JSON array"));
}

TEST(PerLevelCodec, TheWritersTextAndOtherJsonDecodeAlike) {
  const std::vector<LevelWork> levels = {{0, 1280, 720, 921600, 35, 140},
                                         {1, 640, 360, 230400, 0, 0},
                                         {-3, 2147483647, -2147483648, 0, -7, 999999999999}};
  const std::string text = encode_per_level(levels);
  EXPECT_TRUE(text.starts_with(R"([{"height":720,"iterations":140,"level":0,"pixels":921600,)"))
      << text;
  EXPECT_EQ(decode_per_level(text), levels);  // the writer's own text (read without a parser)
  EXPECT_TRUE(decode_per_level("[]").empty());
  // Text the writer does not produce goes through the JSON parser, to the same values.
  EXPECT_EQ(decode_per_level(R"([ {"level":0,"width":1280,"height":720,"pixels":921600,)"
                             R"("points":35,"iterations":140} ])"),
            std::vector<LevelWork>{levels[0]});
  EXPECT_EQ(decode_per_level(R"([{"height":720,"iterations":-0,"level":0,"pixels":921600,)"
                             R"("points":35,"width":1280}])")
                .at(0)
                .iterations,
            0);
  EXPECT_EQ(decode_per_level(R"([{"height":720,"iterations":1.0,"level":0,"pixels":9,)"
                             R"("points":35,"width":1280}])")
                .at(0)
                .iterations,
            1);
  // And what the parser refuses is refused.
  for (const char* bad : {"[", "[{}",
                          R"([{"height":07,"iterations":1,"level":0,"pixels":9,)"
                          R"("points":35,"width":1280}])",
                          R"([{"height":7,"iterations":1,"level":0,"pixels":9,"points":35,)"
                          R"("width":1280}] x)",
                          "{}"}) {
    EXPECT_THROW(decode_per_level(bad), std::invalid_argument) << bad;
  }
  EXPECT_THROW(decode_per_level(R"([{"level":0}])"), std::invalid_argument);
}

TEST_F(TraceTest, ReaderRejectsNonIncreasingTimestamps) {
  const fs::path path = write_sample(3);
  {
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE);
    db.exec("UPDATE frames SET timestamp_ns = 1 WHERE frame_id = 2");
  }
  TraceReader reader(path);
  EXPECT_THAT([&] { reader.read_all(); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("frames row 2: timestamp 1")));
}

TEST_F(TraceTest, ReaderRejectsNonTrace) {
  const fs::path path = dir_ / "other.db";
  {
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    db.exec("CREATE TABLE t (x INTEGER)");
  }
  EXPECT_THAT([&] { TraceReader{path}; },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("not an edx trace")));
  EXPECT_THAT([&] { TraceReader{dir_ / "missing.db"}; },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("no such trace file")));
}

}  // namespace
}  // namespace edx::trace
