// Fuzzes the PNG decoder (workloads/datasets/png_io.hpp) with the file's bytes: a rejection must
// be a std::runtime_error (libpng's errors turned into ours, nothing printed, no abort); what
// decodes is encoded again and must decode to the same pixels. The chunks' CRC-32s are made to
// hold first, so that mutations reach libpng instead of stopping at the decoder's CRC check
// (which the unit tests cover: tests/workloads/datasets/bad_input_test.cpp).
#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <exception>
#include <span>
#include <vector>

#include "workloads/datasets/png_io.hpp"

namespace {

/// Rewrites the CRC-32 of every whole chunk after the 8-byte signature (length, type, data, CRC).
void fix_crcs(std::vector<unsigned char>& png) {
  std::size_t at = 8;
  while (png.size() >= at + 12) {
    const std::uint64_t length =
        (std::uint64_t{png[at]} << 24) | (png[at + 1] << 16) | (png[at + 2] << 8) | png[at + 3];
    if (length > png.size() - at - 12) return;
    const uLong crc = crc32(crc32(0L, Z_NULL, 0), &png[at + 4], static_cast<uInt>(length + 4));
    for (int i = 0; i < 4; ++i) {
      png[at + 8 + length + i] = static_cast<unsigned char>(crc >> (24 - 8 * i));
    }
    at += 12 + length;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<unsigned char> png(data, data + size);
  fix_crcs(png);
  cv::Mat image;
  try {
    image = edx::datasets::decode_png_gray(png, "fuzz.png");
  } catch (const std::runtime_error&) {
    return 0;
  }
  const std::vector<unsigned char> again = edx::datasets::encode_png_gray(image);
  if (cv::norm(edx::datasets::decode_png_gray(again, "again.png"), image, cv::NORM_INF) != 0) {
    std::abort();  // the writer and the reader disagree: a finding
  }
  return 0;
}
