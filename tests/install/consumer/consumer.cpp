// A program outside cdm's tree that runs a scene through the installed library.
#include <cstdio>

#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  cdm::Simulation sim(cdm::load_scene(argv[1]));
  sim.run();
  std::printf("t = %.6g s after %llu steps, %zu particles\n", sim.time(), static_cast<unsigned long long>(sim.steps()),
              sim.particles().size());
  return sim.steps() > 0 ? 0 : 1;
}
