#include "cdm/solver/io/monitors.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <optional>

#include "cdm/solver/io/counted_sums.hpp"
#include "cdm/solver/io/layers.hpp"
#include "cdm/solver/io/output_fields.hpp"
#include "cdm/solver/simulation.hpp"

namespace cdm {

namespace {

double coordinate(Vec3 x, int axis) { return axis == 0 ? x.x : axis == 1 ? x.y : x.z; }

double plane_pressure(const Simulation& sim, int axis, double position) {
  const fluid::GasField& gas = *sim.gas();
  return layer_mean(gas.grid(), sim.gas_planes(), gas.p, axis, layer_of(gas.grid(), axis, position));
}

double bed_height(const MonitorSpec& m, const Simulation& sim) {
  const fluid::StaggeredGrid& g = sim.gas()->grid();
  const int a = m.axis, o1 = (a + 1) % 3, o2 = (a + 2) % 3;
  const double lo = g.lo(a), area = g.length(o1) * g.length(o2);
  const int layers = std::max(1, static_cast<int>(std::ceil(g.length(a) / m.bin - 1e-9)));
  const ParticleStore& p = sim.local_particles();
  const std::vector<double> solid = counted_sums(sim, static_cast<std::size_t>(layers), [&](std::size_t i, auto&& add) {
    const int k = static_cast<int>(std::floor((coordinate(p.position(i), a) - lo) / m.bin));
    if (k >= 0 && k < layers) add(static_cast<std::size_t>(k), p.volume(i));
  });
  for (int k = layers - 1; k >= 0; --k) {
    const double thickness = std::min(m.bin, g.length(a) - k * m.bin);
    if (solid[static_cast<std::size_t>(k)] / (thickness * area) >= m.threshold) return k * m.bin + thickness;
  }
  return 0.0;
}

double mass_flow(const MonitorSpec& m, const Simulation& sim) {
  const ParticleStore& p = sim.local_particles();
  const double flux = counted_sums(sim, 1, [&](std::size_t i, auto&& add) {
    if (std::abs(coordinate(p.position(i), m.axis) - m.position) <= 0.5 * m.bin)
      add(0, p.mass[i] * coordinate(p.velocity(i), m.axis));
  })[0];
  return flux / m.bin;
}

std::vector<std::string> monitor_columns(const MonitorSpec& m) {
  switch (m.kind) {
    case MonitorKind::pressure:
    case MonitorKind::plane_pressure: return {"t[s]", "pressure[Pa]"};
    case MonitorKind::pressure_drop: return {"t[s]", "pressure_drop[Pa]"};
    case MonitorKind::bed_height: return {"t[s]", "bed_height[m]"};
    case MonitorKind::mass_flow: return {"t[s]", "mass_flow[kg/s]"};
    case MonitorKind::wall_force: return {"t[s]", std::string("force_") + "xyz"[m.axis] + "[N]"};
  }
  return {};
}

/// The table's # line; @p spec names the walls.
std::string monitor_comment(const MonitorSpec& m, const SceneSpec& spec) {
  const std::string axis(1, "xyz"[m.axis]);
  auto num = [](double v) {  // the shortest text that reads back as v
    char b[32];
    const auto r = std::to_chars(b, b + sizeof b, v);
    return std::string(b, r.ptr);
  };
  std::string what = "cdm monitor " + m.name + " (" + to_string(m.kind) + "): ";
  switch (m.kind) {
    case MonitorKind::pressure:
      return what + "pressure of the gas cell holding (" + num(m.point.x) + ", " + num(m.point.y) + ", " +
             num(m.point.z) + ") m";
    case MonitorKind::plane_pressure:
      return what + "mean pressure over the cell layer holding " + axis + " = " + num(m.position) + " m";
    case MonitorKind::pressure_drop:
      return what + "mean pressure of the cell layer holding " + axis + " = " + num(m.from) + " m minus that at " +
             axis + " = " + num(m.to) + " m";
    case MonitorKind::bed_height:
      return what + "top of the highest layer of " + num(m.bin) + " m along " + axis +
             " with solids fraction >= " + num(m.threshold) + ", from the gas domain's lower face";
    case MonitorKind::mass_flow:
      return what + "solids mass flux through " + axis + " = " + num(m.position) + " m, sum of m v_" + axis +
             " over the particles within " + num(0.5 * m.bin) + " m of the plane, over " + num(m.bin) + " m";
    case MonitorKind::wall_force:
      return what + "force along " + axis + " on the particles from " +
             (m.wall < 0 ? std::string("every wall") : "the wall " + spec.walls[static_cast<std::size_t>(m.wall)].name) +
             " (normal and tangential), evaluated at the sampled state";
  }
  return what;
}

}  // namespace

double monitor_value(const MonitorSpec& m, const Simulation& sim, const std::vector<double>* walls) {
  switch (m.kind) {
    case MonitorKind::pressure: {
      const fluid::GasField& gas = *sim.gas();
      const fluid::StaggeredGrid& g = gas.grid();
      const Vec3 x = m.point;
      return cell_value(g, sim.gas_planes(), gas.p, layer_of(g, 0, x.x), layer_of(g, 1, x.y),
                        g.two_d() ? 0 : layer_of(g, 2, x.z));
    }
    case MonitorKind::plane_pressure: return plane_pressure(sim, m.axis, m.position);
    case MonitorKind::pressure_drop: return plane_pressure(sim, m.axis, m.from) - plane_pressure(sim, m.axis, m.to);
    case MonitorKind::bed_height: return bed_height(m, sim);
    case MonitorKind::mass_flow: return mass_flow(m, sim);
    case MonitorKind::wall_force: {
      std::vector<double> own;
      const std::vector<double>& f = walls ? *walls : (own = wall_forces(sim));
      double sum = 0.0;
      for (std::size_t w = 0; 3 * w < f.size(); ++w)
        if (m.wall < 0 || static_cast<std::size_t>(m.wall) == w) sum += f[3 * w + static_cast<std::size_t>(m.axis)];
      return sum;
    }
  }
  return 0.0;
}

std::string monitor_file(const MonitorSpec& m) { return "monitor_" + m.name + ".dat"; }

MonitorObserver::MonitorObserver(const std::string& out_dir, const Simulation& sim,
                                 const std::vector<std::uint64_t>& resume_at)
    : schedule_(sim, sim.spec().log_interval) {
  const auto& ms = sim.spec().monitors;
  for (std::size_t k = 0; k < ms.size(); ++k) {
    const std::string path = out_dir.empty() ? std::string() : (std::filesystem::path(out_dir) / monitor_file(ms[k])).string();
    const std::optional<std::uint64_t> recorded =
        k < resume_at.size() ? std::optional<std::uint64_t>(resume_at[k]) : std::nullopt;
    tables_.push_back(std::make_unique<TableWriter>(path, monitor_columns(ms[k]),
                                                    std::vector<std::string>{monitor_comment(ms[k], sim.spec())},
                                                    table_resume_point(path, sim, recorded)));
  }
}

void MonitorObserver::operator()(const Simulation& sim) {
  if (tables_.empty() || !schedule_.due(sim)) return;
  const auto& ms = sim.spec().monitors;
  std::optional<std::vector<double>> walls;  // evaluated once per sample, for every wall_force monitor
  for (std::size_t k = 0; k < ms.size(); ++k) {
    if (ms[k].kind == MonitorKind::wall_force && !walls) walls = wall_forces(sim);
    tables_[k]->row({sim.time(), monitor_value(ms[k], sim, walls ? &*walls : nullptr)});
  }
}

std::vector<std::uint64_t> MonitorObserver::sync() {
  std::vector<std::uint64_t> n;
  for (auto& t : tables_) n.push_back(t->sync());
  return n;
}

void MonitorObserver::close() {
  for (auto& t : tables_) t->close();
}

}  // namespace cdm
