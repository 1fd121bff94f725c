// Vocabulary files: save -> load round trip, the byte layout, and corrupted files rejected with
// errors naming the file and what was expected.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>

#include "tests/support/temp_dir.hpp"
#include "workloads/backend/registration/bow/vocabulary.hpp"

namespace edx::bow {
namespace {

namespace fs = std::filesystem;

Vocabulary small_vocabulary() {
  std::mt19937 rng(9);
  std::vector<Descriptor> descriptors(300);
  for (auto& d : descriptors) {
    for (auto& byte : d) byte = static_cast<std::uint8_t>(rng() & 0xFF);
  }
  VocabularyOptions options;
  options.branching = 4;
  options.depth = 3;
  Vocabulary voc = Vocabulary::create(descriptors, options);
  std::vector<std::vector<Descriptor>> images;
  for (std::size_t i = 0; i < descriptors.size(); i += 30) {
    images.emplace_back(descriptors.begin() + static_cast<std::ptrdiff_t>(i),
                        descriptors.begin() + static_cast<std::ptrdiff_t>(i + 30));
  }
  voc.set_idf(images);
  return voc;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

void put_u32(std::string& bytes, std::size_t offset, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes[offset + i] = static_cast<char>((v >> (8 * i)) & 0xFF);
}

/// Expects load(path) to throw a runtime_error whose message names the file and contains `what`.
void expect_rejected(const fs::path& path, const std::string& what) {
  try {
    Vocabulary::load(path);
    ADD_FAILURE() << "loaded a corrupted file, expected an error containing: " << what;
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
  }
}

class BowVocabularyFile : public ::testing::Test {
 protected:
  void SetUp() override {
    voc_ = small_vocabulary();
    path_ = dir_.path() / "voc.bin";
    voc_.save(path_);
    bytes_ = read_bytes(path_);
  }
  edx::testing::TempDir dir_;  // one per test: CTest runs the tests concurrently
  fs::path path_;
  Vocabulary voc_;
  std::string bytes_;
};

TEST_F(BowVocabularyFile, RoundTripIsExact) {
  const Vocabulary loaded = Vocabulary::load(path_);
  EXPECT_TRUE(loaded == voc_);
  EXPECT_EQ(loaded.word_count(), voc_.word_count());
  for (WordId w = 0; w < voc_.word_count(); ++w) {
    EXPECT_EQ(loaded.word_weight(w), voc_.word_weight(w));
  }
  Descriptor probe{};
  probe[3] = 0x5A;
  EXPECT_EQ(loaded.word_of(probe), voc_.word_of(probe));
  // No temporary file left beside it.
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir_.path())) ++files;
  EXPECT_EQ(files, 1u);
}

TEST_F(BowVocabularyFile, ByteLayout) {
  // 24-byte header + 44 bytes per node.
  ASSERT_EQ(bytes_.size(), 24 + 44 * voc_.node_count());
  EXPECT_EQ(bytes_.substr(0, 8), "EDXVOCAB");
  auto u32 = [&](std::size_t offset) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) {
      v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes_[offset + i])) << (8 * i);
    }
    return v;
  };
  EXPECT_EQ(u32(8), 1u);   // version
  EXPECT_EQ(u32(12), 4u);  // k
  EXPECT_EQ(u32(16), 3u);  // L
  EXPECT_EQ(u32(20), voc_.node_count());
  EXPECT_EQ(u32(24), 0xFFFFFFFFu);  // root's parent
  EXPECT_EQ(u32(24 + 44), 0u);      // node 1's parent: the root
  const Descriptor d1 = voc_.node_descriptor(1);
  EXPECT_EQ(bytes_.substr(24 + 44 + 4, 32), std::string(d1.begin(), d1.end()));
}

TEST_F(BowVocabularyFile, RejectsBadMagic) {
  std::string bytes = bytes_;
  bytes[0] = 'X';
  write_bytes(path_, bytes);
  expect_rejected(path_, "expected magic \"EDXVOCAB\"");
}

TEST_F(BowVocabularyFile, RejectsOtherVersion) {
  std::string bytes = bytes_;
  put_u32(bytes, 8, 2);
  write_bytes(path_, bytes);
  expect_rejected(path_, "version 2, expected 1");
}

TEST_F(BowVocabularyFile, RejectsTruncatedFiles) {
  write_bytes(path_, bytes_.substr(0, bytes_.size() - 10));
  expect_rejected(path_, "truncated");
  write_bytes(path_, bytes_.substr(0, 14));
  expect_rejected(path_, "truncated vocabulary file: expected branching");
  write_bytes(path_, "");
  expect_rejected(path_, "truncated vocabulary file: expected magic");
}

TEST_F(BowVocabularyFile, RejectsTrailingBytes) {
  write_bytes(path_, bytes_ + "x");
  expect_rejected(path_, "trailing bytes");
}

TEST_F(BowVocabularyFile, RejectsInconsistentTree) {
  std::string bytes = bytes_;
  put_u32(bytes, 24 + 44 * 2, 5);  // node 2's parent listed after it
  write_bytes(path_, bytes);
  expect_rejected(path_, "node 2 has parent 5, expected a parent listed before it");

  bytes = bytes_;
  put_u32(bytes, 12, 1);  // branching 1
  write_bytes(path_, bytes);
  expect_rejected(path_, "branching = 1, expected 2..64");

  bytes = bytes_;
  put_u32(bytes, 16, 1);  // depth 1 while nodes sit at level 3
  write_bytes(path_, bytes);
  expect_rejected(path_, "expected at most depth 1");

  bytes = bytes_;
  put_u32(bytes, 20, voc_.node_count() - 1);  // node count disagrees with the size
  write_bytes(path_, bytes);
  expect_rejected(path_, "trailing bytes");

  bytes = bytes_;
  bytes[24 + 44 - 1] = static_cast<char>(0xFF);  // root weight: bits of a NaN
  bytes[24 + 44 - 2] = static_cast<char>(0xFF);
  write_bytes(path_, bytes);
  expect_rejected(path_, "expected a finite value >= 0");
}

TEST_F(BowVocabularyFile, EmptyVocabularyIsNotSaved) {
  EXPECT_THROW(Vocabulary().save(dir_.path() / "empty.bin"), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir_.path() / "empty.bin"));
}

TEST_F(BowVocabularyFile, MissingFileNamed) {
  expect_rejected(dir_.path() / "absent.bin", "cannot open vocabulary file");
}

}  // namespace
}  // namespace edx::bow
