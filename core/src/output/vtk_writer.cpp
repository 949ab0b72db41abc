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
#include <variant>
#include <vector>

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
               std::vector<std::int64_t>>
      values;

  [[nodiscard]] std::string_view typeName() const {
    switch (values.index()) {
      case 0: return "Float64";
      case 1: return "UInt64";
      case 2: return "UInt32";
      default: return "Int64";
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
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
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

/// A PolyData piece: points, point data and one cell section (Verts or Polys).
struct PolyDataPiece {
  std::size_t point_count = 0;
  VtkArray points;
  std::vector<VtkArray> point_data;
  std::string_view cell_section;  ///< "Verts" or "Polys"
  std::size_t cell_count = 0;
  VtkArray connectivity;
  VtkArray offsets;
};

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
  for (std::string_view section : {"Verts", "Polys", "Lines", "Strips"}) {
    const std::size_t n = section == piece.cell_section ? piece.cell_count : 0;
    xml.append("\" NumberOf").append(section).append("=\"").append(std::to_string(n));
  }
  xml.append("\">\n");

  std::uint64_t offset = 0;
  std::vector<const VtkArray*> blocks{&piece.points};
  xml.append("      <Points>\n");
  writeArrayXml(xml, piece.points, encoding, offset, "        ");
  xml.append("      </Points>\n");
  if (!piece.point_data.empty()) {
    xml.append("      <PointData Scalars=\"radius\">\n");
    for (const VtkArray& array : piece.point_data) {
      writeArrayXml(xml, array, encoding, offset, "        ");
      blocks.push_back(&array);
    }
    xml.append("      </PointData>\n");
  }
  xml.append("      <").append(piece.cell_section).append(">\n");
  writeArrayXml(xml, piece.connectivity, encoding, offset, "        ");
  writeArrayXml(xml, piece.offsets, encoding, offset, "        ");
  xml.append("      </").append(piece.cell_section).append(">\n");
  blocks.push_back(&piece.connectivity);
  blocks.push_back(&piece.offsets);
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
  piece.cell_section = "Verts";
  piece.cell_count = n;
  std::vector<std::int64_t> connectivity(n);
  std::vector<std::int64_t> offsets(n);
  for (std::size_t i = 0; i < n; ++i) {
    connectivity[i] = static_cast<std::int64_t>(i);
    offsets[i] = static_cast<std::int64_t>(i + 1);
  }
  piece.connectivity = {"connectivity", 1, std::move(connectivity)};
  piece.offsets = {"offsets", 1, std::move(offsets)};
  writePolyData(path, piece, encoding);
}

void writeMeshVtp(const std::string& path, std::span<const Vec3> vertices,
                  std::span<const std::array<std::uint32_t, 3>> triangles, VtkEncoding encoding) {
  std::vector<std::int64_t> connectivity;
  std::vector<std::int64_t> offsets;
  connectivity.reserve(3 * triangles.size());
  offsets.reserve(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::uint32_t v : triangles[t]) {
      if (v >= vertices.size()) {
        throw std::invalid_argument("writeMeshVtp: triangle " + std::to_string(t) + " uses vertex " +
                                    std::to_string(v) + " of " + std::to_string(vertices.size()));
      }
      connectivity.push_back(v);
    }
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  PolyDataPiece piece;
  piece.point_count = vertices.size();
  piece.points = vectorColumn("position", vertices);
  piece.cell_section = "Polys";
  piece.cell_count = triangles.size();
  piece.connectivity = {"connectivity", 1, std::move(connectivity)};
  piece.offsets = {"offsets", 1, std::move(offsets)};
  writePolyData(path, piece, encoding);
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
