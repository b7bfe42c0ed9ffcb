#pragma once
/// @file vtk_xml.hpp
/// @brief One VTK XML file (PolyData, ImageData) assembled in memory and written in one
/// go, its data arrays encoded either
///  - binary: appended raw data, zlib-compressed (compressor="vtkZLibDataCompressor",
///    header_type="UInt64"), every array a sequence of blocks of at most block_bytes
///    uncompressed bytes preceded by the header VTK specifies:
///    [number of blocks][block size][size of the last block, 0 when it is full]
///    [compressed size of each block], all UInt64; the array's `offset` attribute is
///    where that header starts after the `_` that opens the appended data;
///  - ascii: the values inline, floating point as %.16e (round trip), one tuple per line.
/// ParaView and VTK's own readers (python3-vtk9) read both.
#include <cstddef>
#include <cstdint>
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

  /// A file of @p type ("PolyData", "ImageData"); @p dataset_attributes go on the
  /// dataset element (WholeExtent, Origin, Spacing for ImageData).
  XmlFile(Encoding encoding, std::string type, std::string dataset_attributes = "");

  /// Append raw XML (piece and section elements) to the body.
  void open(const std::string& element) { line(element); }
  void close(const std::string& element) { line(element); }

  /// A data array of @p components per tuple in the current section.
  void array(const std::string& name, int components, const std::vector<double>& v);
  void array(const std::string& name, int components, const std::vector<std::int64_t>& v);
  void array(const std::string& name, int components, const std::vector<std::int32_t>& v);
  /// A field-data array of strings (always inline: they are few and short).
  void strings(const std::string& name, const std::vector<std::string>& v);

  /// The whole file: XML, then the appended data when binary.
  void write(const std::string& path) const;

 private:
  void line(const std::string& s);
  /// An array's element with its data: inline text, or a reference into the appended data.
  template <class T>
  void typed(const std::string& name, int components, const std::vector<T>& v);
  void element(const std::string& name, const char* type, int components, std::size_t tuples, const void* data,
               std::size_t bytes, const std::string& ascii);

  Encoding encoding_;
  std::string type_, dataset_attributes_;
  std::string body_;      // XML inside the dataset element
  std::string appended_;  // the binary arrays, each with its block header
};

}  // namespace cdm::vtk
