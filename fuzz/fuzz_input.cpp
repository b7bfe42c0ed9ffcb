/// @file fuzz_input.cpp
/// @brief libFuzzer target for everything a user can hand cdm: scene files and
/// checkpoints. The first byte picks which (or CDM_FUZZ_ONLY does: 0 scenes only, 1
/// checkpoints only, so that each reader gets a campaign of its own); the rest is the
/// file. Every input must
/// either load or be refused with SceneError/CheckpointError (what `cdm run` turns into
/// exit status 2); anything else — a crash, another exception, a hang, unbounded
/// allocation — is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cdm/solver/checkpoint.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
#ifdef CDM_FUZZ_ONLY
  const bool checkpoint = CDM_FUZZ_ONLY == 1;
#else
  const bool checkpoint = data[0] & 1;
#endif
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  if (!checkpoint) {
    try {
      const cdm::SceneSpec spec = cdm::load_scene_from_string(text, "fuzz.toml");
      // A scene that loads must also build (only small ones: building is not parsing).
      if (spec.particles.size() <= 2000) {
        cdm::Simulation sim(spec);
        (void)sim;
      }
    } catch (const cdm::SceneError&) {
    }
    return 0;
  }
  try {
    const cdm::CheckpointData d = cdm::read_checkpoint_bytes(std::vector<char>(text.begin(), text.end()), "fuzz.cdmck");
    const cdm::SceneSpec spec = cdm::load_scene_from_string(d.origin.scene_text, d.origin.scene_name, d.origin.overrides);
    if (spec.particles.size() <= 2000) {
      cdm::Simulation sim(spec);
      cdm::restore_checkpoint(d, sim, "fuzz.cdmck");
    }
  } catch (const cdm::CheckpointError&) {
  } catch (const cdm::SceneError&) {
  }
  return 0;
}
