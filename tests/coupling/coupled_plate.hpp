#pragma once
/// The client side of the coupled-plate comparison: a plate of mass m dropped onto the
/// gravel bed of tests/fmu/plate_in_bed.cfg, whose vertical motion the client integrates
/// from the force the server returns. Every transport's master (the C++ client, the C ABI
/// in both of its send-first orders, the FMU) drives this same integrator, so the only
/// thing that differs between them is the transport.
///
/// Send first: at t_k the client sends the plate's state, receives the mean force over
/// [t_k, t_k + h] and integrates m dv/dt = F + m g exactly for that force held constant.
#include <cmath>
#include <cstdio>
#include <vector>

namespace demlink::coupling {

inline constexpr double kStartHeight = 0.11;  ///< plate centre at rest at the start [m] (plate_in_bed.cfg)
inline constexpr double kGravity = -9.81;     ///< [m/s^2]

class CoupledPlate {
 public:
  explicit CoupledPlate(double mass) : mass_(mass) {}

  [[nodiscard]] double height() const { return z_; }    ///< plate centre [m]
  [[nodiscard]] double velocity() const { return v_; }  ///< [m/s]

  /// Integrates one interval of length h [s] with the mean vertical force F [N] on the plate.
  void advance(double force, double h) {
    const double a = force / mass_ + kGravity;
    z_ += v_ * h + 0.5 * a * h * h;
    v_ += a * h;
    heights_.push_back(z_);
  }

  /// Mean plate height over the last quarter of the intervals [m] (the rest depth once the
  /// plate has settled into the bed).
  [[nodiscard]] double restHeight() const {
    const std::size_t from = heights_.size() - heights_.size() / 4;
    double sum = 0.0;
    for (std::size_t i = from; i < heights_.size(); ++i) sum += heights_[i];
    return heights_.size() > from ? sum / static_cast<double>(heights_.size() - from) : std::nan("");
  }

  /// The one line every master prints and the comparison test parses.
  void printSummary(const char* transport, double h, double timeStep) const {
    std::printf("coupled_plate %s: interval %.9g s, time step %.9g s, intervals %zu, rest height %.12g m, "
                "final height %.12g m\n",
                transport, h, timeStep, heights_.size(), restHeight(), z_);
    std::fflush(stdout);
  }

 private:
  double mass_;
  double z_ = kStartHeight;
  double v_ = 0.0;
  std::vector<double> heights_;
};

}  // namespace demlink::coupling
