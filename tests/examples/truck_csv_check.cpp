/// Checks a demlink-truck run (scenario `source`) from its truck.csv against the physics
/// it must show. Usage: truck_csv_check TRUCK_CSV LOAD_TARGET_KG
///
/// Why a separate checker: the co-simulation runs as two processes (server, truck), so the
/// test is a script; the checks are arithmetic on the CSV and belong in code that can fail
/// with a clear message. Checks (each prints measured and expected values):
///  1. the load mass at the end is the target within 5 %;
///  2. at rest (phase "holding") the axle forces sum to (body mass + load) g within 2 %;
///  3. accelerating, the rear axle force rises by the analytic load transfer
///     a (m_b h_b + m_L h_L) / wheelbase within 35 % (h: height of each centre of gravity
///     above the spring seats; the body's from the header, the load's from the sensor);
///  4. turning left, the right (outer) side gains over the left by the analytic roll
///     transfer 2 a_y (m_b h_b + m_L h_L) / (2 half_track) within 35 %.
/// The means are taken over the second half of each phase (after the step response).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Table {
  std::map<std::string, double> params;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  [[nodiscard]] std::size_t column(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return i;
    }
    std::fprintf(stderr, "truck_csv_check: no column '%s'\n", name.c_str());
    std::exit(1);
  }
  [[nodiscard]] double param(const std::string& name) const {
    const auto it = params.find(name);
    if (it == params.end()) {
      std::fprintf(stderr, "truck_csv_check: no header parameter '%s'\n", name.c_str());
      std::exit(1);
    }
    return it->second;
  }
  /// Mean of column `name` over the second half of the rows in `phase` that have a value.
  [[nodiscard]] double mean(const std::string& phase, const std::string& name) const {
    const std::size_t p = column("phase");
    const std::size_t c = column(name);
    std::vector<double> values;
    for (const auto& r : rows) {
      if (r[p] == phase && !r[c].empty()) values.push_back(std::stod(r[c]));  // empty cell: missing
    }
    if (values.size() < 4) {
      std::fprintf(stderr, "truck_csv_check: phase '%s' has %zu rows\n", phase.c_str(), values.size());
      std::exit(1);
    }
    double sum = 0.0;
    for (std::size_t i = values.size() / 2; i < values.size(); ++i) sum += values[i];
    return sum / static_cast<double>(values.size() - values.size() / 2);
  }
};

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string item;
  while (std::getline(ss, item, sep)) out.push_back(item);
  return out;
}

Table read(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "truck_csv_check: cannot read %s\n", path.c_str());
    std::exit(1);
  }
  Table t;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      for (const auto& kv : split(line.substr(1), ' ')) {
        const auto eq = kv.find('=');
        if (eq != std::string::npos) t.params[kv.substr(0, eq)] = std::stod(kv.substr(eq + 1));
      }
    } else if (t.header.empty()) {
      t.header = split(line, ',');
    } else {
      t.rows.push_back(split(line, ','));
      if (t.rows.back().size() != t.header.size()) {
        std::fprintf(stderr, "truck_csv_check: a row has %zu fields, the header %zu\n", t.rows.back().size(),
                     t.header.size());
        std::exit(1);
      }
    }
  }
  return t;
}

bool report(const char* what, double measured, double expected, double tolerance) {
  const double rel = std::fabs(measured - expected) / std::fabs(expected);
  const bool ok = rel <= tolerance;
  std::printf("%-4s %-40s measured %12.3f  expected %12.3f  (%.2f %%, tolerance %.0f %%)\n", ok ? "ok" : "FAIL", what,
              measured, expected, 100.0 * rel, 100.0 * tolerance);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: truck_csv_check TRUCK_CSV LOAD_TARGET_KG\n");
    return 2;
  }
  const Table t = read(argv[1]);
  const double target = std::atof(argv[2]);
  const double g = 9.81;
  if (t.rows.empty()) {
    std::fprintf(stderr, "truck_csv_check: no rows\n");
    return 1;
  }
  const double bodyMass = t.param("body_mass_kg");
  const double hBody = t.param("cg_above_seats_m");
  const double seatZ = t.param("cg_z_m") - hBody;  // world height of the spring seats [m]
  const double wheelbase = t.param("front_axle_x_m") - t.param("rear_axle_x_m");
  const double halfTrack = t.param("half_track_m");
  bool ok = true;

  // 1. Load mass at the end.
  const double finalLoad = std::stod(t.rows.back()[t.column("load_mass_kg")]);
  ok = report("load mass at the end [kg]", finalLoad, target, 0.05) && ok;

  // 2. Static equilibrium at rest.
  const double load = t.mean("holding", "load_mass_kg");
  const double axles = t.mean("holding", "axle_front_N") + t.mean("holding", "axle_rear_N");
  ok = report("axle forces at rest [N]", axles, (bodyMass + load) * g, 0.02) && ok;

  // 3. Load transfer to the rear axle while accelerating.
  const double hLoadRest = t.mean("holding", "load_com_z_m") - seatZ;
  const double ax = t.mean("accelerating", "frame_ax_m_s2");
  const double hLoadAcc = t.mean("accelerating", "load_com_z_m") - seatZ;
  const double rearGain = t.mean("accelerating", "axle_rear_N") - t.mean("holding", "axle_rear_N");
  const double rearExpected = ax * (bodyMass * hBody + load * 0.5 * (hLoadRest + hLoadAcc)) / wheelbase;
  ok = report("rear axle gain accelerating [N]", rearGain, rearExpected, 0.35) && ok;
  const double shareRest = t.mean("holding", "axle_rear_N") / axles;
  const double shareAcc =
      t.mean("accelerating", "axle_rear_N") / (t.mean("accelerating", "axle_front_N") + t.mean("accelerating", "axle_rear_N"));
  std::printf("     rear axle share: at rest %.4f, accelerating %.4f\n", shareRest, shareAcc);
  if (!(shareAcc > shareRest)) {
    std::printf("FAIL the rear axle share did not increase while accelerating\n");
    ok = false;
  }

  // 4. Roll transfer to the outer (right) side while turning left.
  const double ay = t.mean("turning", "frame_ay_m_s2");
  const double hLoadTurn = t.mean("turning", "load_com_z_m") - seatZ;
  const double sideRest = t.mean("holding", "side_right_N") - t.mean("holding", "side_left_N");
  const double sideTurn = t.mean("turning", "side_right_N") - t.mean("turning", "side_left_N");
  const double sideExpected = 2.0 * ay * (bodyMass * hBody + load * hLoadTurn) / (2.0 * halfTrack);
  ok = report("right - left gain turning [N]", sideTurn - sideRest, sideExpected, 0.35) && ok;

  std::printf(ok ? "truck_csv_check: all checks passed\n" : "truck_csv_check: FAILED\n");
  return ok ? 0 : 1;
}
