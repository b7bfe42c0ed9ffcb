// The checkpoint archive read from a file (a restart streams the state into place) gives
// exactly what the same bytes give from memory, across its blocks' boundaries, refuses a
// length that runs past the data as the in-memory reader does, checks each block it reads
// against its checksum and reads no block it skips.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <vector>

#include "cdm/solver/archive.hpp"

namespace {

using cdm::ArchiveCorrupt;
using cdm::ArchiveError;
using cdm::BlockSums;
using cdm::checksum_block;
using cdm::InArchive;
using cdm::OutArchive;

struct File {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f{std::tmpfile(), &std::fclose};
};

// Small values around vectors of less and more than a block.
void write_sample(OutArchive& a) {
  for (std::uint64_t k = 0; k < 9000; ++k) a.put(k * 3 + 1);  // 72 kB of single values
  std::vector<double> big(200000);
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = 0.5 * static_cast<double>(i) - 7.0;
  a.put(big);
  a.put(std::uint8_t{7});
  a.put(std::vector<char>(65536, 'x'));
  a.put(std::vector<std::uint32_t>(3, 9));
  a.put(std::string("end"));
}

void read_sample(InArchive& a) {
  for (std::uint64_t k = 0; k < 9000; ++k) {
    std::uint64_t v = 0;
    a.get(v);
    ASSERT_EQ(v, k * 3 + 1);
  }
  std::vector<double> big;
  a.get(big);
  ASSERT_EQ(big.size(), 200000u);
  for (std::size_t i = 0; i < big.size(); ++i) ASSERT_EQ(big[i], 0.5 * static_cast<double>(i) - 7.0);
  std::uint8_t b = 0;
  a.get(b);
  EXPECT_EQ(b, 7);
  std::vector<char> x;
  a.get(x);
  EXPECT_EQ(x, std::vector<char>(65536, 'x'));
  std::vector<std::uint32_t> three;
  a.get(three);
  EXPECT_EQ(three, std::vector<std::uint32_t>(3, 9));
  std::string s;
  a.get(s);
  EXPECT_EQ(s, "end");
  EXPECT_TRUE(a.done());
}

std::vector<char> contents(std::FILE* f) {
  std::fseek(f, 0, SEEK_END);
  std::vector<char> bytes(static_cast<std::size_t>(std::ftell(f)));
  std::rewind(f);
  EXPECT_EQ(std::fread(bytes.data(), 1, bytes.size(), f), bytes.size());
  return bytes;
}

TEST(Archive, FileAndMemoryReadTheSameValues) {
  File file;
  OutArchive out(file.f.get());
  write_sample(out);
  ASSERT_FALSE(out.failed());
  const std::vector<char> bytes = contents(file.f.get());
  ASSERT_EQ(bytes.size(), out.size());
  ASSERT_GT(bytes.size(), checksum_block);
  {
    InArchive mem(bytes.data(), bytes.size());
    read_sample(mem);
  }
  // Each block's checksum is the checksum of its bytes, the last block shorter.
  const std::vector<std::uint64_t> sums = out.block_sums();
  ASSERT_EQ(sums.size(), BlockSums::blocks(bytes.size()));
  for (std::size_t b = 0; b < sums.size(); ++b) {
    const std::size_t start = b * checksum_block, n = std::min<std::size_t>(checksum_block, bytes.size() - start);
    EXPECT_EQ(sums[b], cdm::fnv1a64(bytes.data() + start, n)) << "block " << b;
  }
  const BlockSums blocks{0, bytes.size(), sums};
  InArchive disk(file.f.get(), blocks, 0, bytes.size());
  read_sample(disk);
  // Nothing is read past the archive's own bytes.
  EXPECT_EQ(std::ftell(file.f.get()), static_cast<long>(bytes.size()));
}

TEST(Archive, FileReaderRefusesWhatRunsPastItsBytes) {
  File file;
  OutArchive out(file.f.get());
  write_sample(out);
  const std::uint64_t size = out.size();
  const BlockSums blocks{0, size, out.block_sums()};
  // The archive cut short of its big vector's end: its length is refused before any read.
  InArchive cut(file.f.get(), blocks, 0, 9000 * 8 + 8 + 1000);
  for (std::uint64_t k = 0; k < 9000; ++k) {
    std::uint64_t v = 0;
    cut.get(v);
  }
  std::vector<double> big;
  EXPECT_THROW(cut.get(big), ArchiveError);
  // A single value past the end, and a skip past it.
  InArchive tail(file.f.get(), blocks, 0, 4);
  std::uint64_t v = 0;
  EXPECT_THROW(tail.get(v), ArchiveError);
  EXPECT_THROW(tail.skip(5), ArchiveError);
  // A range past the archive's end is refused as it is opened.
  EXPECT_THROW(InArchive(file.f.get(), blocks, 8, size), ArchiveError);
  // A file shorter than the archive's stated size: reading fails (where the reader
  // first asks for the missing bytes), it never takes them as zeros.
  const BlockSums longer_sums{0, size + 8, blocks.sums};
  InArchive longer(file.f.get(), longer_sums, 0, size + 8);
  EXPECT_THROW(
      {
        read_sample(longer);
        longer.get(v);
      },
      ArchiveError);
}

// A changed byte is found in the block that holds it, before any of that block's bytes
// are used; a reader that skips that block entirely never reads it and reads the rest.
TEST(Archive, BlocksReadAreCheckedAndBlocksSkippedAreNotRead) {
  File file;
  OutArchive out(file.f.get());
  const std::size_t n = 5 * checksum_block / sizeof(double);  // five blocks and a bit
  std::vector<double> values(n);
  for (std::size_t i = 0; i < n; ++i) values[i] = 1.0 + static_cast<double>(i);
  out.put(values);
  ASSERT_FALSE(out.failed());
  const BlockSums blocks{0, out.size(), out.block_sums()};
  ASSERT_EQ(blocks.sums.size(), 6u);
  // One byte of the third block changed.
  const long changed = static_cast<long>(2 * checksum_block + 100);
  std::fseek(file.f.get(), changed, SEEK_SET);
  const int byte = std::fgetc(file.f.get());
  std::fseek(file.f.get(), changed, SEEK_SET);
  std::fputc(byte ^ 0xff, file.f.get());
  std::fflush(file.f.get());
  const std::size_t changed_value = (changed - 8) / sizeof(double);
  {
    InArchive whole(file.f.get(), blocks, 0, blocks.bytes);
    std::vector<double> got;
    EXPECT_THROW(whole.get(got), ArchiveCorrupt);
  }
  // Values up to the third block's start, then past its end: the skip reads nothing.
  InArchive around(file.f.get(), blocks, 0, blocks.bytes);
  ASSERT_EQ(around.get_length(UINT64_MAX, sizeof(double)), n);
  const std::size_t before = (2 * checksum_block - 8) / sizeof(double);      // values wholly before it
  const std::size_t after = (3 * checksum_block - 8) / sizeof(double) + 1;  // the first wholly after it
  ASSERT_LT(before, changed_value);
  ASSERT_GT(after, changed_value);
  std::vector<double> got(n, 0.0);
  around.get_values(got.data(), before);
  around.skip((after - before) * sizeof(double));
  around.get_values(got.data() + after, n - after);
  EXPECT_TRUE(around.done());
  for (std::size_t i = 0; i < n; ++i) {
    if (i >= before && i < after) continue;
    ASSERT_EQ(got[i], values[i]) << "value " << i;
  }
  // A read of the one value that holds the changed byte is refused.
  InArchive one(file.f.get(), blocks, 8 + changed_value * sizeof(double), sizeof(double));
  double x = 0.0;
  EXPECT_THROW(one.get(x), ArchiveCorrupt);
}

TEST(Archive, RewindReadsTheSameValuesWithoutReadingTheKeptBlockAgain) {
  File file;
  OutArchive out(file.f.get());
  const std::vector<double> values{1.5, -2.25, 3.0};
  out.put(values);
  ASSERT_FALSE(out.failed());
  const BlockSums blocks{0, out.size(), out.block_sums()};
  InArchive a(file.f.get(), blocks, 0, blocks.bytes);
  double first = 0.0;
  ASSERT_EQ(a.get_length(UINT64_MAX, sizeof(double)), values.size());
  a.get(first);
  EXPECT_EQ(first, values[0]);
  // The file's only block changed after it was read: read again, it would not match.
  std::fseek(file.f.get(), 9, SEEK_SET);
  std::fputc(0x5a, file.f.get());
  std::fflush(file.f.get());
  a.rewind();
  std::vector<double> got;
  a.get(got);
  EXPECT_EQ(got, values);
  EXPECT_TRUE(a.done());
  InArchive fresh(file.f.get(), blocks, 0, blocks.bytes);
  EXPECT_THROW(fresh.get(got), ArchiveCorrupt);
  // In memory likewise, from its first byte.
  std::vector<char> bytes(static_cast<std::size_t>(blocks.bytes));
  std::fseek(file.f.get(), 0, SEEK_SET);
  ASSERT_EQ(std::fread(bytes.data(), 1, bytes.size(), file.f.get()), bytes.size());
  InArchive m(bytes.data(), bytes.size());
  std::uint64_t length = 0;
  m.get(length);
  m.rewind();
  m.get(got);
  EXPECT_EQ(got.size(), values.size());
  EXPECT_TRUE(m.done());
}

}  // namespace
