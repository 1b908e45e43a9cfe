#include "model/initial_conditions.h"

namespace clothsim {
namespace {

// SplitMix64 (Steele, Lea and Flood 2014): tiny, fast, and fully specified, unlike the
// distributions of <random>, whose output differs between standard libraries.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [-1, 1).
  double symmetric() { return static_cast<double>(next() >> 11) * 0x1.0p-52 - 1.0; }

 private:
  std::uint64_t state_;
};

}  // namespace

void apply_initial_conditions(const ClothModel& model, const InitialConditions& initial, ClothState& state) {
  Vec3 centre;
  for (const Vec3& p : model.particle_rest_position) centre += p;
  centre *= 1.0 / static_cast<double>(model.particle_count());

  SplitMix64 random(initial.seed);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    // Draw for every particle, anchored or not, so that anchoring one particle does not shift
    // the perturbation of all the others.
    const Vec3 dx{random.symmetric(), random.symmetric(), random.symmetric()};
    const Vec3 dv{random.symmetric(), random.symmetric(), random.symmetric()};
    if (model.is_anchored(p)) continue;
    state.position[p] += initial.position_noise * dx;
    state.velocity[p] =
        initial.velocity + cross(initial.angular_velocity, state.position[p] - centre) + initial.velocity_noise * dv;
  }
}

}  // namespace clothsim
