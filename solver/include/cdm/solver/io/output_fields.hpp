#pragma once
/// @file output_fields.hpp
/// @brief Quantities the outputs write that the simulation does not keep as such,
/// computed from its state without changing it.
#include <array>
#include <cstdint>
#include <vector>

namespace cdm {

class Simulation;

/// The total contact force [N] on each particle (particle–particle and particle–wall),
/// by slot: x, y and z; empty without contacts. The simulation adds contact forces into
/// the same array as every other force, so they are evaluated afresh here, by a copy of
/// the contact module (its lists and tangential history) on the particles with their
/// force arrays set aside, at the state the outputs write: positions and velocities at
/// time(), the tangential springs as the last step left them, not advanced (Δt = 0).
/// The forces of the last step were evaluated at the same positions with velocities one
/// kick earlier, so the two differ by the damping of that velocity change.
/// Where the MPI processes share the contact list and it stands as the step left it
/// (Simulation::own_contacts_current), each process evaluates its own particles' with its
/// part of the list, as a step does (from_owners: Simulation::written_rows gathers them
/// from their owners). Otherwise the copy lists every pair again on process 0 from the
/// whole list's contacts, with the state gathered there (Simulation::hold_contacts,
/// written_particles), and only process 0 evaluates them. A collective call when
/// several processes share the particles.
struct ContactForces {
  std::array<std::vector<double>, 3> f;
  bool from_owners = false;
};
ContactForces contact_forces(const Simulation& sim);

/// The particle–particle contacts at the state the outputs write, evaluated like
/// contact_forces(): per contact the identities of its two particles (i, j), the force
/// on i from j split into its normal and tangential parts [N], and the overlap
/// r_i + r_j − |x_j − x_i| [m]; in the order of the Verlet list. Where each process
/// evaluates its own (from_owners), it holds its own slabs' contacts, which follow one
/// another in rank order (Simulation::ordered_to_writer); else process 0 holds them all
/// and the others none. A collective call when several processes share the particles.
struct ContactNetwork {
  std::vector<std::int64_t> pairs;  ///< i j per contact
  std::vector<double> normal, tangential;  ///< x y z per contact
  std::vector<double> overlap;
  bool from_owners = false;
};
ContactNetwork contact_network(const Simulation& sim);

/// The force each of the scene's [[walls]] exerts on the particles [N], x y z per wall in
/// scene order, evaluated like contact_forces() and summed over the particles
/// (counted_sums.hpp: the same on any number of threads and processes); empty without
/// contacts. A collective call when several processes share the particles.
std::vector<double> wall_forces(const Simulation& sim);

/// Values on the gas cells of a run of planes along z from plane @p first: 3 values a
/// cell, x fastest, then y, then z (VTK's order), from the first plane's first cell.
struct CellPlanes {
  int first = 0;
  std::vector<double> values;
};
/// The solids velocity [m/s] on the cells of @p planes (along z): the volume-weighted mean
/// velocity of the particles whose centres lie in the cell, 3 values a cell; zero in cells
/// without particles. Summed exactly (exact_sums.hpp), each process its own particles: the
/// same on any number of processes. Where the processes divide the gas by planes and each
/// one's particles lie within its reach (PlaneShare), each adds up the planes of its reach
/// only; else every cell (a collective call when several share the particles).
CellPlanes solids_velocity(const Simulation& sim, std::pair<int, int> planes);

}  // namespace cdm
