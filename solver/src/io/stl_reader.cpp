#include "cdm/solver/io/stl_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace cdm {

namespace {

std::string triangle_text(std::size_t t) { return "triangle " + std::to_string(t + 1); }

/// Finite corners and a non-zero area, or the reason naming the triangle.
void check_triangle(const std::array<Vec3, 3>& c, std::size_t t, const std::string& name, const std::string& where) {
  for (const Vec3& v : c)
    if (!is_finite(v)) {
      std::ostringstream os;
      os << name << ": " << triangle_text(t) << where << " has a non-finite vertex (" << v.x << ", " << v.y << ", "
         << v.z << "): expected finite coordinates";
      throw StlError(os.str());
    }
  const Vec3 e0 = c[1] - c[0], e1 = c[2] - c[1], e2 = c[0] - c[2];
  const double longest2 = std::max({dot(e0, e0), dot(e1, e1), dot(e2, e2)});
  const double area2 = norm(cross(e0, c[2] - c[0]));  // twice the area
  // A relative test: a sliver whose normal is lost in rounding is as useless as zero area.
  if (!(area2 > 1e-12 * longest2)) {
    std::ostringstream os;
    os << name << ": " << triangle_text(t) << where << " has zero area (vertices (" << c[0].x << ", " << c[0].y << ", "
       << c[0].z << "), (" << c[1].x << ", " << c[1].y << ", " << c[1].z << "), (" << c[2].x << ", " << c[2].y << ", "
       << c[2].z << ")): expected three corners not on one line";
    throw StlError(os.str());
  }
}

std::vector<std::array<Vec3, 3>> parse_binary(const std::string& b, const std::string& name, std::uint32_t count) {
  std::vector<std::array<Vec3, 3>> tris(count);
  for (std::uint32_t t = 0; t < count; ++t) {
    float f[12];
    std::memcpy(f, b.data() + 84 + 50 * static_cast<std::size_t>(t), sizeof f);
    for (int k = 0; k < 3; ++k)
      tris[t][static_cast<std::size_t>(k)] = {f[3 + 3 * k], f[4 + 3 * k], f[5 + 3 * k]};
    check_triangle(tris[t], t, name, "");
  }
  return tris;
}

/// ASCII STL, token by token, with the line of each token for messages.
class AsciiStl {
 public:
  AsciiStl(const std::string& text, std::string name) : s_(text), name_(std::move(name)) {}

  std::vector<std::array<Vec3, 3>> parse() {
    std::vector<std::array<Vec3, 3>> tris;
    expect_word("solid", "the file to begin with 'solid'");
    skip_line();  // the solid's name, if any
    for (;;) {
      std::string w = next();
      if (w.empty()) fail_end(tris.size(), "'endsolid'");
      if (w == "endsolid") {
        skip_line();
        std::string more = next();
        if (more.empty()) break;
        if (more != "solid") fail(tris.size(), "'solid' or the end of the file", more);
        skip_line();
        continue;
      }
      const std::size_t t = tris.size();
      if (w != "facet") fail(t, "'facet' or 'endsolid'", w);
      expect_in(t, "normal");
      for (int k = 0; k < 3; ++k) number(t);
      expect_in(t, "outer");
      expect_in(t, "loop");
      std::array<Vec3, 3> c;
      for (int k = 0; k < 3; ++k) {
        expect_in(t, "vertex");
        const double x = number(t), y = number(t), z = number(t);
        c[static_cast<std::size_t>(k)] = {x, y, z};
      }
      expect_in(t, "endloop");
      expect_in(t, "endfacet");
      check_triangle(c, t, name_, " (line " + std::to_string(line_) + ")");
      tris.push_back(c);
    }
    return tris;
  }

 private:
  std::string next() {
    while (at_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[at_]))) {
      if (s_[at_] == '\n') ++line_;
      ++at_;
    }
    const std::size_t b = at_;
    while (at_ < s_.size() && !std::isspace(static_cast<unsigned char>(s_[at_]))) ++at_;
    return s_.substr(b, at_ - b);
  }
  void skip_line() {
    while (at_ < s_.size() && s_[at_] != '\n') ++at_;
  }
  [[noreturn]] void fail(std::size_t t, const std::string& expected, const std::string& found) const {
    std::ostringstream os;
    os << name_ << ": line " << line_ << ", in " << triangle_text(t) << ": expected " << expected << ", found '"
       << (found.size() > 40 ? found.substr(0, 40) + "..." : found) << "'";
    throw StlError(os.str());
  }
  [[noreturn]] void fail_end(std::size_t t, const std::string& expected) const {
    throw StlError(name_ + ": ends at line " + std::to_string(line_) + " in " + triangle_text(t) + " (expected " +
                   expected + "): the file is truncated");
  }
  void expect_word(const std::string& w, const std::string& what) {
    const std::string got = next();
    if (got != w) throw StlError(name_ + ": is not an STL file: expected " + what);
  }
  void expect_in(std::size_t t, const std::string& w) {
    const std::string got = next();
    if (got.empty()) fail_end(t, "'" + w + "'");
    if (got != w) fail(t, "'" + w + "'", got);
  }
  double number(std::size_t t) {
    const std::string tok = next();
    if (tok.empty()) fail_end(t, "a number");
    char* end = nullptr;
    const double v = std::strtod(tok.c_str(), &end);
    if (end != tok.c_str() + tok.size()) fail(t, "a number", tok);
    return v;
  }

  const std::string& s_;
  std::string name_;
  std::size_t at_ = 0;
  std::size_t line_ = 1;
};

}  // namespace

std::vector<std::array<Vec3, 3>> parse_stl(const std::string& b, const std::string& name) {
  if (b.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, b.data() + 80, 4);
    if (b.size() == 84 + 50 * static_cast<std::uint64_t>(count)) {
      if (count == 0) throw StlError(name + ": a binary STL with no triangles: expected at least one");
      return parse_binary(b, name, count);
    }
  }
  std::size_t first = 0;
  while (first < b.size() && std::isspace(static_cast<unsigned char>(b[first]))) ++first;
  if (b.compare(first, 5, "solid") == 0) {
    auto tris = AsciiStl(b, name).parse();
    if (tris.empty()) throw StlError(name + ": an ASCII STL with no triangles: expected at least one facet");
    return tris;
  }
  std::ostringstream os;
  os << name << ": is not an STL file: it does not begin with 'solid' (ASCII STL)";
  if (b.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, b.data() + 80, 4);
    os << ", and as binary STL its header counts " << count << " triangles, which take "
       << 84 + 50 * static_cast<std::uint64_t>(count) << " bytes, where the file has " << b.size()
       << " (truncated, or not STL)";
  } else {
    os << ", and at " << b.size() << " bytes it is shorter than a binary STL's 84-byte header";
  }
  throw StlError(os.str());
}

std::vector<std::array<Vec3, 3>> read_stl(const std::string& path) {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st)) throw StlError(path + ": cannot open the STL file (no such file)");
  if (!std::filesystem::is_regular_file(st)) throw StlError(path + ": is not a regular file: expected an STL file");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw StlError(path + ": cannot read the STL file's size (" + ec.message() + ")");
  if (size > max_stl_bytes)
    throw StlError(path + ": is " + std::to_string(size) + " bytes: expected an STL file of at most " +
                   std::to_string(max_stl_bytes) + " bytes");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw StlError(path + ": cannot open the STL file");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw StlError(path + ": cannot read the STL file");
  return parse_stl(bytes, path);
}

}  // namespace cdm
