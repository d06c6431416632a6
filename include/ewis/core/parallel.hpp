#pragma once
// Deterministic parallel helpers (DESIGN.md "Performance habits"): the range is cut into blocks whose
// boundaries depend only on the size and the grain, never on the thread count; per-block results are
// combined in block order, so a reduction gives the same bits for any number of threads.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace ewis {

// Calls body(begin, end) for fixed blocks of `grain` items, in parallel.
template <class Body>
void parallel_blocks(std::size_t n, std::size_t grain, const Body& body) {
  if (n == 0) return;
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t blocks = (n + grain - 1) / grain;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t b = r.begin(); b != r.end(); ++b)
                        body(b * grain, std::min(n, (b + 1) * grain));
                    },
                    tbb::simple_partitioner());
}

// Calls body(i) for every i in [0, n), in parallel.
template <class Body>
void parallel_for_each_index(std::size_t n, const Body& body, std::size_t grain = 1024) {
  parallel_blocks(n, grain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) body(i);
  });
}

// Deterministic reduction: block_fn(begin, end) -> T per fixed block, combined left to right.
template <class T, class BlockFn, class Combine>
T parallel_reduce_ordered(std::size_t n, std::size_t grain, T identity, const BlockFn& block_fn,
                          const Combine& combine) {
  if (n == 0) return identity;
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t blocks = (n + grain - 1) / grain;
  std::vector<T> partial(blocks, identity);
  parallel_blocks(n, grain, [&](std::size_t b, std::size_t e) { partial[b / grain] = block_fn(b, e); });
  T total = identity;
  for (const T& p : partial) total = combine(total, p);
  return total;
}

// Indices i in [0, n) with keep(i), in increasing order, computed in parallel.
template <class Pred>
std::vector<std::uint32_t> parallel_select(std::size_t n, const Pred& keep, std::size_t grain = 4096) {
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t blocks = (n + grain - 1) / grain;
  std::vector<std::vector<std::uint32_t>> parts(blocks);
  parallel_blocks(n, grain, [&](std::size_t b, std::size_t e) {
    auto& out = parts[b / grain];
    for (std::size_t i = b; i < e; ++i)
      if (keep(i)) out.push_back(static_cast<std::uint32_t>(i));
  });
  std::vector<std::uint32_t> result;
  std::size_t total = 0;
  for (const auto& p : parts) total += p.size();
  result.reserve(total);
  for (const auto& p : parts) result.insert(result.end(), p.begin(), p.end());
  return result;
}

}  // namespace ewis
