// hipfai — the FAI penetration study's independent units (studies/fai_study.h): each hip of the
// grid at the main edge, then each of thesis Table 10's archetypes on the grid at each other edge
// of the resolution table. A unit generates (or takes from the cache) its hip and runs the
// penetration method over the motion; it runs the same in this process or on a worker rank.
#pragma once

#include "studies/fai_study.h"

#include <string>
#include <vector>

namespace hipfai::studies {

struct FaiUnit {
  double ce_deg = 0, alpha_deg = 0;
  double edge_mm = 0;
};

// The study's units in the order they are computed: the grid (CE outer, alpha inner) at
// options.edge_mm, then per edge of options.resolution_edges_mm other than the main one (as given)
// each archetype (fai_archetypes() order) whose angles are on the grid.
std::vector<FaiUnit> fai_study_units(const FaiStudyOptions& options);

// "ce20_alpha40", and " at 3 mm" for an edge other than the main one.
std::string fai_unit_name(const FaiUnit& unit, const FaiStudyOptions& options);

// The unit's hip as the study runs it: generated into options.cache_dir (or taken from there),
// the tissues of both depths loaded, the femur at options.femoral_neutral.
LoadedHip load_fai_unit_hip(const FaiUnit& unit, const FaiStudyOptions& options, StageLog& log);

// Runs the unit: its hip, the penetration over `motion` with options.threads (per-step VTP files of
// the hips options.vtp_models asks for at the main edge, into options.out_dir), the first contact
// along the motion's axis.
FaiModelRun run_fai_unit(const FaiUnit& unit, const Motion& motion, const FaiStudyOptions& options, StageLog& log);

}  // namespace hipfai::studies
