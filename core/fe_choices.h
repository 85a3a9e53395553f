// hipfai — the choices a user makes for the finite-element ground truth: the mesh level and the
// solver, as enums with one table of names each. The CLI, scenes, studies, the worker processes'
// command lines and the reports all read and write them through these, and the names are what
// the files record ("coarse", "substructured", ...). Free of the FE module, so scenes and result
// readers know the names in a build without it.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hipfai {

// Mesh levels of the hip FE model (fem/hip_fe_model.h has what each means; docs/fem-levels.md).
enum class FeLevel { kCoarse, kDefault, kFine };
inline constexpr std::array<FeLevel, 3> kFeLevels{FeLevel::kCoarse, FeLevel::kDefault, FeLevel::kFine};

// Linear solvers of a contact step: each body factorised once and the contact condensed, MUMPS on
// the whole system per active set (the monolithic reference), or CG with algebraic multigrid.
enum class FeSolver { kSubstructured, kDirect, kCg };
inline constexpr std::array<FeSolver, 3> kFeSolvers{FeSolver::kSubstructured, FeSolver::kDirect, FeSolver::kCg};

// "coarse", "default", "fine"; "substructured", "direct", "cg".
const char* to_string(FeLevel level);
const char* to_string(FeSolver solver);
// The names in enum order (for the CLI's checks and help).
const std::vector<std::string>& fe_level_names();
const std::vector<std::string>& fe_solver_names();
// std::nullopt for a name not in the table.
std::optional<FeLevel> fe_level_from_name(std::string_view name);
std::optional<FeSolver> fe_solver_from_name(std::string_view name);
// The same, throwing hipfai::Error "<what>: unknown FE level 'x' (coarse, default or fine)".
FeLevel parse_fe_level(std::string_view name, std::string_view what);
FeSolver parse_fe_solver(std::string_view name, std::string_view what);

}  // namespace hipfai
