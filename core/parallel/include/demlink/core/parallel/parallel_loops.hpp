#pragma once
/// Parallel loops over the ThreadPool. The work is cut into chunks that depend only
/// on the loop's size, never on the pool's size or on which thread runs which chunk:
/// a loop whose chunks write disjoint data, or whose per-chunk partial results are
/// combined in chunk order, gives bit-identical results for any thread count. A null
/// pool (or a pool of one) runs the same chunks serially.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "demlink/core/parallel/thread_pool.hpp"

namespace demlink::core {

/// Elements per chunk of the element-wise loops (kick, drift, the rebuild guard): large
/// enough that claiming a chunk (one compare-and-swap) costs far less than running it
/// (about a microsecond for a kick of 256 particles), small enough that two threads
/// split a loop of a few thousand particles evenly (larger chunks leave an odd count of
/// them, one thread getting one more) [-].
inline constexpr std::size_t kChunkElements = 256;

/// Chunks of a loop of n elements: ceil(n / grain), at least 1 and at most
/// ThreadPool::kMaxChunks.
[[nodiscard]] inline std::uint32_t chunkCount(std::size_t n, std::size_t grain = kChunkElements) {
  const std::size_t chunks = (n + grain - 1) / grain;
  return static_cast<std::uint32_t>(std::clamp<std::size_t>(chunks, 1, ThreadPool::kMaxChunks));
}

/// First element of chunk c of `chunks` over [0, n) (n * c fits 64 bits below 2^48 elements).
[[nodiscard]] inline std::size_t chunkBegin(std::size_t n, std::uint32_t chunks, std::uint32_t c) {
  return n * c / chunks;
}

/// Calls body(begin, end) once per chunk of [0, n) (chunkCount(n) chunks).
template <class Body>
void parallelChunks(ThreadPool* pool, std::size_t n, const Body& body) {
  const std::uint32_t chunks = chunkCount(n);
  if (pool == nullptr || chunks == 1) {
    body(std::size_t{0}, n);
    return;
  }
  pool->run(chunks, [&](std::uint32_t c) { body(chunkBegin(n, chunks, c), chunkBegin(n, chunks, c + 1)); });
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
