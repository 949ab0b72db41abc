/// VTK XML PolyData / collection writer (see vtk_writer.hpp for the format).
///
/// Every file is assembled from a list of typed columns (VtkArray): the XML
/// header is written first with, for the appended encoding, each column's byte
/// offset into the appended block (offset_k = sum over j < k of 8 + bytes_j, the
/// 8 being the UInt64 length header); then the block itself. Values are copied
/// into flat vectors first so no Eigen layout assumption leaks into the file.
#include "demlink/core/output/vtk_writer.hpp"

#include <bit>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "demlink/core/output/csv_table.hpp"

namespace demlink::core {
namespace {

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big,
              "mixed-endian machines are not supported by the VTK writer");
constexpr std::string_view kByteOrder =
    std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";

/// One DataArray: a name, its component count and flat values.
struct VtkArray {
  std::string name;
  int components = 1;
  std::variant<std::vector<double>, std::vector<std::uint64_t>, std::vector<std::uint32_t>,
               std::vector<std::int64_t>, std::vector<std::uint8_t>>
      values;

  [[nodiscard]] std::string_view typeName() const {
    switch (values.index()) {
      case 0: return "Float64";
      case 1: return "UInt64";
      case 2: return "UInt32";
      case 3: return "Int64";
      default: return "UInt8";
    }
  }
  [[nodiscard]] std::size_t byteCount() const {
    return std::visit([](const auto& v) { return v.size() * sizeof(v[0]); }, values);
  }
};

VtkArray vectorColumn(std::string name, std::span<const Vec3> vectors) {
  std::vector<double> flat;
  flat.reserve(3 * vectors.size());
  for (const Vec3& v : vectors) flat.insert(flat.end(), {v.x(), v.y(), v.z()});
  return {std::move(name), 3, std::move(flat)};
}

template <class T>
VtkArray scalarColumn(std::string name, std::span<const T> values) {
  return {std::move(name), 1, std::vector<T>(values.begin(), values.end())};
}

void appendNumber(std::string& out, auto value) {
  char buffer[32];
  // UInt8 values print as numbers, not characters.
  const auto result = std::to_chars(buffer, buffer + sizeof buffer,
                                    std::conditional_t<std::is_same_v<decltype(value), std::uint8_t>, unsigned,
                                                       decltype(value)>(value));
  out.append(buffer, result.ptr);
}

/// Writes one DataArray element; for AppendedRaw advances `offset` [bytes].
void writeArrayXml(std::string& xml, const VtkArray& array, VtkEncoding encoding, std::uint64_t& offset,
                   std::string_view indent) {
  xml.append(indent).append("<DataArray type=\"").append(array.typeName()).append("\" Name=\"");
  xml.append(array.name).append("\" NumberOfComponents=\"").append(std::to_string(array.components));
  if (encoding == VtkEncoding::AppendedRaw) {
    xml.append("\" format=\"appended\" offset=\"").append(std::to_string(offset)).append("\"/>\n");
    offset += sizeof(std::uint64_t) + array.byteCount();
    return;
  }
  xml.append("\" format=\"ascii\">\n").append(indent).append("  ");
  std::visit(
      [&xml](const auto& values) {
        for (std::size_t k = 0; k < values.size(); ++k) {
          if (k > 0) xml.push_back(k % 12 == 0 ? '\n' : ' ');
          appendNumber(xml, values[k]);
        }
      },
      array.values);
  xml.append("\n").append(indent).append("</DataArray>\n");
}

/// One cell section of a PolyData piece ("Verts", "Lines" or "Polys").
struct CellSection {
  std::string_view name;
  std::size_t cell_count = 0;
  VtkArray connectivity;
  VtkArray offsets;
};

/// A PolyData piece: points, point data, cell data (over the sections' cells in the
/// order Verts, Lines, Polys) and the cell sections in that order.
struct PolyDataPiece {
  std::size_t point_count = 0;
  VtkArray points;
  std::vector<VtkArray> point_data;
  std::vector<VtkArray> cell_data;
  std::vector<CellSection> sections;
};

/// Connectivity and offsets of cells of `corners` nodes each, every index < pointCount.
template <std::size_t corners>
CellSection cellsOf(std::string_view name, std::span<const std::array<std::uint32_t, corners>> cells,
                    std::size_t pointCount, std::string_view who) {
  std::vector<std::int64_t> connectivity;
  std::vector<std::int64_t> offsets;
  connectivity.reserve(corners * cells.size());
  offsets.reserve(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    for (std::uint32_t v : cells[c]) {
      if (v >= pointCount) {
        throw std::invalid_argument(std::string(who) + ": cell " + std::to_string(c) + " uses point " +
                                    std::to_string(v) + " of " + std::to_string(pointCount));
      }
      connectivity.push_back(v);
    }
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  return {name, cells.size(), {"connectivity", 1, std::move(connectivity)}, {"offsets", 1, std::move(offsets)}};
}

VtkArray flagColumn(std::string name, std::span<const char> flags) {
  std::vector<std::uint8_t> values(flags.size());
  for (std::size_t k = 0; k < flags.size(); ++k) values[k] = flags[k] != 0 ? 1 : 0;
  return {std::move(name), 1, std::move(values)};
}

void writeFile(const std::string& path, const std::string& text, const std::vector<const VtkArray*>& blocks) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot open " + path + " for writing: " + std::strerror(errno));
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!blocks.empty()) {
    out << "  <AppendedData encoding=\"raw\">\n   _";
    for (const VtkArray* array : blocks) {
      const std::uint64_t bytes = array->byteCount();
      out.write(reinterpret_cast<const char*>(&bytes), sizeof bytes);
      std::visit(
          [&out](const auto& v) {
            out.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(v[0])));
          },
          array->values);
    }
    out << "\n  </AppendedData>\n</VTKFile>\n";
  }
  out.close();
  if (!out) throw std::runtime_error("error while writing " + path);
}

void writePolyData(const std::string& path, const PolyDataPiece& piece, VtkEncoding encoding) {
  std::string xml;
  xml.append("<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"")
      .append(kByteOrder)
      .append("\" header_type=\"UInt64\">\n  <PolyData>\n");
  xml.append("    <Piece NumberOfPoints=\"").append(std::to_string(piece.point_count));
  for (std::string_view name : {"Verts", "Polys", "Lines", "Strips"}) {
    std::size_t n = 0;
    for (const CellSection& section : piece.sections) {
      if (section.name == name) n = section.cell_count;
    }
    xml.append("\" NumberOf").append(name).append("=\"").append(std::to_string(n));
  }
  xml.append("\">\n");

  std::uint64_t offset = 0;
  std::vector<const VtkArray*> blocks{&piece.points};
  xml.append("      <Points>\n");
  writeArrayXml(xml, piece.points, encoding, offset, "        ");
  xml.append("      </Points>\n");
  const auto writeData = [&](std::string_view element, std::string_view attributes,
                             const std::vector<VtkArray>& arrays) {
    if (arrays.empty()) return;
    xml.append("      <").append(element).append(attributes).append(">\n");
    for (const VtkArray& array : arrays) {
      writeArrayXml(xml, array, encoding, offset, "        ");
      blocks.push_back(&array);
    }
    xml.append("      </").append(element).append(">\n");
  };
  writeData("PointData", " Scalars=\"radius\"", piece.point_data);
  writeData("CellData", "", piece.cell_data);
  for (const CellSection& section : piece.sections) {
    xml.append("      <").append(section.name).append(">\n");
    writeArrayXml(xml, section.connectivity, encoding, offset, "        ");
    writeArrayXml(xml, section.offsets, encoding, offset, "        ");
    xml.append("      </").append(section.name).append(">\n");
    blocks.push_back(&section.connectivity);
    blocks.push_back(&section.offsets);
  }
  xml.append("    </Piece>\n  </PolyData>\n");

  if (encoding == VtkEncoding::Ascii) {
    xml.append("</VTKFile>\n");
    blocks.clear();
  }
  writeFile(path, xml, blocks);
}

std::string escapeXmlAttribute(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

void writeParticlesVtp(const std::string& path, const ParticleArrays& particles, VtkEncoding encoding) {
  const std::size_t n = particles.size();
  PolyDataPiece piece;
  piece.point_count = n;
  piece.points = vectorColumn("position", particles.position);
  piece.point_data.push_back(scalarColumn<std::uint64_t>("id", particles.id));
  piece.point_data.push_back(scalarColumn<double>("radius", particles.radius));
  piece.point_data.push_back(vectorColumn("velocity", particles.velocity));
  piece.point_data.push_back(vectorColumn("angular_velocity", particles.angular_velocity));
  piece.point_data.push_back(vectorColumn("force", particles.force));
  piece.point_data.push_back(scalarColumn<std::uint32_t>("material", particles.material));
  piece.point_data.push_back(scalarColumn<std::uint64_t>("clump_id", particles.clump_id));
  std::vector<std::int64_t> connectivity(n);
  std::vector<std::int64_t> offsets(n);
  for (std::size_t i = 0; i < n; ++i) {
    connectivity[i] = static_cast<std::int64_t>(i);
    offsets[i] = static_cast<std::int64_t>(i + 1);
  }
  piece.sections.push_back({"Verts", n, {"connectivity", 1, std::move(connectivity)}, {"offsets", 1, std::move(offsets)}});
  writePolyData(path, piece, encoding);
}

void writeMeshVtp(const std::string& path, std::span<const Vec3> vertices,
                  std::span<const std::array<std::uint32_t, 3>> triangles, VtkEncoding encoding) {
  PolyDataPiece piece;
  piece.point_count = vertices.size();
  piece.points = vectorColumn("position", vertices);
  piece.sections.push_back(cellsOf<3>("Polys", triangles, vertices.size(), "writeMeshVtp"));
  writePolyData(path, piece, encoding);
}

void writeContactsVtp(const std::string& path, std::span<const ContactRecord> contacts, VtkEncoding encoding) {
  const std::size_t n = contacts.size();
  std::vector<Vec3> points;
  points.reserve(2 * n);
  std::vector<std::array<std::uint32_t, 2>> lines(n);
  std::vector<Vec3> normalForce(n), tangentialForce(n), contactPoint(n), normal(n);
  std::vector<double> component(n), overlap(n);
  std::vector<std::uint8_t> kind(n);
  std::vector<std::uint64_t> particle(n), other(n);
  std::vector<std::uint32_t> triangle(n);
  for (std::size_t c = 0; c < n; ++c) {
    const ContactRecord& r = contacts[c];
    lines[c] = {static_cast<std::uint32_t>(points.size()), static_cast<std::uint32_t>(points.size() + 1)};
    points.push_back(r.centre);
    points.push_back(r.other_point);
    normalForce[c] = r.normal_force;
    tangentialForce[c] = r.tangential_force;
    component[c] = r.normal_force.dot(r.normal);
    overlap[c] = r.overlap;
    contactPoint[c] = r.contact_point;
    normal[c] = r.normal;
    kind[c] = static_cast<std::uint8_t>(r.kind);
    particle[c] = r.particle;
    other[c] = r.other;
    triangle[c] = r.triangle;
  }
  PolyDataPiece piece;
  piece.point_count = points.size();
  piece.points = vectorColumn("position", points);
  piece.cell_data.push_back(vectorColumn("normal_force", normalForce));
  piece.cell_data.push_back(vectorColumn("tangential_force", tangentialForce));
  piece.cell_data.push_back(scalarColumn<double>("force_normal_component", component));
  piece.cell_data.push_back(scalarColumn<double>("overlap", overlap));
  piece.cell_data.push_back(vectorColumn("contact_point", contactPoint));
  piece.cell_data.push_back(vectorColumn("normal", normal));
  piece.cell_data.push_back(scalarColumn<std::uint8_t>("kind", kind));
  piece.cell_data.push_back(scalarColumn<std::uint64_t>("particle", particle));
  piece.cell_data.push_back(scalarColumn<std::uint64_t>("other", other));
  piece.cell_data.push_back(scalarColumn<std::uint32_t>("triangle", triangle));
  piece.sections.push_back(cellsOf<2>("Lines", std::span<const std::array<std::uint32_t, 2>>(lines), points.size(),
                                      "writeContactsVtp"));
  writePolyData(path, piece, encoding);
}

void writeBondsVtp(const std::string& path, const BondSet& bonds, const ParticleArrays& particles,
                   VtkEncoding encoding) {
  const std::vector<ParallelBond>& list = bonds.bonds();
  const std::size_t n = list.size();
  std::vector<Vec3> points;
  points.reserve(2 * n);
  std::vector<std::array<std::uint32_t, 2>> lines(n);
  std::vector<double> normalForce(n), twisting(n), tensile(n), shear(n);
  std::vector<Vec3> shearForce(n), bending(n);
  std::vector<std::uint8_t> intact(n);
  std::vector<std::uint64_t> a(n), b(n);
  for (std::size_t k = 0; k < n; ++k) {
    const ParallelBond& bond = list[k];
    lines[k] = {static_cast<std::uint32_t>(points.size()), static_cast<std::uint32_t>(points.size() + 1)};
    points.push_back(particles.position[bond.slot_a]);
    points.push_back(particles.position[bond.slot_b]);
    normalForce[k] = bond.normal_force;
    shearForce[k] = bond.shear_force;
    twisting[k] = bond.twisting_moment;
    bending[k] = bond.bending_moment;
    const BondStress stress = bondStress(bond, bonds.section(bond, particles));
    tensile[k] = stress.tensile;
    shear[k] = stress.shear;
    intact[k] = bond.broken ? 0 : 1;
    a[k] = bond.id_a;
    b[k] = bond.id_b;
  }
  PolyDataPiece piece;
  piece.point_count = points.size();
  piece.points = vectorColumn("position", points);
  piece.cell_data.push_back(scalarColumn<double>("normal_force", normalForce));
  piece.cell_data.push_back(vectorColumn("shear_force", shearForce));
  piece.cell_data.push_back(scalarColumn<double>("twisting_moment", twisting));
  piece.cell_data.push_back(vectorColumn("bending_moment", bending));
  piece.cell_data.push_back(scalarColumn<double>("tensile_stress", tensile));
  piece.cell_data.push_back(scalarColumn<double>("shear_stress", shear));
  piece.cell_data.push_back(scalarColumn<std::uint8_t>("intact", intact));
  piece.cell_data.push_back(scalarColumn<std::uint64_t>("particle_a", a));
  piece.cell_data.push_back(scalarColumn<std::uint64_t>("particle_b", b));
  piece.sections.push_back(
      cellsOf<2>("Lines", std::span<const std::array<std::uint32_t, 2>>(lines), points.size(), "writeBondsVtp"));
  writePolyData(path, piece, encoding);
}

void writeMeshLoadsVtp(const std::string& path, std::span<const Vec3> vertices,
                       std::span<const std::array<std::uint32_t, 3>> triangles, std::span<const TriangleLoad> loads,
                       VtkEncoding encoding) {
  if (!loads.empty() && loads.size() != triangles.size()) {
    throw std::invalid_argument("writeMeshLoadsVtp: " + std::to_string(loads.size()) + " loads for " +
                                std::to_string(triangles.size()) + " triangles");
  }
  PolyDataPiece piece;
  piece.point_count = vertices.size();
  piece.points = vectorColumn("position", vertices);
  piece.sections.push_back(cellsOf<3>("Polys", triangles, vertices.size(), "writeMeshLoadsVtp"));
  const std::size_t n = triangles.size();
  std::vector<Vec3> force(n, Vec3::Zero());
  std::vector<double> normal(n, 0.0), tangential(n, 0.0), pressure(n, 0.0), normalImpulse(n, 0.0),
      tangentialImpulse(n, 0.0), archard(n, 0.0), friction(n, 0.0);
  for (std::size_t t = 0; t < n && !loads.empty(); ++t) {
    const TriangleLoad& load = loads[t];
    const auto& v = triangles[t];
    const double area = 0.5 * (vertices[v[1]] - vertices[v[0]]).cross(vertices[v[2]] - vertices[v[0]]).norm();
    force[t] = load.force;
    normal[t] = load.normal_force;
    tangential[t] = load.tangential_force;
    pressure[t] = area > 0.0 ? load.normal_force / area : 0.0;
    normalImpulse[t] = load.normal_impulse;
    tangentialImpulse[t] = load.tangential_impulse;
    archard[t] = load.archard_work;
    friction[t] = load.friction_work;
  }
  piece.cell_data.push_back(vectorColumn("load_force", force));
  piece.cell_data.push_back(scalarColumn<double>("normal_force", normal));
  piece.cell_data.push_back(scalarColumn<double>("tangential_force", tangential));
  piece.cell_data.push_back(scalarColumn<double>("pressure", pressure));
  piece.cell_data.push_back(scalarColumn<double>("normal_impulse", normalImpulse));
  piece.cell_data.push_back(scalarColumn<double>("tangential_impulse", tangentialImpulse));
  piece.cell_data.push_back(scalarColumn<double>("archard_work", archard));
  piece.cell_data.push_back(scalarColumn<double>("friction_work", friction));
  writePolyData(path, piece, encoding);
}

const std::vector<std::string>& contactsCsvColumns() {
  static const std::vector<std::string> columns{
      "kind",         "particle",     "other",        "triangle",     "contact_x_m",  "contact_y_m",
      "contact_z_m",  "normal_x",     "normal_y",     "normal_z",     "overlap_m",    "normal_force_N",
      "normal_fx_N",  "normal_fy_N",  "normal_fz_N",  "tangential_fx_N", "tangential_fy_N", "tangential_fz_N"};
  return columns;
}

void writeContactsCsv(const std::string& path, std::span<const ContactRecord> contacts) {
  std::ofstream out(path, std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write " + path);
  const std::vector<std::string>& columns = contactsCsvColumns();
  for (std::size_t c = 0; c < columns.size(); ++c) out << (c == 0 ? "" : ",") << columns[c];
  out << '\n';
  std::string line;
  for (const ContactRecord& r : contacts) {
    line.clear();
    appendNumber(line, static_cast<unsigned>(r.kind));
    for (const std::uint64_t id : {r.particle, r.other, std::uint64_t{r.triangle}}) {
      line += ',';
      appendNumber(line, id);
    }
    for (const double value :
         {r.contact_point.x(), r.contact_point.y(), r.contact_point.z(), r.normal.x(), r.normal.y(), r.normal.z(),
          r.overlap, r.normal_force.dot(r.normal), r.normal_force.x(), r.normal_force.y(), r.normal_force.z(),
          r.tangential_force.x(), r.tangential_force.y(), r.tangential_force.z()}) {
      line += ',';
      appendCsvNumber(line, value);  // the one CSV cell rule (csv_table.hpp)
    }
    out << line << '\n';
  }
  out.flush();
  if (!out) throw std::runtime_error("cannot write " + path);
}

void writeDeformableVtp(const std::string& path, const DeformableFrame& frame, VtkEncoding encoding) {
  const std::size_t n = frame.positions.size();
  if (frame.displacements.size() != n || frame.velocities.size() != n || frame.spring_intact.size() != frame.springs.size() ||
      frame.triangle_active.size() != frame.triangles.size()) {
    throw std::invalid_argument("writeDeformableVtp: array sizes differ");
  }
  PolyDataPiece piece;
  piece.point_count = n;
  piece.points = vectorColumn("position", frame.positions);
  piece.point_data.push_back(vectorColumn("displacement", frame.displacements));
  piece.point_data.push_back(vectorColumn("velocity", frame.velocities));
  // Cell data runs over the lines first, then the polygons (VTK's cell order).
  std::vector<char> intact(frame.spring_intact.begin(), frame.spring_intact.end());
  intact.insert(intact.end(), frame.triangle_active.begin(), frame.triangle_active.end());
  piece.cell_data.push_back(flagColumn("intact", intact));
  std::vector<std::uint8_t> kind(frame.springs.size(), 0);
  kind.resize(frame.springs.size() + frame.triangles.size(), 1);
  piece.cell_data.push_back({"cell_kind", 1, std::move(kind)});
  piece.sections.push_back(cellsOf<2>("Lines", frame.springs, n, "writeDeformableVtp"));
  piece.sections.push_back(cellsOf<3>("Polys", frame.triangles, n, "writeDeformableVtp"));
  writePolyData(path, piece, encoding);
}

void writeTetrahedraVtu(const std::string& path, std::span<const Vec3> positions, std::span<const Vec3> displacements,
                        std::span<const Vec3> velocities, std::span<const std::vector<std::uint32_t>> elements,
                        std::span<const double> vonMises, VtkEncoding encoding) {
  const std::size_t n = positions.size();
  if (displacements.size() != n || velocities.size() != n || vonMises.size() != elements.size()) {
    throw std::invalid_argument("writeTetrahedraVtu: array sizes differ");
  }
  std::vector<std::int64_t> connectivity;
  std::vector<std::int64_t> offsets;
  std::vector<std::uint8_t> types;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const std::vector<std::uint32_t>& element = elements[e];
    if (element.size() != 4 && element.size() != 10) {
      throw std::invalid_argument("writeTetrahedraVtu: element " + std::to_string(e) + " has " +
                                  std::to_string(element.size()) + " nodes (4 or 10)");
    }
    for (std::uint32_t v : element) {
      if (v >= n) {
        throw std::invalid_argument("writeTetrahedraVtu: element " + std::to_string(e) + " uses node " +
                                    std::to_string(v) + " of " + std::to_string(n));
      }
      connectivity.push_back(v);
    }
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    types.push_back(element.size() == 4 ? 10 : 24);  // VTK_TETRA, VTK_QUADRATIC_TETRA
  }
  const VtkArray points = vectorColumn("position", positions);
  const std::vector<VtkArray> pointData{vectorColumn("displacement", displacements), vectorColumn("velocity", velocities)};
  const VtkArray stress = scalarColumn<double>("von_mises_stress", vonMises);
  const VtkArray cellConnectivity{"connectivity", 1, std::move(connectivity)};
  const VtkArray cellOffsets{"offsets", 1, std::move(offsets)};
  const VtkArray cellTypes{"types", 1, std::move(types)};

  std::string xml;
  xml.append("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"")
      .append(kByteOrder)
      .append("\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n");
  xml.append("    <Piece NumberOfPoints=\"").append(std::to_string(n)).append("\" NumberOfCells=\"");
  xml.append(std::to_string(elements.size())).append("\">\n");
  std::uint64_t offset = 0;
  std::vector<const VtkArray*> blocks;
  const auto add = [&](const VtkArray& array) {
    writeArrayXml(xml, array, encoding, offset, "        ");
    blocks.push_back(&array);
  };
  xml.append("      <Points>\n");
  add(points);
  xml.append("      </Points>\n      <PointData Vectors=\"displacement\">\n");
  for (const VtkArray& array : pointData) add(array);
  xml.append("      </PointData>\n      <CellData Scalars=\"von_mises_stress\">\n");
  add(stress);
  xml.append("      </CellData>\n      <Cells>\n");
  add(cellConnectivity);
  add(cellOffsets);
  add(cellTypes);
  xml.append("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");
  if (encoding == VtkEncoding::Ascii) {
    xml.append("</VTKFile>\n");
    blocks.clear();
  }
  writeFile(path, xml, blocks);
}

void writePvd(const std::string& path, std::span<const PvdEntry> entries) {
  std::string xml;
  xml.append("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"")
      .append(kByteOrder)
      .append("\">\n  <Collection>\n");
  for (const PvdEntry& entry : entries) {
    xml.append("    <DataSet timestep=\"");
    appendNumber(xml, entry.time);
    xml.append("\" group=\"\" part=\"0\" file=\"").append(escapeXmlAttribute(entry.file)).append("\"/>\n");
  }
  xml.append("  </Collection>\n</VTKFile>\n");
  writeFile(path, xml, {});
}

}  // namespace demlink::core
