#include "softflow/io/vtu_writer.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <regex>
#include <vector>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/mesh/quality.hpp"

namespace softflow::io {

std::string base64_encode(const unsigned char* data, std::size_t n) {
  static constexpr char kTable[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve(4 * ((n + 2) / 3));
  for (std::size_t i = 0; i < n; i += 3) {
    const std::uint32_t b0 = data[i];
    const std::uint32_t b1 = i + 1 < n ? data[i + 1] : 0;
    const std::uint32_t b2 = i + 2 < n ? data[i + 2] : 0;
    const std::uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
    out += kTable[(triple >> 18) & 63];
    out += kTable[(triple >> 12) & 63];
    out += i + 1 < n ? kTable[(triple >> 6) & 63] : '=';
    out += i + 2 < n ? kTable[triple & 63] : '=';
  }
  return out;
}

namespace {

// VTK inline binary: base64 of a UInt32 byte count followed by the bytes.
template <class T>
std::string encode_array(const std::vector<T>& values) {
  const std::uint32_t bytes = static_cast<std::uint32_t>(values.size() * sizeof(T));
  std::vector<unsigned char> buffer(sizeof(bytes) + bytes);
  std::memcpy(buffer.data(), &bytes, sizeof(bytes));
  if (bytes) std::memcpy(buffer.data() + sizeof(bytes), values.data(), bytes);
  return base64_encode(buffer.data(), buffer.size());
}

template <class T>
void write_data_array(std::ofstream& out, const char* type, const char* name, int components,
                      const std::vector<T>& values) {
  out << fmt::format("<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"binary\">\n",
                     type, name, components)
      << encode_array(values) << "\n</DataArray>\n";
}

}  // namespace

const PointField& SubdomainPiece::field(const std::string& name) const {
  for (const auto& f : fields)
    if (f.name == name) return f;
  throw Error(fmt::format("no field '{}' in the output piece", name));
}

SubdomainPiece extract_subdomain(const mesh::Mesh& mesh, const std::vector<FieldData>& sources,
                                 int region) {
  SubdomainPiece piece;
  piece.region = region;
  // Fields without element values (interface multipliers) are not point data.
  auto on_elements = [](const fem::DofMap& dofs, int f) {
    return dofs.field(f).space->n_element_nodes() > 0;
  };
  for (const auto& source : sources)
    for (int f = 0; f < source.dofs->n_fields(); ++f)
      if (on_elements(*source.dofs, f))
        piece.fields.push_back({source.dofs->field(f).name, source.dofs->field(f).components, {}});
  std::vector<int> local(mesh.n_nodes(), -1);
  for (int t = 0; t < mesh.n_tets(); ++t) {
    if (mesh.tet_region[t] != region) continue;
    mesh::Tet10 cell{};
    for (int k = 0; k < 10; ++k) {
      const int node = mesh.tets[t][k];
      if (local[node] < 0) {
        local[node] = static_cast<int>(piece.points.size());
        piece.points.push_back(mesh.nodes[node]);
        std::size_t out_field = 0;
        for (const auto& source : sources) {
          const fem::DofMap& dofs = *source.dofs;
          const auto d = dofs.element_dofs(t);
          for (int f = 0; f < dofs.n_fields(); ++f) {
            if (!on_elements(dofs, f)) continue;
            auto& out = piece.fields[out_field++].values;
            const int n_c = dofs.field(f).components;
            const int* fd = d.data() + dofs.element_offset(f);
            for (int c = 0; c < n_c; ++c) {
              if (dofs.field(f).space->degree() == 2 || k < 4) {
                out.push_back(source.values[fd[k * n_c + c]]);
              } else {  // P1 at an edge node: the mean of the edge's vertices
                const auto& e = mesh::kTetEdges[k - 4];
                out.push_back(0.5 * (source.values[fd[e[0] * n_c + c]] +
                                     source.values[fd[e[1] * n_c + c]]));
              }
            }
          }
        }
      }
      cell[k] = local[node];
    }
    piece.cells.push_back(cell);
    piece.tets.push_back(t);
  }
  return piece;
}

SubdomainPiece extract_subdomain(const mesh::Mesh& mesh, int region) {
  return extract_subdomain(mesh, std::vector<FieldData>{}, region);
}

SubdomainPiece extract_subdomain(const mesh::Mesh& mesh, const fem::DofMap& dofs,
                                 const std::vector<double>& solution, int region) {
  return extract_subdomain(mesh, std::vector<FieldData>{{&dofs, solution}}, region);
}

void write_vtu(const std::filesystem::path& path, const SubdomainPiece& piece) {
  for (const auto& f : piece.cell_fields)  // before the file exists
    if (f.values.size() != piece.cells.size())
      throw Error(fmt::format("cell field '{}' has {} values for {} cells", f.name, f.values.size(),
                              piece.cells.size()));
  std::ofstream out(path);
  if (!out) throw Error(fmt::format("cannot write {}", path.string()));
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt32\">\n<UnstructuredGrid>\n";
  out << fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", piece.points.size(),
                     piece.cells.size());
  std::vector<double> xyz;
  xyz.reserve(3 * piece.points.size());
  for (const auto& p : piece.points) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  out << "<Points>\n";
  write_data_array(out, "Float64", "Points", 3, xyz);
  out << "</Points>\n<Cells>\n";
  std::vector<std::int32_t> connectivity, offsets;
  std::vector<std::uint8_t> types(piece.cells.size(), 24);  // VTK_QUADRATIC_TETRA
  for (const auto& c : piece.cells) {
    connectivity.insert(connectivity.end(), c.begin(), c.end());
    offsets.push_back(static_cast<std::int32_t>(connectivity.size()));
  }
  write_data_array(out, "Int32", "connectivity", 1, connectivity);
  write_data_array(out, "Int32", "offsets", 1, offsets);
  write_data_array(out, "UInt8", "types", 1, types);
  std::string active;  // ParaView's default vector and scalar: the first of each
  for (const auto& f : piece.fields) {
    if (f.components == 3 && active.find("Vectors") == std::string::npos)
      active += fmt::format(" Vectors=\"{}\"", f.name);
    if (f.components == 1 && active.find("Scalars") == std::string::npos)
      active += fmt::format(" Scalars=\"{}\"", f.name);
  }
  out << "</Cells>\n<PointData" << active << ">\n";
  for (const auto& f : piece.fields)
    write_data_array(out, "Float64", f.name.c_str(), f.components, f.values);
  out << "</PointData>\n";
  if (!piece.cell_fields.empty()) {
    out << fmt::format("<CellData Scalars=\"{}\">\n", piece.cell_fields.front().name);
    for (const auto& f : piece.cell_fields)
      write_data_array(out, "Float64", f.name.c_str(), 1, f.values);
    out << "</CellData>\n";
  }
  out << "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  if (!out) throw Error(fmt::format("error while writing {}", path.string()));
}

namespace {

/// Writes one piece per region into `directory` (matrix.vtu, object_k.vtu),
/// each made by `piece_of(region)`, and `pvd_name` listing them as the parts
/// of one time step.
void write_region_pieces(const std::filesystem::path& directory, const std::string& pvd_name,
                         const mesh::Mesh& mesh, double time,
                         const std::function<SubdomainPiece(int)>& piece_of) {
  std::ofstream pvd(directory / pvd_name);
  pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (int region = 0; region <= mesh.n_objects; ++region) {
    const std::string name = region == 0 ? "matrix.vtu" : fmt::format("object_{}.vtu", region);
    write_vtu(directory / name, piece_of(region));
    pvd << fmt::format("<DataSet timestep=\"{}\" part=\"{}\" file=\"{}\"/>\n", time, region, name);
  }
  pvd << "</Collection>\n</VTKFile>\n";
  if (!pvd) throw Error(fmt::format("error while writing {}", (directory / pvd_name).string()));
}

}  // namespace

void write_stokes_fields(const std::filesystem::path& directory, const mesh::Mesh& mesh,
                         const fem::DofMap& dofs, const std::vector<double>& solution,
                         double time) {
  write_region_pieces(directory, "fields.pvd", mesh, time,
                      [&](int region) { return extract_subdomain(mesh, dofs, solution, region); });
}

void write_mesh(const std::filesystem::path& directory, const mesh::Mesh& mesh) {
  write_region_pieces(directory, "mesh.pvd", mesh, 0.0, [&](int region) {
    auto piece = extract_subdomain(mesh, region);
    CellField quality{"quality", {}};
    quality.values.reserve(piece.tets.size());
    for (const int t : piece.tets) quality.values.push_back(mesh::tet_quality(mesh, t));
    piece.cell_fields.push_back(std::move(quality));
    return piece;
  });
}

FieldSeries::FieldSeries(std::filesystem::path directory, std::filesystem::path pvd_path)
    : directory_(std::move(directory)), pvd_path_(std::move(pvd_path)) {
  std::filesystem::create_directories(directory_);
}

void FieldSeries::write(const mesh::Mesh& mesh, const std::vector<FieldData>& sources,
                        double time, int step) {
  for (int region = 0; region <= mesh.n_objects; ++region) {
    const std::string name = region == 0 ? fmt::format("matrix_{:06d}.vtu", step)
                                         : fmt::format("object_{}_{:06d}.vtu", region, step);
    write_vtu(directory_ / name, extract_subdomain(mesh, sources, region));
    const auto relative = std::filesystem::relative(directory_ / name, pvd_path_.parent_path());
    entries_.push_back({time, region, relative.string()});
  }
  std::string pvd = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (const auto& e : entries_)
    pvd += fmt::format("<DataSet timestep=\"{:.10g}\" part=\"{}\" file=\"{}\"/>\n", e.time, e.part, e.file);
  pvd += "</Collection>\n</VTKFile>\n";
  const auto tmp = pvd_path_.string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << pvd;
    if (!out) throw Error(fmt::format("cannot write {}", tmp));
  }
  std::filesystem::rename(tmp, pvd_path_);
}

void FieldSeries::resume(int step) {
  std::ifstream in(pvd_path_);
  entries_.clear();
  // Our own PVD: one <DataSet timestep="t" part="p" file="f"/> per line, the
  // step number being the digits before ".vtu" in f.
  const std::regex line(R"re(<DataSet timestep="([^"]*)" part="([^"]*)" file="([^"]*_([0-9]+)\.vtu)"/>)re");
  std::string text;
  while (std::getline(in, text)) {
    std::smatch m;
    if (!std::regex_search(text, m, line) || std::stoi(m[4].str()) > step) continue;
    entries_.push_back({std::stod(m[1].str()), std::stoi(m[2].str()), m[3].str()});
  }
}

}  // namespace softflow::io
