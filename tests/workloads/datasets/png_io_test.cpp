// The PNG module (workloads/datasets/png_io.hpp) against OpenCV's imgcodecs, the independent
// reference it replaces: every PNG kind a dataset may hold decodes to cv::imdecode's gray pixels,
// and the writer gives cv::imwrite's bytes.
#include "workloads/datasets/png_io.hpp"

#include <gtest/gtest.h>
#include <png.h>
#include <zlib.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "tests/support/error_of.hpp"
#include "tests/workloads/datasets/tiny_datasets.hpp"

namespace edx::datasets {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;

/// A PNG made with libpng from raw (packed, big-endian) rows: the kinds cv::imencode cannot make.
struct RawPng {
  int width = 0;
  int height = 0;
  int bit_depth = 8;
  int color_type = PNG_COLOR_TYPE_GRAY;
  bool interlaced = false;
  std::vector<png_color> palette;   ///< PLTE, for PNG_COLOR_TYPE_PALETTE
  Bytes palette_alpha;              ///< tRNS of a palette image
  std::optional<png_color_16> key;  ///< tRNS of a gray or RGB image (the transparent colour)
  std::vector<Bytes> rows;          ///< as stored, before filtering
};

RawPng raw_png(int width, int height, int bit_depth, int color_type) {
  RawPng png;
  png.width = width;
  png.height = height;
  png.bit_depth = bit_depth;
  png.color_type = color_type;
  return png;
}

int channels_of(int color_type) {
  switch (color_type) {
    case PNG_COLOR_TYPE_GRAY_ALPHA:
      return 2;
    case PNG_COLOR_TYPE_RGB:
      return 3;
    case PNG_COLOR_TYPE_RGB_ALPHA:
      return 4;
    default:
      return 1;  // gray, palette
  }
}

/// Random rows (any byte is a valid sample; palettes below have 2^bit_depth entries).
RawPng random_png(int width, int height, int bit_depth, int color_type, std::uint32_t seed) {
  RawPng png = raw_png(width, height, bit_depth, color_type);
  std::mt19937 rng(seed);
  const std::size_t row_bytes =
      (static_cast<std::size_t>(width) * channels_of(color_type) * bit_depth + 7) / 8;
  for (int y = 0; y < height; ++y) {
    Bytes row(row_bytes);
    for (auto& b : row) b = static_cast<unsigned char>(rng() & 0xff);
    png.rows.push_back(std::move(row));
  }
  if (color_type == PNG_COLOR_TYPE_PALETTE) {
    for (int i = 0; i < (1 << bit_depth); ++i) {
      png.palette.push_back({static_cast<png_byte>(rng() & 0xff),
                             static_cast<png_byte>(rng() & 0xff),
                             static_cast<png_byte>(rng() & 0xff)});
    }
  }
  return png;
}

void append(png_structp png, png_bytep data, std::size_t size) {
  auto* out = static_cast<Bytes*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + size);
}

/// Encodes with libpng's defaults (a libpng error aborts the test binary: no setjmp here).
Bytes encode(const RawPng& raw) {
  Bytes out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_set_write_fn(png, &out, append, nullptr);
  png_set_IHDR(png, info, static_cast<png_uint_32>(raw.width), static_cast<png_uint_32>(raw.height),
               raw.bit_depth, raw.color_type,
               raw.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (!raw.palette.empty()) {
    png_set_PLTE(png, info, raw.palette.data(), static_cast<int>(raw.palette.size()));
  }
  if (!raw.palette_alpha.empty()) {
    png_set_tRNS(png, info, raw.palette_alpha.data(), static_cast<int>(raw.palette_alpha.size()),
                 nullptr);
  }
  if (raw.key) {
    png_color_16 key = *raw.key;
    png_set_tRNS(png, info, nullptr, 0, &key);
  }
  png_write_info(png, info);
  std::vector<png_bytep> rows;
  for (const Bytes& row : raw.rows) rows.push_back(const_cast<png_bytep>(row.data()));
  png_write_image(png, rows.data());
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return out;
}

cv::Mat random_mat(int rows, int cols, int type, std::uint32_t seed) {
  cv::Mat m(rows, cols, type);
  cv::theRNG().state = seed;
  cv::randu(m, 0, CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256);
  return m;
}

Bytes imencode(const cv::Mat& image, const std::vector<int>& params = {}) {
  Bytes bytes;
  EXPECT_TRUE(cv::imencode(".png", image, bytes, params));
  return bytes;
}

/// Our decoder gives cv::imdecode(..., IMREAD_GRAYSCALE)'s pixels exactly (and prints nothing).
void expect_as_opencv(const Bytes& bytes, const std::string& kind) {
  SCOPED_TRACE(kind);
  ::testing::internal::CaptureStderr();
  const cv::Mat ours = decode_png_gray(bytes, kind + ".png");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  const cv::Mat reference = cv::imdecode(bytes, cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(reference.empty());
  ASSERT_EQ(ours.type(), CV_8UC1);
  ASSERT_EQ(ours.size(), reference.size());
  EXPECT_EQ(cv::norm(ours, reference, cv::NORM_INF), 0);
}

TEST(PngIo, EveryKindDecodesToOpenCvsGrayPixels) {
  // Odd sizes: partial bytes of packed rows, and Adam7 passes of unequal lengths.
  const int w = 37;
  const int h = 23;
  // Kinds cv::imencode makes: 8/16-bit gray, RGB, RGBA, and 1-bit gray (IMWRITE_PNG_BILEVEL).
  expect_as_opencv(imencode(random_mat(h, w, CV_8UC1, 1)), "gray8");
  expect_as_opencv(imencode(random_mat(h, w, CV_16UC1, 2)), "gray16");
  expect_as_opencv(imencode(random_mat(h, w, CV_8UC3, 3)), "rgb8");
  expect_as_opencv(imencode(random_mat(h, w, CV_16UC3, 4)), "rgb16");
  expect_as_opencv(imencode(random_mat(h, w, CV_8UC4, 5)), "rgba8");
  expect_as_opencv(imencode(random_mat(h, w, CV_16UC4, 6)), "rgba16");
  cv::Mat bilevel = random_mat(h, w, CV_8UC1, 7);
  bilevel = (bilevel > 127) / 255;  // 0 or 1: the bit IMWRITE_PNG_BILEVEL stores
  expect_as_opencv(imencode(bilevel, {cv::IMWRITE_PNG_BILEVEL, 1}), "gray1_opencv");
  // Kinds made with libpng: gray+alpha, 1/2/4-bit gray, palettes, tRNS, Adam7.
  std::uint32_t seed = 100;
  for (const bool interlaced : {false, true}) {
    const std::string suffix = interlaced ? "_adam7" : "";
    for (const auto& [depth, type, name] :
         std::vector<std::tuple<int, int, std::string>>{{1, PNG_COLOR_TYPE_GRAY, "gray1"},
                                                        {2, PNG_COLOR_TYPE_GRAY, "gray2"},
                                                        {4, PNG_COLOR_TYPE_GRAY, "gray4"},
                                                        {8, PNG_COLOR_TYPE_GRAY, "gray8"},
                                                        {16, PNG_COLOR_TYPE_GRAY, "gray16"},
                                                        {8, PNG_COLOR_TYPE_GRAY_ALPHA, "ga8"},
                                                        {16, PNG_COLOR_TYPE_GRAY_ALPHA, "ga16"},
                                                        {8, PNG_COLOR_TYPE_RGB, "rgb8"},
                                                        {16, PNG_COLOR_TYPE_RGB, "rgb16"},
                                                        {8, PNG_COLOR_TYPE_RGB_ALPHA, "rgba8"},
                                                        {1, PNG_COLOR_TYPE_PALETTE, "pal1"},
                                                        {4, PNG_COLOR_TYPE_PALETTE, "pal4"},
                                                        {8, PNG_COLOR_TYPE_PALETTE, "pal8"}}) {
      RawPng raw = random_png(w, h, depth, type, ++seed);
      raw.interlaced = interlaced;
      expect_as_opencv(encode(raw), name + suffix);
    }
    // tRNS: a palette's alpha table (shorter than the palette), a gray key, an RGB key.
    RawPng pal = random_png(w, h, 8, PNG_COLOR_TYPE_PALETTE, ++seed);
    pal.interlaced = interlaced;
    pal.palette_alpha = {0, 128, 255, 7};
    expect_as_opencv(encode(pal), "pal8_trns" + suffix);
    RawPng gray = random_png(w, h, 4, PNG_COLOR_TYPE_GRAY, ++seed);
    gray.interlaced = interlaced;
    gray.key = png_color_16{0, 0, 0, 0, 5};
    expect_as_opencv(encode(gray), "gray4_trns" + suffix);
    RawPng rgb = random_png(w, h, 8, PNG_COLOR_TYPE_RGB, ++seed);
    rgb.interlaced = interlaced;
    rgb.key = png_color_16{0, rgb.rows[0][0], rgb.rows[0][1], rgb.rows[0][2], 0};
    expect_as_opencv(encode(rgb), "rgb8_trns" + suffix);
  }
}

/// Hand-computed pixels, independent of OpenCV: libpng's fixed-point gray of RGB from the
/// coefficients 0.299 and 0.587 (9797, 19234 and 32768 - 9797 - 19234 = 3737 of 2^15), the high
/// byte of 16-bit samples, 2-bit gray scaled to 0..255 (v * 85), the gray under an alpha.
TEST(PngIo, PixelsAreTheHandComputedOnes) {
  RawPng rgb = raw_png(3, 1, 8, PNG_COLOR_TYPE_RGB);
  rgb.rows = {{255, 0, 0, 0, 255, 0, 10, 200, 30}};
  const cv::Mat g = decode_png_gray(encode(rgb), "rgb.png");
  EXPECT_EQ(g.at<unsigned char>(0, 0), (9797 * 255) >> 15);                           // 76
  EXPECT_EQ(g.at<unsigned char>(0, 1), (19234 * 255) >> 15);                          // 149
  EXPECT_EQ(g.at<unsigned char>(0, 2), (9797 * 10 + 19234 * 200 + 3737 * 30) >> 15);  // 123
  RawPng gray16 = raw_png(2, 1, 16, PNG_COLOR_TYPE_GRAY);
  gray16.rows = {{0x12, 0xff, 0xab, 0x01}};
  const cv::Mat g16 = decode_png_gray(encode(gray16), "g16.png");
  EXPECT_EQ(g16.at<unsigned char>(0, 0), 0x12);
  EXPECT_EQ(g16.at<unsigned char>(0, 1), 0xab);
  RawPng gray2 = raw_png(4, 1, 2, PNG_COLOR_TYPE_GRAY);
  gray2.rows = {{0b00011011}};  // 0, 1, 2, 3
  const cv::Mat g2 = decode_png_gray(encode(gray2), "g2.png");
  const cv::Mat expected = (cv::Mat_<unsigned char>(1, 4) << 0, 85, 170, 255);
  EXPECT_EQ(cv::norm(g2, expected, cv::NORM_INF), 0);
  RawPng ga = raw_png(2, 1, 8, PNG_COLOR_TYPE_GRAY_ALPHA);
  ga.rows = {{77, 0, 201, 255}};
  const cv::Mat gga = decode_png_gray(encode(ga), "ga.png");
  EXPECT_EQ(gga.at<unsigned char>(0, 0), 77);
  EXPECT_EQ(gga.at<unsigned char>(0, 1), 201);
}

TEST(PngIo, WriterGivesCvImwritesBytes) {
  const testing::TempFolder folder("png_io");
  for (const cv::Size size : {cv::Size(37, 23), cv::Size(752, 480), cv::Size(1, 1)}) {
    SCOPED_TRACE(size);
    const cv::Mat image = random_mat(size.height, size.width, CV_8UC1, 11);
    const std::vector<int> params = {cv::IMWRITE_PNG_STRATEGY,
                                     cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY};
    EXPECT_EQ(encode_png_gray(image), imencode(image, params));
    const fs::path ours = folder.path() / "ours.png";
    const fs::path theirs = folder.path() / "theirs.png";
    write_png_gray(ours, image);
    ASSERT_TRUE(cv::imwrite(theirs.string(), image, params));
    const auto read = [](const fs::path& p) {
      std::ifstream in(p, std::ios::binary);
      return Bytes(std::istreambuf_iterator<char>(in), {});
    };
    EXPECT_EQ(read(ours), read(theirs));
    EXPECT_EQ(cv::norm(cv::imread(ours.string(), cv::IMREAD_UNCHANGED), image, cv::NORM_INF), 0);
  }
  // A view into a wider image (rows not contiguous) is written as its own pixels.
  const cv::Mat wide = random_mat(20, 50, CV_8UC1, 12);
  const cv::Mat view = wide(cv::Rect(3, 2, 30, 15));
  EXPECT_EQ(cv::norm(decode_png_gray(encode_png_gray(view), "view.png"), view, cv::NORM_INF), 0);
  EXPECT_EQ(encode_png_gray(view), imencode(view.clone(), {cv::IMWRITE_PNG_STRATEGY,
                                                           cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY}));
}

using edx::testing::error_of;

/// Rewrites the CRC-32 of the chunk at `at` (after its data was changed on purpose).
void fix_crc(Bytes& png, std::size_t at) {
  const std::uint32_t length = (std::uint32_t{png[at]} << 24) | (std::uint32_t{png[at + 1]} << 16) |
                               (std::uint32_t{png[at + 2]} << 8) | png[at + 3];
  const uLong crc = crc32(crc32(0L, Z_NULL, 0), &png[at + 4], length + 4);
  for (int i = 0; i < 4; ++i)
    png[at + 8 + length + i] = static_cast<unsigned char>(crc >> (24 - 8 * i));
}

TEST(PngIo, BadInputIsOneLineNamingTheFile) {
  EXPECT_EQ(error_of([] {
              decode_png_gray(Bytes{'G', 'I', 'F', '8', '9', 'a', 0, 0, 0}, "a.gif");
            }),
            "a.gif: cannot read image: not a PNG file (expected a PNG image)");
  const Bytes jpeg = [] {
    Bytes b;
    cv::imencode(".jpg", cv::Mat(8, 8, CV_8UC1, cv::Scalar(3)), b);
    return b;
  }();
  EXPECT_EQ(error_of([&] { decode_png_gray(jpeg, "x.jpg"); }),
            "x.jpg: cannot read image: not a PNG file (expected a PNG image)");
  // Damage that the chunks' CRC-32s do not see (they are made to hold): libpng's own error,
  // ours in one line, nothing printed.
  const Bytes good = imencode(random_mat(24, 32, CV_8UC1, 13));
  ASSERT_EQ(std::string(good.begin() + 37, good.begin() + 41), "IDAT");
  Bytes deflate = good;
  deflate[41] ^= 0xff;  // the zlib header of the IDAT data
  fix_crc(deflate, 33);
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(
      error_of([&] { decode_png_gray(deflate, "z.png"); }).rfind("z.png: damaged PNG (libpng: ", 0),
      0u);
  Bytes depth = good;
  depth[24] = 3;  // IHDR bit depth 3: not a PNG bit depth
  fix_crc(depth, 8);
  EXPECT_EQ(
      error_of([&] { decode_png_gray(depth, "d.png"); }).rfind("d.png: damaged PNG (libpng: ", 0),
      0u);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  // A header asking for more than OpenCV's 2^30 pixels is refused before any allocation.
  Bytes huge = good;
  const std::uint32_t width = 1000000, height = 1100;
  for (int i = 0; i < 4; ++i) {
    huge[16 + i] = static_cast<unsigned char>(width >> (24 - 8 * i));
    huge[20 + i] = static_cast<unsigned char>(height >> (24 - 8 * i));
  }
  fix_crc(huge, 8);
  EXPECT_EQ(error_of([&] { decode_png_gray(huge, "h.png"); }),
            "h.png: PNG image of 1000000x1100 pixels, more than the 2^30 allowed");
  EXPECT_NE(error_of([] { encode_png_gray(cv::Mat(4, 4, CV_8UC3)); }).find("8-bit gray"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              write_png_gray("/nonexistent-dir/x.png", cv::Mat(4, 4, CV_8UC1));
            }).find("/nonexistent-dir/x.png"),
            std::string::npos);
}

}  // namespace
}  // namespace edx::datasets
