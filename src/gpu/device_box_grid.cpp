#include "gpu/device_box_grid.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <span>

#include "collision/box_grid.h"
#include "core/assert.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/box_grid.h"

namespace clothsim::gpu {
namespace {

constexpr std::uint64_t kWord = sizeof(std::uint32_t);
static_assert(BoxGrid::kOversize == kOversizeCells, "the device keeps the CPU's boxes aside");

std::vector<std::uint32_t> words(Device& device, const Buffer& buffer, std::size_t count) {
  std::vector<std::uint32_t> out(count);
  if (count > 0) download(device, buffer, std::as_writable_bytes(std::span(out)));
  return out;
}

}  // namespace

DeviceBoxGrid::DeviceBoxGrid(Device& device, Precision precision, std::uint32_t capacity)
    : device_(device),
      precision_(precision),
      capacity_(std::max<std::uint32_t>(capacity, 1)),
      grid_real_(device, real_size(precision), Memory::device_local),
      low_cell_(device, 3 * kWord * capacity_, Memory::device_local),
      cells_of_(device, kWord * capacity_, Memory::device_local),
      oversize_flag_(device, kWord * capacity_, Memory::device_local),
      oversize_(device, kWord * capacity_, Memory::device_local),
      extent_(device, 6 * kWord, Memory::device_local),
      entries_(device, kEntryWords * kWord, Memory::device_local),
      bucket_start_(device, 16 * kWord, Memory::device_local),
      fill_(device, 16 * kWord, Memory::device_local),
      sorted_(device, kWord, Memory::device_local),
      cells_scan_(device, capacity_),
      oversize_scan_(device, capacity_),
      pass_(shader_pipeline(device, "box_grid", precision, 11, sizeof(GridPassConstants))) {
  cells_scan_.bind(cells_of_);
  oversize_scan_.bind(oversize_flag_);
}

void DeviceBoxGrid::bind() {
  pass_.bind(std::vector<const Buffer*>{boxes_, &grid_real_, &low_cell_, &cells_of_, &oversize_flag_, &oversize_,
                                        &extent_, &entries_, &bucket_start_, &fill_, &sorted_});
}

void DeviceBoxGrid::build(const Buffer& boxes, std::uint32_t count, double cell_size) {
  CLOTHSIM_ASSERT(count <= capacity_, "at most the capacity's boxes");
  CLOTHSIM_ASSERT(cell_size > 0.0, "a positive cell size");
  boxes_ = &boxes;
  upload(device_, grid_real_, real_bytes(std::vector<double>{cell_size}, precision_));
  constexpr std::int32_t kFar = std::numeric_limits<std::int32_t>::max();
  const std::array<std::int32_t, 6> no_extent{kFar, kFar, kFar, -kFar, -kFar, -kFar};
  upload(device_, extent_, std::as_bytes(std::span(no_extent)));
  bind();
  // The cells each box enters and the boxes kept aside, counted and scanned.
  device_.submit([&](VkCommandBuffer commands) {
    const GridPassConstants cells{kGridCells, count, bucket_mask_, 0};
    if (count > 0) pass_.dispatch(commands, &cells, count);
    cells_scan_.record(commands, count);
    oversize_scan_.record(commands, count);
    const GridPassConstants aside{kGridOversize, count, bucket_mask_, 0};
    if (count > 0) pass_.dispatch(commands, &aside, count);
  });
  entry_count_ = cells_scan_.total(count);
  oversize_count_ = oversize_scan_.total(count);
  // The CPU's buckets: twice the entries, a power of two, at least 16.
  const std::uint32_t buckets = std::bit_ceil(std::max<std::uint32_t>(2 * entry_count_, 16));
  bucket_mask_ = buckets - 1;
  if (entries_.bytes() < std::uint64_t{entry_count_} * kEntryWords * kWord) {
    entries_ = Buffer(device_, std::uint64_t{entry_count_} * kEntryWords * kWord, Memory::device_local);
    sorted_ = Buffer(device_, std::uint64_t{entry_count_} * kWord, Memory::device_local);
  }
  if (bucket_start_.bytes() < std::uint64_t{buckets} * kWord) {
    bucket_start_ = Buffer(device_, std::uint64_t{buckets} * kWord, Memory::device_local);
    fill_ = Buffer(device_, std::uint64_t{buckets} * kWord, Memory::device_local);
  }
  if (!bucket_scan_ || bucket_scan_->capacity() < buckets) bucket_scan_.emplace(device_, buckets);
  bucket_scan_->bind(bucket_start_);
  bind();
  // The entries, the buckets' counts, their starts, the entries in their buckets, sorted there.
  device_.submit([&](VkCommandBuffer commands) {
    record_zero(commands, bucket_start_, std::uint64_t{buckets} * kWord);
    record_zero(commands, fill_, std::uint64_t{buckets} * kWord);
    const GridPassConstants write{kGridEntries, count, bucket_mask_, entry_count_};
    if (count > 0) pass_.dispatch(commands, &write, count);
    bucket_scan_->record(commands, buckets);
    const GridPassConstants place{kGridFill, count, bucket_mask_, entry_count_};
    if (entry_count_ > 0) pass_.dispatch(commands, &place, entry_count_);
    const GridPassConstants sort{kGridSort, count, bucket_mask_, entry_count_};
    pass_.dispatch(commands, &sort, buckets);
  });
}

std::vector<std::uint32_t> DeviceBoxGrid::bucket_starts() const {
  std::vector<std::uint32_t> starts = words(device_, bucket_start_, bucket_count());
  starts.push_back(entry_count_);
  return starts;
}

std::vector<std::uint32_t> DeviceBoxGrid::entries_by_bucket() const {
  const std::vector<std::uint32_t> order = words(device_, sorted_, entry_count_);
  const std::vector<std::uint32_t> all = words(device_, entries_, std::size_t{entry_count_} * kEntryWords);
  std::vector<std::uint32_t> out;
  out.reserve(all.size());
  for (const std::uint32_t e : order) {
    const auto first = all.begin() + static_cast<std::ptrdiff_t>(std::size_t{e} * kEntryWords);
    out.insert(out.end(), first, first + kEntryWords);
  }
  return out;
}

std::vector<std::uint32_t> DeviceBoxGrid::oversize() const { return words(device_, oversize_, oversize_count_); }

std::array<std::int32_t, 6> DeviceBoxGrid::extent() const {
  std::array<std::int32_t, 6> out{};
  download(device_, extent_, std::as_writable_bytes(std::span(out)));
  return out;
}

DeviceGridQuery::DeviceGridQuery(Device& device, Precision precision, std::uint32_t capacity)
    : device_(device),
      capacity_(std::max<std::uint32_t>(capacity, 1)),
      counts_(device, kWord * capacity_, Memory::device_local),
      pairs_(device, 2 * kWord, Memory::device_local),
      no_exclude_(device, 3 * kWord, Memory::device_local),
      pass_(shader_pipeline(device, "box_grid_query", precision, 11, sizeof(GridQueryConstants))) {}

std::uint32_t DeviceGridQuery::count_and_write(GridQueryConstants constants, std::uint32_t invocations,
                                               const std::vector<const Buffer*>& inputs) {
  if (counts_.bytes() < std::uint64_t{invocations} * kWord) {
    counts_ = Buffer(device_, std::uint64_t{invocations} * kWord, Memory::device_local);
  }
  if (!scan_ || scan_->capacity() < invocations) scan_.emplace(device_, std::max(invocations, capacity_));
  scan_->bind(counts_);
  const auto bind = [&] {
    std::vector<const Buffer*> buffers = inputs;
    buffers.insert(buffers.end(), {&counts_, &pairs_});
    pass_.bind(buffers);
  };
  bind();
  device_.submit([&](VkCommandBuffer commands) {
    if (invocations > 0) pass_.dispatch(commands, &constants, invocations);
    scan_->record(commands, invocations);
  });
  pair_count_ = scan_->total(invocations);
  if (pairs_.bytes() < std::uint64_t{pair_count_} * 2 * kWord) {
    pairs_ = Buffer(device_, std::uint64_t{pair_count_} * 2 * kWord, Memory::device_local);
    bind();
  }
  constants.phase = constants.phase == kQueryCount ? kQueryWrite : kJoinWrite;
  if (invocations > 0)
    device_.submit([&](VkCommandBuffer commands) { pass_.dispatch(commands, &constants, invocations); });
  return pair_count_;
}

std::uint32_t DeviceGridQuery::run(const DeviceBoxGrid& grid, const Buffer& stored, const Buffer& queries,
                                   std::uint32_t count, const Buffer* exclude) {
  CLOTHSIM_ASSERT(count <= capacity_, "at most the capacity's queries");
  const DeviceBoxGrid::Arrays a = grid.arrays();
  const GridQueryConstants constants{kQueryCount,
                                     count,
                                     grid.bucket_count() - 1,
                                     grid.entry_count(),
                                     grid.oversize_count(),
                                     exclude != nullptr ? 1u : 0u,
                                     0};
  return count_and_write(constants, count,
                         {&queries, &stored, a.grid_real, a.extent, a.entries, a.bucket_start, a.sorted, a.oversize,
                          exclude != nullptr ? exclude : &no_exclude_});
}

std::uint32_t DeviceGridQuery::join(const DeviceBoxGrid& grid, const Buffer& stored, std::uint32_t stored_count,
                                    const Buffer* exclude) {
  const DeviceBoxGrid::Arrays a = grid.arrays();
  const GridQueryConstants constants{
      kJoinCount,  0, grid.bucket_count() - 1, grid.entry_count(), grid.oversize_count(), exclude != nullptr ? 1u : 0u,
      stored_count};
  return count_and_write(constants, grid.bucket_count() + grid.oversize_count(),
                         {&stored, &stored, a.grid_real, a.extent, a.entries, a.bucket_start, a.sorted, a.oversize,
                          exclude != nullptr ? exclude : &no_exclude_});
}

std::vector<std::uint32_t> DeviceGridQuery::pairs() const {
  return words(device_, pairs_, 2 * std::size_t{pair_count_});
}

}  // namespace clothsim::gpu
