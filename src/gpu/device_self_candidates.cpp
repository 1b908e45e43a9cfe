#include "gpu/device_self_candidates.h"

#include <algorithm>
#include <span>

#include "gpu/real_arrays.h"
#include "gpu/shaders/self_step.h"

namespace clothsim::gpu {
namespace {

template <std::size_t N>
Buffer index_buffer(Device& device, const std::vector<std::array<std::uint32_t, N>>& items) {
  std::vector<std::uint32_t> words;
  for (const auto& item : items) words.insert(words.end(), item.begin(), item.end());
  if (words.empty()) words.push_back(0);
  Buffer buffer(device, words.size() * sizeof(std::uint32_t), Memory::device_local);
  upload(device, buffer, std::as_bytes(std::span(words)));
  return buffer;
}

std::uint64_t box_bytes(std::uint32_t count, Precision precision) {
  return std::max<std::uint64_t>(count, 1) * 6 * real_size(precision);
}

}  // namespace

DeviceSelfCandidates::DeviceSelfCandidates(Device& device, Precision precision, std::uint32_t particles,
                                           const SheetElements& elements)
    : device_(device),
      precision_(precision),
      particles_(particles),
      triangles_(static_cast<std::uint32_t>(elements.triangle.size())),
      edges_(static_cast<std::uint32_t>(elements.edge.size())),
      triangle_capacity_(triangles_),
      edge_capacity_(edges_),
      triangle_corners_(index_buffer(device, elements.triangle)),
      edge_ends_(index_buffer(device, elements.edge)),
      point_boxes_(device, box_bytes(particles, precision), Memory::device_local),
      triangle_boxes_(device, box_bytes(triangles_, precision), Memory::device_local),
      edge_boxes_(device, box_bytes(edges_, precision), Memory::device_local),
      self_real_(device, 3 * real_size(precision), Memory::device_local),
      detect_real_(device, real_size(precision), Memory::device_local),
      flags_(device, sizeof(std::uint32_t), Memory::device_local),
      start_distance_(device, real_size(precision), Memory::device_local),
      keep_(device, sizeof(std::uint32_t), Memory::device_local),
      keep_flag_(device, sizeof(std::uint32_t), Memory::device_local),
      pairs_(device, 2 * sizeof(std::uint32_t), Memory::device_local),
      select_real_(device, real_size(precision), Memory::device_local),
      boxes_pass_(shader_pipeline(device, "self_boxes", precision, 8, sizeof(BoxesPassConstants))),
      select_pass_(shader_pipeline(device, "self_select", precision, 9, sizeof(SelectPassConstants))),
      detect_pass_(shader_pipeline(device, "self_detect", precision, 11, sizeof(DetectPassConstants))),
      keep_scan_(device, 1),
      triangle_grid_(device, precision, triangles_),
      edge_grid_(device, precision, edges_),
      point_query_(device, precision, particles),
      edge_query_(device, precision, 1) {}

bool DeviceSelfCandidates::set_elements(const SheetElements& elements) {
  const auto triangles = static_cast<std::uint32_t>(elements.triangle.size());
  const auto edges = static_cast<std::uint32_t>(elements.edge.size());
  if (triangles > triangle_capacity_ || edges > edge_capacity_) return false;
  triangles_ = triangles;
  edges_ = edges;
  triangle_corners_ = index_buffer(device_, elements.triangle);
  edge_ends_ = index_buffer(device_, elements.edge);
  point_triangle_count_ = edge_pair_count_ = kept_count_ = 0;
  return true;
}

void DeviceSelfCandidates::bind_boxes(const Buffer& start, const Buffer& end, double margin) {
  if (margin != margin_) {
    upload(device_, self_real_, real_bytes(std::vector<double>{margin}, precision_));
    margin_ = margin;
  }
  boxes_pass_.bind(std::vector<const Buffer*>{&start, &end, &triangle_corners_, &edge_ends_, &point_boxes_,
                                              &triangle_boxes_, &edge_boxes_, &self_real_});
}

void DeviceSelfCandidates::record_boxes(VkCommandBuffer commands, bool cell_sizes) const {
  const auto pass = [&](std::uint32_t phase, std::uint32_t invocations) {
    const BoxesPassConstants constants{phase, particles_, triangles_, edges_};
    if (invocations > 0) boxes_pass_.dispatch(commands, &constants, invocations);
  };
  pass(kBoxesPoints, particles_);
  pass(kBoxesElements, triangles_ + edges_);
  pass(kBoxesGrow, particles_);
  if (cell_sizes) pass(kBoxesCells, 1);
}

void DeviceSelfCandidates::find(const Buffer& start, const Buffer& end, double margin) {
  bind_boxes(start, end, margin);
  device_.submit([&](VkCommandBuffer commands) { record_boxes(commands, true); });
  std::vector<std::byte> bytes(3 * real_size(precision_));
  download(device_, self_real_, bytes);
  const std::vector<double> reals = reals_from_bytes(bytes, precision_);
  triangle_grid_.build(triangle_boxes_, triangles_, reals[1]);
  edge_grid_.build(edge_boxes_, edges_, reals[2]);
  point_triangle_count_ =
      point_query_.run(triangle_grid_, triangle_boxes_, point_boxes_, particles_, &triangle_corners_);
  edge_pair_count_ = edge_query_.join(edge_grid_, edge_boxes_, edges_, &edge_ends_);
  select(nullptr, 0.0);
}

void DeviceSelfCandidates::prune(const Buffer& x, double reach) { select(&x, reach); }

void DeviceSelfCandidates::select(const Buffer* x, double reach) {
  const std::uint32_t found = point_triangle_count_ + edge_pair_count_;
  if (keep_scan_.capacity() < found) {
    // Room for the search's pairs, and some to spare: a sheet that folds finds more every step.
    const std::uint32_t capacity = found + found / 2;
    keep_ = Buffer(device_, std::uint64_t{capacity} * sizeof(std::uint32_t), Memory::device_local);
    keep_flag_ = Buffer(device_, std::uint64_t{capacity} * sizeof(std::uint32_t), Memory::device_local);
    pairs_ = Buffer(device_, std::uint64_t{capacity} * 2 * sizeof(std::uint32_t), Memory::device_local);
    keep_scan_.reserve(capacity);
    keep_scan_.bind(keep_);
  }
  upload(device_, select_real_, real_bytes(std::vector<double>{reach}, precision_));
  select_pass_.bind(std::vector<const Buffer*>{x != nullptr ? x : &select_real_, &triangle_corners_, &edge_ends_,
                                               &point_query_.pair_buffer(), &edge_query_.pair_buffer(), &keep_,
                                               &keep_flag_, &pairs_, &select_real_});
  const std::uint32_t keep_all = x == nullptr ? 1u : 0u;
  device_.submit([&](VkCommandBuffer commands) {
    if (found == 0) return;
    const SelectPassConstants measure{kSelectMeasure, point_triangle_count_, edge_pair_count_, keep_all};
    select_pass_.dispatch(commands, &measure, found);
    keep_scan_.record(commands, found);
    const SelectPassConstants write{kSelectWrite, point_triangle_count_, edge_pair_count_, keep_all};
    select_pass_.dispatch(commands, &write, found);
  });
  kept_count_ = found == 0 ? 0 : keep_scan_.total(found);
}

void DeviceSelfCandidates::prepare_detect(const Buffer& start, const Buffer& end, double thickness) {
  bind_boxes(start, end, 0.5 * thickness);
  if (thickness != detect_thickness_) {
    upload(device_, detect_real_, real_bytes(std::vector<double>{thickness}, precision_));
    detect_thickness_ = thickness;
  }
  const std::uint32_t candidates = kept_count_;
  if (flags_.bytes() < std::uint64_t{candidates} * sizeof(std::uint32_t)) {
    flags_ = Buffer(device_, std::uint64_t{candidates} * sizeof(std::uint32_t), Memory::device_local);
    start_distance_ = Buffer(device_, std::uint64_t{candidates} * real_size(precision_), Memory::device_local);
  }
  detect_pass_.bind(std::vector<const Buffer*>{&start, &end, &triangle_corners_, &edge_ends_, &point_boxes_,
                                               &triangle_boxes_, &edge_boxes_, &pairs_, &flags_, &start_distance_,
                                               &detect_real_});
}

void DeviceSelfCandidates::record_detect(VkCommandBuffer commands) const {
  record_boxes(commands, false);  // grown by half the thickness; no grid to build
  const DetectPassConstants counts{kept_count_};
  if (kept_count_ > 0) detect_pass_.dispatch(commands, &counts, kept_count_);
}

void DeviceSelfCandidates::detect(const Buffer& start, const Buffer& end, double thickness) {
  prepare_detect(start, end, thickness);
  device_.submit([&](VkCommandBuffer commands) { record_detect(commands); });
}

std::vector<std::uint32_t> DeviceSelfCandidates::flags() const {
  std::vector<std::uint32_t> out(kept_count_);
  if (!out.empty()) download(device_, flags_, std::as_writable_bytes(std::span(out)));
  return out;
}

std::vector<std::uint32_t> DeviceSelfCandidates::pairs() const {
  std::vector<std::uint32_t> out(2 * std::size_t{kept_count_});
  if (!out.empty()) download(device_, pairs_, std::as_writable_bytes(std::span(out)));
  return out;
}

std::vector<double> DeviceSelfCandidates::start_distances() const {
  std::vector<std::byte> bytes(std::size_t{kept_count_} * real_size(precision_));
  if (!bytes.empty()) download(device_, start_distance_, bytes);
  return reals_from_bytes(bytes, precision_);
}

}  // namespace clothsim::gpu
