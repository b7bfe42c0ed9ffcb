#include "cdm/solver/io/vtk_writer.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "cdm/solver/checkpoint.hpp"
#include "cdm/solver/io/durable_file.hpp"
#include "cdm/solver/output.hpp"
#include "cdm/solver/simulation.hpp"

namespace cdm {

namespace fs = std::filesystem;

namespace {

void time_field(std::FILE* f, double t) {
  std::fprintf(f, "    <FieldData>\n      <DataArray type=\"Float64\" Name=\"TIME\" NumberOfTuples=\"1\" format=\"ascii\">%.16e</DataArray>\n    </FieldData>\n", t);
}

template <class Get>
void array(std::FILE* f, const char* name, int components, std::size_t n, Get&& get, const char* indent) {
  std::fprintf(f, "%s<DataArray type=\"Float64\" Name=\"%s\" NumberOfComponents=\"%d\" format=\"ascii\">\n", indent, name,
               components);
  for (std::size_t i = 0; i < n; ++i) {
    double v[3] = {0, 0, 0};
    get(i, v);
    std::fprintf(f, "%s ", indent);
    for (int c = 0; c < components; ++c) std::fprintf(f, c ? " %.16e" : "%.16e", v[c]);
    std::fputc('\n', f);
  }
  std::fprintf(f, "%s</DataArray>\n", indent);
}

}  // namespace

void write_particles_vtp(const std::string& path, const Simulation& sim) {
  const ParticleStore& p = sim.particles();
  const std::size_t n = p.size();
  // Points in identity order (p.slot_of), whatever order the store keeps them in.
  AtomicFile af(path);
  std::FILE* f = af.get();
  std::fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\">\n");
  std::fprintf(f, "  <PolyData>\n");
  time_field(f, sim.time());
  std::fprintf(f, "    <Piece NumberOfPoints=\"%zu\" NumberOfVerts=\"%zu\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n", n, n);
  std::fprintf(f, "      <Points>\n");
  array(f, "position", 3, n, [&](std::size_t i, double* v) { const std::size_t s = p.slot_of(i); v[0] = p.x[s]; v[1] = p.y[s]; v[2] = p.z[s]; }, "        ");
  std::fprintf(f, "      </Points>\n      <Verts>\n");
  std::fprintf(f, "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
  for (std::size_t i = 0; i < n; ++i) std::fprintf(f, "%zu\n", i);
  std::fprintf(f, "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  for (std::size_t i = 0; i < n; ++i) std::fprintf(f, "%zu\n", i + 1);
  std::fprintf(f, "        </DataArray>\n      </Verts>\n");
  std::fprintf(f, "      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n");
  array(f, "id", 1, n, [&](std::size_t i, double* v) { v[0] = static_cast<double>(i); }, "        ");
  array(f, "radius", 1, n, [&](std::size_t i, double* v) { v[0] = p.radius[p.slot_of(i)]; }, "        ");
  array(f, "velocity", 3, n, [&](std::size_t i, double* v) { const std::size_t s = p.slot_of(i); v[0] = p.vx[s]; v[1] = p.vy[s]; v[2] = p.vz[s]; }, "        ");
  if (p.has_rotation())
    array(f, "angular_velocity", 3, n, [&](std::size_t i, double* v) { const std::size_t s = p.slot_of(i); v[0] = p.wx[s]; v[1] = p.wy[s]; v[2] = p.wz[s]; },
          "        ");
  std::fprintf(f, "      </PointData>\n    </Piece>\n  </PolyData>\n</VTKFile>\n");
  af.commit();
}

void write_gas_vti(const std::string& path, const Simulation& sim) {
  const fluid::GasField& gas = *sim.gas();
  const fluid::StaggeredGrid& g = gas.grid();
  const int nx = g.n(0), ny = g.n(1), nz = g.n(2);
  const std::size_t nc = g.cell_count();
  AtomicFile af(path);
  std::FILE* f = af.get();
  std::fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\">\n");
  std::fprintf(f, "  <ImageData WholeExtent=\"0 %d 0 %d 0 %d\" Origin=\"%.16e %.16e %.16e\" Spacing=\"%.16e %.16e %.16e\">\n",
               nx, ny, nz, g.lo(0), g.lo(1), g.lo(2), g.h(0), g.h(1), g.h(2));
  time_field(f, sim.time());
  std::fprintf(f, "    <Piece Extent=\"0 %d 0 %d 0 %d\">\n      <CellData Vectors=\"velocity\">\n", nx, ny, nz);
  // VTK orders cells with x fastest, then y, then z.
  auto ijk = [&](std::size_t c, int& i, int& j, int& k) {
    i = static_cast<int>(c % static_cast<std::size_t>(nx));
    j = static_cast<int>((c / static_cast<std::size_t>(nx)) % static_cast<std::size_t>(ny));
    k = static_cast<int>(c / (static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny)));
  };
  const double c_t = gas.time_factor();
  array(f, "velocity", 3, nc, [&](std::size_t c, double* v) {
    int i, j, k;
    ijk(c, i, j, k);
    v[0] = c_t * 0.5 * (gas.u[g.at(i, j, k)] + gas.u[g.at(i + 1, j, k)]);
    v[1] = c_t * 0.5 * (gas.v[g.at(i, j, k)] + gas.v[g.at(i, j + 1, k)]);
    v[2] = g.two_d() ? 0.0 : c_t * 0.5 * (gas.w[g.at(i, j, k)] + gas.w[g.at(i, j, k + 1)]);
  }, "        ");
  if (gas.has_pressure())
    array(f, "pressure", 1, nc, [&](std::size_t c, double* v) {
      int i, j, k;
      ijk(c, i, j, k);
      v[0] = gas.p[g.at(i, j, k)];
    }, "        ");
  if (gas.has_void_fraction())
    array(f, "gas_volume_fraction", 1, nc, [&](std::size_t c, double* v) {
      int i, j, k;
      ijk(c, i, j, k);
      v[0] = gas.eps_g[g.at(i, j, k)];
    }, "        ");
  std::fprintf(f, "      </CellData>\n    </Piece>\n  </ImageData>\n</VTKFile>\n");
  af.commit();
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
    : dir_(out_dir), interval_(sim.spec().output_interval) {
  make_output_directory((fs::path(dir_) / "vtk").string());
  if (!sim.restarted()) return;
  last_ = resume ? resume->last : output_sample(sim, interval_);
  if (!resume) return;  // the first run wrote no VTK: new collections from here on
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
}

VtkMark VtkObserver::sync() const {
  sync_directory((fs::path(dir_) / "vtk").string());
  sync_directory(dir_);
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
  char name[64];
  std::snprintf(name, sizeof name, "vtk/particles_%06lld.vtp", k);
  write_particles_vtp((fs::path(dir_) / name).string(), sim);
  particle_files_.emplace_back(sim.time(), name);
  write_collection((fs::path(dir_) / "particles.pvd").string(), particle_files_);
  if (sim.gas()) {
    std::snprintf(name, sizeof name, "vtk/gas_%06lld.vti", k);
    write_gas_vti((fs::path(dir_) / name).string(), sim);
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
