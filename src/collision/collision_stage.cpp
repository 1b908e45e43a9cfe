#include "collision/collision_stage.h"

#include <limits>

#include "core/parallel.h"

namespace clothsim {

double CollisionStage::begin_step(const ClothModel& model, const ClothState& state, int threads,
                                  CollisionPasses passes) {
  passes_ = passes;
  switch (passes) {
    case CollisionPasses::all: active_ = !model.colliders.empty() || model.collision.self; break;
    case CollisionPasses::self_only: active_ = model.collision.self; break;
    case CollisionPasses::none: active_ = false; break;
  }
  if (!active_) {
    obstacles_.surface_contacts().any = false;
    return std::numeric_limits<double>::infinity();
  }
  start_time_ = state.time;
  start_position_.resize(state.position.size());
  parallel_for(state.position.size(), threads, [&](std::size_t p) { start_position_[p] = state.position[p]; });
  if (passes == CollisionPasses::self_only) return std::numeric_limits<double>::infinity();
  return obstacles_.begin_step(model, state, threads);
}

CollisionCounts CollisionStage::apply(const ClothModel& model, ClothState& state, ForceTerms terms, int threads) {
  CollisionCounts counts;
  if (!active_) return counts;
  if (passes_ == CollisionPasses::all) {
    counts.obstacles = obstacles_.apply(model, state, start_position_, start_time_, terms, threads);
  }
  counts.self = self_.apply(model, state, start_position_, state.time - start_time_, terms, threads);
  return counts;
}

std::size_t CollisionStage::bytes() const {
  return start_position_.capacity() * sizeof(Vec3) + obstacles_.bytes() + self_.bytes();
}

}  // namespace clothsim
