#include "cdm/solver/io/population_table.hpp"

#include "cdm/solver/io/counted_sums.hpp"
#include "cdm/solver/simulation.hpp"

namespace cdm {

namespace {

std::vector<std::string> columns(const SceneSpec& spec) {
  std::vector<std::string> c = {"t[s]", "inserted[-]", "inserted_mass[kg]"};
  for (const auto& o : spec.outlets) {
    c.push_back(o.name + "[-]");
    c.push_back(o.name + "_mass[kg]");
  }
  c.insert(c.end(), {"particles[-]", "particle_mass[kg]"});
  return c;
}

}  // namespace

PopulationTableObserver::PopulationTableObserver(const std::string& path, const Simulation& sim,
                                                 std::optional<std::uint64_t> resume_at)
    : SampledTable(path, sim, sim.spec().output_interval, columns(sim.spec()),
                   {"cdm population table: scene " + sim.spec().file +
                    "; particles and mass inserted and removed by each outlet since the start, and in the domain"},
                   resume_at) {
  std::vector<bool> integer(columns(sim.spec()).size(), false);
  integer[1] = true;
  for (std::size_t o = 0; o < sim.spec().outlets.size(); ++o) integer[3 + 2 * o] = true;
  integer[integer.size() - 2] = true;
  table_.set_integer_columns(integer);
}

void PopulationTableObserver::operator()(const Simulation& sim) {
  if (!schedule_.due(sim)) return;
  const Population* pop = sim.population();
  std::vector<double> r = {sim.time(), 0.0, 0.0};
  if (pop) {
    for (const auto& t : pop->inserted()) {
      r[1] += static_cast<double>(t.count);
      r[2] += t.mass;
    }
    for (const auto& t : pop->removed()) {
      r.push_back(static_cast<double>(t.count));
      r.push_back(t.mass);
    }
  }
  // The mass in the domain, each process its own particles', added up.
  const ParticleStore& p = sim.local_particles();
  r.push_back(static_cast<double>(p.size()));
  r.push_back(counted_sums(sim, 1, [&](std::size_t i, auto&& add) { add(0, p.mass[i]); })[0]);
  table_.row(r);
  if (sim.steps() == sim.total_steps()) table_.flush();
}

}  // namespace cdm
