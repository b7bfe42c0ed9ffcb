#include "cdm/solver/io/vtk_xml.hpp"

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cinttypes>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "cdm/solver/io/durable_file.hpp"

namespace cdm::vtk {

static_assert(std::endian::native == std::endian::little, "the files declare byte_order=\"LittleEndian\"");

namespace {
/// VTK's name of each element type and the printf format of its ASCII form.
const char* type_name(XmlFile::Type t) {
  return t == XmlFile::Type::float64 ? "Float64" : t == XmlFile::Type::int64 ? "Int64" : "Int32";
}
std::size_t type_bytes(XmlFile::Type t) { return t == XmlFile::Type::int32 ? 4 : 8; }
void format(char* b, std::size_t n, double x) { std::snprintf(b, n, "%.16e", x); }
void format(char* b, std::size_t n, std::int64_t x) { std::snprintf(b, n, "%" PRId64, x); }
void format(char* b, std::size_t n, std::int32_t x) { std::snprintf(b, n, "%" PRId32, x); }
template <class T> constexpr XmlFile::Type type_of();
template <> constexpr XmlFile::Type type_of<double>() { return XmlFile::Type::float64; }
template <> constexpr XmlFile::Type type_of<std::int64_t>() { return XmlFile::Type::int64; }
template <> constexpr XmlFile::Type type_of<std::int32_t>() { return XmlFile::Type::int32; }
}  // namespace

XmlFile::XmlFile(std::string path, Encoding encoding, std::string type, std::string dataset_attributes)
    : path_(std::move(path)), encoding_(encoding), type_(std::move(type)), dataset_attributes_(std::move(dataset_attributes)) {}

XmlFile::~XmlFile() {
  if (spill_) std::fclose(spill_);
}

void XmlFile::line(const std::string& s) {
  if (path_.empty()) return;
  body_ += s;
  body_ += '\n';
}

void XmlFile::spill(const void* data, std::size_t n) {
  if (n && std::fwrite(data, 1, n, spill_) != n) throw_output_error(path_, "write the scratch data of", errno);
  spilled_ += n;
}

void XmlFile::spill_at(std::uint64_t at, const void* data, std::size_t n) {
  if (std::fseek(spill_, static_cast<long>(at), SEEK_SET) != 0 || std::fwrite(data, 1, n, spill_) != n ||
      std::fseek(spill_, 0, SEEK_END) != 0)
    throw_output_error(path_, "write the scratch data of", errno);
}

void XmlFile::begin_array(const std::string& name, Type type, int components, std::size_t tuples) {
  if (cur_.open) throw std::logic_error("XmlFile: an array begun inside another");
  cur_ = Streamed{};
  cur_.open = true;
  cur_.type = type;
  cur_.components = components;
  cur_.values = static_cast<std::uint64_t>(tuples) * static_cast<std::uint64_t>(components);
  cur_.bytes = cur_.values * type_bytes(type);
  if (path_.empty()) return;
  // NumberOfTuples: field data (TIME) is read as empty without it.
  const std::string e = "<DataArray type=\"" + std::string(type_name(type)) + "\" Name=\"" + name +
                        "\" NumberOfComponents=\"" + std::to_string(components) + "\" NumberOfTuples=\"" +
                        std::to_string(tuples) + "\"";
  if (encoding_ == Encoding::ascii) {
    line(e + " format=\"ascii\">");
    return;
  }
  if (!spill_) {
    // Beside the file (a node's /tmp may be small), unlinked at once: nothing is left
    // behind whatever happens to the run.
    std::string scratch = path_ + ".appended.XXXXXX";
    const int fd = ::mkstemp(scratch.data());
    if (fd < 0) throw_output_error(scratch, "create", errno);
    ::unlink(scratch.c_str());
    spill_ = ::fdopen(fd, "w+b");
    if (!spill_) {
      const int err = errno;
      ::close(fd);
      throw_output_error(scratch, "open", err);
    }
  }
  line(e + " format=\"appended\" offset=\"" + std::to_string(spilled_) + "\"/>");
  const std::uint64_t nblocks = (cur_.bytes + block_bytes - 1) / block_bytes;
  const std::uint64_t head[3] = {nblocks, block_bytes, cur_.bytes % block_bytes};
  cur_.header_at = spilled_;
  spill(head, sizeof head);
  const std::vector<std::uint64_t> sizes(nblocks, 0);  // the compressed sizes, filled in by end_array()
  spill(sizes.data(), sizes.size() * sizeof(std::uint64_t));
  block_.clear();
}

void XmlFile::flush_block() {
  if (block_.empty()) return;
  deflated_.resize(compressBound(static_cast<uLong>(block_bytes)));
  uLongf len = static_cast<uLongf>(deflated_.size());
  // Level 1: most of the gain of deflate on floating-point data at a fraction of the time.
  if (compress2(deflated_.data(), &len, block_.data(), static_cast<uLong>(block_.size()), 1) != Z_OK)
    throw std::runtime_error("zlib failed to compress a VTK array");
  spill(deflated_.data(), len);
  cur_.sizes.push_back(len);
  block_.clear();
}

template <class T>
void XmlFile::push_values(Type type, const T* v, std::size_t count) {
  if (!cur_.open || cur_.type != type) throw std::logic_error("XmlFile: values pushed outside their array");
  if (cur_.pushed + count > cur_.values) throw std::logic_error("XmlFile: more values pushed than the array holds");
  const std::uint64_t first = cur_.pushed;
  cur_.pushed += count;
  if (path_.empty()) return;
  if (encoding_ == Encoding::ascii) {
    char buf[40];
    const auto comps = static_cast<std::uint64_t>(cur_.components);
    for (std::size_t k = 0; k < count; ++k) {
      format(buf, sizeof buf, v[k]);
      body_ += buf;
      body_ += (first + k + 1) % comps ? ' ' : '\n';
    }
    return;
  }
  const auto* bytes = reinterpret_cast<const unsigned char*>(v);
  std::size_t left = count * sizeof(T);
  while (left) {
    const std::size_t take = std::min(left, block_bytes - block_.size());
    block_.insert(block_.end(), bytes, bytes + take);
    bytes += take;
    left -= take;
    if (block_.size() == block_bytes) flush_block();
  }
}

void XmlFile::push(const double* v, std::size_t count) { push_values(Type::float64, v, count); }
void XmlFile::push(const std::int64_t* v, std::size_t count) { push_values(Type::int64, v, count); }
void XmlFile::push(const std::int32_t* v, std::size_t count) { push_values(Type::int32, v, count); }

void XmlFile::end_array() {
  if (!cur_.open) throw std::logic_error("XmlFile: an array ended that was not begun");
  // A process that only sends its values pushes none.
  if (!path_.empty() && cur_.pushed != cur_.values)
    throw std::logic_error("XmlFile: fewer values pushed than the array holds");
  cur_.open = false;
  if (path_.empty()) return;
  if (encoding_ == Encoding::ascii) {
    line("</DataArray>");
    return;
  }
  flush_block();
  if (!cur_.sizes.empty())
    spill_at(cur_.header_at + 3 * sizeof(std::uint64_t), cur_.sizes.data(), cur_.sizes.size() * sizeof(std::uint64_t));
}

template <class T>
void XmlFile::typed(const std::string& name, Type type, int components, const std::vector<T>& v) {
  begin_array(name, type, components, v.size() / static_cast<std::size_t>(components));
  push_values(type, v.data(), v.size());
  end_array();
}

void XmlFile::array(const std::string& name, int components, const std::vector<double>& v) {
  typed(name, type_of<double>(), components, v);
}
void XmlFile::array(const std::string& name, int components, const std::vector<std::int64_t>& v) {
  typed(name, type_of<std::int64_t>(), components, v);
}
void XmlFile::array(const std::string& name, int components, const std::vector<std::int32_t>& v) {
  typed(name, type_of<std::int32_t>(), components, v);
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
  if (!path_.empty()) body_ += s;
  line("</Array>");
}

void XmlFile::write() {
  if (cur_.open) throw std::logic_error("XmlFile: written with an array still open");
  if (path_.empty()) return;
  const bool bin = encoding_ == Encoding::binary;
  AtomicFile af(path_);
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
    if (spill_) {
      if (std::fflush(spill_) != 0 || std::fseek(spill_, 0, SEEK_SET) != 0)
        throw_output_error(path_, "read back the scratch data of", errno);
      std::vector<char> buf(std::size_t{1} << 20);
      for (std::uint64_t left = spilled_; ok && left;) {
        const std::size_t take = static_cast<std::size_t>(std::min<std::uint64_t>(left, buf.size()));
        if (std::fread(buf.data(), 1, take, spill_) != take) throw_output_error(path_, "read back the scratch data of", errno ? errno : EIO);
        ok = std::fwrite(buf.data(), 1, take, f) == take;
        left -= take;
      }
    }
    const std::string end = "\n</AppendedData>\n";
    ok = ok && std::fwrite(end.data(), 1, end.size(), f) == end.size();
  }
  ok = ok && std::fputs("</VTKFile>\n", f) >= 0;
  if (!ok) throw_output_error(path_, "write", errno);
  af.commit();
}

}  // namespace cdm::vtk
