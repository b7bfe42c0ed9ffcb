#pragma once
/// @file stl_reader.hpp
/// @brief STL files (ASCII and binary) read into triangles, every triangle checked: the
/// file must be STL, complete, with finite vertices and no triangle of zero area.
///
/// Format: binary STL is an 80-byte header, a little-endian uint32 triangle count N and
/// N records of 50 bytes (normal and three vertices as 12 float32, a uint16 attribute),
/// so its size is exactly 84 + 50 N; ASCII STL is `solid [name]`, then per triangle
/// `facet normal nx ny nz / outer loop / vertex x y z (3 times) / endloop / endfacet`,
/// then `endsolid [name]`. The stored normals are ignored: a triangle's normal is taken
/// from its vertex order (right-handed), which is what STL writers keep consistent.
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "cdm/solver/vec3.hpp"

namespace cdm {

/// A file that is not a usable STL: the message names the file and, where it applies,
/// the triangle (counted from 1) and the line of an ASCII file.
class StlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Largest STL read [bytes] (a 2 GiB binary file holds 43 million triangles).
constexpr std::uint64_t max_stl_bytes = std::uint64_t{1} << 31;

/// The triangles of the STL file at @p path, three corners each, in the file's units and
/// order. A file of exactly 84 + 50 N bytes whose bytes 80-83 count N triangles is
/// binary; otherwise a file that begins with `solid` is ASCII. Throws StlError when the
/// file cannot be read, is neither, is truncated, or has a non-finite coordinate or a
/// triangle of zero area (its cross product below 1e-12 of its longest edge squared).
std::vector<std::array<Vec3, 3>> read_stl(const std::string& path);

/// The same from bytes in memory (@p name stands for the file in messages).
std::vector<std::array<Vec3, 3>> parse_stl(const std::string& bytes, const std::string& name);

}  // namespace cdm
