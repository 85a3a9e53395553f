#include "fem/reduced_system.h"

#include "core/error.h"
#include "fem/thread_chunks.h"

#include <algorithm>
#include <cmath>

namespace hipfai::fem {

using dealii::types::global_dof_index;

void ReducedSystem::reset() {
  cholesky_.reset();
  if (matrix_) MatDestroy(&matrix_);
  matrix_ = nullptr;
  valid_ = false;
}

void ReducedSystem::map_columns(const dealii::AffineConstraints<double>& c,
                                global_dof_index n_dofs) {
  mapped_.assign(n_dofs, kDirichlet);
  free_dofs_.clear();
  for (global_dof_index i = 0; i < n_dofs; ++i) {
    if (c.is_constrained(i)) continue;
    mapped_[i] = static_cast<PetscInt>(free_dofs_.size());
    free_dofs_.push_back(i);
  }
  expansion_begin_.assign(1, 0);
  expansion_.clear();
  expansion_last_.clear();
  incoming_.assign(free_dofs_.size(), {});
  for (global_dof_index i = 0; i < n_dofs; ++i) {
    if (mapped_[i] >= 0) continue;
    const auto* entries = c.get_constraint_entries(i);
    if (!entries) continue;
    for (const auto& [j, weight] : *entries) {
      if (weight == 0.0) continue;
      if (mapped_[j] < 0) throw_error("fem: constraint of dof ", i, " names constrained dof ", j);
      expansion_.push_back({mapped_[j], weight});
      incoming_[mapped_[j]].emplace_back(i, weight);
    }
    if (expansion_.size() == expansion_begin_.back()) continue;
    mapped_[i] = kExpanded - static_cast<PetscInt>(expansion_begin_.size() - 1);
    PetscInt last = 0;
    for (std::size_t t = expansion_begin_.back(); t < expansion_.size(); ++t)
      last = std::max(last, expansion_[t].column);
    expansion_last_.push_back(last);
    expansion_begin_.push_back(expansion_.size());
  }
}

void ReducedSystem::build_rows(const CsrMatrix& k, std::size_t n_threads) {
  // Rows in chunks on threads, each into its own CSR piece; concatenated in row order.
  struct Piece {
    std::vector<PetscInt> row_length, columns;  // entries per row; column of each entry
    std::vector<double> values;                 // value of each entry
  };
  const std::size_t n_free = free_dofs_.size();
  const std::size_t chunk = chunk_size(n_free, n_threads);
  std::vector<Piece> pieces((n_free + chunk - 1) / chunk);
  auto build_chunk = [&](std::size_t first, std::size_t last) {
    if (first >= last) return;
    Piece& piece = pieces[first / chunk];
    piece.row_length.reserve(last - first);
    piece.columns.reserve(k.row_start[free_dofs_[last - 1] + 1] - k.row_start[free_dofs_[first]]);
    piece.values.reserve(piece.columns.capacity());
    std::vector<double> accumulator(n_free, 0.0);
    std::vector<char> touched(n_free, 0);
    std::vector<PetscInt> row_columns;
    for (std::size_t r = first; r < last; ++r) {
      const PetscInt diagonal = static_cast<PetscInt>(r);
      const global_dof_index j = free_dofs_[r];
      // Most rows are K's row with its columns renumbered: copied as they come (K's rows hold
      // the diagonal first, then ascending columns, which the renumbering keeps in order).
      if (incoming_[r].empty()) {
        const std::size_t mark = piece.columns.size();
        bool simple = true;
        PetscInt previous = -1;
        for (std::size_t e = k.row_start[j]; e < k.row_start[j + 1]; ++e) {
          const PetscInt c = mapped_[k.columns[e]];
          if (c >= diagonal) {
            if (c <= previous) {
              simple = false;
              break;
            }
            piece.columns.push_back(c);
            piece.values.push_back(k.values[e]);
            previous = c;
          } else if (c <= kExpanded) {
            simple = false;
            break;
          }
        }
        if (simple) {
          piece.row_length.push_back(static_cast<PetscInt>(piece.columns.size() - mark));
          continue;
        }
        piece.columns.resize(mark);
        piece.values.resize(mark);
      }
      row_columns.clear();
      const auto add = [&](PetscInt c, double value) {
        if (c < diagonal) return;  // lower triangle
        if (!touched[c]) {
          touched[c] = 1;
          row_columns.push_back(c);
        }
        accumulator[c] += value;
      };
      const auto add_row = [&](global_dof_index row, double scale) {
        for (std::size_t e = k.row_start[row]; e < k.row_start[row + 1]; ++e) {
          const PetscInt c = mapped_[k.columns[e]];
          const double value = scale * k.values[e];
          if (c >= 0) {
            add(c, value);
          } else if (c <= kExpanded) {
            const std::size_t x = static_cast<std::size_t>(kExpanded - c);
            if (expansion_last_[x] < diagonal) continue;  // all in the lower triangle
            for (std::size_t t = expansion_begin_[x]; t < expansion_begin_[x + 1]; ++t) {
              add(expansion_[t].column, value * expansion_[t].weight);
            }
          }
        }
      };
      add_row(j, 1.0);
      for (const auto& [row, weight] : incoming_[r]) add_row(row, weight);
      std::sort(row_columns.begin(), row_columns.end());
      piece.row_length.push_back(static_cast<PetscInt>(row_columns.size()));
      for (const PetscInt c : row_columns) {
        piece.columns.push_back(c);
        piece.values.push_back(accumulator[c]);
        accumulator[c] = 0.0;
        touched[c] = 0;
      }
    }
  };
  run_in_chunks(n_free, n_threads, build_chunk);
  row_start_.assign(n_free + 1, 0);
  columns_.clear();
  values_.clear();
  std::size_t nonzeros = 0;
  for (const Piece& piece : pieces) nonzeros += piece.columns.size();
  columns_.reserve(nonzeros);
  values_.reserve(nonzeros);
  std::size_t next_row = 0;
  for (Piece& piece : pieces) {
    for (const PetscInt length : piece.row_length) {
      row_start_[next_row + 1] = row_start_[next_row] + length;
      ++next_row;
    }
    columns_.insert(columns_.end(), piece.columns.begin(), piece.columns.end());
    values_.insert(values_.end(), piece.values.begin(), piece.values.end());
    piece = Piece();
  }
}

void ReducedSystem::build(const CsrMatrix& k, const dealii::AffineConstraints<double>& c,
                          std::size_t n_threads) {
  reset();
  map_columns(c, k.row_start.size() - 1);
  build_rows(k, n_threads);
  const PetscInt n_free = static_cast<PetscInt>(free_dofs_.size());
  // The arrays stay alive (and unchanged) until the next reset.
  MatCreateSeqSBAIJWithArrays(PETSC_COMM_SELF, 1, n_free, n_free, row_start_.data(),
                              columns_.data(), values_.data(), &matrix_);
  MatSetOption(matrix_, MAT_SPD, PETSC_TRUE);
  cholesky_ = std::make_unique<CholeskySolve>(PETSC_COMM_SELF, matrix_);
  valid_ = true;
}

void ReducedSystem::right_hand_side(const dealii::AffineConstraints<double>& constraint,
                                    const dealii::SparseMatrix<double>& k,
                                    dealii::Vector<double>& g, dealii::Vector<double>& kg,
                                    std::vector<double>& rhs) const {
  g = 0.0;
  for (global_dof_index i = 0; i < g.size(); ++i) {
    if (mapped_[i] < 0 && constraint.is_inhomogeneously_constrained(i))
      g(i) = constraint.get_inhomogeneity(i);
  }
  k.vmult(kg, g);
  for (std::size_t r = 0; r < free_dofs_.size(); ++r) {
    double value = -kg(free_dofs_[r]);
    for (const auto& [row, weight] : incoming_[r]) value -= weight * kg(row);
    rhs[r] = value;
  }
}

void ReducedSystem::add_transposed_row(global_dof_index dof, double value,
                                       std::vector<double>& y) const {
  const PetscInt c = mapped_[dof];
  if (c >= 0) {
    y[c] += value;
  } else if (c <= kExpanded) {
    const std::size_t x = static_cast<std::size_t>(kExpanded - c);
    for (std::size_t t = expansion_begin_[x]; t < expansion_begin_[x + 1]; ++t) {
      y[expansion_[t].column] += value * expansion_[t].weight;
    }
  }
}

bool ReducedSystem::solve(const std::vector<std::vector<double>>& rhs,
                          std::vector<std::vector<double>>& x, LinearSolverStatistics& statistics,
                          dealii::TimerOutput& timer, dealii::ConditionalOStream& log) {
  const std::size_t n = free_dofs_.size();
  x.assign(rhs.size(), std::vector<double>(n, 0.0));
  // Zero right-hand sides have the zero solution (and a block of them would ask MUMPS for
  // nothing); the others go in one block.
  std::vector<std::size_t> columns;
  for (std::size_t i = 0; i < rhs.size(); ++i) {
    if (std::any_of(rhs[i].begin(), rhs[i].end(), [](double value) { return value != 0.0; }))
      columns.push_back(i);
  }
  if (columns.empty()) return true;
  if (!cholesky_->factorised()) {
    dealii::TimerOutput::Scope scope(timer, "solver setup");
    cholesky_->factorise();
    ++statistics.factorisations;
  }
  dealii::TimerOutput::Scope scope(timer, "linear solves");
  const std::size_t k = columns.size();
  statistics.linear_iterations += static_cast<unsigned int>(k);
  const PetscInt rows = static_cast<PetscInt>(n);
  if (k == 1) {
    Vec b, v;
    VecCreateSeqWithArray(PETSC_COMM_SELF, 1, rows, rhs[columns.front()].data(), &b);
    VecCreateSeqWithArray(PETSC_COMM_SELF, 1, rows, x[columns.front()].data(), &v);
    const bool ok = cholesky_->solve(b, v, log);
    VecDestroy(&b);
    VecDestroy(&v);
    return ok;
  }
  std::vector<double> block(n * k), answers(n * k, 0.0);
  for (std::size_t c = 0; c < k; ++c) {
    std::copy(rhs[columns[c]].begin(), rhs[columns[c]].end(),
              block.begin() + static_cast<std::ptrdiff_t>(c * n));
  }
  if (!cholesky_->solve_block(rows, static_cast<PetscInt>(k), block.data(), answers.data(), log))
    return false;
  for (std::size_t c = 0; c < k; ++c) {
    const auto first = answers.begin() + static_cast<std::ptrdiff_t>(c * n);
    const auto last = first + static_cast<std::ptrdiff_t>(n);
    if (!std::all_of(first, last, [](double value) { return std::isfinite(value); })) return false;
    std::copy(first, last, x[columns[c]].begin());
  }
  return true;
}

}  // namespace hipfai::fem
