#include "workloads/datasets/png_io.hpp"

#include <fmt/core.h>
#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>

#include "common/atomic_file.hpp"

namespace edx::datasets {
namespace {

constexpr std::array<unsigned char, 8> kPngSignature = {0x89, 'P',  'N',  'G',
                                                        '\r', '\n', 0x1a, '\n'};

/// OpenCV's default limit on decoded pixels (CV_IO_MAX_IMAGE_PIXELS, 2^30), kept so that the
/// same files are accepted and a forged header cannot ask for more than 1 GiB. libpng itself
/// refuses a width or height above 10^6.
constexpr std::uint64_t kMaxPixels = std::uint64_t{1} << 30;

std::uint32_t big_endian_u32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

/// Walks a PNG's chunks (PNG spec, sec. 5.3: length, type, data, CRC-32 of type and data) up to
/// IEND, so that a truncated or damaged file is named by where it breaks (libpng's own message
/// says only "Read Error" or "CRC error"). Anything else wrong (a damaged deflate stream under
/// valid CRCs, a bad header) is libpng's message, turned into ours by decode_png_gray.
void check_png_chunks(std::span<const unsigned char> bytes, const std::filesystem::path& file) {
  std::size_t at = kPngSignature.size();
  while (true) {
    if (bytes.size() - at < 12) {
      throw std::runtime_error(fmt::format(
          "{}: truncated PNG ({} bytes, ends before its IEND chunk)", file.string(), bytes.size()));
    }
    const std::uint64_t length = big_endian_u32(&bytes[at]);
    if (length > bytes.size() - at - 12) {
      throw std::runtime_error(fmt::format(
          "{}: truncated PNG ({} bytes; the chunk at byte {} declares {} bytes of data)",
          file.string(), bytes.size(), at, length));
    }
    const unsigned char* type = &bytes[at + 4];
    const uLong crc = ::crc32(::crc32(0L, Z_NULL, 0), type, static_cast<uInt>(length + 4));
    if (crc != big_endian_u32(type + 4 + length)) {
      throw std::runtime_error(
          fmt::format("{}: damaged PNG (the {} chunk at byte {} fails its CRC)", file.string(),
                      std::string(reinterpret_cast<const char*>(type), 4), at));
    }
    if (std::memcmp(type, "IEND", 4) == 0) return;
    at += 12 + length;
  }
}

/// What libpng's callbacks share with the caller: the bytes read or written and libpng's error
/// message. Errors leave libpng by png_longjmp to the setjmp of the stage that called it (see
/// read_header, read_pixels, encode_rows); nothing with a destructor lives between the two.
struct PngContext {
  std::span<const unsigned char> input;          ///< reading: the file's bytes
  std::size_t at = 0;                            ///< reading: bytes consumed
  std::vector<unsigned char>* output = nullptr;  ///< writing: the encoded bytes
  std::array<char, 256> error{};                 ///< libpng's message, when a stage failed
};

PngContext& context_of(png_structp png) {
  return *static_cast<PngContext*>(png_get_error_ptr(png));
}

/// libpng's error callback: keeps the message and leaves libpng (it must not return: libpng's
/// default handler would print the message to stderr).
[[noreturn]] void on_error(png_structp png, png_const_charp message) {
  std::snprintf(context_of(png).error.data(), context_of(png).error.size(), "%s", message);
  png_longjmp(png, 1);
}

/// libpng's warnings (an odd ancillary chunk, say) are not errors of the image: dropped, so that
/// nothing is printed.
void on_warning(png_structp, png_const_charp) {}

void read_from_memory(png_structp png, png_bytep out, std::size_t size) {
  PngContext& ctx = context_of(png);
  if (size > ctx.input.size() - ctx.at) png_error(png, "unexpected end of data");
  std::memcpy(out, ctx.input.data() + ctx.at, size);
  ctx.at += size;
}

void write_to_memory(png_structp png, png_bytep data, std::size_t size) {
  bool failed = false;
  try {
    context_of(png).output->insert(context_of(png).output->end(), data, data + size);
  } catch (const std::bad_alloc&) {
    failed = true;  // png_error (a longjmp) is called outside the handler
  }
  if (failed) png_error(png, "out of memory");
}

void flush_nothing(png_structp) {}

/// Owns a libpng read or write struct and its info struct.
class PngHandle {
 public:
  PngHandle(bool write, PngContext& ctx) : write_(write) {
    png_ = write ? png_create_write_struct(PNG_LIBPNG_VER_STRING, &ctx, on_error, on_warning)
                 : png_create_read_struct(PNG_LIBPNG_VER_STRING, &ctx, on_error, on_warning);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
    if (info_ == nullptr) {
      destroy();
      throw std::runtime_error("libpng: cannot create its structures (out of memory)");
    }
  }
  PngHandle(const PngHandle&) = delete;
  PngHandle& operator=(const PngHandle&) = delete;
  ~PngHandle() { destroy(); }
  png_structp png() const { return png_; }
  png_infop info() const { return info_; }

 private:
  void destroy() {
    if (png_ == nullptr) return;
    if (write_) {
      png_destroy_write_struct(&png_, info_ != nullptr ? &info_ : nullptr);
    } else {
      png_destroy_read_struct(&png_, info_ != nullptr ? &info_ : nullptr, nullptr);
    }
  }
  bool write_;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};

struct PngHeader {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int bit_depth = 0;
  int color_type = 0;
};

/// Stage 1: reads the chunks up to the image data; false (message in the context) on an error.
bool read_header(const PngHandle& h, PngContext& ctx, PngHeader& header) {
  if (setjmp(png_jmpbuf(h.png()))) return false;
  png_set_read_fn(h.png(), &ctx, read_from_memory);
  png_read_info(h.png(), h.info());
  png_get_IHDR(h.png(), h.info(), &header.width, &header.height, &header.bit_depth,
               &header.color_type, nullptr, nullptr, nullptr);
  return true;
}

/// Stage 2: the transformations of OpenCV 4.6's PngDecoder::readData for an 8-bit gray target,
/// called in its order, then the rows into `rows` (one pointer per row of `width` bytes).
bool read_pixels(const PngHandle& h, const PngHeader& header, png_bytepp rows) {
  if (setjmp(png_jmpbuf(h.png()))) return false;
  png_structp png = h.png();
  if (header.bit_depth == 16) png_set_strip_16(png);  // keep each sample's high byte
  png_set_strip_alpha(png);                           // gray+alpha, RGBA, tRNS: colour only
  if (header.color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if ((header.color_type & PNG_COLOR_MASK_COLOR) == 0 && header.bit_depth < 8) {
    png_set_expand_gray_1_2_4_to_8(png);
  }
  png_set_rgb_to_gray(png, PNG_ERROR_ACTION_NONE, 0.299, 0.587);  // a no-op on gray images
  png_set_interlace_handling(png);  // Adam7: libpng assembles the passes in place
  png_read_update_info(png, h.info());
  if (png_get_rowbytes(png, h.info()) != header.width) png_error(png, "not 8-bit gray after all");
  png_read_image(png, rows);
  png_read_end(png, nullptr);
  return true;
}

/// Encodes `rows` (8-bit gray, `width` x `height`) as OpenCV 4.6's PngEncoder::write does with
/// IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY and no IMWRITE_PNG_COMPRESSION: the same calls in the same
/// order, so zlib sees the same input with the same settings and gives the same bytes.
bool encode_rows(const PngHandle& h, PngContext& ctx, png_uint_32 width, png_uint_32 height,
                 png_bytepp rows) {
  if (setjmp(png_jmpbuf(h.png()))) return false;
  png_structp png = h.png();
  png_set_write_fn(png, &ctx, write_to_memory, flush_nothing);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_level(png, Z_BEST_SPEED);
  png_set_compression_strategy(png, Z_HUFFMAN_ONLY);
  png_set_IHDR(png, h.info(), width, height, 8, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, h.info());
  png_write_image(png, rows);
  png_write_end(png, h.info());
  return true;
}

/// Row pointers into a continuous or strided CV_8UC1 image (non-const because libpng's write
/// API takes them so, though it only reads them).
std::vector<png_bytep> row_pointers(const cv::Mat& image) {
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.rows));
  for (int y = 0; y < image.rows; ++y) {
    rows[static_cast<std::size_t>(y)] = const_cast<png_bytep>(image.ptr(y));
  }
  return rows;
}

/// True when `bytes` start with the 8-byte PNG signature (PNG spec, sec. 5.2).
bool has_png_signature(std::span<const unsigned char> bytes) {
  return bytes.size() >= kPngSignature.size() &&
         std::equal(kPngSignature.begin(), kPngSignature.end(), bytes.begin());
}

}  // namespace

cv::Mat decode_png_gray(std::span<const unsigned char> bytes, const std::filesystem::path& file) {
  if (!has_png_signature(bytes)) {
    throw std::runtime_error(
        fmt::format("{}: cannot read image: not a PNG file (expected a PNG image)", file.string()));
  }
  check_png_chunks(bytes, file);
  PngContext ctx;
  ctx.input = bytes;
  const PngHandle handle(false, ctx);
  const auto fail = [&] {
    return std::runtime_error(
        fmt::format("{}: damaged PNG (libpng: {})", file.string(), ctx.error.data()));
  };
  PngHeader header;
  if (!read_header(handle, ctx, header)) throw fail();
  if (std::uint64_t{header.width} * header.height > kMaxPixels) {
    throw std::runtime_error(
        fmt::format("{}: PNG image of {}x{} pixels, more than the 2^30 allowed", file.string(),
                    header.width, header.height));
  }
  cv::Mat image(static_cast<int>(header.height), static_cast<int>(header.width), CV_8UC1);
  std::vector<png_bytep> rows = row_pointers(image);
  if (!read_pixels(handle, header, rows.data())) throw fail();
  return image;
}

std::vector<unsigned char> encode_png_gray(const cv::Mat& image) {
  if (image.type() != CV_8UC1 || image.empty()) {
    throw std::runtime_error(
        fmt::format("encode_png_gray: expected a non-empty 8-bit gray image, "
                    "got type {} of {}x{}",
                    image.type(), image.cols, image.rows));
  }
  std::vector<unsigned char> bytes;
  PngContext ctx;
  ctx.output = &bytes;
  const PngHandle handle(true, ctx);
  std::vector<png_bytep> rows = row_pointers(image);
  if (!encode_rows(handle, ctx, static_cast<png_uint_32>(image.cols),
                   static_cast<png_uint_32>(image.rows), rows.data())) {
    throw std::runtime_error(fmt::format("cannot encode PNG: {}", ctx.error.data()));
  }
  return bytes;
}

void write_png_gray(const std::filesystem::path& file, const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  try {
    bytes = encode_png_gray(image);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("{}: cannot write image: {}", file.string(), e.what()));
  }
  common::write_file(file,
                     std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace edx::datasets
