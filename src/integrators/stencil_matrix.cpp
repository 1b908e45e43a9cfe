#include "integrators/stencil_matrix.h"

#include <algorithm>

#include "core/assert.h"

namespace clothsim {

SymmetricStencilMatrix::SymmetricStencilMatrix(std::size_t rows, std::size_t cols, std::span<const Offset> upper)
    : rows_(rows), cols_(cols), slots_(upper.size()) {
  CLOTHSIM_ASSERT(!upper.empty() && upper.size() <= kMaxSlots && (upper[0] == Offset{0, 0}),
                  "the upper stencil: (0, 0) first, at most kMaxSlots offsets");
  for (std::size_t s = 0; s < slots_; ++s) {
    const auto [di, dj] = upper[s];
    CLOTHSIM_ASSERT(di >= 0 && di <= 2 && dj >= -2 && dj <= 2 && (s == 0 || di > 0 || dj > 0),
                    "an upper offset within two rows and two columns");
    offset_[s] = upper[s];
    const std::ptrdiff_t d = di * static_cast<std::ptrdiff_t>(cols) + dj;
    node_offset_[s] = d > 0 ? static_cast<std::size_t>(d) : 0;
  }
  block_.assign(rows * cols * slots_, Block{});
}

std::size_t SymmetricStencilMatrix::slot(int di, int dj) const {
  for (std::size_t s = 0; s < slots_; ++s) {
    if (offset_[s] == Offset{di, dj}) return s;
  }
  return kMaxSlots;
}

void SymmetricStencilMatrix::clear_row(std::size_t node) {
  std::fill_n(block_.begin() + static_cast<std::ptrdiff_t>(node * slots_), slots_, Block{});
}

}  // namespace clothsim
