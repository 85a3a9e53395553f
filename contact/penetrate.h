// hipfai — the one entry point of the penetration-depth methods: a request in
// (penetration_request.h), a response out (penetration_result.h).
//
// Behind it, per depth asked for:
//   - curvilinear: one pose cache of M per distinct step axis (cylindrical_segmenting.h,
//     CylindricalPoseCache, §3.2.3.2: M's circles about the axis crossed with F once, then each
//     step visits only the vertices that can penetrate at its angle), over a ring table of F
//     restricted to M and built without the angular index (the cache reads every crossing);
//   - radial: F's table about the centre (radial_table.h), and M prepared once for all steps
//     (RadialPoseQuery: vertices in buckets, those a step's spans rule out dropped whole), each
//     step answered as radial_segmenting on M posed by the step's rotation, bit for bit.
// The other ways to the same answers (the one-pass cylindrical query, the per-pose radial query,
// the hybrid split, the oracles) stay in their headers for the benchmark and the tests; this
// choice is the fastest over a motion, and a different choice would change the time, not the
// pairs.
#pragma once

#include "contact/penetration_request.h"
#include "contact/penetration_result.h"

namespace hipfai::contact {

// Never throws for data-dependent reasons (a bad mesh or pose is a kInvalidInput response); throws
// hipfai::Error only when a table cannot be written to the request's cache folder.
PenetrationResponse penetrate(const PenetrationRequest& request);

}  // namespace hipfai::contact
