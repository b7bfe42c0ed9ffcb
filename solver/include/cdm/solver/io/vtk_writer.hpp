#pragma once
/// @file vtk_writer.hpp
/// @brief VTK output that ParaView opens: VTK XML files (vtk_xml.hpp: zlib-compressed
/// appended binary by default, or ASCII; every value Float64 at full precision) and a
/// ParaView collection (.pvd) per series.
///  - particles: PolyData (.vtp), one vertex per particle in identity order, point data
///    id (Int64), material (Int32, an index into the field data material_names), radius
///    [m], velocity [m/s], angular_velocity [rad/s] (with rotation) and contact_force [N]
///    (with contacts; see contact_forces in output_fields.hpp);
///  - contacts (output.contacts): PolyData (.vtp), the particles as points and one line
///    per particle–particle contact between the two centres (force chains), cell data
///    particles (the two ids, Int64), normal_force and tangential_force [N] (on the
///    first particle from the second) and overlap [m] (see contact_network in
///    output_fields.hpp);
///  - gas: ImageData (.vti), one VTK cell per grid cell, cell data velocity [m/s] (face
///    values averaged to the cell centre), pressure [Pa] / gas_volume_fraction [-] when
///    the scene carries them, and solids_velocity [m/s] (volume-weighted mean particle
///    velocity per cell, zero without particles) when there are particles;
///  - walls (a scene with [[walls]] or [[meshes]]): PolyData (.vtp), the surfaces where
///    their motion has them: each mesh's triangles, each cylinder or cone as 64 quads
///    around (and its closed ends as polygons), each plane as a square across what the run
///    shows (particles, gas domain, meshes, insertion boxes; planes are infinite), cell
///    data wall (Int32, an index into the field data wall_names: the walls in scene
///    order, then the meshes) and material.
/// Every file holds its simulated time as field data TIME [s].
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cdm/solver/io/vtk_xml.hpp"

namespace cdm {

class Simulation;

/// Where a VTK series stood when a checkpoint was taken: the last sample index written
/// and the number of frames each collection listed.
struct VtkMark {
  long long last = -1;
  std::uint64_t particle_frames = 0, gas_frames = 0;
};

/// Writes OUTDIR/vtk/particles_<k>.vtp (and gas_<k>.vti with a gas, contacts_<k>.vtp
/// with output.contacts, walls_<k>.vtp with walls or meshes) at every output
/// sample of the scene (the same samples as the particle table), and keeps
/// OUTDIR/particles.pvd (and gas.pvd, contacts.pvd, walls.pvd) listing them. Walls that
/// do not move are written once, at the first sample. After a restart it continues the
/// collections the first run wrote, cut back to the frames the checkpoint recorded
/// (@p resume); without them in OUTDIR it starts new collections. Every file is written
/// atomically (temporary file, fsync, rename); failures throw OutputError. With an empty
/// OUTDIR nothing is written: each sample only reads the particles (among MPI processes,
/// those other than rank 0 thus take part in each frame as rank 0 writes it: they send
/// their particles' values, rows_to_writer, and add up what sums over them).
/// The write_* functions below are collective calls when several processes share the
/// particles; a process given an empty path writes nothing.
class VtkObserver {
 public:
  VtkObserver(const std::string& out_dir, const Simulation& sim, std::optional<VtkMark> resume = std::nullopt);
  void operator()(const Simulation& sim);
  /// Make the frames written so far durable (fsync the directories) and say where the
  /// collections stand (recorded by a checkpoint).
  VtkMark sync() const;

 private:
  void write(const Simulation& sim, long long k);
  void write_collection(const std::string& path, const std::vector<std::pair<double, std::string>>& entries) const;

  std::string dir_;
  double interval_;
  vtk::Encoding encoding_;
  bool contacts_;
  bool walls_, walls_move_;
  long long last_ = -1;
  std::vector<std::pair<double, std::string>> particle_files_, gas_files_, contact_files_, wall_files_;
};

/// The particles alone, as one .vtp file (used by the observer; handy in tests).
void write_particles_vtp(const std::string& path, const Simulation& sim,
                         vtk::Encoding encoding = vtk::Encoding::binary);
/// The particle–particle contacts, as one .vtp file of lines.
void write_contacts_vtp(const std::string& path, const Simulation& sim,
                        vtk::Encoding encoding = vtk::Encoding::binary);
/// The walls and meshes at the simulation's time, as one .vtp file of polygons.
void write_walls_vtp(const std::string& path, const Simulation& sim,
                     vtk::Encoding encoding = vtk::Encoding::binary);
/// The gas cell data, as one .vti file.
void write_gas_vti(const std::string& path, const Simulation& sim, vtk::Encoding encoding = vtk::Encoding::binary);

}  // namespace cdm
