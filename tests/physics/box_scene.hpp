#pragma once
// A scene shared by the physics tests: frictional spheres thrown about a walled box.
namespace cdm_test {

// 6 x 6 x 6 frictional spheres thrown about a walled box: contacts, walls, spins.
inline const char* box_scene = R"(
units = "SI"
[modules]
gravity = true
normal_contact = "linear_spring_dashpot"
tangential = "spring_coulomb"
[gravity]
g = [0.0, 0.0, -9.81]
[[materials]]
name = "glass"
density = 2500.0
[[materials]]
name = "wall"
[[contacts]]
pair = ["glass", "glass"]
kn = 1.0e3
en = 0.9
mu = 0.5
[[contacts]]
pair = ["glass", "wall"]
kn = 1.0e3
en = 0.9
mu = 0.5
[[walls]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
material = "wall"
[[walls]]
name = "x-"
point = [0.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
material = "wall"
[[walls]]
name = "x+"
point = [0.0066, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
material = "wall"
[[lattices]]
material = "glass"
radius = 0.5e-3
origin = [0.00055, 0.00055, 0.00055]
spacing = [0.0011, 0.0011, 0.0011]
count = [6, 6, 6]
velocity_jitter = 0.5
seed = 7
[integrator]
scheme = "velocity_verlet"
dt = "auto"
end_time = 0.05
)";

}  // namespace cdm_test
