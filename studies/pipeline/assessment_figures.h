// hipfai — the figures of an assessment report, plain SVG:
//
//   coronal_ce.svg          the pelvis and femur cut by the coronal plane through the femoral head
//                           (pelvis frame), the frame's right and superior axes, and the lateral CE
//                           drawn from the head centre to the rim point;
//   notzli_alpha.svg        the femur cut by Nötzli's plane, the fitted head circle, the neck axis and
//                           the alpha angle to where the contour leaves the circle (before and, when
//                           resected, after);
//   impingement_clock.svg   two clock faces, the acetabular rim and the head-neck junction, with the
//                           contact point of every clinical motion's limit;
//   rom.svg                 the clinical ranges of motion as bars, before and after the resections;
//   alpha_profile.svg       the clock profile of alpha, before and after.
#pragma once

#include "studies/pipeline/assessment.h"

#include <filesystem>

namespace hipfai::studies {

// Writes the figures into `dir` (which must exist); each file atomically.
void write_assessment_figures(const AssessmentResult& result, const std::filesystem::path& dir);

}  // namespace hipfai::studies
