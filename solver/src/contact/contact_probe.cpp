// Copies of the contact module that evaluate the state a step left, for output
// (output_fields.hpp), without changing the run.
#include <optional>
#include <utility>

#include "cdm/solver/contact/contact_module.hpp"

namespace cdm {

void ContactModule::add_listed_forces(ParticleStore& p) {
  worst_ = {};
  n_active_ = 0;
  evaluate(p, 0.0, false);
}

ContactModule ContactModule::evaluation_copy() const {
  // The run's list set aside (an empty one in its place) while the rest is copied; the
  // copy then gets the list without its build positions.
  ContactModule& self = const_cast<ContactModule&>(*this);
  VerletList list({}, false, 0.0);
  std::swap(self.list_, list);
  std::optional<ContactModule> copy;
  try {
    copy.emplace(*this);
  } catch (...) {
    std::swap(self.list_, list);
    throw;
  }
  std::swap(self.list_, list);
  copy->list_ = list_.copy_without_build_positions();
  return std::move(*copy);
}

}  // namespace cdm
