#include "softflow/io/checkpoint.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <signal.h>
#include <hdf5.h>
#include <unistd.h>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/common/fnv1a.hpp"
#include "softflow/common/xxh64.hpp"

namespace softflow::io {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormatName = "softflow-checkpoint";

/// Thrown inside this file on any HDF5 failure; turned into a message that
/// names the file by the public functions.
struct Hdf5Failure {
  std::string what;
  bool in_hdf5 = false;  ///< an HDF5 call failed (not one of this file's own checks)
};

/// Thrown inside this file when the file was damaged: a checksum or content
/// hash that does not match, or HDF5 failing on a file that is a checkpoint
/// of this format (which has everything the reader asks for).
struct Corruption {
  std::string what;
};

/// What the failed HDF5 call's error stack says, walked from its innermost entry.
struct Hdf5Errors {
  bool checksum = false;  ///< a metadata checksum failed: the file was damaged
  std::string cause;      ///< the innermost description, HDF5's own words
};

herr_t read_error_entry(unsigned, const H5E_error2_t* error, void* data) {
  auto* errors = static_cast<Hdf5Errors*>(data);
  if (error->desc == nullptr) return 0;
  // HDF5 1.10 has no error class of its own for it: "incorrect metadata
  // checksum ...", "data error detected by Fletcher32 checksum".
  if (std::strstr(error->desc, "checksum") != nullptr) errors->checksum = true;
  if (errors->cause.empty()) errors->cause = error->desc;
  return 0;
}

/// The error stack of the last HDF5 call (empty if it succeeded).
Hdf5Errors hdf5_errors() {
  Hdf5Errors errors;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, read_error_entry, &errors);
  return errors;
}

/// Throws for a failed HDF5 call, right after it: its error stack is still
/// there to tell a failed metadata checksum (a damaged file) from the rest,
/// and to say what HDF5 found.
[[noreturn]] void fail(std::string what) {
  const Hdf5Errors errors = hdf5_errors();
  if (errors.checksum) throw Corruption{what + ": HDF5's metadata checksum does not match"};
  if (errors.cause.empty()) throw Hdf5Failure{std::move(what)};
  throw Hdf5Failure{what + " (HDF5: " + errors.cause + ")", true};
}

hid_t checked(hid_t id, const std::string& what) {
  if (id < 0) fail(what);
  return id;
}

void checked(herr_t status, const char* what, const std::string& name) {
  if (status < 0) fail(fmt::format("{} '{}'", what, name));
}

/// An HDF5 identifier that closes itself.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, -1)), close_(other.close_) {}
  [[nodiscard]] hid_t get() const { return id_; }
  /// Closes now and reports failure (a file's close is where data reaches it).
  herr_t close() {
    const herr_t status = id_ >= 0 ? close_(id_) : 0;
    id_ = -1;
    return status;
  }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

/// HDF5 prints an error stack to stderr on every failed call unless told not
/// to; our callers report failures themselves, once, with the file's name.
class QuietHdf5Errors {
 public:
  QuietHdf5Errors() {
    H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5Errors() {
    if (restore_) H5Eset_auto2(H5E_DEFAULT, function_, data_);
  }
  QuietHdf5Errors(const QuietHdf5Errors&) = delete;
  QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;

  /// Keeps HDF5 quiet for the rest of the process. HDF5 1.10 leaks memory
  /// when a metadata checksum fails (every handle of ours is closed), and
  /// at exit, finding its free lists not empty, prints "HDF5: infinite loop
  /// closing library" and a line of package names after our message
  /// (issue 33) -- unless its automatic error printing is off then.
  void stay_quiet() { restore_ = false; }

 private:
  H5E_auto2_t function_ = nullptr;
  void* data_ = nullptr;
  bool restore_ = true;
};

Handle make_group(hid_t parent, const std::string& name) {
  return Handle(checked(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                        "cannot create group " + name),
                H5Gclose);
}

Handle open_group(hid_t parent, const std::string& name) {
  return Handle(checked(H5Gopen2(parent, name.c_str(), H5P_DEFAULT), "cannot open group " + name),
                H5Gclose);
}

void write_attribute(hid_t object, const std::string& name, hid_t type, const void* value) {
  Handle space(checked(H5Screate(H5S_SCALAR), "dataspace " + name), H5Sclose);
  Handle attribute(
      checked(H5Acreate2(object, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
              "cannot create attribute " + name),
      H5Aclose);
  checked(H5Awrite(attribute.get(), type, value), "cannot write attribute", name);
}

// ---- datasets: rows x cols (cols = 0: one-dimensional) ----

/// Chunks of about 1 MiB: each has its own checksum.
constexpr std::size_t kChunkBytes = std::size_t{1} << 20;

/// The name of the attribute holding a dataset's content hash.
constexpr const char* kHashAttribute = "xxh64";

/// XXH64 of the bytes written, seeded with the shape: what the restart
/// will read must be these bytes in this shape. Fletcher32 checks each chunk
/// that HDF5 finds, but not that the chunk index finds the right one: a
/// flipped bit there gives another dataset's chunk, or none (HDF5 then
/// reads zeros), and both pass it (issue 33).
std::uint64_t content_hash(const void* data, std::size_t bytes, std::size_t rows,
                           std::size_t cols) {
  Fnv1a shape;
  shape.scalar(rows);
  shape.scalar(cols);
  return xxh64(data, bytes, shape.value());
}

/// The dataset's path in the file, for messages ("/state/time_loop/solution").
std::string path_of(hid_t object) {
  std::string name(256, '\0');
  const ssize_t length = H5Iget_name(object, name.data(), name.size());
  if (length <= 0) return "?";
  if (static_cast<std::size_t>(length) >= name.size()) {
    name.resize(static_cast<std::size_t>(length) + 1);
    H5Iget_name(object, name.data(), name.size());
  }
  name.resize(static_cast<std::size_t>(length));
  return name;
}

void check_content_hash(hid_t set, const void* data, std::size_t bytes, std::size_t rows,
                        std::size_t cols) {
  // A file of this format without the hash was damaged (or not written by us).
  if (H5Aexists(set, kHashAttribute) <= 0)
    fail(fmt::format("dataset {} has no content hash", path_of(set)));
  std::uint64_t stored = 0;
  {
    Handle attribute(checked(H5Aopen(set, kHashAttribute, H5P_DEFAULT), "content hash"), H5Aclose);
    checked(H5Aread(attribute.get(), H5T_NATIVE_UINT64, &stored), "cannot read attribute",
            kHashAttribute);
  }
  if (stored != content_hash(data, bytes, rows, cols))
    throw Corruption{
        fmt::format("dataset {} is not what was written (its content hash differs)", path_of(set))};
}

bool has_checksum(hid_t set) {
  Handle properties(H5Dget_create_plist(set), H5Pclose);
  if (properties.get() < 0) return false;
  unsigned flags = 0;
  return H5Pget_filter_by_id2(properties.get(), H5Z_FILTER_FLETCHER32, &flags, nullptr, nullptr,
                              0, nullptr, nullptr) >= 0;
}

/// Writes a dataset with its content hash; returns it, open.
Handle write_array(hid_t parent, const std::string& name, hid_t type, const void* data,
                   std::size_t rows, std::size_t cols) {
  const hsize_t dims[2] = {rows, cols};
  const int rank = cols > 0 ? 2 : 1;
  const std::size_t row_bytes = H5Tget_size(type) * std::max<std::size_t>(cols, 1);
  Handle space(checked(H5Screate_simple(rank, dims, nullptr), "dataspace " + name), H5Sclose);
  // Every dataset with data carries a Fletcher32 checksum per chunk, which
  // HDF5 checks on every read. A dataset of zero rows cannot be chunked, and
  // has no data to damage: it stays contiguous.
  Handle properties(checked(H5Pcreate(H5P_DATASET_CREATE), "properties " + name), H5Pclose);
  if (rows > 0) {
    const std::size_t rows_per_chunk =
        std::clamp<std::size_t>(kChunkBytes / std::max<std::size_t>(row_bytes, 1), 1, rows);
    const hsize_t chunk[2] = {rows_per_chunk, cols};
    checked(H5Pset_chunk(properties.get(), rank, chunk), "cannot chunk", name);
    checked(H5Pset_fletcher32(properties.get()), "cannot checksum", name);
  }
  Handle set(checked(H5Dcreate2(parent, name.c_str(), type, space.get(), H5P_DEFAULT,
                                properties.get(), H5P_DEFAULT),
                     "cannot create dataset " + name),
             H5Dclose);
  if (rows > 0)
    checked(H5Dwrite(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "cannot write", name);
  const std::uint64_t hash = content_hash(data, rows * row_bytes, rows, cols);
  write_attribute(set.get(), kHashAttribute, H5T_NATIVE_UINT64, &hash);
  return set;
}

/// Reads a dataset of `cols` columns (0: one-dimensional) into a vector.
template <class T>
std::vector<T> read_array(hid_t parent, const std::string& name, hid_t type, std::size_t cols) {
  Handle set(checked(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), "cannot open dataset " + name),
             H5Dclose);
  Handle space(checked(H5Dget_space(set.get()), "dataspace " + name), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  hsize_t dims[2] = {0, 0};
  if (rank != (cols > 0 ? 2 : 1) || H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0 ||
      (cols > 0 && dims[1] != cols))
    fail(fmt::format("dataset {} has the wrong shape", name));
  std::vector<T> out(dims[0] * (cols > 0 ? cols : 1));
  if (!out.empty()) {
    // Written by this file, every dataset with data has a checksum; one
    // without was not written by us, or its header was damaged.
    if (!has_checksum(set.get()))
      fail(fmt::format("dataset {} has no checksum", path_of(set.get())));
    if (H5Dread(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
      throw Corruption{fmt::format("dataset {} fails its checksum", path_of(set.get()))};
  }
  check_content_hash(set.get(), out.data(), out.size() * sizeof(T), dims[0], cols);
  return out;
}

void write_points(hid_t parent, const std::string& name, const std::vector<mesh::Point>& points) {
  // Eigen::Vector3d is three contiguous doubles, so a vector of them is an n x 3 array.
  static_assert(sizeof(mesh::Point) == 3 * sizeof(double));
  write_array(parent, name, H5T_NATIVE_DOUBLE, points.data(), points.size(), 3);
}

std::vector<mesh::Point> read_points(hid_t parent, const std::string& name) {
  const auto flat = read_array<double>(parent, name, H5T_NATIVE_DOUBLE, 3);
  std::vector<mesh::Point> points(flat.size() / 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = mesh::Point(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
  return points;
}


template <std::size_t N>
void write_cells(hid_t parent, const std::string& name,
                 const std::vector<std::array<int, N>>& cells) {
  write_array(parent, name, H5T_NATIVE_INT, cells.data(), cells.size(), N);
}

template <std::size_t N>
std::vector<std::array<int, N>> read_cells(hid_t parent, const std::string& name) {
  const auto flat = read_array<int>(parent, name, H5T_NATIVE_INT, N);
  std::vector<std::array<int, N>> cells(flat.size() / N);
  for (std::size_t i = 0; i < cells.size(); ++i)
    std::copy(flat.begin() + i * N, flat.begin() + (i + 1) * N, cells[i].begin());
  return cells;
}

// ---- attributes ----

void write_int(hid_t object, const std::string& name, int value) {
  write_attribute(object, name, H5T_NATIVE_INT, &value);
}
void write_double(hid_t object, const std::string& name, double value) {
  write_attribute(object, name, H5T_NATIVE_DOUBLE, &value);
}
void write_string(hid_t object, const std::string& name, const std::string& value) {
  // Fixed-length, NUL-terminated: readable by h5dump and h5py as plain text.
  Handle type(checked(H5Tcopy(H5T_C_S1), "string type"), H5Tclose);
  checked(H5Tset_size(type.get(), value.size() + 1), "string size", name);
  checked(H5Tset_strpad(type.get(), H5T_STR_NULLTERM), "string padding", name);
  write_attribute(object, name, type.get(), value.c_str());
}

Handle open_attribute(hid_t object, const std::string& name) {
  return Handle(
      checked(H5Aopen(object, name.c_str(), H5P_DEFAULT), "cannot open attribute " + name),
      H5Aclose);
}

int read_int(hid_t object, const std::string& name) {
  Handle attribute = open_attribute(object, name);
  int value = 0;
  checked(H5Aread(attribute.get(), H5T_NATIVE_INT, &value), "cannot read attribute", name);
  return value;
}

double read_double(hid_t object, const std::string& name) {
  Handle attribute = open_attribute(object, name);
  double value = 0.0;
  checked(H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &value), "cannot read attribute", name);
  return value;
}

std::string read_string(hid_t object, const std::string& name) {
  Handle attribute = open_attribute(object, name);
  Handle type(checked(H5Aget_type(attribute.get()), "type of " + name), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0)
    fail(fmt::format("attribute {} is not a fixed-length string", name));
  std::string buffer(H5Tget_size(type.get()), '\0');
  checked(H5Aread(attribute.get(), type.get(), buffer.data()), "cannot read attribute", name);
  return buffer.substr(0, buffer.find('\0'));
}

// ---- the mesh ----

void write_mesh(hid_t file, const mesh::Mesh& m) {
  Handle g = make_group(file, "mesh");
  write_double(g.get(), "length", m.box.length);
  write_double(g.get(), "height", m.box.height);
  write_double(g.get(), "width", m.box.width);
  write_int(g.get(), "periodic_x", m.box.periodic_x ? 1 : 0);
  write_int(g.get(), "periodic_z", m.box.periodic_z ? 1 : 0);
  write_int(g.get(), "n_objects", m.n_objects);
  write_points(g.get(), "nodes", m.nodes);
  write_array(g.get(), "is_vertex", H5T_NATIVE_UINT8, m.is_vertex.data(), m.is_vertex.size(), 0);
  write_cells(g.get(), "tets", m.tets);
  write_array(g.get(), "tet_region", H5T_NATIVE_INT, m.tet_region.data(), m.tet_region.size(), 0);
  write_cells(g.get(), "boundary_faces", m.boundary_faces);
  std::vector<int> tags(m.boundary_face_tag.size());
  for (std::size_t i = 0; i < tags.size(); ++i) tags[i] = static_cast<int>(m.boundary_face_tag[i]);
  write_array(g.get(), "boundary_face_tag", H5T_NATIVE_INT, tags.data(), tags.size(), 0);
  write_cells(g.get(), "interface_faces", m.interface_faces);
  write_array(g.get(), "interface_object", H5T_NATIVE_INT, m.interface_object.data(),
              m.interface_object.size(), 0);
  write_array(g.get(), "periodic_master", H5T_NATIVE_INT, m.periodic_master.data(),
              m.periodic_master.size(), 0);
}

mesh::Mesh read_mesh(hid_t file) {
  Handle g = open_group(file, "mesh");
  mesh::Mesh m;
  m.box.length = read_double(g.get(), "length");
  m.box.height = read_double(g.get(), "height");
  m.box.width = read_double(g.get(), "width");
  m.box.periodic_x = read_int(g.get(), "periodic_x") != 0;
  m.box.periodic_z = read_int(g.get(), "periodic_z") != 0;
  m.n_objects = read_int(g.get(), "n_objects");
  m.nodes = read_points(g.get(), "nodes");
  m.is_vertex = read_array<std::uint8_t>(g.get(), "is_vertex", H5T_NATIVE_UINT8, 0);
  m.tets = read_cells<10>(g.get(), "tets");
  m.tet_region = read_array<int>(g.get(), "tet_region", H5T_NATIVE_INT, 0);
  m.boundary_faces = read_cells<6>(g.get(), "boundary_faces");
  for (int tag : read_array<int>(g.get(), "boundary_face_tag", H5T_NATIVE_INT, 0))
    m.boundary_face_tag.push_back(static_cast<mesh::BoundaryTag>(tag));
  m.interface_faces = read_cells<6>(g.get(), "interface_faces");
  m.interface_object = read_array<int>(g.get(), "interface_object", H5T_NATIVE_INT, 0);
  m.periodic_master = read_array<int>(g.get(), "periodic_master", H5T_NATIVE_INT, 0);
  // Sizes that must agree, or indices below would run off the arrays.
  const auto n = m.nodes.size();
  bool ok = m.is_vertex.size() == n && m.tet_region.size() == m.tets.size() &&
            m.boundary_face_tag.size() == m.boundary_faces.size() &&
            m.interface_object.size() == m.interface_faces.size() &&
            (m.periodic_master.empty() || m.periodic_master.size() == n);
  for (const auto& t : m.tets)
    for (int i : t) ok = ok && i >= 0 && static_cast<std::size_t>(i) < n;
  if (!ok) fail("the mesh arrays are inconsistent");
  return m;
}

/// Data reaches the disk only with fsync; the rename is durable only once
/// the directory is synced too.
void sync_path(const fs::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0)
    fail(fmt::format("cannot open {} to sync it: {}", path.string(), std::strerror(errno)));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) fail(fmt::format("cannot sync {}: {}", path.string(), std::strerror(err)));
}

// ---- the state: one dataset per entry, groups from the key's path ----

void write_state(hid_t file, const StateRecord& state) {
  Handle root = make_group(file, "state");
  std::map<std::string, std::unique_ptr<Handle>> groups;  // "a", "a/b", ... as created
  for (const auto& [key, entry] : state.entries()) {
    hid_t parent = root.get();
    std::size_t start = 0;
    for (std::size_t slash = key.find('/'); slash != std::string::npos;
         slash = key.find('/', slash + 1)) {
      const std::string path = key.substr(0, slash);
      auto it = groups.find(path);
      if (it == groups.end()) {
        const std::string group = key.substr(start, slash - start);
        auto handle = std::make_unique<Handle>(
            checked(H5Gcreate2(parent, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                    "cannot create group " + path),
            H5Gclose);
        it = groups.emplace(path, std::move(handle)).first;
      }
      parent = it->second->get();
      start = slash + 1;
    }
    const std::string name = key.substr(start);
    const std::size_t columns = static_cast<std::size_t>(entry.columns);
    Handle set = write_array(parent, name, H5T_NATIVE_DOUBLE, entry.values.data(),
                             entry.values.size() / columns, columns);
    write_int(set.get(), "kind", static_cast<int>(entry.kind));
  }
}

struct StateVisit {
  StateRecord* state;
  std::string failure;
  bool corrupt = false;  ///< the failure is damage to the file
};

herr_t read_state_entry(hid_t root, const char* name, const H5O_info_t* info, void* data) {
  auto* visit = static_cast<StateVisit*>(data);
  if (info->type != H5O_TYPE_DATASET) return 0;
  try {
    Handle set(checked(H5Dopen2(root, name, H5P_DEFAULT), std::string("dataset ") + name),
               H5Dclose);
    Handle space(checked(H5Dget_space(set.get()), std::string("dataspace ") + name), H5Sclose);
    hsize_t dims[2] = {0, 0};
    if (H5Sget_simple_extent_ndims(space.get()) != 2 ||
        H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0 || dims[1] == 0)
      fail(fmt::format("state entry {} has the wrong shape", name));
    StateRecord::Entry entry;
    const int kind = read_int(set.get(), "kind");
    if (kind < 0 || kind > 2) fail(fmt::format("state entry {} has an unknown kind {}", name, kind));
    entry.kind = static_cast<StateRecord::Kind>(kind);
    entry.columns = static_cast<int>(dims[1]);
    entry.values = read_array<double>(root, name, H5T_NATIVE_DOUBLE, dims[1]);
    visit->state->insert(name, std::move(entry));
  } catch (const Hdf5Failure& e) {
    visit->failure = e.what;
    return -1;
  } catch (const Corruption& e) {
    visit->failure = e.what;
    visit->corrupt = true;
    return -1;
  }
  return 0;
}

StateRecord read_state(hid_t file) {
  Handle root = open_group(file, "state");
  StateRecord state;
  StateVisit visit{&state, {}};
  if (H5Ovisit2(root.get(), H5_INDEX_NAME, H5_ITER_INC, read_state_entry, &visit, H5O_INFO_BASIC) <
      0) {
    if (visit.corrupt) throw Corruption{"state " + visit.failure};
    fail(visit.failure.empty() ? "cannot read the state" : visit.failure);
  }
  return state;
}

/// FNV-1a of the attributes: the header, the mesh's box, each state entry's
/// key, kind and shape. The datasets have their content hashes; HDF5's own
/// metadata checksums catch most, not all, damage to object headers, and
/// say nothing of it clearly.
std::uint64_t attributes_checksum(const Checkpoint& c) {
  Fnv1a h;
  h.scalar(c.format_version);
  h.text(c.softflow_version);
  h.text(c.case_toml);
  h.text(c.run_json);
  h.scalar(c.step);
  h.scalar(c.time);
  const auto& m = c.reference_mesh;
  h.scalar(m.box.length);
  h.scalar(m.box.height);
  h.scalar(m.box.width);
  h.scalar(static_cast<int>(m.box.periodic_x));
  h.scalar(static_cast<int>(m.box.periodic_z));
  h.scalar(m.n_objects);
  for (const auto& [key, entry] : c.state.entries()) {
    h.text(key);
    h.scalar(static_cast<int>(entry.kind));
    h.scalar(entry.columns);
    h.scalar(entry.values.size());
  }
  return h.value();
}

void write_file(const fs::path& path, const Checkpoint& c) {
  // HDF5 1.10's file format: its object headers and chunk indexes carry
  // checksums of their own (1.8's v1 B-trees, which index the chunks, have
  // none), and it takes no v1 B-tree node of 2.6 kB per dataset.
  Handle access(checked(H5Pcreate(H5P_FILE_ACCESS), "file access properties"), H5Pclose);
  checked(H5Pset_libver_bounds(access.get(), H5F_LIBVER_V110, H5F_LIBVER_LATEST),
          "cannot set the format bounds of", path.string());
  Handle file(checked(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()),
                      "cannot create the file"),
              H5Fclose);
  const hid_t root = file.get();
  write_string(root, "format", kFormatName);
  write_int(root, "format_version", c.format_version);
  write_string(root, "softflow_version", c.softflow_version);
  write_string(root, "case_toml", c.case_toml);
  write_string(root, "run_json", c.run_json);
  write_int(root, "step", c.step);
  write_double(root, "time", c.time);
  write_mesh(root, c.reference_mesh);
  write_state(root, c.state);
  const std::uint64_t checksum = attributes_checksum(c);
  write_attribute(root, "attributes_checksum", H5T_NATIVE_UINT64, &checksum);
  if (file.close() < 0) fail("cannot close the file");
}

/// Whether HDF5's signature starts the file, or our format's name is in it:
/// a file HDF5 cannot open is then a damaged one, not some other file.
bool looks_like_a_checkpoint(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return bytes.rfind("\x89HDF\r\n\x1a\n", 0) == 0 ||
         bytes.find(kFormatName) != std::string::npos;
}

hid_t open_file(const fs::path& path) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file >= 0) return file;
  const Hdf5Errors errors = hdf5_errors();
  if (!errors.checksum && !looks_like_a_checkpoint(path)) fail("cannot open it as an HDF5 file");
  throw Corruption{"HDF5 cannot open it (" + errors.cause + ")"};
}

/// The header: refuses what is not a checkpoint of this format.
void read_format(hid_t root, const fs::path& path, Checkpoint& c) {
  const htri_t has_format = H5Aexists(root, "format");
  if (has_format < 0) fail("cannot read its header");
  if (has_format == 0 || read_string(root, "format") != kFormatName)
    fail("it is not a softflow checkpoint");
  c.format_version = read_int(root, "format_version");
  c.softflow_version = read_string(root, "softflow_version");
  if (c.format_version != kCheckpointFormatVersion)
    throw InputError(fmt::format(
        "{}: checkpoint format version {} (written by softflow {}), but this softflow {} reads "
        "only version {}: continue the run with softflow {} (the build that wrote it), or run "
        "the case afresh",
        path.string(), c.format_version, c.softflow_version, SOFTFLOW_VERSION,
        kCheckpointFormatVersion, c.softflow_version));
}

/// Everything after the header, checked against the hashes written with it.
void read_contents(hid_t root, Checkpoint& c) {
  c.case_toml = read_string(root, "case_toml");
  c.run_json = read_string(root, "run_json");
  c.step = read_int(root, "step");
  c.time = read_double(root, "time");
  c.reference_mesh = read_mesh(root);
  c.state = read_state(root);
  std::uint64_t stored = 0;
  {
    Handle attribute = open_attribute(root, "attributes_checksum");
    checked(H5Aread(attribute.get(), H5T_NATIVE_UINT64, &stored), "cannot read attribute",
            "attributes_checksum");
  }
  if (stored != attributes_checksum(c))
    throw Corruption{"its attributes (header, mesh box, state keys) fail their checksum"};
}

Checkpoint read_file(const fs::path& path) {
  Handle file(open_file(path), H5Fclose);
  Checkpoint c;
  try {
    read_format(file.get(), path, c);
  } catch (const Hdf5Failure& e) {
    // An HDF5 file without our header is some other file; one whose header
    // HDF5 fails to read was damaged.
    if (!e.in_hdf5) throw;
    throw Corruption{e.what};
  }
  try {
    read_contents(file.get(), c);
  } catch (const Hdf5Failure& e) {
    // A checkpoint of this format has every group, dataset and attribute
    // asked for, in the shapes asked for: what HDF5 cannot read was damaged.
    throw Corruption{e.what};
  }
  return c;
}

}  // namespace

void remove_stale_temporaries(const fs::path& path) {
  const fs::path directory = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const std::string prefix = path.filename().string() + ".tmp-";
  std::error_code ec;
  for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = name.substr(prefix.size());
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::stol(digits);
    if (pid <= 0 || pid == static_cast<long>(::getpid())) continue;
    // Only a writer known to be gone: EPERM means alive under another user.
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code ignored;
    fs::remove(it->path(), ignored);
  }
}

namespace {

/// The bytes the checkpoint's arrays take, without HDF5's overhead.
double payload_bytes(const Checkpoint& c) {
  const auto& m = c.reference_mesh;
  double bytes = 24.0 * m.nodes.size() + 1.0 * m.is_vertex.size() + 44.0 * m.tets.size() +
                 28.0 * (m.boundary_faces.size() + m.interface_faces.size()) +
                 4.0 * m.periodic_master.size() + c.case_toml.size() + c.run_json.size();
  for (const auto& [key, entry] : c.state.entries()) bytes += 8.0 * entry.values.size() + key.size();
  return bytes;
}

/// A full disk makes HDF5 fail at the close, and then crash in its clean-up
/// at exit (measured: a segmentation fault in H5F__close_cb from
/// MPI_Finalize). So the free space is checked first, against the arrays'
/// size and a margin for HDF5's chunks, checksums and metadata.
void check_free_space(const fs::path& path, const Checkpoint& checkpoint) {
  const fs::path directory = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  const auto space = fs::space(directory, ec);
  if (ec) return;  // unknown: let the write tell
  const double needed = 1.2 * payload_bytes(checkpoint) + 256.0 * 1024.0;
  if (static_cast<double>(space.available) < needed)
    throw Error(fmt::format(
        "cannot write the checkpoint {}: the disk is full ({:.3g} MB free in {}, the checkpoint "
        "needs about {:.3g} MB); free space or choose another output directory",
        path.string(), space.available / 1e6, directory.string(), needed / 1e6));
}

}  // namespace

void write_checkpoint(const fs::path& path, const Checkpoint& checkpoint) {
  QuietHdf5Errors quiet;
  remove_stale_temporaries(path);
  check_free_space(path, checkpoint);
  fs::path tmp = path;
  tmp += fmt::format(".tmp-{}", ::getpid());
  try {
    write_file(tmp, checkpoint);
    sync_path(tmp, O_RDONLY);
  } catch (const Hdf5Failure& e) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(fmt::format("cannot write the checkpoint {}: {}", path.string(), e.what));
  }
  // The previous checkpoint stays in place until this rename replaces it in one step.
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(fmt::format("cannot write the checkpoint {}: {}", path.string(), ec.message()));
  }
  try {
    sync_path(path.has_parent_path() ? path.parent_path() : fs::path("."), O_RDONLY | O_DIRECTORY);
  } catch (const Hdf5Failure&) {
    // The checkpoint is complete and in place; only the rename's durability
    // across a power cut is in doubt, which is no reason to stop the run.
  }
}

Checkpoint read_checkpoint(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError(
        fmt::format("{}: no checkpoint there (the run wrote none yet, or this is not "
                    "a run's output directory)",
                    path.string()));
  QuietHdf5Errors quiet;
  try {
    return read_file(path);
  } catch (const Hdf5Failure& e) {
    quiet.stay_quiet();
    throw InputError(fmt::format("{}: cannot read the checkpoint: {}", path.string(), e.what));
  } catch (const Corruption& e) {
    quiet.stay_quiet();
    throw InputError(fmt::format(
        "{}: corrupt checkpoint: {} (the file was damaged after it was written); restart from "
        "an intact copy, or run the case afresh",
        path.string(), e.what));
  }
}

}  // namespace softflow::io
