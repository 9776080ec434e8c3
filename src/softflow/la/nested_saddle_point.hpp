// A symmetric saddle-point operator kept as its two distinct blocks.
#pragma once

#include <span>
#include <vector>

#include "softflow/la/csr_matrix.hpp"
#include "softflow/la/petsc.hpp"

namespace softflow::la {

/// The operator
///
///     [ A    G ]   primal rows (e.g. velocity)
///     [ G^T  0 ]   constraint rows (e.g. pressure)
///
/// of a symmetric two-field problem, stored as A and G only, each an
/// la::CsrMatrix numbered within its fields (a field's unknowns in global
/// order: rank r owns a contiguous range of each). The unknowns of the
/// whole system keep their own numbering (fields interleaved node by
/// node); `primal` and `constraint` say which of this rank's unknowns
/// belong to which field.
///
/// Why: PCFIELDSPLIT extracts each block it needs from the matrix it is
/// given (MatCreateSubMatrix). From one assembled AIJ matrix those are
/// copies: A, G and G^T again, 1.2 kB per unknown at 934k Taylor-Hood
/// unknowns, as much as the matrix itself. From a MATNEST whose blocks are
/// A, G and G^T (a transpose view, no storage) the extraction hands out
/// references. The Krylov method multiplies with a shell that applies the
/// blocks through one local permutation per product (a MATNEST over
/// interleaved fields would build a VecScatter at every product).
///
/// Usage: declare the blocks' element blocks on primal() and coupling(),
/// create(); per assembly set_block on both, assemble(), then
/// eliminate_primal for Dirichlet data; solve with op() preconditioned
/// through preconditioning().
class NestedSaddlePoint {
 public:
  /// `range`: this rank's unknowns of the whole system; `primal` and
  /// `constraint`: the sorted global indices of this rank's unknowns of each
  /// field (together exactly `range`), referenced, not copied; they must
  /// outlive this object. Collective.
  NestedSaddlePoint(OwnershipRange range, PetscInt n_global, IS primal, IS constraint);
  NestedSaddlePoint(const NestedSaddlePoint&) = delete;
  NestedSaddlePoint& operator=(const NestedSaddlePoint&) = delete;

  /// A (primal x primal) and G (primal x constraint), to declare and fill.
  CsrMatrix& primal() { return a_; }
  CsrMatrix& coupling() { return g_; }

  /// Whether either block's assembly sends rows to other ranks.
  [[nodiscard]] bool rows_cross_ranks() const {
    return a_.rows_cross_ranks() || g_.rows_cross_ranks();
  }

  /// Builds both blocks' patterns, the transpose view, the nest and the
  /// shell. Collective.
  void create();
  /// Assembles both blocks. Collective.
  void assemble();

  /// Dirichlet data on primal unknowns `rows` (whole-system numbering,
  /// owned here): their rows and columns of A are replaced by the identity,
  /// their rows of G (so G^T's columns) by zero, the known values' products
  /// move to `rhs`, and `rhs` and `x` get the values in those rows.
  /// Collective.
  void eliminate_primal(std::span<const PetscInt> rows, std::span<const PetscScalar> values,
                        Vec rhs, Vec x);

  /// The operator, for the Krylov method (MATSHELL: products only).
  [[nodiscard]] Mat op() const { return shell_.get(); }
  /// The same operator as a MATNEST over `primal` and `constraint`, whose
  /// blocks PCFIELDSPLIT takes by reference.
  [[nodiscard]] Mat preconditioning() const { return nest_.get(); }

  /// y = op x. Public for the shell's callback.
  void multiply(Vec x, Vec y);

 private:
  /// Moves the nest's state after its blocks changed. Collective.
  void mark_changed();
  /// Copies a whole-system vector's entries into the two fields' vectors
  /// (and back, `to_fields` false).
  void permute(Vec whole, Vec primal, Vec constraint, bool to_fields) const;

  /// A field's numbering: this rank's unknowns of it follow those of the
  /// ranks before (each rank owns a contiguous range of the whole system).
  struct FieldNumbering {
    explicit FieldNumbering(IS owned);  // collective
    IS owned;
    OwnershipRange range;
    PetscInt n_global = 0;
  };

  OwnershipRange range_;
  PetscInt n_global_ = 0;
  FieldNumbering primal_, constraint_;
  /// For each unknown of `range`: its field (0 primal, 1 constraint).
  std::vector<char> field_of_;
  CsrMatrix a_, g_;  ///< A and G
  Matrix transpose_, nest_, shell_;
  Vector primal_in_, primal_out_, constraint_in_, constraint_out_;
};

}  // namespace softflow::la
