// What the contact module carries in a checkpoint, and the names of its partners.
#include <string>

#include "cdm/solver/contact/contact_module.hpp"

namespace cdm {

void ContactModule::save_state(OutArchive& a) const {
  a.put(static_cast<std::uint8_t>(list_.built()));
  a.put(static_cast<std::uint64_t>(list_.builds()));
  a.put(static_cast<std::uint64_t>(n_active_));
  a.put(worst_.ratio); a.put(worst_.particle); a.put(worst_.partner);  // field by field: no padding bytes
  list_.save_state(a);
  if (mesh_) mesh_->save_state(a);
}

void ContactModule::load_state(InArchive& a) {
  std::uint8_t built = 0;
  std::uint64_t builds = 0, active = 0;
  a.get(built); a.get(builds); a.get(active);
  a.get(worst_.ratio); a.get(worst_.particle); a.get(worst_.partner);
  list_.load_state(a, built != 0, builds);
  if (mesh_) mesh_->load_state(a);
  n_active_ = active;
  damping_stale_ = true;
}

std::string ContactModule::wall_name(long partner) const {
  const auto w = static_cast<std::size_t>(-1 - partner);
  if (w < walls().size()) return "wall '" + walls()[w].name + "'";
  return "mesh '" + mesh_->meshes()[w - walls().size()].name + "'";
}

}  // namespace cdm
