// hipfai — numbers taken from the literature, each with its source, in one place.
//
// Units: millimetres, degrees at interfaces (radians inside), MPa, N. Nothing else in the
// code base should spell these values as literals; include this header instead.
#pragma once

namespace hipfai::literature {

// --- Hip geometry (thesis §4.3.2.2: Arbabi 2009, after Chegini, Beck & Ferguson 2008) ---------
// Articulating surfaces are portions of spheres with a common radius of 25 mm
// (femoral and acetabular cartilage sphericity deviations < 100 um: Macirowski, Tepic & Mann 1994).
inline constexpr double kArticularRadiusMm = 25.0;
// Acetabular cartilage: horseshoe shaped, constant 2 mm thickness.
inline constexpr double kAcetabularCartilageThicknessMm = 2.0;
// Deviation from sphericity of the articular surfaces: < 100 um (Macirowski, Tepic & Mann 1994,
// cited in thesis §4.3.2.2). Surfaces within this of the articular sphere are spherical for the
// study: touching, not penetrating (studies/pipeline/penetration_run.h).
inline constexpr double kSphericityToleranceMm = 0.1;
// Femoral head cartilage: 2 mm at its thickest point, thinning to zero towards the edge
// (Eckstein et al. 1997).
inline constexpr double kFemoralCartilageMaxThicknessMm = 2.0;
// The thickest the acetabular cartilage can be in that model: the whole joint space, both
// cartilages at their thickest (kAcetabularCartilageThicknessMm + kFemoralCartilageMaxThicknessMm),
// which the socket's layer fills alone where the femoral cartilage thins to nothing at its edge.
// Bone of the socket deeper than the articular sphere by more is the acetabular fossa, which holds
// fat and the ligamentum teres, not cartilage. The radiographic joint space (both cartilages) at
// the apex of 446 normal hips measured 4.19 +- 0.92 mm (Lequesne et al. 2004, Ann Rheum Dis
// 63:1145), the same to a quarter of its spread.
inline constexpr double kAcetabularCartilageMaxThicknessMm =
    kAcetabularCartilageThicknessMm + kFemoralCartilageMaxThicknessMm;
// Labrum: triangular cross-section, 7 mm from the acetabular rim to its tip (Won et al. 2003).
inline constexpr double kLabrumHeightMm = 7.0;
// Study grid: CE 0-40 deg, alpha 40-80 deg, 10 deg steps -> 25 models (thesis §4.3.2.2).
inline constexpr double kStudyCeMinDeg = 0.0;
inline constexpr double kStudyCeMaxDeg = 40.0;
inline constexpr double kStudyAlphaMinDeg = 40.0;
inline constexpr double kStudyAlphaMaxDeg = 80.0;
inline constexpr double kStudyStepDeg = 10.0;
// Femoral neck-shaft (CCD) angle ~ 125-130 deg and femoral anteversion ~ 10-15 deg are the usual
// adult values (e.g. Tannast, Siebenrock & Anderson 2007, AJR 188:1540).
inline constexpr double kNeckShaftAngleDeg = 130.0;
inline constexpr double kFemoralAnteversionDeg = 12.0;
// Acetabular anteversion ~ 20 deg in normal adults (Tannast, Siebenrock & Anderson 2007).
inline constexpr double kAcetabularAnteversionDeg = 20.0;
// Labrum base width: its triangular section is 4.7-6.4 mm wide at the rim (Seldes et al. 2001,
// Clin Orthop Relat Res 382:232); 5 mm covers the 2 mm cartilage edge and 3 mm of bony rim.
inline constexpr double kLabrumBaseWidthMm = 5.0;
// Alpha angle of a hip without cam: the thesis's normal hip has alpha 40 deg (§4.3.2.2); Nötzli
// et al. 2002 (JBJS Br 84:556) measured 42 deg on average in asymptomatic hips.
inline constexpr double kNormalAlphaDeg = 40.0;
// Alpha angle definition: Nötzli et al. 2002 (JBJS Br 84:556) measure it on the oblique axial
// MR image through the femoral neck axis, i.e. at the anterior head-neck junction ("3 o'clock"
// on the clock face of a right hip seen from lateral: 12 superior, 3 anterior).
inline constexpr double kNotzliPlaneClockDeg = 0.0;  // from anterior towards superior
// Cam extent: the cam lies anterosuperiorly, between 12 and 3 o'clock; radial MR sequences find
// the largest alpha angles there, at 1:30-3:00, with 3 o'clock (Nötzli's plane) part of it
// (Rakhra et al. 2009, Clin Orthop Relat Res 467:660; Beck et al. 2005, JBJS Br 87:1012). The
// model's cam holds its alpha from 3:00 to 1:30 and tapers towards 12 and 4 o'clock.
inline constexpr double kCamArcBeginDeg = 0.0;   // 3 o'clock
inline constexpr double kCamArcEndDeg = 45.0;    // 1:30
// Cam height: Gosvig et al. 2007 (J Bone Joint Surg Br 89:1309, the triangular index) call a
// head-neck contour cam-shaped when it stands more than 2 mm outside the head's radius; the model's
// cam stands 2.5 mm out, just beyond that threshold. (The index's construction is as the team read
// it; only the paper's abstract was at hand to re-check, and it does not state the construction.)
inline constexpr double kCamHeightMm = 2.5;
// The thesis' normal hip has CE 20 deg (§4.3.2.2; Chegini et al. 2009); the model's socket is a
// hemisphere there (its rim a plane through the HJC) and CE changes its depth all around.
inline constexpr double kThesisNormalCeDeg = 20.0;

// --- Materials (thesis §4.3.2.3) --------------------------------------------------------------
// Articular cartilage, linear elastic (Moglo & Shirazi-Adl 2003).
inline constexpr double kCartilageYoungsModulusMPa = 12.0;
inline constexpr double kCartilagePoissonRatio = 0.45;
// Labrum, linear elastic (Ferguson, Bryant & Ito 2001).
inline constexpr double kLabrumYoungsModulusMPa = 20.0;
inline constexpr double kLabrumPoissonRatio = 0.4;

// --- Motion (thesis §4.3.2.3, after Bergmann et al. 2001) ------------------------------------
// Standing-to-sitting: the pose of largest contact stress, (flexion, adduction, internal
// rotation) = (59.6, 13.6, 10.9) deg, reached in 30 equal sub-motions from neutral.
inline constexpr double kStandToSitFlexionDeg = 59.6;
inline constexpr double kStandToSitAdductionDeg = 13.6;
inline constexpr double kStandToSitInternalRotationDeg = 10.9;
inline constexpr int kStandToSitSubMotions = 30;
// Where the femur's neutral is. The ISB femoral frame (Wu et al. 2002, J Biomech 35:543) takes
// its long axis from the midpoint of the epicondyles to the HJC: the mechanical axis, not the
// shaft. The anatomic (shaft) axis leans from it by the anatomic-mechanical angle, 6 deg on
// average (SD 1, range 3-9 deg; 100 volunteers, J Bone Joint Surg Br 2004;86-B(Supp I):31,
// doi:10.1302/0301-620X.86BSUPP_I.0860031b). A generated femur is built with its shaft along Z; at
// the ISB neutral (mechanical axis along Z) it stands adducted by this angle (study fai
// --femoral-neutral mechanical; docs/hip-geometry.md measures both).
inline constexpr double kAnatomicMechanicalAngleDeg = 6.0;
// Peak resultant hip force during sitting down, average patient: about 156 % body weight
// (Bergmann et al. 2001, J Biomech 34:859).
inline constexpr double kStandToSitPeakForcePercentBW = 156.0;

// --- Statistics (thesis §4.3.2.5, after Chan 2003) --------------------------------------------
// Pearson r bands: poor < 0.3, fair 0.31-0.5, moderate 0.51-0.6, moderately strong 0.61-0.8,
// very strong 0.81-1.0; significance p < 0.05.
inline constexpr double kSignificanceLevel = 0.05;

}  // namespace hipfai::literature

// ==== Sitting-down joint load (fem-parts; appended block, see studies/pipeline/motion.h) ================
// What is taken from Bergmann et al. (2001, J Biomech 34:859-871) is only the peak resultant for
// sitting down of their average patient, kStandToSitPeakForcePercentBW above (about 156 %BW).
// The numbers below are NOT read from the paper: they are the assumptions that turn that one
// number into a per-step load, named here so that nobody mistakes them for measurements, and
// each is a parameter of studies::SittingDownLoadOptions that a user may replace.
namespace hipfai::literature {
// Assumption: resultant at the start of the motion (upright stance), of the order of body
// weight; the curve then rises smoothly (half-cosine) to the peak.
inline constexpr double kSitDownAssumedStartForcePercentBW = 100.0;
// Assumption: the peak falls on the last sub-motion, because the thesis's end pose
// (59.6, 13.6, 10.9) deg is the pose of largest contact stress (thesis §4.3.2.3).
inline constexpr double kSitDownAssumedPeakPhase = 1.0;
// Assumption: resultant after the peak (when peak phase < 1), seated load of the order of half
// body weight; half-cosine decay from the peak.
inline constexpr double kSitDownAssumedEndForcePercentBW = 50.0;
// Assumption: direction fixed in the hip frame, tilted medially from +Z by this angle in the
// frontal plane (the usual inclination of the hip resultant) and not tilted in the sagittal plane.
inline constexpr double kSitDownAssumedFrontalAngleDeg = 15.0;
inline constexpr double kSitDownAssumedSagittalAngleDeg = 0.0;
}  // namespace hipfai::literature

// ==== Contact-pressure estimator (thesis §4.5; appended block, see stats/pressure_estimator.h) ==
namespace hipfai::literature {
// f = 1944 features "from femur bone, cartilage and acetabulum soft tissues" (§4.5.3.4). The
// thesis gives neither the grid nor the tissue split; our choice (studies/pressure_features.h):
// 4 tissues (femur bone, femoral cartilage, acetabular cartilage, labrum) x 18 polar x 27 azimuth.
inline constexpr int kEstimatorFeatureCount = 1944;
inline constexpr int kEstimatorGridPolarSteps = 18;
inline constexpr int kEstimatorGridAzimuthSteps = 27;
// e = 10 effective features kept after PCA (§4.5.3.4); e' = 1..10 evaluated.
inline constexpr int kEstimatorEffectiveFeatures = 10;
// Eq. 22: the 4 training sets with the smallest DIST1 are shortlisted ("4 was chosen by trial").
inline constexpr int kEstimatorNearestSets = 4;
// §4.5.4: leave-one-out mean error at e' = 10, case 1 (first half of the motion): 5.14 % over all
// 25 hips (sd 9.1 %), 1.62 % (sd 0.79 %) over the non-bordering ones.
inline constexpr double kEstimatorThesisMeanErrorPercent = 5.14;
inline constexpr double kEstimatorThesisInteriorErrorPercent = 1.62;
}  // namespace hipfai::literature

// ==== Hip joint centre (thesis §4.4; appended block, see geometry/hjc.h, studies/hjc_study.h) ====
namespace hipfai::literature {
// Functional HJC (dconst, dref): simulated circumduction with an elevation of 20 deg (thesis
// §4.4.2.2.2 after Gilles 2007 and Kang, Sadri, Moccozet & Magnenat-Thalmann 2003, "Hip joint
// modeling for the control of the joint center and the range of motions", 5th IFAC Symposium on
// Modelling and Control in Biomedical Systems, 20-24).
inline constexpr double kCircumductionElevationDeg = 20.0;
// Mean accuracy of the MRI bone segmentation of the thesis' subjects: 1.5 mm (thesis §4.4.2.1.2,
// after Gilles 2007). The HJC cohort's surface noise goes up to it (0.5, 1.0, 1.5 mm RMS).
inline constexpr double kSegmentationAccuracyMm = 1.5;
// Normal hip range of motion, American Academy of Orthopaedic Surgeons, "Joint Motion: Method of
// Measuring and Recording" (1965): the amplitudes of the HJC study's six medical rotations. (The
// thesis took its amplitudes from the cadaveric study of Genoud et al. 2000, whose values it does
// not print; these clinical norms stand in for them.)
inline constexpr double kAaosFlexionDeg = 120.0;
inline constexpr double kAaosExtensionDeg = 30.0;
inline constexpr double kAaosAbductionDeg = 45.0;
inline constexpr double kAaosAdductionDeg = 30.0;
inline constexpr double kAaosInternalRotationDeg = 45.0;
inline constexpr double kAaosExternalRotationDeg = 45.0;
// Hip rotation measured supine in 120 adults: external 38.5 deg, internal 29.6 deg (Kouyoumdjian,
// Coulomb, Sanchez & Asencio 2012, Orthop Traumatol Surg Res 98:17-23).
inline constexpr double kSupineExternalRotationDeg = 38.5;
inline constexpr double kSupineInternalRotationDeg = 29.6;
// Thesis §4.4.5, differences of the maximum penetration depths to those about the dref centre,
// mean over 10 MRI subjects and six rotations: radial about 30 % on average; femoralheadsphere and
// doublesphere below 19 % (radial) and 0.42 mm (curvilinear); dconst about 55 % and 1.87 mm.
inline constexpr double kThesisHjcRadialDiffPercent = 30.0;
inline constexpr double kThesisHjcSphereRadialDiffPercent = 19.0;
inline constexpr double kThesisHjcSphereCurvilinearDiffMm = 0.42;
inline constexpr double kThesisHjcDconstRadialDiffPercent = 55.0;
inline constexpr double kThesisHjcDconstCurvilinearDiffMm = 1.87;
// --- Patient-specific assessment: pelvis frame, acetabulum, clinical measures ------------------
// Anterior pelvic plane: through both anterior superior iliac spines and the pubic tubercles
// (Lewinnek et al. 1978, J Bone Joint Surg Am 60:217). Found automatically as Kai et al. 2014
// (J Biomech 47:1229) do: the plane laid on the front of the pelvis, refined until its contacts settle.
// A whole pelvis mirrored through its plane of symmetry lies within a few mm of itself (measured on
// the LHDL pelvis: see tests/anatomy/pelvis_landmarks_test.cpp); a hemipelvis mirrored lies a large
// part of the pelvis' width away. The bound between them, as a fraction of the width:
inline constexpr double kPelvisMaxSymmetryResidualFraction = 0.05;
// The midline slab where the pubic symphysis is looked for, as a fraction of the pelvis' width (the
// symphysis is ~ 40 mm wide across; the pelvis ~ 250-300 mm).
inline constexpr double kPelvisMidlineSlabFraction = 0.05;
// Acetabular orientation (Murray 1993, J Bone Joint Surg Br 75:228): the acetabular axis is the
// normal of the plane of the acetabular rim, pointing out of the socket. Radiographic inclination:
// the angle between the longitudinal axis and the acetabular axis projected on the coronal plane;
// radiographic anteversion: the angle between the acetabular axis and the coronal plane. Anatomic
// inclination: the angle between the acetabular and longitudinal axes; anatomic anteversion: the
// angle between the transverse axis and the acetabular axis projected on the transverse plane.
// Lateral centre-edge angle (Wiberg 1939, Acta Chir Scand 83 Suppl 58): in the coronal plane through
// the femoral head centre, between the longitudinal axis and the line to the lateral edge of the
// acetabular roof. Classification thresholds (Tannast, Siebenrock & Anderson 2007, AJR 188:1540):
// LCE < 20 deg: dysplasia; LCE > 39 deg: over-coverage (pincer). Cam: alpha above 50.5 deg (Nötzli et
// al. 2002, J Bone Joint Surg Br 84:556, the value separating their normal and FAI hips; Tannast et
// al. 2007 use > 50 deg).
inline constexpr double kDysplasiaMaxLateralCeDeg = 20.0;
inline constexpr double kPincerMinLateralCeDeg = 39.0;
inline constexpr double kCamMinAlphaDeg = 50.5;
// Anterior head-neck offset (Eijer et al. 2001, J Orthop Trauma 15:475): the anterior head radius
// minus the anterior neck radius, measured perpendicular to the neck axis in the plane through it
// towards anterior; offset ratio = offset / head diameter. Beaulé et al. 2005 (J Orthop Res 23:1286)
// report ratios below 0.15 in cam hips (normals ~ 0.2).
inline constexpr double kCamMaxHeadNeckOffsetRatio = 0.15;
// (end of the pelvis and measures section)

// --- Patient-specific assessment: femur landmarks and frame -------------------------------------
// Diaphysis of a long bone: the cross-sections at 20 % to 80 % of bone length from the distal end
// (Ruff & Hayes 1983, Am J Phys Anthropol 60:359, sections at 20, 35, 50, 65 and 80 %); the
// femur's shaft axis is fitted to section centroids over that span (anatomy/femur_landmarks.h).
inline constexpr double kDiaphysisBeginFraction = 0.20;
inline constexpr double kDiaphysisEndFraction = 0.80;
// Femoral neck-shaft (CCD) angle and femoral torsion (version) measured automatically on 1070 CT
// femurs of skeletally mature subjects (Hartel et al. 2016, PLoS One 11:e0149480): neck angle
// median 122.2 deg, range 100.1-146.2; torsion median 14.2 deg, range -23.6 to 48.7 (anteversion +).
inline constexpr double kAdultNeckShaftAngleMinDeg = 100.1;
inline constexpr double kAdultNeckShaftAngleMaxDeg = 146.2;
inline constexpr double kAdultFemoralVersionMinDeg = -23.6;
inline constexpr double kAdultFemoralVersionMaxDeg = 48.7;
// (end of the femur section)

// --- Patient-specific assessment: clinical motions to impingement -------------------------------
// Clinical examination positions simulated on the bones (anatomy/clinical_motions.h).
// Internal rotation in 90 deg of flexion, and the anterior impingement test (FADIR): 90 deg of
// flexion, then adduction, then maximal internal rotation, as simulated with bony collision
// detection by Kubiak-Langer, Tannast, Murphy, Siebenrock & Langlotz 2007 (Clin Orthop Relat Res
// 458:117-124) and Tannast, Kubiak-Langer, Langlotz, Puls, Murphy & Siebenrock 2007 (J Orthop Res
// 25:122-131, HipMotion), who use 15 deg of adduction for the impingement test. (Value from those
// papers' methods as recalled; the search corpus had no copy of either to confirm it.)
inline constexpr double kImpingementTestFlexionDeg = 90.0;
inline constexpr double kFadirAdductionDeg = 15.0;
// FABER (Patrick's figure-of-four: flexion, abduction, external rotation), simulated as the
// external-rotation range about the femur's long axis from a flexed and abducted start pose, as
// in the examination manoeuvres simulated on CT bones by Bedi, Thompson, Uliana, Magennis & Kelly
// 2013 (Hip Int 23 Suppl 9:S27-34). The start pose angles are ASSUMED (a figure-of-four puts the
// hip in roughly half of full flexion, moderately abducted), not taken from that paper.
inline constexpr double kFaberAssumedFlexionDeg = 45.0;
inline constexpr double kFaberAssumedAbductionDeg = 30.0;
// Passive hip range of motion of asymptomatic hips, 430 college freshman athletes (Czuppon et al.
// 2017, PM R 9:660-667), mean degrees, male / female: flexion 115.8 / 122.0; internal rotation at 0 deg
// flexion 29.0 / 38.9 and at 90 deg flexion 26.9 / 34.7; external rotation at 0 deg 39.8 / 37.6 and at
// 90 deg 44.7 / 49.7. Clinical (soft-tissue limited) values, beside which bony limits are larger.
inline constexpr double kCzupponFlexionMaleDeg = 115.8, kCzupponFlexionFemaleDeg = 122.0;
inline constexpr double kCzupponInternalRotationMaleDeg = 29.0, kCzupponInternalRotationFemaleDeg = 38.9;
inline constexpr double kCzupponInternalRotation90MaleDeg = 26.9, kCzupponInternalRotation90FemaleDeg = 34.7;
inline constexpr double kCzupponExternalRotationMaleDeg = 39.8, kCzupponExternalRotationFemaleDeg = 37.6;
inline constexpr double kCzupponExternalRotation90MaleDeg = 44.7, kCzupponExternalRotation90FemaleDeg = 49.7;
// Internal rotation on impingement testing (flexion, adduction, internal rotation to bony contact),
// computed on 3D hip models (Audenaert et al. 2012, Am J Sports Med 40:1329-1336), mean degrees:
// healthy controls 27.9, asymptomatic hips with radiographic FAI features 21.1, FAI patients 12.3.
inline constexpr double kAudenaertImpingementIrHealthyDeg = 27.9;
inline constexpr double kAudenaertImpingementIrAsymptomaticDeg = 21.1;
inline constexpr double kAudenaertImpingementIrFaiDeg = 12.3;
// (end of the clinical motions section)

// --- Patient-specific assessment: virtual resections ---------------------------------------------
// Target alpha angle of a virtual cam resection (anatomy/resection.h): 50 deg, the upper limit of
// normal that Nötzli et al. 2002 (J Bone Joint Surg Br 84:556-560) proposed from their
// asymptomatic hips (mean 42 deg). Later thresholds for classifying a cam are higher, about 60 deg
// (systematic review: van Klij et al. 2020, Orthop J Sports Med 8(8), PMC7418265); resecting to
// the stricter 50 deg leaves a hip normal by either. (Nötzli's value as recalled; the review's
// abstract was read.)
inline constexpr double kCamResectionTargetAlphaDeg = 50.0;
// (end of the resections section)

}  // namespace hipfai::literature

// ==== Space-filling designs (appended block, see stats/space_filling_design.h) ==================
namespace hipfai::literature {
// Maximin Latin hypercubes are optimised through the phi_p criterion, (sum over pairs of d^-p)^(1/p),
// of Morris & Mitchell (1995, J Stat Plan Inference 43:381-402), which tends to the maximin
// criterion as p grows; p = 50 as in Jin, Chen & Sudjianto (2005, J Stat Plan Inference
// 134:268-287) and Damblin, Couplet & Iooss (2013, J Simulation 7:276-289; R DiceDesign's default).
inline constexpr int kMaximinPhiPower = 50;
}  // namespace hipfai::literature

// ==== Estimator intervals on hips it has not seen (appended block, see stats/conformal_interval.h) ==
namespace hipfai::literature {
// Conformal prediction: an interval from the k-th smallest of n calibration scores, k =
// ceil((n + 1) * nominal), holds a new exchangeable row's truth with probability >= nominal (Vovk,
// Gammerman & Shafer 2005, "Algorithmic Learning in a Random World", Springer, ch. 2; the split /
// inductive form: Papadopoulos, Proedrou, Vovk & Gammerman 2002, ECML, LNCS 2430:345-356; per group,
// "Mondrian" conformal predictors: Vovk, Lindsay, Nouretdinov & Gammerman 2003, Mondrian confidence
// machine, technical report, Royal Holloway). The nominal coverage reported by default is 90 %.
inline constexpr double kEstimatorNominalCoverage = 0.90;
// A step's estimate counts as in error when it is more than 10 % off the FE value: twice the
// thesis' mean leave-one-out error (5.14 %, §4.5.4), the "large error" the flag is checked against.
inline constexpr double kEstimatorLargeErrorFraction = 0.10;
// Thesis Table 13 (§4.5.3.5): leave-one-out mean error over the whole motion (case 2) at e' = 10,
// mean of its 20 hips: 4.85 %.
inline constexpr double kEstimatorThesisCase2MeanErrorPercent = 4.85;
}  // namespace hipfai::literature
