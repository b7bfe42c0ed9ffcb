// VTK XML files whose arrays are streamed a few values at a time (vtk_xml.hpp): the same
// bytes as the arrays given whole, binary arrays that decompress to the values pushed, a
// scratch file that leaves nothing behind, and a file without a path that writes nothing.
#include <gtest/gtest.h>

#include <unistd.h>
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "cdm/solver/io/vtk_xml.hpp"

namespace {

namespace fs = std::filesystem;
using cdm::vtk::Encoding;
using cdm::vtk::XmlFile;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct Arrays {
  std::vector<double> d;
  std::vector<std::int64_t> i64;
  std::vector<std::int32_t> i32;
};

Arrays sample() {
  Arrays a;
  // 3 × 30,000 doubles: 720,000 bytes, eleven blocks of 64 KiB and a partial one.
  for (std::size_t k = 0; k < 90000; ++k) a.d.push_back(1e-3 * static_cast<double>(k) + 1.0 / (1.0 + k));
  for (std::int64_t k = 0; k < 20000; ++k) a.i64.push_back(k * k - 7);
  for (std::int32_t k = 0; k < 5; ++k) a.i32.push_back(-k);
  return a;
}

void whole(const fs::path& path, Encoding e, const Arrays& a) {
  XmlFile f(path.string(), e, "PolyData");
  f.open("<Piece>");
  f.array("position", 3, a.d);
  f.array("id", 1, a.i64);
  f.array("material", 1, a.i32);
  f.array("empty", 3, std::vector<double>{});
  f.close("</Piece>");
  f.write();
}

// The same arrays pushed in uneven pieces.
template <class T>
void pieces(XmlFile& f, const std::vector<T>& v) {
  const std::size_t cuts[] = {1, 7, 8191, 3, 65536};
  std::size_t at = 0, c = 0;
  while (at < v.size()) {
    const std::size_t m = std::min(cuts[c++ % 5], v.size() - at);
    f.push(v.data() + at, m);
    at += m;
  }
}

void streamed(const fs::path& path, Encoding e, const Arrays& a) {
  XmlFile f(path.string(), e, "PolyData");
  f.open("<Piece>");
  f.begin_array("position", XmlFile::Type::float64, 3, a.d.size() / 3);
  pieces(f, a.d);
  f.end_array();
  f.begin_array("id", XmlFile::Type::int64, 1, a.i64.size());
  pieces(f, a.i64);
  f.end_array();
  f.begin_array("material", XmlFile::Type::int32, 1, a.i32.size());
  pieces(f, a.i32);
  f.end_array();
  f.begin_array("empty", XmlFile::Type::float64, 3, 0);
  f.end_array();
  f.close("</Piece>");
  f.write();
}

class VtkXml : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cdm-vtk-xml-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(VtkXml, StreamedArraysWriteTheSameBytesAsWholeOnes) {
  const Arrays a = sample();
  for (const Encoding e : {Encoding::binary, Encoding::ascii}) {
    whole(dir_ / "whole.vtp", e, a);
    streamed(dir_ / "streamed.vtp", e, a);
    const std::string w = slurp(dir_ / "whole.vtp"), s = slurp(dir_ / "streamed.vtp");
    EXPECT_GT(w.size(), 1000u);
    EXPECT_EQ(w, s) << (e == Encoding::binary ? "binary" : "ascii");
    // Nothing else in the directory: the scratch file of the binary arrays is gone.
    std::size_t files = 0;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      (void)entry;
      ++files;
    }
    EXPECT_EQ(files, 2u);
  }
}

TEST_F(VtkXml, BinaryArraysDecompressToTheValuesPushed) {
  const Arrays a = sample();
  streamed(dir_ / "f.vtp", Encoding::binary, a);
  const std::string s = slurp(dir_ / "f.vtp");
  // The first array's data: its header right after the '_' that opens the appended data.
  const std::size_t start = s.find("<AppendedData encoding=\"raw\">\n_");
  ASSERT_NE(start, std::string::npos);
  const char* p = s.data() + start + std::strlen("<AppendedData encoding=\"raw\">\n_");
  std::uint64_t head[3];
  std::memcpy(head, p, sizeof head);
  const std::uint64_t bytes = a.d.size() * sizeof(double), block = XmlFile::block_bytes;
  EXPECT_EQ(head[0], (bytes + block - 1) / block);
  EXPECT_EQ(head[1], block);
  EXPECT_EQ(head[2], bytes % block);
  std::vector<std::uint64_t> sizes(head[0]);
  std::memcpy(sizes.data(), p + sizeof head, sizes.size() * sizeof(std::uint64_t));
  const char* data = p + sizeof head + sizes.size() * sizeof(std::uint64_t);
  std::vector<double> back(a.d.size());
  auto* out = reinterpret_cast<Bytef*>(back.data());
  for (std::uint64_t b = 0; b < head[0]; ++b) {
    uLongf len = static_cast<uLongf>(std::min<std::uint64_t>(block, bytes - b * block));
    ASSERT_EQ(uncompress(out + b * block, &len, reinterpret_cast<const Bytef*>(data), static_cast<uLong>(sizes[b])), Z_OK);
    data += sizes[b];
  }
  EXPECT_EQ(back, a.d);
}

TEST_F(VtkXml, WithoutAPathNothingIsWritten) {
  const Arrays a = sample();
  XmlFile f("", Encoding::binary, "PolyData");
  EXPECT_FALSE(f.writes());
  // A process that only sends its values pushes none of them.
  f.begin_array("position", XmlFile::Type::float64, 3, a.d.size() / 3);
  f.end_array();
  f.array("id", 1, a.i64);
  f.write();
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(VtkXml, AnArrayTakesExactlyItsValues) {
  XmlFile f((dir_ / "f.vtp").string(), Encoding::binary, "PolyData");
  const std::vector<double> v(10, 1.0);
  f.begin_array("a", XmlFile::Type::float64, 1, 9);
  EXPECT_THROW(f.push(v.data(), 10), std::logic_error);
  f.push(v.data(), 8);
  EXPECT_THROW(f.end_array(), std::logic_error);  // one value short
  EXPECT_THROW(f.begin_array("b", XmlFile::Type::int64, 1, 1), std::logic_error);  // one still open
}

}  // namespace
