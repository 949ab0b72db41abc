#include "demlink/core/step/pair_loop_partition.hpp"

#include <algorithm>

namespace demlink::core {

void PairLoopPartition::plan(std::span<const std::uint32_t> offsets, std::uint32_t parts) {
  const std::size_t rows = offsets.empty() ? 0 : offsets.size() - 1;
  const std::uint64_t pairs = offsets.empty() ? 0 : offsets.back();
  parts = std::max<std::uint32_t>(1, parts);
  row_begin_.assign(parts + 1, rows);
  row_begin_[0] = 0;
  for (std::uint32_t t = 1; t < parts; ++t) {
    // First row whose pair offset reaches t/parts of all pairs.
    const std::uint64_t target = pairs * t / parts;
    const auto it = std::lower_bound(offsets.begin(), offsets.begin() + static_cast<std::ptrdiff_t>(rows), target);
    row_begin_[t] = std::max(row_begin_[t - 1], static_cast<std::size_t>(it - offsets.begin()));
  }
  force_.resize(parts);
  torque_.resize(parts);
  for (std::uint32_t t = 1; t < parts; ++t) {
    force_[t].resize(rows - row_begin_[t]);
    torque_[t].resize(rows - row_begin_[t]);
  }
}

}  // namespace demlink::core
