// ParaView output: one VTU per subdomain on quadratic tetrahedra, collected by a PVD file.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "softflow/fem/dof_map.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::io {

/// Values of one field at the points of a piece.
struct PointField {
  std::string name;
  int components = 1;
  std::vector<double> values;  ///< `components` per point

  [[nodiscard]] double at(std::size_t point, int component = 0) const {
    return values[point * components + component];
  }
};

/// Values of one field per cell of a piece (e.g. the element quality).
struct CellField {
  std::string name;
  std::vector<double> values;  ///< one per cell
};

/// One subdomain's piece of a solution on its own copy of the nodes, so
/// that per-region fields (pressure, a conformation tensor, a slip
/// velocity) may jump at the interface. Cells are VTK_QUADRATIC_TETRA.
/// Every field of the dof map becomes a point field of the same name; P1
/// fields are interpolated linearly to the edge nodes, so that ParaView
/// shows the P1 field.
struct SubdomainPiece {
  int region = 0;
  std::vector<mesh::Point> points;
  std::vector<mesh::Tet10> cells;  ///< indices into points
  std::vector<int> tets;           ///< the mesh's tetrahedron of each cell
  std::vector<PointField> fields;  ///< in the dof map's field order
  std::vector<CellField> cell_fields;  ///< written as CellData, one value per cell

  /// The field called `name`; throws if there is none.
  [[nodiscard]] const PointField& field(const std::string& name) const;
};

/// Values of every field of a dof map (all dofs, as gathered on this rank):
/// one source of output fields. A run's output is a list of sources, e.g.
/// the Stokes solution and each field added to the run.
struct FieldData {
  const fem::DofMap* dofs = nullptr;
  std::vector<double> values;
};

/// The piece of `region` with every field of every source.
SubdomainPiece extract_subdomain(const mesh::Mesh& mesh, const std::vector<FieldData>& sources,
                                 int region);
SubdomainPiece extract_subdomain(const mesh::Mesh& mesh, const fem::DofMap& dofs,
                                 const std::vector<double>& solution, int region);

/// The piece of `region` without fields: its points and cells only (a mesh
/// to look at before a run, `softflow mesh --output`).
SubdomainPiece extract_subdomain(const mesh::Mesh& mesh, int region);

/// Writes `piece` as a binary (base64) XML UnstructuredGrid file.
void write_vtu(const std::filesystem::path& path, const SubdomainPiece& piece);

/// Writes matrix.vtu, object_1.vtu, ... into `directory` and fields.pvd
/// listing them as parts of one time step (ParaView opens the PVD).
void write_stokes_fields(const std::filesystem::path& directory, const mesh::Mesh& mesh,
                         const fem::DofMap& dofs, const std::vector<double>& solution,
                         double time = 0.0);

/// Writes the mesh alone into `directory`: matrix.vtu, object_1.vtu, ...
/// with each element's quality (mesh::tet_quality) as cell data "quality",
/// and mesh.pvd listing them (ParaView opens the PVD).
void write_mesh(const std::filesystem::path& directory, const mesh::Mesh& mesh);

/// Fields at several times as one ParaView time series: every call to
/// write() adds matrix_<step>.vtu, object_k_<step>.vtu to `directory` and
/// rewrites `directory`/../<pvd_name> to list every time written so far (the
/// PVD is replaced atomically, so an interrupted run leaves a readable one).
class FieldSeries {
 public:
  FieldSeries(std::filesystem::path directory, std::filesystem::path pvd_path);
  void write(const mesh::Mesh& mesh, const std::vector<FieldData>& sources, double time,
             int step);
  /// Continues the series of an earlier run (a restart): takes the entries
  /// of the existing PVD file up to `step`, so that later writes extend it.
  void resume(int step);

 private:
  struct Entry {
    double time;
    int part;
    std::string file;
  };
  std::filesystem::path directory_;
  std::filesystem::path pvd_path_;
  std::vector<Entry> entries_;
};

/// Standard base64 of raw bytes (VTK's inline binary encoding).
std::string base64_encode(const unsigned char* data, std::size_t n);

}  // namespace softflow::io
