#pragma once
/// Parallel loops over the ThreadPool. Work is always cut the same way for a
/// given pool size, so results are bit-identical run to run for that size. A null
/// pool (or a pool of one) runs the loop serially.
#include <cstddef>
#include <cstdint>

#include "demlink/core/step/thread_pool.hpp"

namespace demlink::core {

/// Calls body(begin, end) on one contiguous chunk of [0, n) per pool thread.
template <class Body>
void parallelChunks(ThreadPool* pool, std::size_t n, const Body& body) {
  const std::uint32_t parts = pool != nullptr ? pool->size() : 1;
  if (parts == 1 || n < 4 * static_cast<std::size_t>(parts)) {
    body(std::size_t{0}, n);
    return;
  }
  pool->run(parts, [&](std::uint32_t part) { body(n * part / parts, n * (part + 1) / parts); });
}

/// Calls body(part) for part in [0, parts), spread over the pool.
template <class Body>
void parallelParts(ThreadPool* pool, std::uint32_t parts, const Body& body) {
  if (pool == nullptr) {
    for (std::uint32_t part = 0; part < parts; ++part) body(part);
    return;
  }
  pool->run(parts, body);
}

}  // namespace demlink::core
