#pragma once
// 8-bit gray PNG reading and writing with libpng used directly: the one image format of the
// datasets (EuRoC, KITTI and what `edx gen` writes; docs/DATASETS.md). OpenCV's imgcodecs is
// not linked: it pulls ~140 shared libraries (GDAL, OpenEXR, Qt, ...) into every edx process,
// 0.05-0.07 s of CPU before main (issue 44, docs/BENCH.md).
#include <cstddef>
#include <filesystem>
#include <opencv2/core.hpp>
#include <span>
#include <vector>

namespace edx::datasets {

/// Decodes the PNG `bytes` (read from `file`, named in errors) to 8-bit gray (CV_8UC1), pixel
/// for pixel as OpenCV 4.6's cv::imdecode(bytes, cv::IMREAD_GRAYSCALE): the same libpng
/// transformations, so every PNG kind gives the same pixels. 16-bit samples keep their high byte
/// (png_set_strip_16), alpha and tRNS are dropped (png_set_strip_alpha; the colour under a
/// transparent pixel is kept), a palette is expanded to RGB, 1/2/4-bit gray is scaled to 8 bits
/// (v * 255 / (2^bits - 1)), and colour becomes gray in libpng's 15-bit fixed point from the
/// coefficients 0.299 and 0.587 OpenCV passes (each truncated, c * 32768 / 100000, blue the
/// rest): for 8-bit RGB, Y = (9797 R + 19234 G + 3737 B) >> 15, truncated, and R = G = B kept as
/// it is (16-bit colour is converted before its low byte is dropped). Adam7 interlacing is undone.
/// The chunks are walked to IEND with their CRC-32 first, so a truncated or damaged file is named
/// precisely. Throws std::runtime_error "<file>: ..." in one line; libpng never prints nor
/// aborts.
cv::Mat decode_png_gray(std::span<const unsigned char> bytes, const std::filesystem::path& file);

/// Encodes an 8-bit gray image (CV_8UC1) as the bytes cv::imwrite(file, image,
/// {IMWRITE_PNG_STRATEGY, IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY}) writes (OpenCV 4.6): libpng's SUB
/// filter on every row (each byte minus its left neighbour), zlib level 1 (Z_BEST_SPEED) with
/// the Huffman-only strategy, no interlacing, no ancillary chunks. Throws std::runtime_error on
/// an image that is not CV_8UC1 or empty.
std::vector<unsigned char> encode_png_gray(const cv::Mat& image);

/// Writes encode_png_gray(image) to `file` (in place, one write of the encoded bytes); throws
/// std::runtime_error "<file>: cannot write image: <reason>".
void write_png_gray(const std::filesystem::path& file, const cv::Mat& image);

}  // namespace edx::datasets
