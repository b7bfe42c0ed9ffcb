// The checkpoint archive read from a file (a restart streams the state into place) gives
// exactly what the same bytes give from memory, across its buffer's boundaries, and
// refuses a length that runs past the data as the in-memory reader does.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <memory>
#include <vector>

#include "cdm/solver/archive.hpp"

namespace {

using cdm::ArchiveError;
using cdm::InArchive;
using cdm::OutArchive;

struct File {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f{std::tmpfile(), &std::fclose};
};

// Small values around vectors below, at and above the 64 KiB read buffer.
void write_sample(OutArchive& a) {
  for (std::uint64_t k = 0; k < 9000; ++k) a.put(k * 3 + 1);  // 72 kB of single values
  std::vector<double> big(100000);
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
  ASSERT_EQ(big.size(), 100000u);
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
  {
    InArchive mem(bytes.data(), bytes.size());
    read_sample(mem);
  }
  std::rewind(file.f.get());
  InArchive disk(file.f.get(), bytes.size());
  read_sample(disk);
  // Nothing is read past the archive's own bytes.
  EXPECT_EQ(std::ftell(file.f.get()), static_cast<long>(bytes.size()));
}

TEST(Archive, FileReaderRefusesWhatRunsPastItsBytes) {
  File file;
  OutArchive out(file.f.get());
  write_sample(out);
  const std::uint64_t size = out.size();
  // The archive cut short of its big vector's end: its length is refused before any read.
  std::rewind(file.f.get());
  InArchive cut(file.f.get(), 9000 * 8 + 8 + 1000);
  for (std::uint64_t k = 0; k < 9000; ++k) {
    std::uint64_t v = 0;
    cut.get(v);
  }
  std::vector<double> big;
  EXPECT_THROW(cut.get(big), ArchiveError);
  // A single value past the end.
  std::rewind(file.f.get());
  InArchive tail(file.f.get(), 4);
  std::uint64_t v = 0;
  EXPECT_THROW(tail.get(v), ArchiveError);
  // A file shorter than the archive's stated size: reading fails (where the reader
  // first asks for the missing bytes), it never takes them as zeros.
  std::rewind(file.f.get());
  InArchive longer(file.f.get(), size + 8);
  EXPECT_THROW(
      {
        read_sample(longer);
        longer.get(v);
      },
      ArchiveError);
}

}  // namespace
