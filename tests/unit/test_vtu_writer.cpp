// VTU output pieces: base64 encoding and per-subdomain extraction.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/fem/dof_map.hpp"
#include "softflow/io/vtu_writer.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "support/verification/structured_box.hpp"

using namespace softflow;

TEST(VtuWriter, Base64MatchesTheStandardVectors) {
  auto enc = [](const std::string& s) {
    return io::base64_encode(reinterpret_cast<const unsigned char*>(s.data()), s.size());
  };
  EXPECT_EQ(enc(""), "");
  EXPECT_EQ(enc("M"), "TQ==");
  EXPECT_EQ(enc("Ma"), "TWE=");
  EXPECT_EQ(enc("Man"), "TWFu");
  EXPECT_EQ(enc("foobar"), "Zm9vYmFy");
}

TEST(VtuWriter, SubdomainPiecesCarryTheirOwnPressureAtSharedNodes) {
  mesh::Box box;
  box.length = box.height = box.width = 2.0;
  box.periodic_x = box.periodic_z = false;
  auto mesh = mesh::structured_box(box, 2, 2, 2);
  mesh.n_objects = 1;
  for (int t = 0; t < mesh.n_tets(); ++t) {
    double xc = 0;
    for (int k = 0; k < 4; ++k) xc += mesh.nodes[mesh.tets[t][k]].x() / 4;
    if (xc > 0) mesh.tet_region[t] = 1;
  }
  const auto dofs = physics::make_stokes_dof_map(mesh, false);
  // Velocity = node x coordinate in every component, pressure = region + 1.
  std::vector<double> solution(dofs.n_dofs());
  for (int i = 0; i < dofs.n_dofs(); ++i)
    solution[i] = dofs.field_of(i) == physics::kVelocityField ? mesh.nodes[dofs.node_of(i)].x()
                                                              : dofs.region_of(i) + 1.0;
  int n_cells = 0;
  for (int region : {0, 1}) {
    const auto piece = io::extract_subdomain(mesh, dofs, solution, region);
    n_cells += static_cast<int>(piece.cells.size());
    const auto& velocity = piece.field("velocity");
    const auto& pressure = piece.field("pressure");
    ASSERT_EQ(velocity.values.size(), 3 * piece.points.size());
    for (std::size_t p = 0; p < piece.points.size(); ++p) {
      EXPECT_DOUBLE_EQ(pressure.at(p), region + 1.0);  // interface points too
      EXPECT_DOUBLE_EQ(velocity.at(p, 0), piece.points[p].x());
    }
  }
  EXPECT_EQ(n_cells, mesh.n_tets());
}

TEST(VtuWriter, CellFieldsAreWrittenAsCellDataAndAWrongSizeWritesNothing) {
  mesh::Box box;
  box.length = box.height = box.width = 2.0;
  box.periodic_x = box.periodic_z = false;
  const auto mesh = mesh::structured_box(box, 1, 1, 1);
  auto piece = io::extract_subdomain(mesh, 0);
  ASSERT_EQ(piece.cells.size(), static_cast<std::size_t>(mesh.n_tets()));
  ASSERT_EQ(piece.tets.size(), piece.cells.size());
  EXPECT_TRUE(piece.fields.empty());
  io::CellField index{"tet", {}};
  for (const int t : piece.tets) index.values.push_back(t);
  piece.cell_fields.push_back(index);
  const auto dir = std::filesystem::temp_directory_path() / "softflow_vtu_cell_data";
  std::filesystem::create_directories(dir);
  io::write_vtu(dir / "piece.vtu", piece);
  std::ifstream in(dir / "piece.vtu");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("<CellData Scalars=\"tet\">"), std::string::npos);
  EXPECT_NE(text.find("Name=\"tet\""), std::string::npos);

  piece.cell_fields.front().values.pop_back();  // one value short
  EXPECT_THROW(io::write_vtu(dir / "short.vtu", piece), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "short.vtu"));
  std::filesystem::remove_all(dir);
}
