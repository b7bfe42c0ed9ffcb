#include "cdm/solver/io/vtk_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <type_traits>

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

/// The array @p name of @p n values of type T, value k get(k), pushed a block at a time.
template <class T, class Get>
void generated(vtk::XmlFile& f, const std::string& name, vtk::XmlFile::Type type, std::size_t n, Get&& get) {
  if (!f.writes()) return;
  f.begin_array(name, type, 1, n);
  std::vector<T> chunk;
  constexpr std::size_t kChunk = 8192;
  for (std::size_t k0 = 0; k0 < n; k0 += kChunk) {
    chunk.clear();
    for (std::size_t k = k0; k < std::min(n, k0 + kChunk); ++k) chunk.push_back(static_cast<T>(get(k)));
    f.push(chunk.data(), chunk.size());
  }
  f.end_array();
}

/// The array @p name of the particles' values of @p arrays (one component each), in
/// identity order: gathered to the writing process row by row (Simulation::written_rows,
/// @p from_owners), never whole; @p order is the frame's identity order.
void per_particle(vtk::XmlFile& f, const Simulation& sim, const IdentityOrder& order, const std::string& name,
                  const std::vector<const std::vector<double>*>& arrays, bool from_owners = false) {
  const std::size_t m = arrays.size();
  f.begin_array(name, vtk::XmlFile::Type::float64, static_cast<int>(m), sim.particle_count());
  sim.written_rows(order, arrays, [&](std::size_t, const double* v) { f.push(v, m); }, from_owners);
  f.end_array();
}

}  // namespace

void write_particles_vtp(const std::string& path, const Simulation& sim, vtk::Encoding encoding) {
  // The contact forces first: where they cannot be evaluated by each process, the state
  // is gathered to the writer for them.
  const ContactForces fc = contact_forces(sim);
  const bool owners = fc.from_owners;
  const ParticleStore& p = sim.local_particles();
  const std::size_t n = p.size();
  // Points in identity order, whatever order the store keeps them in; each array streamed
  // to the file as it is gathered.
  const IdentityOrder order(p);
  vtk::XmlFile f(path, encoding, "PolyData");
  field_data(f, sim.time(), sim.spec().materials);
  f.open("<Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"" + std::to_string(n) +
         "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">");
  f.open("<Points>");
  per_particle(f, sim, order, "position", {&p.x, &p.y, &p.z}, owners);
  f.close("</Points>");
  f.open("<Verts>");
  using T = vtk::XmlFile::Type;
  generated<std::int64_t>(f, "connectivity", T::int64, n, [](std::size_t k) { return k; });
  generated<std::int64_t>(f, "offsets", T::int64, n, [](std::size_t k) { return k + 1; });
  f.close("</Verts>");
  f.open("<PointData Scalars=\"radius\" Vectors=\"velocity\">");
  generated<std::int64_t>(f, "id", T::int64, n, [](std::size_t k) { return k; });
  // Every process holds every particle's material; the radius is its owner's.
  generated<std::int32_t>(f, "material", T::int32, n, [&](std::size_t k) { return p.material[order.slot_of(k)]; });
  per_particle(f, sim, order, "radius", {&p.radius}, owners);
  per_particle(f, sim, order, "velocity", {&p.vx, &p.vy, &p.vz}, owners);
  if (p.has_rotation()) per_particle(f, sim, order, "angular_velocity", {&p.wx, &p.wy, &p.wz}, owners);
  if (sim.contact()) per_particle(f, sim, order, "contact_force", {&fc.f[0], &fc.f[1], &fc.f[2]}, owners);
  f.close("</PointData>");
  f.close("</Piece>");
  f.write();
}

void write_contacts_vtp(const std::string& path, const Simulation& sim, vtk::Encoding encoding) {
  const ContactNetwork net = contact_network(sim);
  const bool owners = net.from_owners;
  const std::size_t n = sim.particle_count(), nc = sim.rank_sum(net.overlap.size());
  vtk::XmlFile f(path, encoding, "PolyData");
  field_data(f, sim.time());
  f.open("<Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"0\" NumberOfLines=\"" +
         std::to_string(nc) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">");
  const ParticleStore& p = sim.local_particles();
  const IdentityOrder order(p);
  f.open("<Points>");
  per_particle(f, sim, order, "position", {&p.x, &p.y, &p.z}, owners);
  f.close("</Points>");
  // Each process's contacts after the ranks below's, streamed to the writer.
  using T = vtk::XmlFile::Type;
  auto ordered = [&](const std::string& name, T type, int components, std::size_t tuples, const auto& mine) {
    using V = typename std::decay_t<decltype(mine)>::value_type;
    f.begin_array(name, type, components, tuples);
    sim.ordered_to_writer(mine.data(), mine.size(), sizeof(V),
                          [&](const void* d, std::size_t m) { f.push(static_cast<const V*>(d), m); });
    f.end_array();
  };
  f.open("<Lines>");
  ordered("connectivity", T::int64, 1, 2 * nc, net.pairs);
  generated<std::int64_t>(f, "offsets", T::int64, nc, [](std::size_t c) { return 2 * (c + 1); });
  f.close("</Lines>");
  f.open("<CellData Vectors=\"normal_force\">");
  ordered("particles", T::int64, 2, nc, net.pairs);
  ordered("normal_force", T::float64, 3, nc, net.normal);
  ordered("tangential_force", T::float64, 3, nc, net.tangential);
  ordered("overlap", T::float64, 1, nc, net.overlap);
  f.close("</CellData>");
  f.close("</Piece>");
  f.write();
}

void write_gas_vti(const std::string& path, const Simulation& sim, vtk::Encoding encoding) {
  const fluid::GasField& gas = *sim.gas();
  const fluid::StaggeredGrid& g = gas.grid();
  const int nx = g.n(0), ny = g.n(1), nz = g.n(2);
  const std::size_t nc = g.cell_count();
  char geometry[320];
  std::snprintf(geometry, sizeof geometry, "WholeExtent=\"0 %d 0 %d 0 %d\" Origin=\"%.16e %.16e %.16e\" Spacing=\"%.16e %.16e %.16e\"",
                nx, ny, nz, g.lo(0), g.lo(1), g.lo(2), g.h(0), g.h(1), g.h(2));
  vtk::XmlFile f(path, encoding, "ImageData", geometry);
  field_data(f, sim.time());
  f.open("<Piece Extent=\"0 " + std::to_string(nx) + " 0 " + std::to_string(ny) + " 0 " + std::to_string(nz) + "\">");
  f.open("<CellData Vectors=\"velocity\">");
  // Each process's own planes of cells along z, which it keeps current, streamed to the
  // writer in rank order (the planes' order: PlaneShare::planes_of), so that the gas is
  // never gathered whole; where each process steps the whole gas, process 0 writes it all.
  // VTK orders cells with x fastest, then y, then z.
  const fluid::PlaneShare& share = sim.gas_planes();
  const std::pair<int, int> planes = share.processes() > 1 ? share.mine(nz)
                                     : sim.writes_rows()    ? std::pair{0, nz}
                                                            : std::pair{0, 0};
  const auto plane = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  // Each process adds its own particles to the solids velocity: every process takes part.
  const CellPlanes solids = sim.particle_count() ? solids_velocity(sim, planes) : CellPlanes{};
  auto by_planes = [&](const std::string& name, int components, auto&& get) {
    const std::size_t first = plane * static_cast<std::size_t>(planes.first);
    const std::vector<double> mine = tuples(plane * static_cast<std::size_t>(planes.second) - first, components,
                                            [&](std::size_t c, double* v) {
                                              const std::size_t at = first + c;
                                              get(static_cast<int>(at % static_cast<std::size_t>(nx)),
                                                  static_cast<int>(at / static_cast<std::size_t>(nx) % static_cast<std::size_t>(ny)),
                                                  static_cast<int>(at / plane), v);
                                            });
    f.begin_array(name, vtk::XmlFile::Type::float64, components, nc);
    sim.ordered_to_writer(mine.data(), mine.size(), sizeof(double),
                          [&](const void* d, std::size_t m) { f.push(static_cast<const double*>(d), m); });
    f.end_array();
  };
  const double c_t = gas.time_factor();
  by_planes("velocity", 3, [&](int i, int j, int k, double* v) {
    v[0] = c_t * 0.5 * (gas.u[g.at(i, j, k)] + gas.u[g.at(i + 1, j, k)]);
    v[1] = c_t * 0.5 * (gas.v[g.at(i, j, k)] + gas.v[g.at(i, j + 1, k)]);
    v[2] = g.two_d() ? 0.0 : c_t * 0.5 * (gas.w[g.at(i, j, k)] + gas.w[g.at(i, j, k + 1)]);
  });
  if (gas.has_pressure()) by_planes("pressure", 1, [&](int i, int j, int k, double* v) { v[0] = gas.p[g.at(i, j, k)]; });
  if (gas.has_void_fraction())
    by_planes("gas_volume_fraction", 1, [&](int i, int j, int k, double* v) { v[0] = gas.eps_g[g.at(i, j, k)]; });
  if (sim.particle_count())
    by_planes("solids_velocity", 3, [&](int i, int j, int k, double* v) {
      const auto z = [](int x) { return static_cast<std::size_t>(x); };
      const std::size_t at = 3 * (z(i) + z(nx) * z(j) + plane * z(k - solids.first));
      std::copy_n(solids.values.data() + at, 3, v);
    });
  f.close("</CellData>");
  f.close("</Piece>");
  f.write();
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
  write(sim, k);
}

void VtkObserver::write(const Simulation& sim, long long k) {
  // Every process makes each call (they gather to the writer, or add up over the
  // processes); only one with a directory writes the files.
  char name[64];
  auto frame = [&](const char* kind, const char* ext, auto&& write_file, std::vector<std::pair<double, std::string>>& files,
                   const char* collection, bool due = true) {
    std::snprintf(name, sizeof name, "vtk/%s_%06lld.%s", kind, k, ext);
    const bool writes = due && !dir_.empty();
    write_file(writes ? (fs::path(dir_) / name).string() : std::string(), sim, encoding_);
    if (!writes) return;
    files.emplace_back(sim.time(), name);
    write_collection((fs::path(dir_) / collection).string(), files);
  };
  frame("particles", "vtp", write_particles_vtp, particle_files_, "particles.pvd");
  if (contacts_) frame("contacts", "vtp", write_contacts_vtp, contact_files_, "contacts.pvd");
  // With each frame where a wall moves, else once; every process takes part either way.
  if (walls_) frame("walls", "vtp", write_walls_vtp, wall_files_, "walls.pvd", walls_move_ || wall_files_.empty());
  if (sim.gas()) frame("gas", "vti", write_gas_vti, gas_files_, "gas.pvd");
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
