#include "cdm/solver/io/vtk_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "cdm/solver/checkpoint.hpp"
#include "cdm/solver/io/durable_file.hpp"
#include "cdm/solver/io/output_fields.hpp"
#include "cdm/solver/output.hpp"
#include "cdm/solver/simulation.hpp"

namespace cdm {

namespace fs = std::filesystem;

namespace {

/// Field data: the time TIME [s], and the names @p materials when there are any.
void field_data(vtk::XmlFile& f, double t, const std::vector<Material>& materials = {}) {
  f.open("<FieldData>");
  f.array("TIME", 1, std::vector<double>{t});
  std::vector<std::string> names;
  for (const Material& m : materials) names.push_back(m.name);
  if (!names.empty()) f.strings("material_names", names);
  f.close("</FieldData>");
}

/// @p n tuples of @p components values, tuple k filled by get(k, v).
template <class Get>
std::vector<double> tuples(std::size_t n, int components, Get&& get) {
  std::vector<double> out(n * static_cast<std::size_t>(components));
  for (std::size_t k = 0; k < n; ++k) get(k, out.data() + k * static_cast<std::size_t>(components));
  return out;
}

/// The particles' centres as the points, in identity order (p.slot_of), whatever order
/// the store keeps them in.
void particle_points(vtk::XmlFile& f, const ParticleStore& p) {
  f.open("<Points>");
  f.array("position", 3, tuples(p.size(), 3, [&](std::size_t k, double* v) {
    const std::size_t s = p.slot_of(k);
    v[0] = p.x[s]; v[1] = p.y[s]; v[2] = p.z[s];
  }));
  f.close("</Points>");
}

}  // namespace

void write_particles_vtp(const std::string& path, const Simulation& sim, vtk::Encoding encoding) {
  const ParticleStore& p = sim.written_particles();
  const std::size_t n = p.size();
  // Points in identity order (p.slot_of), whatever order the store keeps them in.
  vtk::XmlFile f(encoding, "PolyData");
  field_data(f, sim.time(), sim.spec().materials);
  f.open("<Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"" + std::to_string(n) +
         "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">");
  particle_points(f, p);
  f.open("<Verts>");
  std::vector<std::int64_t> ids(n), offsets(n);
  for (std::size_t k = 0; k < n; ++k) {
    ids[k] = static_cast<std::int64_t>(k);
    offsets[k] = static_cast<std::int64_t>(k + 1);
  }
  f.array("connectivity", 1, ids);
  f.array("offsets", 1, offsets);
  f.close("</Verts>");
  f.open("<PointData Scalars=\"radius\" Vectors=\"velocity\">");
  f.array("id", 1, ids);
  std::vector<std::int32_t> material(n);
  for (std::size_t k = 0; k < n; ++k) material[k] = p.material[p.slot_of(k)];
  f.array("material", 1, material);
  f.array("radius", 1, tuples(n, 1, [&](std::size_t k, double* v) { v[0] = p.radius[p.slot_of(k)]; }));
  f.array("velocity", 3, tuples(n, 3, [&](std::size_t k, double* v) {
    const std::size_t s = p.slot_of(k);
    v[0] = p.vx[s]; v[1] = p.vy[s]; v[2] = p.vz[s];
  }));
  if (p.has_rotation())
    f.array("angular_velocity", 3, tuples(n, 3, [&](std::size_t k, double* v) {
      const std::size_t s = p.slot_of(k);
      v[0] = p.wx[s]; v[1] = p.wy[s]; v[2] = p.wz[s];
    }));
  if (sim.contact()) f.array("contact_force", 3, contact_forces(sim));
  f.close("</PointData>");
  f.close("</Piece>");
  f.write(path);
}

void write_contacts_vtp(const std::string& path, const Simulation& sim, vtk::Encoding encoding) {
  const ParticleStore& p = sim.written_particles();
  const std::size_t n = p.size();
  const ContactNetwork net = contact_network(sim);
  const std::size_t nc = net.overlap.size();
  vtk::XmlFile f(encoding, "PolyData");
  field_data(f, sim.time());
  f.open("<Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"0\" NumberOfLines=\"" +
         std::to_string(nc) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">");
  particle_points(f, p);
  f.open("<Lines>");
  std::vector<std::int64_t> offsets(nc);
  for (std::size_t c = 0; c < nc; ++c) offsets[c] = static_cast<std::int64_t>(2 * (c + 1));
  f.array("connectivity", 1, net.pairs);
  f.array("offsets", 1, offsets);
  f.close("</Lines>");
  f.open("<CellData Vectors=\"normal_force\">");
  f.array("particles", 2, net.pairs);
  f.array("normal_force", 3, net.normal);
  f.array("tangential_force", 3, net.tangential);
  f.array("overlap", 1, net.overlap);
  f.close("</CellData>");
  f.close("</Piece>");
  f.write(path);
}

void write_gas_vti(const std::string& path, const Simulation& sim, vtk::Encoding encoding) {
  const fluid::GasField& gas = *sim.gas();
  const fluid::StaggeredGrid& g = gas.grid();
  const int nx = g.n(0), ny = g.n(1), nz = g.n(2);
  const std::size_t nc = g.cell_count();
  char geometry[320];
  std::snprintf(geometry, sizeof geometry, "WholeExtent=\"0 %d 0 %d 0 %d\" Origin=\"%.16e %.16e %.16e\" Spacing=\"%.16e %.16e %.16e\"",
                nx, ny, nz, g.lo(0), g.lo(1), g.lo(2), g.h(0), g.h(1), g.h(2));
  vtk::XmlFile f(encoding, "ImageData", geometry);
  field_data(f, sim.time());
  f.open("<Piece Extent=\"0 " + std::to_string(nx) + " 0 " + std::to_string(ny) + " 0 " + std::to_string(nz) + "\">");
  f.open("<CellData Vectors=\"velocity\">");
  // VTK orders cells with x fastest, then y, then z.
  auto ijk = [&](std::size_t c, int& i, int& j, int& k) {
    i = static_cast<int>(c % static_cast<std::size_t>(nx));
    j = static_cast<int>((c / static_cast<std::size_t>(nx)) % static_cast<std::size_t>(ny));
    k = static_cast<int>(c / (static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny)));
  };
  const double c_t = gas.time_factor();
  f.array("velocity", 3, tuples(nc, 3, [&](std::size_t c, double* v) {
    int i, j, k;
    ijk(c, i, j, k);
    v[0] = c_t * 0.5 * (gas.u[g.at(i, j, k)] + gas.u[g.at(i + 1, j, k)]);
    v[1] = c_t * 0.5 * (gas.v[g.at(i, j, k)] + gas.v[g.at(i, j + 1, k)]);
    v[2] = g.two_d() ? 0.0 : c_t * 0.5 * (gas.w[g.at(i, j, k)] + gas.w[g.at(i, j, k + 1)]);
  }));
  if (gas.has_pressure())
    f.array("pressure", 1, tuples(nc, 1, [&](std::size_t c, double* v) {
      int i, j, k;
      ijk(c, i, j, k);
      v[0] = gas.p[g.at(i, j, k)];
    }));
  if (gas.has_void_fraction())
    f.array("gas_volume_fraction", 1, tuples(nc, 1, [&](std::size_t c, double* v) {
      int i, j, k;
      ijk(c, i, j, k);
      v[0] = gas.eps_g[g.at(i, j, k)];
    }));
  if (sim.particle_count()) f.array("solids_velocity", 3, solids_velocity(sim));
  f.close("</CellData>");
  f.close("</Piece>");
  f.write(path);
}

namespace {

/// The entries of the collection @p path in order ((time, file) pairs); none when there
/// is no such file.
std::vector<std::pair<double, std::string>> read_collection(const std::string& path) {
  std::vector<std::pair<double, std::string>> entries;
  std::ifstream in(path);
  const std::regex re(R"re(<DataSet timestep="([^"]+)" part="0" file="([^"]+)"/>)re");
  std::string line;
  std::smatch m;
  while (std::getline(in, line))
    if (std::regex_search(line, m, re)) entries.emplace_back(std::stod(m[1]), m[2]);
  return entries;
}

}  // namespace

VtkObserver::VtkObserver(const std::string& out_dir, const Simulation& sim, std::optional<VtkMark> resume)
    : dir_(out_dir), interval_(sim.spec().output_interval), encoding_(sim.spec().output_vtk_format),
      contacts_(sim.spec().output_contacts),
      walls_(!sim.spec().walls.empty() || !sim.spec().meshes.empty()),
      walls_move_(std::any_of(sim.spec().walls.begin(), sim.spec().walls.end(), [](const Wall& w) { return w.motion.moving(); }) ||
                  std::any_of(sim.spec().meshes.begin(), sim.spec().meshes.end(),
                              [](const TriangleMesh& m) { return m.motion.moving(); })) {
  if (!dir_.empty()) make_output_directory((fs::path(dir_) / "vtk").string());
  if (!sim.restarted()) return;
  last_ = resume ? resume->last : output_sample(sim, interval_);
  // Without a recorded mark the first run wrote no VTK: new collections from here on.
  if (!resume || dir_.empty()) return;
  // Continue the collections: cut them back to the frames the checkpoint recorded.
  auto reload = [&](const std::string& name, std::uint64_t frames, std::vector<std::pair<double, std::string>>& entries) {
    const std::string path = (fs::path(dir_) / name).string();
    if (regular_file_size(path) < 0) return;  // none here: a new collection from here on
    entries = read_collection(path);
    if (entries.size() < frames)
      throw CheckpointError(path + ": lists " + std::to_string(entries.size()) + " frames, fewer than the " +
                            std::to_string(frames) +
                            " the checkpoint recorded: not the collection this checkpoint continues (restart into "
                            "another -o directory to start new collections)");
    entries.resize(frames);
    write_collection(path, entries);
  };
  reload("particles.pvd", resume->particle_frames, particle_files_);
  if (sim.gas()) reload("gas.pvd", resume->gas_frames, gas_files_);
  if (contacts_) reload("contacts.pvd", resume->particle_frames, contact_files_);  // written with each particle frame
  // Written with each particle frame, or with the first alone when nothing moves.
  if (walls_) reload("walls.pvd", walls_move_ ? resume->particle_frames : std::min<std::uint64_t>(1, resume->particle_frames), wall_files_);
}

VtkMark VtkObserver::sync() const {
  if (!dir_.empty()) {
    sync_directory((fs::path(dir_) / "vtk").string());
    sync_directory(dir_);
  }
  return {last_, particle_files_.size(), gas_files_.size()};
}

void VtkObserver::operator()(const Simulation& sim) {
  const bool last = sim.steps() == sim.total_steps();
  long long k = output_sample(sim, interval_);
  if (k <= last_ && !last) return;
  if (k <= last_) k = last_ + 1;  // the final state, after the last sample
  last_ = k;
  const auto held = sim.hold_contacts();  // for the contact forces and network, from every rank
  sim.written_particles();                // the frame's state, gathered where it is written
  if (!dir_.empty()) write(sim, k);
}

void VtkObserver::write(const Simulation& sim, long long k) {
  char name[64];
  std::snprintf(name, sizeof name, "vtk/particles_%06lld.vtp", k);
  write_particles_vtp((fs::path(dir_) / name).string(), sim, encoding_);
  particle_files_.emplace_back(sim.time(), name);
  write_collection((fs::path(dir_) / "particles.pvd").string(), particle_files_);
  if (contacts_) {
    std::snprintf(name, sizeof name, "vtk/contacts_%06lld.vtp", k);
    write_contacts_vtp((fs::path(dir_) / name).string(), sim, encoding_);
    contact_files_.emplace_back(sim.time(), name);
    write_collection((fs::path(dir_) / "contacts.pvd").string(), contact_files_);
  }
  if (walls_ && (walls_move_ || wall_files_.empty())) {
    std::snprintf(name, sizeof name, "vtk/walls_%06lld.vtp", k);
    write_walls_vtp((fs::path(dir_) / name).string(), sim, encoding_);
    wall_files_.emplace_back(sim.time(), name);
    write_collection((fs::path(dir_) / "walls.pvd").string(), wall_files_);
  }
  if (sim.gas()) {
    std::snprintf(name, sizeof name, "vtk/gas_%06lld.vti", k);
    write_gas_vti((fs::path(dir_) / name).string(), sim, encoding_);
    gas_files_.emplace_back(sim.time(), name);
    write_collection((fs::path(dir_) / "gas.pvd").string(), gas_files_);
  }
}

void VtkObserver::write_collection(const std::string& path,
                                   const std::vector<std::pair<double, std::string>>& entries) const {
  AtomicFile af(path);
  std::FILE* f = af.get();
  std::fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n  <Collection>\n");
  for (const auto& [t, file] : entries)
    std::fprintf(f, "    <DataSet timestep=\"%.16e\" part=\"0\" file=\"%s\"/>\n", t, file.c_str());
  std::fprintf(f, "  </Collection>\n</VTKFile>\n");
  af.commit();
}

}  // namespace cdm
