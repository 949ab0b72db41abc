#pragma once
/// The truck's system model: a dump body (the sprung mass) on four vertical spring-dampers,
/// two per axle (front and rear along x, left and right along y), in the form a Modelica
/// model would have it: a state vector, parameters, inputs held constant over one sample
/// (zero-order hold) and a fixed-step integrator (classical Runge-Kutta, one step per
/// communication interval).
///
/// Why this model: the load's weight and where it sits, and the fictitious forces of a
/// driving truck, must show in the axle forces, and nothing else is needed for that. The
/// body moves only in heave, pitch and roll relative to the truck's frame (small angles);
/// its horizontal position and yaw are held by the chassis, whose horizontal reaction acts
/// at the height of the spring seats. That reaction's moment about the centre of gravity
/// is what shifts load between the axles when the truck accelerates or turns.
///
/// Frame and signs: the model lives in the truck frame, which is the DEM simulation's
/// moving frame while the truck drives. x forward, y left, z up. Pitch theta is a rotation about +y
/// (positive: nose down), roll phi about +x (positive: left side up). A spring seat at
/// (x_i, y_i) relative to the centre of gravity rises by s_i = z - x_i theta + y_i phi;
/// the spring force on the body is F_i = F0_i - k s_i - c ds_i/dt (up positive), F0_i the
/// preload that holds the empty body at s = 0.
#include <array>

namespace demlink::examples::truck {

/// Parameters of the sprung body and its suspension [SI].
struct TruckParameters {
  double body_mass = 2000.0;          ///< dump body + chassis share on the springs [kg]
  double pitch_inertia = 2100.0;      ///< about the centre of gravity, y axis [kg m^2]
  double roll_inertia = 1150.0;       ///< about the centre of gravity, x axis [kg m^2]
  double front_axle_x = 1.8;          ///< front spring seats, x relative to the CG [m]
  double rear_axle_x = -0.8;          ///< rear spring seats, x relative to the CG [m]
  double half_track = 0.9;            ///< spring seats at y = +-half_track [m]
  double seat_height = -0.45;         ///< spring seats (and chassis reaction), z relative to the CG [m]
  double spring_stiffness = 60.0e3;   ///< per spring [N/m]
  double spring_damping = 4.5e3;      ///< per spring [N s/m]
  double gravity = 9.81;              ///< [m/s^2], along -z
};

/// Spring order: front left, front right, rear left, rear right.
inline constexpr int kSprings = 4;

/// Inputs of one sample, held constant over it.
struct TruckInputs {
  std::array<double, 3> dem_force{};   ///< on the body by the particles, truck frame [N]
  std::array<double, 3> dem_torque{};  ///< the same wrench's torque about the CG [N m]
  std::array<double, 3> frame_acceleration{};  ///< of the truck frame at the CG, truck frame [m/s^2]
};

/// State: heave z [m], pitch theta [rad], roll phi [rad] and their rates.
struct TruckState {
  double z = 0.0;
  double theta = 0.0;
  double phi = 0.0;
  double z_rate = 0.0;
  double theta_rate = 0.0;
  double phi_rate = 0.0;
};

class TruckModel {
 public:
  explicit TruckModel(const TruckParameters& parameters);

  /// One fixed step of length h [s] with the inputs held constant (RK4).
  void step(const TruckInputs& inputs, double h);

  [[nodiscard]] const TruckState& state() const { return state_; }
  [[nodiscard]] const TruckParameters& parameters() const { return p_; }
  /// Spring forces on the body (up positive) at the current state [N].
  [[nodiscard]] std::array<double, kSprings> springForces() const { return springForces(state_); }
  /// Seat positions relative to the CG (x, y) per spring [m].
  [[nodiscard]] std::array<double, 2> seat(int spring) const;
  /// The static preload of each spring under the empty body [N].
  [[nodiscard]] double preload(int spring) const { return preload_[static_cast<std::size_t>(spring)]; }

 private:
  [[nodiscard]] std::array<double, kSprings> springForces(const TruckState& s) const;
  [[nodiscard]] TruckState derivative(const TruckState& s, const TruckInputs& in) const;

  TruckParameters p_;
  std::array<double, kSprings> preload_{};
  TruckState state_;
};

}  // namespace demlink::examples::truck
