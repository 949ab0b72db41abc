#pragma once
/// Thin OpenMP layer. Every parallel loop uses a static schedule over a fixed
/// thread count, so results are bit-identical run to run for that count. Without
/// OpenMP (e.g. the sanitizer build) the loops run serially.
#include <cstddef>
#include <cstdint>
#include <utility>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace demlink::core {

/// Calls body(begin, end) on `threads` contiguous chunks of [0, n), in parallel.
template <class Body>
void parallelChunks(std::size_t n, std::uint32_t threads, const Body& body) {
#ifdef _OPENMP
  if (threads > 1 && n >= 4 * static_cast<std::size_t>(threads)) {
#pragma omp parallel num_threads(static_cast<int>(threads))
    {
      const auto t = static_cast<std::size_t>(omp_get_thread_num());
      const auto count = static_cast<std::size_t>(omp_get_num_threads());
      body(n * t / count, n * (t + 1) / count);
    }
    return;
  }
#endif
  (void)threads;
  body(std::size_t{0}, n);
}

/// Calls body(part) for every part in [0, parts), spread over up to `parts`
/// threads. Each part's work is fixed, whatever number of threads the runtime
/// actually grants, so the result does not depend on it.
template <class Body>
void parallelParts(std::uint32_t parts, const Body& body) {
#ifdef _OPENMP
  if (parts > 1) {
#pragma omp parallel num_threads(static_cast<int>(parts))
    {
      const auto count = static_cast<std::uint32_t>(omp_get_num_threads());
      for (auto part = static_cast<std::uint32_t>(omp_get_thread_num()); part < parts; part += count) body(part);
    }
    return;
  }
#endif
  for (std::uint32_t part = 0; part < parts; ++part) body(part);
}

/// One parallel region whose body runs on every thread and may separate phases
/// with barrier(): fewer fork/joins than one region per loop, which matters when
/// a step takes only ~100 us.
class ParallelRegion {
 public:
  ParallelRegion(std::uint32_t thread, std::uint32_t count) : thread_(thread), count_(count) {}
  [[nodiscard]] std::uint32_t thread() const { return thread_; }
  [[nodiscard]] std::uint32_t count() const { return count_; }
  /// [begin, end) of this thread's contiguous share of n items.
  [[nodiscard]] std::pair<std::size_t, std::size_t> share(std::size_t n) const {
    return {n * thread_ / count_, n * (thread_ + 1) / count_};
  }
  void barrier() const {
#ifdef _OPENMP
#pragma omp barrier
#endif
  }

 private:
  std::uint32_t thread_;
  std::uint32_t count_;
};

template <class Body>
void parallelRegion(std::uint32_t threads, const Body& body) {
#ifdef _OPENMP
  if (threads > 1) {
#pragma omp parallel num_threads(static_cast<int>(threads))
    {
      const ParallelRegion region(static_cast<std::uint32_t>(omp_get_thread_num()),
                                  static_cast<std::uint32_t>(omp_get_num_threads()));
      body(region);
    }
    return;
  }
#endif
  (void)threads;
  body(ParallelRegion(0, 1));
}

}  // namespace demlink::core
