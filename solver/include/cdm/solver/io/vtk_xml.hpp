#pragma once
/// @file vtk_xml.hpp
/// @brief One VTK XML file (PolyData, ImageData), its data arrays encoded either
///  - binary: appended raw data, zlib-compressed (compressor="vtkZLibDataCompressor",
///    header_type="UInt64"), every array a sequence of blocks of at most block_bytes
///    uncompressed bytes preceded by the header VTK specifies:
///    [number of blocks][block size][size of the last block, 0 when it is full]
///    [compressed size of each block], all UInt64; the array's `offset` attribute is
///    where that header starts after the `_` that opens the appended data;
///  - ascii: the values inline, floating point as %.16e (round trip), one tuple per line.
/// ParaView and VTK's own readers (python3-vtk9) read both.
///
/// An array is given whole (array()) or streamed a few values at a time (begin_array(),
/// push(), end_array()), so that a frame of many particles is never held whole: each
/// block is compressed as it fills, and the binary arrays go to a scratch file beside the
/// output (opened and unlinked at once, so that it leaves nothing behind) until write()
/// puts the XML and then them into the file. The XML (with ascii values inline) is held
/// in memory. A file without a path writes nothing: the MPI processes that only send
/// their particles' values to the writing one run the same calls.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cdm/solver/keywords.hpp"

namespace cdm::vtk {

enum class Encoding { binary, ascii };
/// The scene keyword of each encoding (output.vtk_format).
inline constexpr Keywords<Encoding, 2> encoding_keywords{{{"binary", Encoding::binary}, {"ascii", Encoding::ascii}}};

class XmlFile {
 public:
  /// Uncompressed bytes per compressed block.
  static constexpr std::size_t block_bytes = 1 << 16;

  /// A file of @p type ("PolyData", "ImageData") to be written to @p path (none: nothing
  /// is kept or written); @p dataset_attributes go on the dataset element (WholeExtent,
  /// Origin, Spacing for ImageData).
  XmlFile(std::string path, Encoding encoding, std::string type, std::string dataset_attributes = "");
  ~XmlFile();
  XmlFile(const XmlFile&) = delete;
  XmlFile& operator=(const XmlFile&) = delete;

  /// Append raw XML (piece and section elements) to the body.
  void open(const std::string& element) { line(element); }
  void close(const std::string& element) { line(element); }

  /// A data array of @p components per tuple in the current section.
  void array(const std::string& name, int components, const std::vector<double>& v);
  void array(const std::string& name, int components, const std::vector<std::int64_t>& v);
  void array(const std::string& name, int components, const std::vector<std::int32_t>& v);
  /// A field-data array of strings (always inline: they are few and short).
  void strings(const std::string& name, const std::vector<std::string>& v);

  /// The element type of a streamed array.
  enum class Type { float64, int64, int32 };
  /// Start a data array of @p tuples tuples of @p components values, pushed in order
  /// (exactly components × tuples of them) before end_array().
  void begin_array(const std::string& name, Type type, int components, std::size_t tuples);
  void push(const double* v, std::size_t count);
  void push(const std::int64_t* v, std::size_t count);
  void push(const std::int32_t* v, std::size_t count);
  void end_array();

  /// The whole file: XML, then the appended data when binary.
  void write();
  /// Whether the file has a path (else every call is a no-op).
  bool writes() const { return !path_.empty(); }

 private:
  void line(const std::string& s);
  template <class T>
  void typed(const std::string& name, Type type, int components, const std::vector<T>& v);
  template <class T>
  void push_values(Type type, const T* v, std::size_t count);
  /// Compress the block buffered (binary) into the scratch file.
  void flush_block();
  /// Write @p n bytes at the scratch file's end (or at @p at), checked.
  void spill(const void* data, std::size_t n);
  void spill_at(std::uint64_t at, const void* data, std::size_t n);

  std::string path_;
  Encoding encoding_;
  std::string type_, dataset_attributes_;
  std::string body_;  // XML inside the dataset element (and the ascii values)
  // The binary arrays: the scratch file, its length, and the array being streamed.
  std::FILE* spill_ = nullptr;
  std::uint64_t spilled_ = 0;
  struct Streamed {
    bool open = false;
    Type type = Type::float64;
    int components = 1;
    std::uint64_t values = 0, pushed = 0, bytes = 0;  // expected and pushed values, their bytes
    std::uint64_t header_at = 0;                      // where its block header is in the scratch file
    std::vector<std::uint64_t> sizes;                 // each compressed block's
  } cur_;
  std::vector<unsigned char> block_, deflated_;
};

}  // namespace cdm::vtk
