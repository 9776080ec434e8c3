// Thin RAII wrappers over PETSc objects; the only place (with la/*.cpp) that includes PETSc.
#pragma once

#include <petscksp.h>

#include <span>
#include <string>
#include <utility>
#include <vector>

namespace softflow::la {

/// Throws SolverError with PETSc's message if `code` is an error.
void check(PetscErrorCode code, const char* what);

/// Owns a PETSc object handle and destroys it exactly once.
template <class Handle, PetscErrorCode (*destroy)(Handle*)>
class Owned {
 public:
  Owned() = default;
  explicit Owned(Handle h) : handle_(h) {}
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  Owned(Owned&& o) noexcept : handle_(std::exchange(o.handle_, nullptr)) {}
  Owned& operator=(Owned&& o) noexcept {
    if (this != &o) {
      reset();
      handle_ = std::exchange(o.handle_, nullptr);
    }
    return *this;
  }
  ~Owned() { reset(); }
  void reset() {
    if (handle_) destroy(&handle_);
    handle_ = nullptr;
  }
  [[nodiscard]] Handle get() const { return handle_; }
  Handle* out() {
    reset();
    return &handle_;
  }
  explicit operator bool() const { return handle_ != nullptr; }

 private:
  Handle handle_ = nullptr;
};

using Vector = Owned<Vec, VecDestroy>;
using Matrix = Owned<Mat, MatDestroy>;
using Solver = Owned<KSP, KSPDestroy>;
using IndexSet = Owned<IS, ISDestroy>;
using NullSpace = Owned<MatNullSpace, MatNullSpaceDestroy>;

/// Contiguous ownership of global indices [begin, end) on this rank.
struct OwnershipRange {
  PetscInt begin = 0;
  PetscInt end = 0;
  [[nodiscard]] bool owns(PetscInt i) const { return i >= begin && i < end; }
  [[nodiscard]] PetscInt size() const { return end - begin; }
};

int mpi_rank(MPI_Comm comm = PETSC_COMM_WORLD);
int mpi_size(MPI_Comm comm = PETSC_COMM_WORLD);
/// Gives every rank of `comm` rank `root`'s `text` (a message, a file read on one rank).
/// Collective.
void broadcast_text(std::string& text, int root = 0, MPI_Comm comm = PETSC_COMM_WORLD);

/// A distributed vector with the given local size.
Vector make_vector(PetscInt n_local, PetscInt n_global);

/// An index set of this rank's global indices (sorted, owned).
IndexSet make_index_set(std::span<const PetscInt> owned_indices, PetscInt block_size = 1);

/// One field of a block system: its name (fieldsplit options address it
/// as -<prefix>fieldsplit_<name>_...) and this rank's rows of it.
struct NamedIndexSet {
  std::string name;
  IS rows = nullptr;  ///< not owned
};

/// A direct solver: MUMPS LU applied once (preonly) to `a`, its choices
/// overridable under the options prefix (e.g. -transport_pc_type ilu).
Solver lu_solver(Mat a, const std::string& prefix);

/// Makes `pc` a shell preconditioner with these callbacks; `destroy` frees
/// `context` (PCShellGetContext gives it back to the callbacks).
void make_shell_preconditioner(PC pc, void* context, PetscErrorCode (*set_up)(PC),
                               PetscErrorCode (*apply)(PC, Vec, Vec),
                               PetscErrorCode (*destroy)(PC), const char* name);

/// The six rigid-body modes (3 translations, 3 rotations) of a vector field
/// given the coordinates of this rank's nodes as x y z triples: the
/// near-nullspace smoothed-aggregation AMG needs for elasticity-like blocks.
NullSpace rigid_body_modes(std::span<const PetscScalar> xyz);

/// Gives `matrix` the span of `basis` (mutually orthogonal vectors, not
/// necessarily normalised: normalised copies are made) as its null space
/// and as its transpose's: KSPSolve then projects the right-hand side onto
/// the range and Krylov methods solve the singular, consistent system. For
/// operators whose left and right null spaces agree, e.g. a pressure free
/// up to a constant with continuity rows that sum to zero.
void attach_null_space(Mat matrix, std::span<const Vec> basis);

}  // namespace softflow::la
