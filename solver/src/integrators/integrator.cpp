#include "cdm/solver/integrators/integrator.hpp"

#include "cdm/solver/integrators/exponential_midpoint.hpp"
#include "cdm/solver/integrators/paper_euler.hpp"
#include "cdm/solver/integrators/tracer_rk.hpp"
#include "cdm/solver/integrators/velocity_verlet.hpp"
#include "cdm/solver/own_particles.hpp"
#include "cdm/solver/parallel.hpp"

namespace cdm::integrators {

std::unique_ptr<Integrator> make_integrator(const IntegratorParts& parts) {
  switch (parts.spec.integrator) {
    case IntegratorScheme::paper_euler: return std::make_unique<PaperEuler>(parts);
    case IntegratorScheme::velocity_verlet: return std::make_unique<VelocityVerlet>(parts);
    case IntegratorScheme::exponential_midpoint: return std::make_unique<ExponentialMidpoint>(parts);
    case IntegratorScheme::rk2: return std::make_unique<TracerRungeKutta>(parts, false);
    case IntegratorScheme::rk4: return std::make_unique<TracerRungeKutta>(parts, true);
  }
  return std::make_unique<PaperEuler>(parts);
}

double own_state_not_finite(RankSplit* ranks, const ParticleStore& p) {
  if (!ranks) return -1.0;
  return max_own(ranks, p.size(), [&](std::size_t i) { return p.state_finite(i) ? 0.0 : 1.0; });
}

void wrap_positions(ParticleStore& p, const PeriodicBox& box, RankSplit* ranks) {
  if (!box.any()) return;
  for_own(ranks, p.size(), [&](std::size_t i) {
    p.x[i] = box.wrap(p.x[i], 0);
    p.y[i] = box.wrap(p.y[i], 1);
    p.z[i] = box.wrap(p.z[i], 2);
  });
}

void permute_arrays(std::initializer_list<std::vector<double>*> arrays, std::size_t n,
                    const std::vector<std::uint32_t>& from) {
  std::vector<double> tmp;
  for (auto* v : arrays)
    if (v->size() == n) permute_array(*v, from, tmp);
}

}  // namespace cdm::integrators
