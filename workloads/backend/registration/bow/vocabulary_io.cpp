// The vocabulary file (docs/BOW.md), all integers little-endian:
//   magic       8 bytes  "EDXVOCAB"
//   version     u32      1
//   branching   u32      k
//   depth       u32      L
//   node_count  u32      nodes including the root
//   node_count times, in node order (breadth first, parents before children):
//     parent      u32      0xFFFFFFFF for the root
//     descriptor  32 bytes the ORB bytes (zero for the root)
//     weight      f64      IEEE 754 binary64 bits as u64: idf for leaves, 0 otherwise
#include <fmt/format.h>
#include <unistd.h>

#include <bit>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string_view>

#include "common/atomic_file.hpp"
#include "workloads/backend/registration/bow/vocabulary.hpp"

namespace edx::bow {
namespace {

constexpr std::string_view kMagic{"EDXVOCAB", 8};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 8 + 4 * 4;
constexpr std::size_t kNodeBytes = 4 + 32 + 8;

void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

void put_u64(std::string& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

/// Reads little-endian fields from the file's bytes; names the file and offset when short.
class Reader {
 public:
  Reader(const std::string& bytes, std::string file) : bytes_(bytes), file_(std::move(file)) {}

  void need(std::size_t n, std::string_view what) const {
    if (bytes_.size() - offset_ < n) {
      throw std::runtime_error(fmt::format(
          "{}: truncated vocabulary file: expected {} ({} bytes) at offset {}, found {} bytes",
          file_, what, n, offset_, bytes_.size() - offset_));
    }
  }
  std::uint32_t u32(std::string_view what) {
    need(4, what);
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) {
      v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes_[offset_ + i])) << (8 * i);
    }
    offset_ += 4;
    return v;
  }
  std::uint64_t u64(std::string_view what) {
    need(8, what);
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) {
      v |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes_[offset_ + i])) << (8 * i);
    }
    offset_ += 8;
    return v;
  }
  std::string_view bytes(std::size_t n, std::string_view what) {
    need(n, what);
    std::string_view out(bytes_.data() + offset_, n);
    offset_ += n;
    return out;
  }
  std::size_t remaining() const { return bytes_.size() - offset_; }

 private:
  const std::string& bytes_;
  std::string file_;
  std::size_t offset_ = 0;
};

}  // namespace

void Vocabulary::save(const std::filesystem::path& path) const {
  if (empty()) throw std::runtime_error(path.string() + ": cannot save an empty vocabulary");
  std::string out;
  out.reserve(kHeaderBytes + nodes_.size() * kNodeBytes);
  out.append(kMagic);
  put_u32(out, kVersion);
  put_u32(out, static_cast<std::uint32_t>(branching_));
  put_u32(out, static_cast<std::uint32_t>(depth_));
  put_u32(out, static_cast<std::uint32_t>(nodes_.size()));
  for (const Node& node : nodes_) {
    put_u32(out, node.parent);
    const Descriptor d = unpack(node.descriptor);
    out.append(reinterpret_cast<const char*>(d.data()), d.size());
    put_u64(out, std::bit_cast<std::uint64_t>(node.weight));
  }

  common::write_file_atomically(path, out);  // readers never see a partial file
}

Vocabulary Vocabulary::load(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(file + ": cannot open vocabulary file");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw std::runtime_error(file + ": read failed");

  Reader reader(bytes, file);
  const std::string_view magic = reader.bytes(kMagic.size(), "magic \"EDXVOCAB\"");
  if (magic != kMagic) {
    throw std::runtime_error(file + ": not an edx vocabulary (expected magic \"EDXVOCAB\")");
  }
  const std::uint32_t version = reader.u32("version");
  if (version != kVersion) {
    throw std::runtime_error(
        fmt::format("{}: vocabulary version {}, expected {}", file, version, kVersion));
  }
  const std::uint32_t branching = reader.u32("branching");
  const std::uint32_t depth = reader.u32("depth");
  VocabularyOptions shape;
  shape.branching = static_cast<int>(std::min<std::uint32_t>(branching, 1000));
  shape.depth = static_cast<int>(std::min<std::uint32_t>(depth, 1000));
  try {
    shape.validate();
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(file + ": " + e.what());
  }
  const std::uint32_t node_count = reader.u32("node count");
  const std::size_t expected = static_cast<std::size_t>(node_count) * kNodeBytes;
  if (reader.remaining() != expected) {
    throw std::runtime_error(fmt::format(
        "{}: {} nodes need {} bytes after the header, found {} ({})", file, node_count, expected,
        reader.remaining(), reader.remaining() < expected ? "truncated" : "trailing bytes"));
  }
  std::vector<NodeId> parents(node_count);
  std::vector<PackedDescriptor> descriptors(node_count);
  std::vector<double> weights(node_count);
  for (std::uint32_t i = 0; i < node_count; ++i) {
    parents[i] = reader.u32("node parent");
    Descriptor d;
    std::memcpy(d.data(), reader.bytes(d.size(), "node descriptor").data(), d.size());
    descriptors[i] = pack(d);
    weights[i] = std::bit_cast<double>(reader.u64("node weight"));
  }
  return from_nodes(shape.branching, shape.depth, std::move(parents), std::move(descriptors),
                    std::move(weights), file);
}

}  // namespace edx::bow
