#pragma once
/// @file scene.hpp
/// @brief SceneSpec: a scene file loaded and validated, every value in SI units.
/// The loader (scene_loader.hpp) is the only place that reads TOML or converts units.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cdm/solver/coupling/deposition.hpp"
#include "cdm/solver/coupling/drag_laws.hpp"
#include "cdm/solver/fluid/gas_solver.hpp"
#include "cdm/solver/fluid/gas_field.hpp"
#include "cdm/solver/insertion_spec.hpp"
#include "cdm/solver/io/monitor_spec.hpp"
#include "cdm/solver/keywords.hpp"
#include "cdm/solver/materials.hpp"
#include "cdm/solver/periodic_box.hpp"
#include "cdm/solver/vec3.hpp"
#include "cdm/solver/io/vtk_xml.hpp"
#include "cdm/solver/contact/mesh_geometry.hpp"
#include "cdm/solver/walls.hpp"

namespace cdm {

enum class TangentialModel { none, spring_coulomb };
inline constexpr Keywords<TangentialModel, 2> tangential_keywords{
    {{"none", TangentialModel::none}, {"spring_coulomb", TangentialModel::spring_coulomb}}};
enum class RollingModel { none, constant_torque };
inline constexpr Keywords<RollingModel, 2> rolling_keywords{
    {{"none", RollingModel::none}, {"constant_torque", RollingModel::constant_torque}}};
enum class IntegratorScheme { paper_euler, velocity_verlet, rk2, rk4, exponential_midpoint };
inline constexpr Keywords<IntegratorScheme, 5> integrator_keywords{{{"paper_euler", IntegratorScheme::paper_euler},
                                                                    {"velocity_verlet", IntegratorScheme::velocity_verlet},
                                                                    {"rk2", IntegratorScheme::rk2},
                                                                    {"rk4", IntegratorScheme::rk4},
                                                                    {"exponential_midpoint", IntegratorScheme::exponential_midpoint}}};
inline const char* to_string(IntegratorScheme s) { return keyword_of(integrator_keywords, s); }
enum class GasModel { none, prescribed, solved };
inline constexpr Keywords<GasModel, 3> gas_model_keywords{
    {{"none", GasModel::none}, {"prescribed", GasModel::prescribed}, {"solved", GasModel::solved}}};

/// A particle of the scene at the start: where it is, its size and material. Its velocity
/// and spin are its group's (ParticleGroup, InitialMotion), not held per particle: a large
/// scene is held whole on every process until the run deals it out.
struct ParticleSpec {
  Vec3 position;        // [m]
  double radius = 0.0;  // [m]
  int material = 0;
};

/// Where a run of consecutive particles came from in the scene file, so messages can
/// name a particle's key ("particles[3]", "lattices[0] (lattice site 4,1,0)") without
/// storing a string per particle, and how they move at the start.
struct ParticleGroup {
  ParticleGroup(std::string k, std::size_t f, std::size_t n, long long cx = 0, long long cy = 0)
      : key(std::move(k)), first(f), count(n), nx(cx), ny(cy) {}
  std::string key;               // "particles[3]" or "lattices[0]"
  std::size_t first = 0, count = 0;
  long long nx = 0, ny = 0;      // lattice counts along x and y (0 for a listed particle)
  Vec3 velocity;                 // each particle's initial velocity [m/s] (but a lattice's jitter)
  Vec3 angular_velocity;         // each particle's initial spin [rad/s]
  /// A lattice's velocity jitter [m/s], its radii and the seed of the one stream both are
  /// drawn from, site by site (LatticeDraws): the loader draws the radii, the run the
  /// velocities, from the same numbers.
  double jitter = 0.0;
  std::uint64_t seed = 1;
  SizeDistribution size;
};

/// The most time steps a scene may plan: beyond it a run would not end in practice
/// (1e12 steps of one particle take days), and the step count no longer fits the
/// integer arithmetic of the clock and the output samples with room to spare.
constexpr double max_steps = 1e12;

/// The number of steps that reach @p end_time at step @p dt (the last may end past it),
/// as a double so that an absurd count is seen before it is cast to an integer.
inline double step_count(double end_time, double dt) { return std::ceil(end_time / dt - 1e-9); }

struct SceneSpec;
/// The scene key particle @p i came from, e.g. "lattices[0] (lattice site 4,1,0)".
std::string particle_source(const SceneSpec& spec, std::size_t i);

struct SceneSpec {
  std::string file;   // path it was loaded from
  std::string units;  // as written in the file ("SI" or "cgs")

  // Modules: only what is named here is built.
  bool gravity = false;
  Vec3 g;                                          // [m/s^2]
  /// The normal contact law of pairs whose [[contacts]] entry names none; no value when
  /// the scene has no contacts at all.
  std::optional<ContactLaw> normal_contact;
  TangentialModel tangential = TangentialModel::none;
  RollingModel rolling = RollingModel::none;
  /// Gas phase: none (a DEM-only scene builds no grid) or a prescribed field.
  GasModel gas = GasModel::none;
  fluid::GasSpec gas_spec;  // when gas != none
  bool tracers = false;     // every particle a massless tracer of the gas (rk2/rk4)
  std::optional<coupling::DragLaw> drag;  // drag module, when named
  coupling::DragUpdate drag_update = coupling::DragUpdate::explicit_force;
  double drag_void_fraction = 0.0;  // ε_g held in the drag law; 0 = from the grid
  bool pressure_gradient = false;   // −V_p ∇P module (eq 30)
  // Solved gas only:
  double gas_dt = 0.0;               // gas step [s]; particles sub-step inside it
  fluid::AdvectionScheme advection = fluid::AdvectionScheme::central;
  fluid::PressureSolverSpec pressure_solver;  // gas.pressure_solver, gas.pressure_tolerance
  fluid::GasDivision gas_division = fluid::GasDivision::automatic;  // gas.division
  Vec3 gas_initial_velocity;         // [m/s]
  Vec3 mean_pressure_gradient;       // imposed ∇P̄ [Pa/m] (solved gas)
  bool two_way = false;              // the particles act on the gas (ε and drag reaction)
  bool implicit_gas_drag = false;    // two-way: the drag coefficient implicit in the gas step
  coupling::CouplingMethod coupling_method = coupling::CouplingMethod::interpolate;
  coupling::Kernel kernel = coupling::Kernel::trilinear;
  double kernel_width = 0.0;         // gaussian σ [m]
  coupling::SlipVelocity gas_velocity = coupling::SlipVelocity::interstitial;  // "interpolate" only
  coupling::DragEvaluation drag_evaluation = coupling::DragEvaluation::every_step;

  std::vector<Material> materials;
  PairTable pairs;
  std::vector<Wall> walls;
  std::vector<TriangleMesh> meshes;  // [[meshes]], placed, in SI
  /// Axes along which particles wrap and interact through the faces: from `[periodic]`,
  /// or those of a gas whose boundaries are periodic.
  PeriodicBox periodic;
  std::vector<ParticleSpec> particles;
  std::vector<ParticleGroup> groups;  // covers particles in order
  /// Particles added over time ([[insertions]]) and regions that remove them ([[outlets]]).
  std::vector<InsertionSpec> insertions;
  std::vector<OutletSpec> outlets;
  /// Whether the particle count may change during the run.
  bool population_changes() const { return !insertions.empty() || !outlets.empty(); }
  /// Verlet-list margin [m]: a tenth of the largest particle diameter. Contacts reach
  /// 2 r_max + verlet_skin.
  double verlet_skin = 0.0;

  IntegratorScheme integrator = IntegratorScheme::paper_euler;
  bool dt_auto = true;
  double dt_divisor = 50.0;  // dt = t_col,min / dt_divisor when dt_auto
  double dt = 0.0;           // [s], explicit or resolved from auto
  double t_col_min = 0.0;    // [s], smallest collision time among pairs that can meet (0 if none or unknown)
  double impact_velocity = 0.0;    // [m/s] largest expected impact speed (Hertz collision time); 0 = not given
  double rayleigh_fraction = 0.0;  // dt = rayleigh_fraction * T_R,min when > 0 (dt_auto only)
  double rayleigh_time_min = 0.0;  // [s] smallest Rayleigh time of the Hertz–Mindlin particles (0 if none)
  double end_time = 0.0;     // [s]

  double output_interval = 0.0;  // [s] between rows of the particle table
  bool output_particles = true;
  bool output_vtk = false;  // VTK files (particles, and the gas) at the output interval
  vtk::Encoding output_vtk_format = vtk::Encoding::binary;
  bool output_contacts = false;  // per-contact VTK files (force chains) with the particle frames
  double checkpoint_interval = 0.0;  // [s] of simulated time between checkpoints; 0 = none
  double log_interval = 0.0;  // [s] between rows of log.dat and the monitors' tables; 0 = no log
  std::vector<MonitorSpec> monitors;

  // Spatial sorting of the particles at Verlet-list rebuilds, at most every this many
  // steps (and at the first build); 0 = never (particles stay in scene order).
  std::uint64_t sort_interval = 1000;

  bool allow_initial_overlap = false;
  double max_overlap_fraction = 1.0;  // stop when overlap / radius reaches this [-]
};

}  // namespace cdm
