#pragma once
/// The fit of demlink-calibrate (docs/materials.md "Calibrating a material"): 1 to 3
/// parameters within bounds, chosen so that the scenes' bulk quantities match measured
/// ones, by a response-surface method that needs no derivatives and tolerates the scatter
/// of a few hundred grains:
///   1. a design over the whole box of bounds (1 parameter: 5 levels; 2: the 3 x 3 grid;
///      3: the face-centred composite design, 15 points);
///   2. each response (one per measurement) is fitted by a quadratic in the parameters
///      (least squares: the smoothing), and the fit's objective, the sum of squared
///      relative misfits, is minimised over the box on the quadratics (a fine grid);
///   3. refinements: the centre and the axial points of a box of half the previous size
///      around that minimum are run, the quadratics refitted with the points outside the
///      box down-weighted by (half-size / distance)^2, and the minimum found again.
/// Pure numerics: the scenes come in through `Evaluate`, so the method is tested on known
/// functions (tests/bench/test_calibration_fit.cpp).
#include <functional>
#include <string>
#include <vector>

namespace demlink::calibrate {

/// Bounds of one fitted parameter, min < max.
struct Bounds {
  double min = 0.0;
  double max = 1.0;
};

/// The responses (one bulk quantity per measurement) at `parameters`.
using Evaluate = std::function<std::vector<double>(const std::vector<double>& parameters)>;

/// One run of Evaluate.
struct Evaluation {
  std::vector<double> parameters;
  std::vector<double> responses;
};

struct FitOptions {
  int refinements = 2;  ///< rounds of step 3 [-]
  /// Called before every evaluation with its index, the count planned so far and the parameters.
  std::function<void(std::size_t index, std::size_t planned, const std::vector<double>& parameters)> progress;
};

struct FitResult {
  std::vector<double> parameters;               ///< the minimum of the last quadratics
  std::vector<double> predicted;                ///< the quadratics' responses there
  std::vector<std::vector<double>> slopes;      ///< [measurement][parameter]: d response / d parameter there
  std::vector<bool> at_bound;                   ///< per parameter: the minimum lies on a bound
  std::vector<Evaluation> evaluations;          ///< every run, in order
};

/// Sum over the measurements of ((response - target) / target)^2.
[[nodiscard]] double relativeMisfit(const std::vector<double>& responses, const std::vector<double>& targets);

/// Fits `bounds.size()` (1..3) parameters to `targets` (non-zero, at least as many as
/// parameters). Deterministic: the same Evaluate gives the same result.
[[nodiscard]] FitResult fitParameters(const std::vector<Bounds>& bounds, const std::vector<double>& targets,
                                      const Evaluate& evaluate, const FitOptions& options = {});

/// Standard deviation of each parameter caused by the responses' scatter: the linearised
/// least-squares covariance (S^T W S)^-1 with the slopes S [measurement][parameter] and
/// W = diag(1 / scatter^2). For one parameter and one measurement this is
/// scatter / |slope|. NaN for a parameter the slopes do not determine (S^T W S singular).
[[nodiscard]] std::vector<double> parameterUncertainty(const std::vector<std::vector<double>>& slopes,
                                                       const std::vector<double>& scatter);

}  // namespace demlink::calibrate
