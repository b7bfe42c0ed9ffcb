#include "cdm/solver/io/vtk_xml.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "cdm/solver/io/durable_file.hpp"

namespace cdm::vtk {

static_assert(std::endian::native == std::endian::little, "the files declare byte_order=\"LittleEndian\"");

namespace {

/// Text of @p n values, @p components to a line, each as @p fmt formats it.
template <class T, class Fmt>
std::string ascii_values(const std::vector<T>& v, int components, Fmt fmt) {
  std::string s;
  char buf[40];
  for (std::size_t k = 0; k < v.size(); ++k) {
    fmt(buf, sizeof buf, v[k]);
    s += buf;
    s += (k + 1) % static_cast<std::size_t>(components) ? ' ' : '\n';
  }
  return s;
}

void put_u64(std::string& out, std::uint64_t v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }

/// @p bytes of @p data as VTK's zlib compressor writes them: the UInt64 block header,
/// then each block deflated on its own.
void compress_blocks(std::string& out, const void* data, std::size_t bytes) {
  const std::size_t block = XmlFile::block_bytes;
  const std::size_t nblocks = (bytes + block - 1) / block;
  const std::size_t header_at = out.size();
  put_u64(out, nblocks);
  put_u64(out, block);
  put_u64(out, bytes % block);
  for (std::size_t b = 0; b < nblocks; ++b) put_u64(out, 0);  // compressed sizes, filled in below
  const auto* src = static_cast<const Bytef*>(data);
  std::vector<Bytef> buf(compressBound(block));
  for (std::size_t b = 0; b < nblocks; ++b) {
    const std::size_t n = std::min(block, bytes - b * block);
    uLongf len = static_cast<uLongf>(buf.size());
    // Level 1: most of the gain of deflate on floating-point data at a fraction of the time.
    if (compress2(buf.data(), &len, src + b * block, static_cast<uLong>(n), 1) != Z_OK)
      throw std::runtime_error("zlib failed to compress a VTK array");
    out.append(reinterpret_cast<const char*>(buf.data()), len);
    const std::uint64_t c = len;
    std::memcpy(out.data() + header_at + (3 + b) * sizeof(std::uint64_t), &c, sizeof c);
  }
}

}  // namespace

XmlFile::XmlFile(Encoding encoding, std::string type, std::string dataset_attributes)
    : encoding_(encoding), type_(std::move(type)), dataset_attributes_(std::move(dataset_attributes)) {}

void XmlFile::line(const std::string& s) {
  body_ += s;
  body_ += '\n';
}

void XmlFile::element(const std::string& name, const char* type, int components, std::size_t tuples, const void* data,
                      std::size_t bytes, const std::string& ascii) {
  // NumberOfTuples: field data (TIME) is read as empty without it.
  std::string e = "<DataArray type=\"" + std::string(type) + "\" Name=\"" + name + "\" NumberOfComponents=\"" +
                  std::to_string(components) + "\" NumberOfTuples=\"" + std::to_string(tuples) + "\"";
  if (encoding_ == Encoding::ascii) {
    line(e + " format=\"ascii\">");
    body_ += ascii;
    line("</DataArray>");
    return;
  }
  line(e + " format=\"appended\" offset=\"" + std::to_string(appended_.size()) + "\"/>");
  compress_blocks(appended_, data, bytes);
}

namespace {
/// VTK's name of each element type and the printf format of its ASCII form.
template <class T> struct Element;
template <> struct Element<double> { static constexpr const char *type = "Float64", *format = "%.16e"; };
template <> struct Element<std::int64_t> { static constexpr const char *type = "Int64", *format = "%" PRId64; };
template <> struct Element<std::int32_t> { static constexpr const char *type = "Int32", *format = "%" PRId32; };
}  // namespace

template <class T>
void XmlFile::typed(const std::string& name, int components, const std::vector<T>& v) {
  const std::string ascii =
      encoding_ == Encoding::ascii
          ? ascii_values(v, components, [](char* b, std::size_t n, T x) { std::snprintf(b, n, Element<T>::format, x); })
          : std::string();
  element(name, Element<T>::type, components, v.size() / static_cast<std::size_t>(components), v.data(),
          v.size() * sizeof(T), ascii);
}

void XmlFile::array(const std::string& name, int components, const std::vector<double>& v) { typed(name, components, v); }
void XmlFile::array(const std::string& name, int components, const std::vector<std::int64_t>& v) {
  typed(name, components, v);
}
void XmlFile::array(const std::string& name, int components, const std::vector<std::int32_t>& v) {
  typed(name, components, v);
}

void XmlFile::strings(const std::string& name, const std::vector<std::string>& v) {
  // VTK's ASCII form of a string array: each string's bytes as numbers, then a 0.
  std::string s;
  for (const auto& str : v) {
    for (unsigned char c : str) s += std::to_string(c) + ' ';
    s += "0\n";
  }
  line("<Array type=\"String\" Name=\"" + name + "\" NumberOfTuples=\"" + std::to_string(v.size()) +
       "\" format=\"ascii\">");
  body_ += s;
  line("</Array>");
}

void XmlFile::write(const std::string& path) const {
  const bool bin = encoding_ == Encoding::binary;
  AtomicFile af(path);
  std::FILE* f = af.get();
  std::string head = "<?xml version=\"1.0\"?>\n<VTKFile type=\"" + type_ +
                     "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"" +
                     (bin ? " compressor=\"vtkZLibDataCompressor\"" : "") + ">\n<" + type_ +
                     (dataset_attributes_.empty() ? "" : " " + dataset_attributes_) + ">\n";
  std::string tail = "</" + type_ + ">\n";
  if (bin) tail += "<AppendedData encoding=\"raw\">\n_";
  bool ok = std::fwrite(head.data(), 1, head.size(), f) == head.size() &&
            std::fwrite(body_.data(), 1, body_.size(), f) == body_.size() &&
            std::fwrite(tail.data(), 1, tail.size(), f) == tail.size();
  if (bin) {
    const std::string end = "\n</AppendedData>\n";
    ok = ok && std::fwrite(appended_.data(), 1, appended_.size(), f) == appended_.size() &&
         std::fwrite(end.data(), 1, end.size(), f) == end.size();
  }
  ok = ok && std::fputs("</VTKFile>\n", f) >= 0;
  if (!ok) throw_output_error(path, "write", errno);
  af.commit();
}

}  // namespace cdm::vtk
