#include "cdm/solver/simulation.hpp"

#include "cdm/solver/contact/rolling_resistance_module.hpp"
#include "cdm/solver/gravity_module.hpp"
#include "cdm/solver/parallel.hpp"
#include "cdm/solver/own_particles.hpp"
#include "cdm/solver/rank_split.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/slot_pages.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "cdm/solver/coupling/substeps.hpp"
#include "cdm/solver/scene_loader.hpp"

namespace cdm {

Simulation::Simulation(SceneSpec spec) : spec_(std::move(spec)) {
  // Build only the modules the scene names. Rotation exists only with a module that
  // makes torque (friction, rolling resistance).
  if (spec_.tangential != TangentialModel::none || spec_.rolling != RollingModel::none) particles_.enable_rotation();
  place_scene();
  if (spec_.gas != GasModel::none) build_gas();
  if (spec_.gravity) {
    modules_.push_back(std::make_unique<GravityModule>(spec_.g));
    gravity_ = modules_.back().get();
  }
  if (spec_.normal_contact) {
    const bool rolling = spec_.rolling == RollingModel::constant_torque;
    auto c = std::make_unique<ContactModule>(spec_.pairs, spec_.walls,
                                             spec_.tangential == TangentialModel::spring_coulomb, spec_.verlet_skin, rolling);
    contact_ = c.get();
    contact_->set_periodic_box(spec_.periodic);
    // A solved gas in 3D is divided among MPI processes by its planes along z
    // (plane_share.hpp): the particles' slabs follow them where the bed's shape allows, on
    // any number of processes alike, so that the particles' order does not depend on it.
    if (solver_ && !gas_->grid().two_d()) contact_->list().prefer_slab_axis(2);
    if (!spec_.meshes.empty()) contact_->set_meshes(spec_.meshes);
    modules_.push_back(std::move(c));
    // Rolling resistance acts through the contacts just evaluated, so it runs after them.
    if (rolling) modules_.push_back(std::make_unique<RollingResistanceModule>(*contact_));
  }
  if (spec_.drag) {
    if (spec_.drag_update != coupling::DragUpdate::explicit_force) particles_.enable_drag_relaxation();
    auto d = std::make_unique<coupling::DragModule>(*gas_, *spec_.drag, spec_.drag_update, spec_.drag_void_fraction,
                                                    spec_.coupling_method, deposition(), spec_.two_way,
                                                    spec_.gas_velocity);
    if (spec_.gas_velocity == coupling::SlipVelocity::superficial) gas_->enable_superficial_velocity();
    if (lagged()) d->evaluate_per_gas_step(gas_clock_);
    drag_ = d.get();
    modules_.push_back(std::move(d));
  }
  if (spec_.pressure_gradient) {
    if (deposition()) gas_->enable_cell_pressure_gradient();
    auto m = std::make_unique<coupling::PressureGradientModule>(*gas_, deposition());
    if (lagged()) m->evaluate_per_gas_step(gas_clock_);
    // Once per gas step with the explicit drag, one evaluation and one pass per step for both.
    if (lagged() && drag_ && spec_.drag_update == coupling::DragUpdate::explicit_force &&
        spec_.coupling_method == coupling::CouplingMethod::interpolate)
      drag_->take_pressure_gradient(*m);
    modules_.push_back(std::move(m));
  }
  total_steps_ = static_cast<std::uint64_t>(step_count(spec_.end_time, spec_.dt));  // <= max_steps (loader)
  integrator_ = integrators::make_integrator({spec_, particles_, gas_.get(), contact_, gravity_ != nullptr});
  if (spec_.population_changes()) population_ = std::make_unique<Population>(spec_);
  split_among_ranks();
  // Among processes each gives motion to the rows it holds from the first build on
  // (ready_for_list, divide_rows_if_due): the others' would only be let go of.
  if (!ranks_) {
    fill_motion();
    if (spec_.tracers) tracers_follow_gas();
  }
}

void Simulation::tracers_follow_gas() {
  // A tracer moves with the gas from the start.
  for_own_in_order(ranks_.get(), particles_.size(), [&](std::size_t i) {
    const Vec3 u = gas_->velocity_at(particles_.position(i));
    particles_.vx[i] = u.x; particles_.vy[i] = u.y; particles_.vz[i] = u.z;
  });
}

Simulation::~Simulation() = default;

void Simulation::split_among_ranks() {
  ranks_ = RankSplit::create();
  if (!ranks_) return;
  world_size_ = ranks_->size();
  integrator_->set_ranks(ranks_.get());
  if (contact_) contact_->set_ranks(ranks_.get());
  std::vector<std::vector<double>*> carried;
  for (auto& m : modules_)
    for (auto* a : m->share_among(ranks_.get())) carried.push_back(a);
  ranks_->set_carried_arrays(std::move(carried));
}

int Simulation::ranks() const { return world_size_; }

std::vector<std::string> Simulation::module_names() const {
  std::vector<std::string> names;
  for (const auto& m : modules_) names.push_back(m->name());
  return names;
}

bool Simulation::sort_due_at_build() const {
  // At most every sort_interval steps, and at the first build.
  return spec_.sort_interval && contact_ && (particles_.id.empty() || steps_ - last_sort_ >= spec_.sort_interval);
}

void Simulation::sort_if_due() {
  // At a Verlet-list rebuild (the list is built anew from the sorted order anyway).
  if (!sort_due_at_build() || !contact_->list().rebuild_due(particles_)) return;
  sort_by(contact_->list().spatial_order(particles_));
}

void Simulation::sort_by(const std::vector<std::uint32_t>& from) {
  permute(from);
  last_sort_ = steps_;
}

void Simulation::permute(const std::vector<std::uint32_t>& from) {
  particles_.permute(from);
  integrator_->permute(from);  // its per-particle arrays, where a step is under way
  for (auto& m : modules_) m->permute(from);
}

void Simulation::remap(const std::vector<std::uint32_t>& from) {
  for (auto& m : modules_) m->remap(from, particles_);
  integrator_->masses_changed();
}

void Simulation::divide_rows_if_due() {
  // Without contacts there are no slabs: each process moves its run of rows of the
  // scene's order (RankSplit::divide_by_rows) from the first step's forces (or the first
  // frame) on, when each gives its own particles their motion, as at a first build.
  if (!ranks_ || contact_ || ranks_->partitioned() || particles_.size() == 0) return;
  ranks_->divide_by_rows(particles_);
  const bool start = motion_pending_;
  fill_motion();
  if (start && spec_.tracers) tracers_follow_gas();
}

void Simulation::ready_for_list(double t) {
  if (!contact_) return divide_rows_if_due();
  contact_->set_time(t);
  if (ranks_) {
    // Where the integrator's drift bound reached the margin without a measure, the list
    // would measure every particle: each rank measures its own, the largest counts.
    VerletList& list = contact_->list();
    if (list.listed(particles_.size()) && !list.displacement_known())
      list.set_displacement(
          max_own(ranks_.get(), particles_.size(), [&](std::size_t i) { return list.displacement(particles_, i); }));
    // A build, and a sort before it, read the positions of each rank's own particles,
    // and of the particles near the slabs it searches, which their owners send (a loaded
    // list listing its pairs again, their build positions, which the rows' holders send);
    // where some particles have no owner yet that holds them, every position, gathered.
    // Between builds a rank needs only the slabs either side of its own.
    const bool build = list.rebuild_due(particles_);
    if (build || list.relist_due(particles_)) {
      // Where every rank holds the whole state, each keeps its run of rows of the sorted
      // order through the sort (RankSplit::hold_rows), as after a restart, and the build
      // reads from the rows' holders the positions its search needs.
      if (!ranks_->partitioned() && particles_.size() > 0) {
        std::vector<std::uint32_t> from;
        if (sort_due_at_build()) from = list.spatial_order(particles_);
        ranks_->hold_rows(particles_, from);
        if (!from.empty()) sort_by(from);
        fill_motion();
      }
      if (ranks_->holds_build(particles_)) {
        if (build && sort_due_at_build()) sort_by(list.held_spatial_order(particles_));
        ranks_->prepare_build(particles_, list);
        return;
      }
      synchronise_ranks(true);
    } else {
      ranks_->exchange_ghosts(particles_);
    }
  }
  sort_if_due();
}

void Simulation::compute_forces(double t, integrators::ForceStart start) {
  ready_for_list(t);
  // Else the integrator zeroed the forces as it read them, or set them to the weight.
  if (start == integrators::ForceStart::stale) particles_.clear_forces();
  const ForceModule* applied = start == integrators::ForceStart::weight ? gravity_ : nullptr;
  const std::size_t builds = contact_ ? contact_->list().builds() : 0;
  for (auto& m : modules_) {
    if (m.get() != applied) m->add_forces(particles_, spec_.dt);
    // A build deals the particles out anew: the gas under this process's, before the
    // modules after the contacts read it.
    if (m.get() == contact_ && (contact_->list().builds() != builds || !reach_stated_)) gas_follows_particles();
  }
  gas_clock_.due = false;  // the gas was evaluated at the particles (if lagged)
  forces_valid_ = true;
}

void Simulation::list_first() {
  if (!contact_) return divide_rows_if_due();
  if (contact_->list().built()) return;
  // The first build as the first step's forces would make it (compute_forces), with
  // nothing evaluated: each process holds the whole state until it.
  ready_for_list(time_);
  contact_->update_list(particles_);
}

RunGuards Simulation::guards() const { return {spec_, particles_, gas_.get(), contact_, drag_}; }

void Simulation::check_state(double nonfinite) const {
  guards().check(time_, steps_, nonfinite);
}

const Simulation::CouplingBalance& Simulation::coupling_balance() const {
  static const CouplingBalance none{};
  return exchange_ ? exchange_->balance() : none;
}

void Simulation::step() {
  const double t_new = static_cast<double>(steps_ + 1) * spec_.dt;
  // 1 if the integrator found the state not finite, 0 if none, -1 if not checked.
  const double nonfinite = integrator_->step(*this, {time_, t_new});
  if (ranks_) {
    ranks_->mark_stale(particles_);
    if (nonfinite > 0.0) synchronise_ranks();  // the guards name the particles, whichever rank moved them
  }
  ++steps_;
  time_ = static_cast<double>(steps_) * spec_.dt;
  // Before the guards: a particle that left the gas domain through an outlet is gone.
  if (population_) update_population();
  // Evaluated once per gas step, the gas reads the particles' positions at the first
  // sub-step (the drag and ∇P at the particles) and at the gas step (the deposits) only.
  const bool gas_read = !lagged() || substep_ == 0 || substep_ + 1 == substeps_;
  bool domain_check = gas_read;
  if (ranks_ && gas_ && gas_read) {
    // Among ranks each looks at its own particles; if any left the gas domain, the
    // guards name them from the whole state.
    domain_check = ranks_->any_own(particles_.size(), [&](std::size_t i0, std::size_t i1) {
      for (std::size_t i = i0; i < i1; ++i)
        if (!gas_->contains(particles_.position(i))) return true;
      return false;
    });
    if (domain_check) synchronise_ranks();
  }
  guards().check(time_, steps_, nonfinite, domain_check);
  if (solver_) {
    // The impulses are gathered over the gas step and deposited at the gas step when the
    // drag is evaluated once per gas step or the gas takes it implicitly (implicit_drag.hpp).
    if (exchange_->two_way() && !implicit_drag_ && !lagged()) {
      // Each rank deposits its own particles' impulses, the cells' sums added up.
      exchange_->deposit_impulses(particles_, time_, ranks_.get());
    }
    if (++substep_ == substeps_) {
      substep_ = 0;
      complete_for_gas_step();
      gas_step();
    }
  }
}

void Simulation::build_gas() {
  const bool solved = spec_.gas == GasModel::solved;
  const bool grid_eps = solved || (spec_.drag && spec_.drag_void_fraction <= 0.0);
  // Where the particles' contacts deal them out by slabs, each process reads the gas on
  // the planes under its own (gas_follows_particles): from the start it holds its own
  // planes only, and receives the others' once it knows its particles.
  const std::pair<int, int> planes = solved && spec_.normal_contact
                                         ? fluid::GasSolver::first_planes(spec_.gas_division, spec_.gas_spec.grid)
                                         : std::pair{0, std::numeric_limits<int>::max()};
  gas_ = std::make_unique<fluid::GasField>(spec_.gas_spec, spec_.gravity ? spec_.g : Vec3{},
                                           spec_.pressure_gradient || solved, grid_eps, planes);
  if (!solved) return;
  const fluid::StaggeredGrid& g = gas_->grid();
  // Initial gas velocity (the boundary conditions then impose theirs).
  g.fill_window(gas_->u, spec_.gas_initial_velocity.x);
  g.fill_window(gas_->v, spec_.gas_initial_velocity.y);
  g.fill_window(gas_->w, g.two_d() ? 0.0 : spec_.gas_initial_velocity.z);
  substeps_ = coupling::gas_substeps(spec_.gas_dt, spec_.dt);
  const coupling::Kernel k =
      spec_.coupling_method == coupling::CouplingMethod::cell_average ? coupling::Kernel::cell : spec_.kernel;
  exchange_ = std::make_unique<coupling::TwoWayExchange>(g, spec_.two_way, k, spec_.kernel_width);
  gas_->mean_pressure_gradient = spec_.mean_pressure_gradient;
  solver_ = std::make_unique<fluid::GasSolver>(
      *gas_, fluid::GasSolverSpec{spec_.advection, spec_.gravity ? spec_.g : Vec3{}, spec_.mean_pressure_gradient,
                                       spec_.pressure_solver, spec_.gas_division});
  if (solver_->divided() && spec_.two_way) exchange_->share_planes(&solver_->planes());
  if (spec_.two_way) {
    particles_.enable_two_way();
    // At the start nothing has run yet: a gas fraction the cells cannot represent is a
    // property of the scene (particles too large for the cells, or piled into them), so
    // it is refused as such, naming the file.
    try {
      exchange_->deposit_void_fraction(particles_, gas_->eps_g, time_);
    } catch (const SimulationError& e) {
      throw SceneError(spec_.file + ": the initial particles do not fit the gas cells: " + std::string(e.what()));
    }
    gas_->refresh();  // with the particles' ε_g
    if (spec_.implicit_gas_drag) implicit_drag_ = std::make_unique<coupling::ImplicitDrag>(g, *exchange_);
  }
}

void Simulation::gas_step() {
  gas_follows_particles();
  fluid::GasSolver& gs = *solver_;
  const double dtg = spec_.gas_dt;
  gs.clear_force();
  if (exchange_->two_way()) {
    // Gathered over the gas step (evaluated once per gas step, or for the implicit drag):
    // the impulses deposited where the particles are now, with ε_g from the same
    // stencils, each rank its own particles.
    const bool together = lagged() || implicit_drag_;
    if (together) exchange_->deposit_impulses_and_void_fraction(particles_, eps_work_, time_, ranks_.get());
    if (implicit_drag_) implicit_drag_->prepare(particles_, gs, ranks_.get());
    exchange_->apply_reaction(gs, dtg);
    if (implicit_drag_) gs.clear_force();  // the gas takes the drag implicitly instead
    if (!together) exchange_->deposit_void_fraction(particles_, eps_work_, time_, ranks_.get());
  } else {
    eps_work_ = gas_->eps_g;
  }
  gs.step(dtg, eps_work_);
  guards().check_gas(gs, dtg, time_);  // before the implicit drag's kick reads the new gas
  if (implicit_drag_) exchange_->add_to_balance(implicit_drag_->give_back(particles_, *gas_, gs, dtg, ranks_.get()));
  gas_clock_.due = true;
}

void Simulation::run(const std::function<void(const Simulation&)>& observer, const std::function<bool()>& stop) {
  if (observer && !restarted_) {
    list_first();
    observer(*this);
  }
  while (steps_ < total_steps_) {
    step();
    if (observer) observer(*this);
    if (stop && stop()) break;
  }
  local_particles();  // the last step completed; a reader of the whole state gathers it
}

void Simulation::save_state(OutArchive& a) const {
  // A checkpoint holds the state at time(), written by process 0: among processes each
  // per-particle array and each array of the gas's planes streams to it (stream_shared).
  const ParticleStore& p = particles_;
  a.put(static_cast<std::uint64_t>(p.size()));
  a.put(steps_);
  a.put(time_);
  a.put(static_cast<std::uint8_t>(forces_valid_));
  save_population(a);
  a.put(p.id);  // the particles' order (empty until sorted); arrays below are in it
  a.put(last_sort_);
  for (const auto* v : {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz, &p.wx, &p.wy, &p.wz, &p.tx, &p.ty,
                        &p.tz, &p.drag_k, &p.ugx, &p.ugy, &p.ugz, &p.dfx, &p.dfy, &p.dfz, &p.jx, &p.jy, &p.jz})
    a.put_particles(*v);
  a.put(static_cast<std::uint64_t>(modules_.size()));
  for (const auto& m : modules_) {
    a.put(m->name());
    m->save_state(a);
  }
  // A solved gas: its fields, the solver's clock, and the exchange accumulated so far in
  // the current gas step.
  a.put(static_cast<std::uint8_t>(solver_ ? 1 : 0));
  if (solver_) {
    gas_->save_state(a);
    a.put(solver_->time());
    a.put(substep_);
    if (lagged()) a.put(static_cast<std::uint8_t>(gas_clock_.due));
    exchange_->save_state(a);
    if (implicit_drag_) implicit_drag_->save_state(a);
  }
}

void Simulation::load_state(InArchive& a) {
  // The checkpoint's state replaces the scene's, but for the masses where the population
  // does not change (they follow from the radii and materials).
  const bool masses_pending = motion_pending_;
  motion_pending_ = false;
  ParticleStore& p = particles_;
  std::uint64_t n = 0;
  a.get(n);
  std::uint64_t steps = 0;
  double time = 0.0;
  std::uint8_t fv = 0;
  a.get(steps); a.get(time); a.get(fv);
  if (n > (std::uint64_t{1} << 32) - 2) throw ArchiveError("it holds too many particles");
  const bool dynamic = load_population(a, n);
  if (!dynamic && n != p.size())
    throw ArchiveError("it holds " + std::to_string(n) + " particles, the scene " + std::to_string(p.size()));
  const std::uint64_t n0 = n;
  // The saved order: a permutation of the particles, or empty (never sorted).
  std::vector<std::uint32_t> id;
  a.get(id, n0);
  std::uint64_t last_sort = 0;
  a.get(last_sort);
  if (!id.empty() && id.size() != n0) throw ArchiveError("its particle order has the wrong length");
  {
    std::vector<std::uint8_t> seen(id.size(), 0);
    for (std::uint32_t k : id) {
      if (k >= n0 || seen[k]) throw ArchiveError("its particle order is not a permutation");
      seen[k] = 1;
    }
  }
  if (dynamic) {
    // The store was read in the saved order: the identities are set as they were.
    p.id.swap(id);
  } else if (!id.empty() || !p.id.empty()) {
    // Slot s takes particle id[s] (particle s when the saved run never sorted).
    std::vector<std::uint32_t> from(n0);
    {
      const IdentityOrder order(p);
      for (std::size_t s = 0; s < n0; ++s) from[s] = static_cast<std::uint32_t>(order.slot_of(id.empty() ? s : id[s]));
    }
    permute(from);
    if (id.empty()) p.id.clear();
  }
  last_sort_ = last_sort;
  auto arr = [&](std::vector<double>& v, std::size_t want) {
    get_slots(a, v, want);
    if (v.size() != want) throw ArchiveError("a particle array has the wrong length");
  };
  // Among processes each keeps its share of the slots only (its run of rows,
  // RankSplit::hold_rows) and lets go of the rest of the scene's: the first listing reads
  // from the rows' holders the positions its search needs, and the state moves to the
  // particles' owners.
  if (ranks_) {
    const auto [first, last] = ranks_->rows(n0);
    a.keep_slots(n0, first, last);
  }
  for (auto* v : {&p.x, &p.y, &p.z}) arr(*v, n0);
  const std::size_t nr = p.has_rotation() ? n0 : 0;
  for (auto* v : {&p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz}) arr(*v, n0);
  for (auto* v : {&p.wx, &p.wy, &p.wz, &p.tx, &p.ty, &p.tz}) arr(*v, nr);
  const std::size_t nd = p.has_drag_relaxation() ? n0 : 0;
  for (auto* v : {&p.drag_k, &p.ugx, &p.ugy, &p.ugz}) arr(*v, nd);
  const std::size_t n2 = p.has_two_way() ? n0 : 0;
  for (auto* v : {&p.dfx, &p.dfy, &p.dfz, &p.jx, &p.jy, &p.jz}) arr(*v, n2);
  std::uint64_t nm = 0;
  a.get(nm);
  if (nm != modules_.size()) throw ArchiveError("its modules differ from the scene's");
  for (auto& m : modules_) {
    std::string name;
    a.get(name);
    if (name != m->name()) throw ArchiveError("it has module '" + name + "' where the scene has '" + m->name() + "'");
    m->load_state(a);
  }
  std::uint8_t has_gas = 0;
  a.get(has_gas);
  if ((has_gas != 0) != static_cast<bool>(solver_)) throw ArchiveError("its gas differs from the scene's");
  if (solver_) {
    gas_->load_state(a);
    double gt = 0.0;
    a.get(gt);
    a.get(substep_);
    if (!std::isfinite(gt) || substep_ >= substeps_) throw ArchiveError("its gas clock is inconsistent");
    if (lagged()) {
      std::uint8_t due = 0;
      a.get(due);
      gas_clock_.due = due != 0;
    }
    exchange_->load_state(a);
    if (implicit_drag_) implicit_drag_->load_state(a);
    solver_->restored(gt);
    gas_->refresh();
  }
  if (!a.done()) throw ArchiveError("it has data after the last module");
  if (steps > total_steps_ || !std::isfinite(time))
    throw ArchiveError("its step count " + std::to_string(steps) + " is beyond the scene's " + std::to_string(total_steps_));
  steps_ = steps;
  time_ = time;
  if (gas_) gas_->set_time(time_);
  forces_valid_ = fv != 0;
  integrator_->discard_pending();  // the velocities read are those at time()
  if (ranks_) ranks_->hold_rows(p, {});
  if (masses_pending && !dynamic && ranks_)
    for (const auto& [first, last] : ranks_->own_runs(n0))
      for (std::uint32_t i = first; i < last; ++i) set_scene_mass(i);
  integrator_->masses_changed();
  restarted_ = true;
}

}  // namespace cdm
