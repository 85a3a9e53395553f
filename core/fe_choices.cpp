// hipfai — FE mesh level and solver names (see fe_choices.h).
#include "core/fe_choices.h"

#include "core/error.h"

namespace hipfai {
namespace {

template <class Enum, std::size_t N>
std::optional<Enum> from_name(std::string_view name, const std::array<Enum, N>& values) {
  for (const Enum value : values) {
    if (name == to_string(value)) return value;
  }
  return std::nullopt;
}

template <class Enum, std::size_t N>
std::vector<std::string> names_of(const std::array<Enum, N>& values) {
  std::vector<std::string> names;
  for (const Enum value : values) names.emplace_back(to_string(value));
  return names;
}

}  // namespace

const char* to_string(FeLevel level) {
  switch (level) {
    case FeLevel::kCoarse: return "coarse";
    case FeLevel::kDefault: return "default";
    case FeLevel::kFine: return "fine";
  }
  return "?";
}

const char* to_string(FeSolver solver) {
  switch (solver) {
    case FeSolver::kSubstructured: return "substructured";
    case FeSolver::kDirect: return "direct";
    case FeSolver::kCg: return "cg";
  }
  return "?";
}

const std::vector<std::string>& fe_level_names() {
  static const std::vector<std::string> names = names_of(kFeLevels);
  return names;
}

const std::vector<std::string>& fe_solver_names() {
  static const std::vector<std::string> names = names_of(kFeSolvers);
  return names;
}

std::optional<FeLevel> fe_level_from_name(std::string_view name) { return from_name(name, kFeLevels); }
std::optional<FeSolver> fe_solver_from_name(std::string_view name) { return from_name(name, kFeSolvers); }

FeLevel parse_fe_level(std::string_view name, std::string_view what) {
  if (const auto level = fe_level_from_name(name)) return *level;
  throw_error(what, ": unknown FE level '", name, "' (coarse, default or fine)");
}

FeSolver parse_fe_solver(std::string_view name, std::string_view what) {
  if (const auto solver = fe_solver_from_name(name)) return *solver;
  throw_error(what, ": unknown FE solver '", name, "' (substructured, direct or cg)");
}

}  // namespace hipfai
