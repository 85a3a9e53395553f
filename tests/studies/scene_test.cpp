#include "studies/pipeline/scene.h"

#include "core/error.h"

#ifdef HIPFAI_WITH_FEM
#include "fem/hip_fe_model.h"
#endif

#include <gtest/gtest.h>

#include <string>

namespace hipfai::studies {
namespace {

const std::string kGood = R"(schema_version: 1
units: {length: mm, angle: deg}
name: normal
hip:
  parametric: {ce_deg: 20, alpha_deg: 40, edge_mm: 2.0}
motion: {builtin: standing_to_sitting, sub_motions: 30}
outputs: [radial_depth]
)";

// `text` with the first `from` replaced by `to` (built by concatenation: g++ 12 warns spuriously
// about std::string::replace with -Wrestrict).
std::string replaced(const std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  return text.substr(0, at) + to + text.substr(at + from.size());
}

// Returns the error message of parsing `text`, or "" if it parsed.
std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "scene.yaml");
  } catch (const hipfai::Error& e) {
    return e.what();
  }
  return "";
}

// The mapping is parsed once, into the enum the radial table takes; the default is the cube.
TEST(Scene, RadialMappingIsParsedIntoTheEnum) {
  EXPECT_EQ(parse_scene(kGood, "scene.yaml").options.mapping, contact::RadialMapping::kCube);
  for (const auto mapping :
       {contact::RadialMapping::kSpherical, contact::RadialMapping::kCartesian, contact::RadialMapping::kCube}) {
    const std::string text = kGood + "options: {mapping: " + contact::to_string(mapping) + "}\n";
    EXPECT_EQ(parse_scene(text, "scene.yaml").options.mapping, mapping);
  }
  const std::string message = error_of(kGood + "options: {mapping: polar}\n");
  EXPECT_NE(message.find("options.mapping"), std::string::npos) << message;
  EXPECT_NE(message.find("expected spherical, cartesian or cube"), std::string::npos) << message;
}

TEST(Scene, ParsesAndDerivesTissuesFromOutputs) {
  const Scene scene = parse_scene(kGood, "scene.yaml");
  ASSERT_TRUE(scene.parametric.has_value());
  EXPECT_DOUBLE_EQ(scene.parametric->ce_deg, 20.0);
  EXPECT_EQ(scene.outputs.size(), 1u);
  // Radial depth needs the femur (bone + cartilage) and the acetabular soft tissues, not the pelvis.
  EXPECT_EQ(scene.tissues,
            (std::set<std::string>{"femur_bone", "femoral_cartilage", "acetabular_cartilage", "labrum"}));
}

TEST(Scene, UnknownKeyIsNamedWithItsLine) {
  std::string text = kGood;
  text = replaced(text, "outputs", "outptus");
  const std::string message = error_of(text);
  EXPECT_NE(message.find("scene.yaml:7: outptus: unknown key"), std::string::npos) << message;
}

TEST(Scene, WrongUnitsAreRejected) {
  std::string text = kGood;
  text = replaced(text, "mm,", "m,");
  EXPECT_NE(error_of(text).find("units.length"), std::string::npos);
  text = kGood;
  text = replaced(text, "deg}", "rad}");
  EXPECT_NE(error_of(text).find("units.angle"), std::string::npos);
}

TEST(Scene, AngleOutOfRangeNamesKeyAndLine) {
  std::string text = kGood;
  text = replaced(text, "ce_deg: 20", "ce_deg: 75");
  const std::string message = error_of(text);
  EXPECT_NE(message.find(":5: hip.parametric.ce_deg: 75 is outside"), std::string::npos) << message;
}

TEST(Scene, MissingTissueForAnOutputIsAnError) {
  std::string text = kGood + "tissues: [femur_bone, femoral_cartilage, labrum]\n";
  EXPECT_NE(error_of(text).find("needs 'acetabular_cartilage'"), std::string::npos);
}

TEST(Scene, MissingFilesAreReportedBeforeWork) {
  std::string text = kGood;
  text = replaced(text, "builtin: standing_to_sitting, sub_motions: 30", "csv: nowhere.csv");
  EXPECT_NE(error_of(text).find("motion.csv: file not found"), std::string::npos);
  text = kGood;
  text = replaced(text, "parametric: {ce_deg: 20, alpha_deg: 40, edge_mm: 2.0}",
                  "model_dir: /no/such/dir");
  EXPECT_NE(error_of(text).find("hip.model_dir: no model.json"), std::string::npos);
}

TEST(Scene, UnknownOutputAndBadYaml) {
  std::string text = kGood;
  text = replaced(text, "[radial_depth]", "[stress]");
  EXPECT_NE(error_of(text).find("unknown output 'stress'"), std::string::npos);
  EXPECT_NE(error_of("schema_version: [1\n").find("YAML syntax error"), std::string::npos);
}

TEST(Scene, FeBlockIsReadAndFeOutputsNeedTheFeTissuesOnly) {
  std::string text = replaced(kGood, "[radial_depth]", "[von_mises, contact_pressure]");
  text += "fe: {level: coarse, body_weight_n: 800}\n";
  const Scene scene = parse_scene(text, "scene.yaml");
  EXPECT_EQ(scene.fe.level, FeLevel::kCoarse);
  EXPECT_DOUBLE_EQ(scene.fe.body_weight_n, 800.0);
  EXPECT_TRUE(needs_fe(scene));
  EXPECT_FALSE(needs_penetration(scene));
  // The hip FE model's tissues; the pelvis is a fixed boundary, not a mesh the FE reads.
  EXPECT_EQ(scene.tissues,
            (std::set<std::string>{"femur_bone", "femoral_cartilage", "acetabular_cartilage", "labrum"}));
}

TEST(Scene, FeBlockDefaults) {
  const Scene scene = parse_scene(kGood, "scene.yaml");
  EXPECT_EQ(scene.fe.level, FeLevel::kDefault);
  EXPECT_DOUBLE_EQ(scene.fe.body_weight_n, 700.0);
  EXPECT_FALSE(needs_fe(scene));
  EXPECT_TRUE(needs_penetration(scene));
#ifdef HIPFAI_WITH_FEM
  EXPECT_DOUBLE_EQ(scene.fe.body_weight_n, fem::kDefaultBodyWeightN);
#endif
}

TEST(Scene, FeBlockErrorsNameKeyAndLine) {
  // kGood has 7 lines: the fe block is line 8.
  std::string message = error_of(kGood + "fe: {level: medium}\n");
  EXPECT_NE(message.find("scene.yaml:8: fe.level: unknown level 'medium'"), std::string::npos) << message;
  message = error_of(kGood + "fe: {body_weight_n: -5}\n");
  EXPECT_NE(message.find("scene.yaml:8: fe.body_weight_n: -5 is outside"), std::string::npos) << message;
  message = error_of(kGood + "fe: {body_weight_n: 0}\n");
  EXPECT_NE(message.find("scene.yaml:8: fe.body_weight_n: must be positive"), std::string::npos) << message;
  message = error_of(kGood + "fe: {body_weight_n: heavy}\n");
  EXPECT_NE(message.find("scene.yaml:8: fe.body_weight_n: expected a number"), std::string::npos) << message;
  message = error_of(kGood + "fe: {level: coarse, mesh: fine}\n");
  EXPECT_NE(message.find("scene.yaml:8: fe.mesh: unknown key"), std::string::npos) << message;
  message = error_of(kGood + "fe: coarse\n");
  EXPECT_NE(message.find("scene.yaml:8: fe: expected a mapping"), std::string::npos) << message;
}

// Every level of the one name table (core/fe_choices.h) reads back as itself.
TEST(Scene, FeLevelsAreTheTablesLevels) {
  for (const FeLevel level : kFeLevels) {
    const Scene scene = parse_scene(kGood + "fe: {level: " + to_string(level) + "}\n", "scene.yaml");
    EXPECT_EQ(scene.fe.level, level);
  }
}


// A segmented hip: the two bone files (paths relative to the scene file or absolute), an optional
// side and frame file; missing files and a bad side are one-line errors naming the line.
TEST(Scene, BonesAreASegmentedHip) {
  const std::string lhdl = std::string(HIPFAI_SOURCE_DIR) + "/meshes/real-hips/LHDL_CT/";
  const std::string head = "schema_version: 1\nunits: {length: mm, angle: deg}\nname: bones\nhip:\n  bones: {femur: " +
                           lhdl + "femur_r.ply, pelvis: " + lhdl + "pelvis_no_sacrum.ply";
  const std::string tail = "}\nmotion: {builtin: standing_to_sitting, sub_motions: 3}\noutputs: [curvilinear_depth]\n";
  const Scene scene = parse_scene(head + ", side: right" + tail, "scene.yaml");
  ASSERT_TRUE(scene.bones.has_value());
  EXPECT_EQ(scene.bones->femur, lhdl + "femur_r.ply");
  EXPECT_EQ(scene.bones->side, anatomy::Side::kRight);
  EXPECT_TRUE(scene.bones->frame.empty());
  EXPECT_FALSE(scene.parametric.has_value());
  std::string message = error_of(head + ", side: middle" + tail);
  EXPECT_NE(message.find("hip.bones.side: expected right or left"), std::string::npos) << message;
  message = error_of(head + ", frame: none.json" + tail);
  EXPECT_NE(message.find("hip.bones.frame: file not found"), std::string::npos) << message;
  message = error_of("schema_version: 1\nunits: {length: mm, angle: deg}\nhip:\n  bones: {femur: " + lhdl +
                     "femur_r.ply}\n" + tail.substr(2));
  EXPECT_NE(message.find("hip.bones.pelvis: missing"), std::string::npos) << message;
  message = error_of("schema_version: 1\nunits: {length: mm, angle: deg}\nhip:\n  model_dir: .\n  bones: {femur: a}\n" +
                     tail.substr(2));
  EXPECT_NE(message.find("give one of parametric, model_dir and bones"), std::string::npos) << message;
}

}  // namespace
}  // namespace hipfai::studies
