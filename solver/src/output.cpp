#include "cdm/solver/output.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "cdm/solver/checkpoint.hpp"
#include "cdm/solver/simulation.hpp"

namespace cdm {

TableWriter::TableWriter(const std::string& path, const std::vector<std::string>& columns,
                         const std::vector<std::string>& comments, std::optional<std::uint64_t> resume_at)
    : ncol_(columns.size()), path_(path) {
  if (path.empty()) return;  // a table nobody asked for: rows are discarded
  if (resume_at) truncate_file(path, *resume_at);
  f_ = std::fopen(path.c_str(), resume_at ? "a" : "w");
  if (!f_) throw_output_error(path, "open for writing", errno);
  if (resume_at) return;  // continuing a table: its header is there already
  bool ok = true;
  for (const auto& c : comments) ok = ok && std::fprintf(f_, "# %s\n", c.c_str()) >= 0;
  ok = ok && std::fputs("#", f_) >= 0;
  for (const auto& c : columns) ok = ok && std::fprintf(f_, " %s", c.c_str()) >= 0;
  ok = ok && std::fputs("\n", f_) >= 0;
  if (!ok) throw_output_error(path, "write", errno);
}

TableWriter::~TableWriter() {
  if (f_) std::fclose(f_);
}

void TableWriter::row(const std::vector<double>& v) {
  if (v.size() != ncol_) throw std::logic_error("table '" + path_ + "': row has the wrong number of columns");
  if (!f_) return;
  bool ok = true;
  for (std::size_t k = 0; k < v.size(); ++k) {
    const bool integer = k < integer_.size() && integer_[k];
    ok = ok && (k == 0 || std::fputc(' ', f_) != EOF) && std::fprintf(f_, integer ? "%.0f" : "%.16e", v[k]) >= 0;
  }
  if (!ok || std::fputs("\n", f_) < 0) throw_output_error(path_, "write", errno);
}

void TableWriter::flush() {
  if (f_ && std::fflush(f_) != 0) throw_output_error(path_, "write", errno);
}

std::uint64_t TableWriter::sync() {
  if (!f_) return 0;
  sync_file(f_, path_);
  const long at = std::ftell(f_);
  if (at < 0) throw_output_error(path_, "find the length of", errno);
  return static_cast<std::uint64_t>(at);
}

void TableWriter::close() {
  if (!f_) return;
  std::FILE* f = f_;
  f_ = nullptr;
  close_file(f, path_);
}

namespace {
std::vector<std::string> particle_columns(bool rot) {
  std::vector<std::string> c = {"t[s]", "id[-]", "x[m]", "y[m]", "z[m]", "vx[m/s]", "vy[m/s]", "vz[m/s]"};
  if (rot) c.insert(c.end(), {"wx[rad/s]", "wy[rad/s]", "wz[rad/s]"});
  c.insert(c.end(), {"radius[m]", "material[-]"});
  return c;
}

/// The particle table's header line: the scene, dt to the last bit, the material names.
std::string particle_comment(const Simulation& sim) {
  char dt[40];
  std::snprintf(dt, sizeof dt, "%.17g", sim.dt());
  std::string s = "cdm particle table: scene " + sim.spec().file + ", dt = " + dt + " s, materials:";
  for (std::size_t m = 0; m < sim.spec().materials.size(); ++m)
    s += (m ? ", " : " ") + std::to_string(m) + " " + sim.spec().materials[m].name;
  return s;
}
}  // namespace

/// Where a restarted run continues the table at @p path: the checkpoint's length, or
/// nowhere (a new table) when there is no table there or no length was recorded.
std::optional<std::uint64_t> table_resume_point(const std::string& path, const Simulation& sim,
                                          std::optional<std::uint64_t> recorded) {
  if (!sim.restarted() || !recorded) return std::nullopt;
  const long long size = regular_file_size(path);
  if (size < 0) return std::nullopt;
  if (static_cast<std::uint64_t>(size) < *recorded)
    throw CheckpointError(path + ": holds " + std::to_string(size) + " bytes, fewer than the " +
                          std::to_string(*recorded) +
                          " the checkpoint recorded: not the table this checkpoint continues (restart into another "
                          "-o directory to start a new table)");
  return recorded;
}

SampleSchedule::SampleSchedule(const Simulation& sim, double interval) : interval_(interval) {
  if (sim.restarted()) last_ = output_sample(sim, interval_);  // that sample was written before the checkpoint
}

bool SampleSchedule::due(const Simulation& sim) {
  const bool last = sim.steps() == sim.total_steps();
  const long long k = output_sample(sim, interval_);
  if (k <= last_ && !last) return false;
  last_ = k;
  return true;
}

SampledTable::SampledTable(const std::string& path, const Simulation& sim, double interval,
                           const std::vector<std::string>& columns, const std::vector<std::string>& comments,
                           std::optional<std::uint64_t> resume_at)
    : table_(path, columns, comments, table_resume_point(path, sim, resume_at)), schedule_(sim, interval) {}

ParticleTableObserver::ParticleTableObserver(const std::string& path, const Simulation& sim,
                                             std::optional<std::uint64_t> resume_at)
    : SampledTable(path, sim, sim.spec().output_interval, particle_columns(sim.local_particles().has_rotation()),
                   {particle_comment(sim)}, resume_at),
      rot_(sim.local_particles().has_rotation()) {
  std::vector<bool> integer(rot_ ? 13 : 10, false);
  integer[1] = integer.back() = true;  // id and material
  table_.set_integer_columns(integer);
}

long long output_sample(const Simulation& sim, double interval) {
  if (interval <= sim.dt()) return static_cast<long long>(sim.steps());
  return static_cast<long long>(std::floor(sim.time() / interval + 1e-9));
}

void ParticleTableObserver::operator()(const Simulation& sim) {
  if (!schedule_.due(sim)) return;
  const bool last = sim.steps() == sim.total_steps();
  // By identity, whatever order the store keeps: the state and the radius from each
  // particle's owner (Simulation::written_rows), its material from this process's store.
  const ParticleStore& p = sim.local_particles();
  std::vector<const std::vector<double>*> moving = {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz};
  if (rot_) moving.insert(moving.end(), {&p.wx, &p.wy, &p.wz});
  moving.push_back(&p.radius);
  std::vector<double> r(rot_ ? 13 : 10);
  const IdentityOrder order(p);
  sim.written_rows(order, moving, [&](std::size_t k, const double* v) {
    if (!table_.writes()) return;  // a process that does not write
    const std::size_t i = order.slot_of(k);
    r[0] = sim.time();
    r[1] = static_cast<double>(k);
    std::copy(v, v + moving.size(), r.begin() + 2);
    r.back() = p.material[i];
    table_.row(r);
  });
  if (last) table_.flush();
}

}  // namespace cdm
