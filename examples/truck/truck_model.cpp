/// The suspension equations (see truck_model.hpp for frame and signs):
///   m z''       = sum F_i + F_dem,z - m g - m a_f,z
///   I_y theta'' = sum (-x_i F_i) + M_dem,y + h H_x
///   I_x phi''   = sum ( y_i F_i) + M_dem,x - h H_y
/// with H = m a_f,h - F_dem,h the chassis' horizontal reaction on the body (the body does
/// not move horizontally in the truck frame), acting at the spring seats' height h below
/// the centre of gravity. The body's own fictitious force acts at its centre of gravity and
/// so has no moment about it; it only enters H.
#include "truck_model.hpp"

namespace demlink::examples::truck {

TruckModel::TruckModel(const TruckParameters& parameters) : p_(parameters) {
  // Empty body at rest: the axle loads by the lever rule, split evenly left/right.
  const double weight = p_.body_mass * p_.gravity;
  const double base = p_.front_axle_x - p_.rear_axle_x;
  const double front = -weight * p_.rear_axle_x / base;
  const double rear = weight * p_.front_axle_x / base;
  preload_ = {0.5 * front, 0.5 * front, 0.5 * rear, 0.5 * rear};
}

std::array<double, 2> TruckModel::seat(int spring) const {
  const double x = spring < 2 ? p_.front_axle_x : p_.rear_axle_x;
  const double y = spring % 2 == 0 ? p_.half_track : -p_.half_track;
  return {x, y};
}

std::array<double, kSprings> TruckModel::springForces(const TruckState& s) const {
  std::array<double, kSprings> f{};
  for (int i = 0; i < kSprings; ++i) {
    const auto [x, y] = seat(i);
    const double rise = s.z - x * s.theta + y * s.phi;
    const double rate = s.z_rate - x * s.theta_rate + y * s.phi_rate;
    f[static_cast<std::size_t>(i)] = preload_[static_cast<std::size_t>(i)] - p_.spring_stiffness * rise -
                                     p_.spring_damping * rate;
  }
  return f;
}

TruckState TruckModel::derivative(const TruckState& s, const TruckInputs& in) const {
  const auto f = springForces(s);
  double fz = 0.0;
  double my = 0.0;
  double mx = 0.0;
  for (int i = 0; i < kSprings; ++i) {
    const auto [x, y] = seat(i);
    const double fi = f[static_cast<std::size_t>(i)];
    fz += fi;
    my -= x * fi;
    mx += y * fi;
  }
  const double m = p_.body_mass;
  const double hx = m * in.frame_acceleration[0] - in.dem_force[0];
  const double hy = m * in.frame_acceleration[1] - in.dem_force[1];
  TruckState d;
  d.z = s.z_rate;
  d.theta = s.theta_rate;
  d.phi = s.phi_rate;
  d.z_rate = (fz + in.dem_force[2] - m * p_.gravity - m * in.frame_acceleration[2]) / m;
  d.theta_rate = (my + in.dem_torque[1] + p_.seat_height * hx) / p_.pitch_inertia;
  d.phi_rate = (mx + in.dem_torque[0] - p_.seat_height * hy) / p_.roll_inertia;
  return d;
}

void TruckModel::step(const TruckInputs& inputs, double h) {
  const auto add = [](const TruckState& a, const TruckState& b, double w) {
    return TruckState{a.z + w * b.z,           a.theta + w * b.theta,           a.phi + w * b.phi,
                      a.z_rate + w * b.z_rate, a.theta_rate + w * b.theta_rate, a.phi_rate + w * b.phi_rate};
  };
  const TruckState& s = state_;
  const TruckState k1 = derivative(s, inputs);
  const TruckState k2 = derivative(add(s, k1, 0.5 * h), inputs);
  const TruckState k3 = derivative(add(s, k2, 0.5 * h), inputs);
  const TruckState k4 = derivative(add(s, k3, h), inputs);
  TruckState next = add(s, k1, h / 6.0);
  next = add(next, k2, h / 3.0);
  next = add(next, k3, h / 3.0);
  next = add(next, k4, h / 6.0);
  state_ = next;
}

}  // namespace demlink::examples::truck
