#include "gpu/device_self_contacts.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <span>

#include "collision/sheet_elements.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/box_grid.h"
#include "gpu/shaders/self_step.h"

namespace clothsim::gpu {
namespace {

constexpr std::uint64_t kWord = sizeof(std::uint32_t);

SheetElements elements_of(const ClothModel& model) {
  SheetElements elements;
  refresh_sheet_elements(model, elements);
  return elements;
}

Buffer real_buffer(Device& device, Precision precision, const std::vector<double>& values) {
  const std::vector<std::byte> bytes = real_bytes(values, precision);
  Buffer buffer(device, std::max<std::uint64_t>(bytes.size(), 8), Memory::device_local);
  if (!bytes.empty()) upload(device, buffer, bytes);
  return buffer;
}

}  // namespace

DeviceSelfContacts::DeviceSelfContacts(Device& device, Precision precision, const ClothModel& model)
    : device_(device),
      precision_(precision),
      particles_(static_cast<std::uint32_t>(model.particle_count())),
      built_broken_(model.broken_connector_count),
      built_inverse_mass_(model.particle_inverse_mass.begin(), model.particle_inverse_mass.end()),
      thickness_(model.collision.thickness),
      friction_(model.collision.friction),
      spacing_(model.spacing),
      candidates_(device, precision, particles_, elements_of(model)),
      inverse_mass_(real_buffer(device, precision, built_inverse_mass_)),
      found_at_(device, std::uint64_t{particles_} * 3 * real_size(precision), Memory::device_local),
      block_motion_(device,
                    std::uint64_t{workgroups_for(particles_, kMotionWorkgroup)} * kMotionValues * real_size(precision),
                    Memory::device_local),
      motion_(device, kMotionValues * real_size(precision), Memory::device_local),
      slot_(device, kWord, Memory::device_local),
      list_(device, kWord, Memory::device_local),
      table_start_(device, std::uint64_t{particles_} * kWord, Memory::device_local),
      table_fill_(device, std::uint64_t{particles_} * kWord, Memory::device_local),
      entries_(device, 4 * kWord, Memory::device_local),
      geometry_(device, kGeometryReals * real_size(precision), Memory::device_local),
      change_(device, kChangeReals * real_size(precision), Memory::device_local),
      counters_(device, kCounters * kWord, Memory::device_local),
      respond_real_(real_buffer(device, precision, {0.0, 0.0, 0.0})),
      listed_(device, kWord, Memory::device_local),
      readback_(device, kCountersOffset + kCounters * kWord, Memory::host_visible),
      motion_pass_(shader_pipeline(device, "self_motion", precision, 5, sizeof(MotionPassConstants), kMotionWorkgroup)),
      list_pass_(shader_pipeline(device, "self_list", precision, 4, sizeof(ListPassConstants))),
      respond_pass_(shader_pipeline(device, "self_respond", precision, 17, sizeof(RespondPassConstants))),
      slot_scan_(device, 1),
      table_scan_(device, particles_) {
  table_scan_.bind(table_start_);
}

std::uint64_t DeviceSelfContacts::bytes_for(const LatticeCounts& counts, Precision precision) {
  const std::uint64_t real = real_size(precision);
  const std::uint64_t n = counts.particles;
  const SheetElementCounts elements = sheet_element_counts(counts);
  const std::uint64_t triangles = elements.triangles;
  const std::uint64_t edges = elements.edges;
  // The elements and the motion's boxes (a low and a high corner each).
  std::uint64_t bytes = (3 * triangles + 2 * edges) * kWord + (n + triangles + edges) * 6 * real;
  // Each grid: a low cell (3 words), a cell count, the oversize marks (2) and two prefix sums a box;
  // five words and a sorted one an entry; two bucket arrays of twice the entries.
  for (const std::uint64_t boxes : {triangles, edges}) {
    const auto entries = static_cast<std::uint64_t>(SelfContacts::kGridEntriesPerBox * static_cast<double>(boxes));
    bytes += boxes * 8 * kWord + entries * (kEntryWords + 1) * kWord +
             2 * std::bit_ceil(std::max<std::uint64_t>(2 * entries, 16)) * kWord;
  }
  // By particle: the inverse mass, where the candidates were found, the query's count, the
  // response table's start and fill.
  bytes += n * (4 * real + 3 * kWord);
  // By candidate: the search's pair (2 words), its keep mark and scan (2), the kept pair (2), its
  // flags, the list's slot and entry (3) and its start distance; listed, its response's entries
  // (4 words), geometry and change.
  const auto candidates = static_cast<std::uint64_t>(SelfContacts::kCandidatesPerParticle * static_cast<double>(n));
  bytes += candidates * (9 * kWord + real) + candidates * (4 * kWord + (kGeometryReals + kChangeReals) * real);
  return bytes;
}

bool DeviceSelfContacts::refresh(const ClothModel& model) {
  if (model.particle_count() != particles_) return false;
  if (model.broken_connector_count != built_broken_) {
    if (!candidates_.set_elements(elements_of(model))) return false;
    built_broken_ = model.broken_connector_count;
    found_ = false;
  }
  if (!std::ranges::equal(model.particle_inverse_mass, built_inverse_mass_)) {
    built_inverse_mass_.assign(model.particle_inverse_mass.begin(), model.particle_inverse_mass.end());
    upload(device_, inverse_mass_, real_bytes(built_inverse_mass_, precision_));
  }
  if (model.collision.thickness != thickness_ || model.collision.friction != friction_) {
    thickness_ = model.collision.thickness;
    friction_ = model.collision.friction;
    respond_step_ = -1.0;  // apply() uploads the response's constants again
  }
  return true;
}

DeviceSelfContacts::Detection DeviceSelfContacts::submit_detection(const Buffer& start, const Buffer& end,
                                                                   std::uint32_t mask, bool motion,
                                                                   bool zero_counters) {
  candidates_.prepare_detect(start, end, thickness_);
  const std::uint32_t candidates = candidates_.candidate_count();
  if (slot_.bytes() < std::uint64_t{candidates} * kWord) {
    const std::uint64_t capacity = candidates + candidates / 2;
    slot_ = Buffer(device_, capacity * kWord, Memory::device_local);
    list_ = Buffer(device_, capacity * kWord, Memory::device_local);
    slot_scan_.reserve(static_cast<std::uint32_t>(capacity));
  }
  slot_scan_.bind(slot_);
  list_pass_.bind(std::vector<const Buffer*>{&candidates_.flag_buffer(), &slot_, &list_, &listed_});
  if (motion) motion_pass_.bind(std::vector<const Buffer*>{&start, &end, &found_at_, &block_motion_, &motion_});
  const std::uint32_t blocks = workgroups_for(particles_, kMotionWorkgroup);
  const std::uint64_t motion_bytes = kMotionValues * real_size(precision_);
  device_.submit([&](VkCommandBuffer commands) {
    if (zero_counters) record_zero(commands, counters_, kCounters * kWord);
    if (motion) {
      const MotionPassConstants per_block{kMotionBlocks, particles_, blocks, 0};
      motion_pass_.dispatch(commands, &per_block, particles_);
      const MotionPassConstants total{kMotionTotal, particles_, blocks, 0};
      motion_pass_.dispatch(commands, &total, kMotionWorkgroup);
      record_readback(commands, motion_, readback_, motion_bytes);
    }
    candidates_.record_detect(commands);
    if (candidates > 0) {
      const ListPassConstants count{kListCount, candidates, mask, 0};
      list_pass_.dispatch(commands, &count, candidates);
      slot_scan_.record(commands, candidates);
      const ListPassConstants write{kListWrite, candidates, mask, 0};
      list_pass_.dispatch(commands, &write, candidates);
    }
    const ListPassConstants total{kListTotal, candidates, mask, 0};
    list_pass_.dispatch(commands, &total, 1);
    record_readback(commands, listed_, readback_, kWord, kListedOffset);
    record_readback(commands, counters_, readback_, kCounters * kWord, kCountersOffset);
  });
  Detection detection;
  std::memcpy(&detection.listed, readback_.mapped() + kListedOffset, kWord);
  if (motion) detection.motion = reals_from_bytes(std::span(readback_.mapped(), motion_bytes), precision_);
  return detection;
}

std::uint32_t DeviceSelfContacts::detect_and_list(const Buffer& start, const Buffer& end, std::uint32_t mask,
                                                  bool zero_counters) {
  const Detection detection = submit_detection(start, end, mask, true, zero_counters);
  // While every position of the motion stays within the reach of where the candidates were found,
  // they hold every pair that can come within the thickness (SelfContacts::refresh_candidates).
  if (found_ && std::sqrt(detection.motion[kMotionFromFound]) <= reach_) return detection.listed;
  const double moved = std::sqrt(detection.motion[kMotionOfStep]);
  const double reach = SelfContacts::candidate_reach(moved, found_ ? reach_ : 0.0, thickness_, spacing_);
  candidates_.find(start, end, thickness_ + reach);
  candidates_.prune(end, SelfContacts::prune_distance(moved, reach, thickness_));
  device_.submit([&](VkCommandBuffer commands) { record_copy(commands, end, found_at_, found_at_.bytes()); });
  reach_ = reach;
  found_ = true;
  return submit_detection(start, end, mask, false, false).listed;
}

void DeviceSelfContacts::prepare_responses(std::uint32_t listed, const Buffer& start, const Buffer& position,
                                           const Buffer& velocity, const MovedLedger& ledger) {
  if (listed > list_capacity_) {
    list_capacity_ = listed + listed / 2;
    const std::uint64_t real = real_size(precision_);
    entries_ = Buffer(device_, std::uint64_t{list_capacity_} * 4 * kWord, Memory::device_local);
    geometry_ = Buffer(device_, std::uint64_t{list_capacity_} * kGeometryReals * real, Memory::device_local);
    change_ = Buffer(device_, std::uint64_t{list_capacity_} * kChangeReals * real, Memory::device_local);
  }
  respond_pass_.bind(std::vector<const Buffer*>{
      &start, &position, &velocity, &inverse_mass_, &candidates_.triangle_buffer(), &candidates_.edge_buffer(),
      &candidates_.pair_buffer(), &list_, &table_start_, &table_fill_, &entries_, &geometry_, &change_, &counters_,
      &respond_real_, ledger_ ? ledger.before : &respond_real_, ledger_ ? ledger.moved : &counters_});
}

void DeviceSelfContacts::respond(VkCommandBuffer commands, std::uint32_t phase, std::uint32_t listed,
                                 bool first_round) const {
  const bool per_particle = phase == kRespondSort || phase == kRespondGather;
  const RespondPassConstants constants{phase, listed, particles_, first_round ? 1u : 0u, ledger_ ? 1u : 0u};
  respond_pass_.dispatch(commands, &constants, per_particle ? particles_ : listed);
}

void DeviceSelfContacts::record_table(VkCommandBuffer commands, std::uint32_t listed) const {
  record_zero(commands, table_start_, std::uint64_t{particles_} * kWord);
  record_zero(commands, table_fill_, std::uint64_t{particles_} * kWord);
  respond(commands, kRespondCount, listed);
  table_scan_.record(commands, particles_);
  respond(commands, kRespondFill, listed);
  respond(commands, kRespondSort, listed);
  respond(commands, kRespondShare, listed);
}

SelfContactCounts DeviceSelfContacts::apply(const Buffer& start, const Buffer& position, const Buffer& velocity,
                                            double step, const MovedLedger& ledger) {
  SelfContactCounts counts;
  ledger_ = ledger.before != nullptr && ledger.moved != nullptr;
  if (step != respond_step_) {
    upload(device_, respond_real_, real_bytes(std::vector<double>{thickness_, friction_, step}, precision_));
    respond_step_ = step;
  }

  // Stage 2: the near pairs pushed to the thickness, on the side they were on at the start.
  const std::uint32_t near = detect_and_list(start, position, kPairNear, true);
  if (near > 0) {
    prepare_responses(near, start, position, velocity, ledger);
    device_.submit([&](VkCommandBuffer commands) {
      record_table(commands, near);
      respond(commands, kRespondNearStart, near);
      for (int iteration = 0; iteration < kProximityIterations; ++iteration) {
        respond(commands, kRespondProximity, near, iteration == 0);
        respond(commands, kRespondGather, near);
      }
    });
  }

  // Stage 3: rounds of detection along the motion and response to the touching pairs.
  std::uint32_t touching = 0;
  for (int round = 0; round <= kImpactRounds; ++round) {
    touching = detect_and_list(start, position, kPairTouching, false);
    if (touching == 0 || round == kImpactRounds) break;
    prepare_responses(touching, start, position, velocity, ledger);
    device_.submit([&](VkCommandBuffer commands) {
      record_table(commands, touching);
      for (int iteration = 0; iteration < kImpactIterations; ++iteration) {
        respond(commands, kRespondImpact, touching);
        respond(commands, kRespondGather, touching);
      }
    });
  }
  // As the last detection, after the last responses, read them back.
  std::vector<std::uint32_t> counted(kCounters);
  std::memcpy(counted.data(), readback_.mapped() + kCountersOffset, kCounters * kWord);
  counts.contacts = counted[kCounterPushed];
  counts.impacts = counted[kCounterImpacts];
  counts.unresolved = touching;
  return counts;
}

}  // namespace clothsim::gpu
