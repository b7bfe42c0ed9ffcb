// The run's contact module evaluating the state a step left, for output
// (output_fields.hpp), without changing the run.
#include <array>
#include <optional>
#include <utility>

#include "cdm/solver/contact/contact_module.hpp"

namespace cdm {

void ContactModule::add_listed_forces(ParticleStore& p) {
  worst_ = {};
  n_active_ = 0;
  evaluate(p, 0.0, false);
}

void ContactModule::probe_listed(bool vectors, const std::function<void(ContactModule&)>& read) {
  // What an evaluation changes besides the history (which the kernels leave as it is
  // while keep_history_ is set) is set aside and put back: the counts, the recorded
  // forces (the run's, which rolling resistance reads, in arrays of their own
  // meanwhile), and the mesh contacts, whose list each evaluation makes anew (a copy:
  // they are the few particles near a mesh).
  const OverlapRecord worst = worst_;
  const std::size_t active = n_active_;
  const bool record = record_, record_vectors = record_vectors_;
  const std::array<std::vector<double>*, 5> recorded = {&fn_pair_, &fn_wall_, &fv_wall_, &fn_mesh_, &fv_pair_};
  std::array<std::vector<double>, 5> run;
  for (std::size_t a = 0; a < recorded.size(); ++a) run[a].swap(*recorded[a]);
  std::optional<MeshContacts> mesh;
  auto restore = [&] {
    keep_history_ = false;
    record_ = record;
    record_vectors_ = record_vectors;
    for (std::size_t a = 0; a < recorded.size(); ++a) {
      recorded[a]->swap(run[a]);
      run[a] = {};
    }
    if (mesh) mesh_ = std::move(mesh);
    worst_ = worst;
    n_active_ = active;
  };
  try {
    mesh = mesh_;
    keep_history_ = record_ = true;
    record_vectors_ = vectors;
    read(*this);
  } catch (...) {
    restore();
    throw;
  }
  restore();
}

}  // namespace cdm
