/// Dump body surface and STL writer (see dump_body_mesh.hpp). The surface is built from
/// quads: outer bottom, four outer walls, the rim (four trapezoids), four inner walls and
/// the inner floor; each quad is split into two triangles.
#include "dump_body_mesh.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace demlink::examples::truck {
namespace {

/// Appends quad a-b-c-d (counter-clockwise seen from the side the normal points to).
void quad(std::vector<Triangle>& out, const Point& a, const Point& b, const Point& c, const Point& d) {
  out.push_back({a, b, c});
  out.push_back({a, c, d});
}

}  // namespace

std::vector<Triangle> dumpBodyTriangles(const DumpBodyShape& s) {
  const double xi = 0.5 * s.length;
  const double yi = 0.5 * s.width;
  const double xo = xi + s.wall_thickness;
  const double yo = yi + s.wall_thickness;
  const double top = s.wall_height;
  const double bottom = -s.floor_thickness;
  // Corners counter-clockwise seen from above: (-,-), (+,-), (+,+), (-,+).
  const auto ring = [](double hx, double hy, double z) {
    return std::array<Point, 4>{Point{-hx, -hy, z}, Point{hx, -hy, z}, Point{hx, hy, z}, Point{-hx, hy, z}};
  };
  const auto ob = ring(xo, yo, bottom);  // outer bottom
  const auto ot = ring(xo, yo, top);     // outer top
  const auto it = ring(xi, yi, top);     // inner top
  const auto ib = ring(xi, yi, 0.0);     // inner floor
  std::vector<Triangle> out;
  out.reserve(28);
  quad(out, ob[0], ob[3], ob[2], ob[1]);  // bottom, normal -z
  for (std::size_t i = 0; i < 4; ++i) {
    const std::size_t j = (i + 1) % 4;
    quad(out, ob[i], ob[j], ot[j], ot[i]);  // outer wall, normal outwards
    quad(out, ot[i], ot[j], it[j], it[i]);  // rim, normal +z
    quad(out, it[i], it[j], ib[j], ib[i]);  // inner wall, normal into the cavity
  }
  quad(out, ib[0], ib[1], ib[2], ib[3]);  // floor, normal +z
  return out;
}

void writeBinaryStl(const std::string& path, const std::vector<Triangle>& triangles) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) throw std::runtime_error("cannot write STL file '" + path + "'");
  char header[80] = {};
  std::snprintf(header, sizeof header, "DEMLink truck dump body");
  const auto count = static_cast<std::uint32_t>(triangles.size());
  bool ok = std::fwrite(header, 1, sizeof header, file) == sizeof header &&
            std::fwrite(&count, sizeof count, 1, file) == 1;
  for (const Triangle& t : triangles) {
    const Point u{t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]};
    const Point v{t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]};
    Point n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (double& c : n) c = len > 0.0 ? c / len : 0.0;
    float record[12];
    for (int k = 0; k < 3; ++k) record[k] = static_cast<float>(n[static_cast<std::size_t>(k)]);
    for (int corner = 0; corner < 3; ++corner) {
      for (int k = 0; k < 3; ++k) {
        record[3 + 3 * corner + k] = static_cast<float>(t[static_cast<std::size_t>(corner)][static_cast<std::size_t>(k)]);
      }
    }
    const std::uint16_t attribute = 0;
    ok = ok && std::fwrite(record, sizeof record, 1, file) == 1 && std::fwrite(&attribute, sizeof attribute, 1, file) == 1;
  }
  ok = std::fclose(file) == 0 && ok;
  if (!ok) throw std::runtime_error("cannot write STL file '" + path + "'");
}

}  // namespace demlink::examples::truck
