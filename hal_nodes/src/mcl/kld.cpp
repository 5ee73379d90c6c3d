#include "hal_nodes/mcl/kld.h"

#include <algorithm>
#include <cmath>

namespace hal_nodes::mcl {

std::size_t kldBound(std::size_t k, const KldParams& p) {
  if (k <= 1) return 1;
  const double km1 = static_cast<double>(k - 1);
  const double a = 2.0 / (9.0 * km1);
  const double b = 1.0 - a + std::sqrt(a) * p.z;
  return static_cast<std::size_t>(std::ceil(km1 / (2.0 * p.epsilon) * b * b * b));
}

void BinCounter::reserve(std::size_t max_items) {
  std::size_t cap = 64;
  while (cap < 2 * max_items) cap <<= 1;
  if (table_.size() != cap) table_.assign(cap, 0);
  mask_ = cap - 1;
  clear();
}

void BinCounter::clear() {
  std::fill(table_.begin(), table_.end(), 0);
  count_ = 0;
}

std::size_t BinCounter::add(double x, double y, double theta, const KldParams& p) {
  // Pack three signed 21-bit bin indices; key 0 is reserved for "empty", hence the +1.
  const auto ix = static_cast<int64_t>(std::floor(x / p.bin_xy)) & 0x1fffff;
  const auto iy = static_cast<int64_t>(std::floor(y / p.bin_xy)) & 0x1fffff;
  const auto it = static_cast<int64_t>(std::floor(theta / p.bin_theta)) & 0x1fffff;
  const uint64_t key = ((static_cast<uint64_t>(ix) << 42) | (static_cast<uint64_t>(iy) << 21) | static_cast<uint64_t>(it)) + 1;
  if (count_ * 2 >= table_.size()) return count_;  // full: enough to hit the maximum anyway
  uint64_t h = key * 0x9e3779b97f4a7c15ULL;
  std::size_t i = static_cast<std::size_t>(h >> 20) & mask_;
  while (table_[i] != 0) {
    if (table_[i] == key) return count_;
    i = (i + 1) & mask_;
  }
  table_[i] = key;
  return ++count_;
}

}  // namespace hal_nodes::mcl
