#include "cdm/solver/output.hpp"

#include <cmath>
#include <stdexcept>

#include "cdm/solver/simulation.hpp"

namespace cdm {

TableWriter::TableWriter(const std::string& path, const std::vector<std::string>& columns,
                         const std::vector<std::string>& comments, bool append)
    : ncol_(columns.size()), path_(path) {
  if (path.empty()) return;  // a table nobody asked for: rows are discarded
  f_ = std::fopen(path.c_str(), append ? "a" : "w");
  if (!f_) throw std::runtime_error("cannot open '" + path + "' for writing");
  if (append) return;  // continuing a table: its header is there already
  for (const auto& c : comments) std::fprintf(f_, "# %s\n", c.c_str());
  std::fputs("#", f_);
  for (const auto& c : columns) std::fprintf(f_, " %s", c.c_str());
  std::fputs("\n", f_);
}

TableWriter::~TableWriter() {
  if (f_) std::fclose(f_);
}

void TableWriter::row(const std::vector<double>& v) {
  if (v.size() != ncol_) throw std::logic_error("table '" + path_ + "': row has the wrong number of columns");
  if (!f_) return;
  for (std::size_t k = 0; k < v.size(); ++k) std::fprintf(f_, k ? " %.16e" : "%.16e", v[k]);
  std::fputs("\n", f_);
}

void TableWriter::flush() {
  if (f_) std::fflush(f_);
}

namespace {
std::vector<std::string> particle_columns(bool rot) {
  std::vector<std::string> c = {"t[s]", "id[-]", "x[m]", "y[m]", "z[m]", "vx[m/s]", "vy[m/s]", "vz[m/s]"};
  if (rot) c.insert(c.end(), {"wx[rad/s]", "wy[rad/s]", "wz[rad/s]"});
  return c;
}
}  // namespace

ParticleTableObserver::ParticleTableObserver(const std::string& path, const Simulation& sim)
    : table_(path, particle_columns(sim.particles().has_rotation()),
             {"cdm particle table: scene " + sim.spec().file + ", dt = " + std::to_string(sim.dt()) + " s"},
             sim.restarted()),
      interval_(sim.spec().output_interval),
      rot_(sim.particles().has_rotation()) {
  if (sim.restarted()) last_ = output_sample(sim, interval_);  // that row was written before the checkpoint
}

long long output_sample(const Simulation& sim, double interval) {
  if (interval <= sim.dt()) return static_cast<long long>(sim.steps());
  return static_cast<long long>(std::floor(sim.time() / interval + 1e-9));
}

void ParticleTableObserver::operator()(const Simulation& sim) {
  const bool last = sim.steps() == sim.total_steps();
  const long long k = output_sample(sim, interval_);
  if (k <= last_ && !last) return;
  last_ = k;
  const ParticleStore& p = sim.particles();
  std::vector<double> r(rot_ ? 11 : 8);
  for (std::size_t k = 0; k < p.size(); ++k) {  // by identity, whatever order the store keeps
    const std::size_t i = p.slot_of(k);
    r[0] = sim.time(); r[1] = static_cast<double>(k);
    r[2] = p.x[i]; r[3] = p.y[i]; r[4] = p.z[i];
    r[5] = p.vx[i]; r[6] = p.vy[i]; r[7] = p.vz[i];
    if (rot_) { r[8] = p.wx[i]; r[9] = p.wy[i]; r[10] = p.wz[i]; }
    table_.row(r);
  }
  if (last) table_.flush();
}

}  // namespace cdm
